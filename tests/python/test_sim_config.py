"""Scene configs: every bad value is an error naming its field; unknown names are errors."""

from __future__ import annotations

import pytest

from a2l.sim import SCENES, PushConfig, make_config, make_scene


def test_unknown_scene_is_named() -> None:
    with pytest.raises(ValueError, match="unknown scene 'kitchen'"):
        make_scene("kitchen")


@pytest.mark.parametrize("scene", SCENES)
def test_unknown_config_key_is_named(scene: str) -> None:
    with pytest.raises(ValueError, match="unknown config key 'colour_of_sky'"):
        make_scene(scene, colour_of_sky="blue")


@pytest.mark.parametrize(
    ("scene", "values", "field"),
    [
        ("push", {"box_position": (2.0, 0.0)}, "box_position"),  # off the table
        ("push", {"box_position": (0.6, -0.74)}, "box_position"),  # footprint over the edge
        ("push", {"box_position": (0.6, -0.69), "object_jitter": 0.03}, "box_position"),
        ("grasp", {"block_position": (0.0, 0.0)}, "block_position"),
        ("press", {"button_position": (0.6, 0.9)}, "button_position"),
        ("press", {"lamp_position": (5.0, 0.0)}, "lamp_position"),
        ("push", {"box_size": (0.07, -0.085, 0.08)}, "box_size"),  # negative size
        ("grasp", {"block_size": (0.03, 0.0, 0.06)}, "block_size"),
        ("grasp", {"block_size": (0.03, 0.08, 0.06)}, "block_size"),  # wider than the gripper
        ("press", {"button_size": (0.06, 0.06)}, "button_size"),  # wrong length
        ("push", {"box_mass": -1.0}, "box_mass"),
        ("push", {"box_friction": float("nan")}, "box_friction"),
        ("push", {"step": 0.0}, "step"),
        ("push", {"states": {"stove": "on"}}, "states"),  # unknown high-level state
        ("push", {"states": {"light": "on"}}, "states"),  # the push scene has no light
        ("press", {"states": {"light": "dim"}}, "states"),  # unknown value
        ("push", {"n_push_effects": 6}, "n_push_effects"),
        ("push", {"context_source": "oracle"}, "context_source"),
        ("push", {"camera_width": 0}, "camera_width"),
        ("push", {"table_size": (0.7, -1.0)}, "table_size"),
        ("push", {"workspace_max": (0.3, 0.45, 0.45)}, "workspace_max"),
        ("push", {"gui": "yes"}, "gui"),
        ("press", {"button_trigger": 0.05}, "button_trigger"),
        ("virtual", {"box_half_size": (0.035, -0.04, 0.04)}, "box_half_size"),
        ("virtual", {"states": {"light": "on"}}, "states"),
        ("virtual", {"eef_radius": -0.01}, "eef_radius"),
    ],
)
def test_bad_values_name_the_field(scene: str, values: dict, field: str) -> None:
    with pytest.raises(ValueError, match=f"'{field}'"):
        make_config(scene, **values)


def test_good_config_is_normalized() -> None:
    cfg = make_config("push", box_size=[0.05, 0.05, 0.05], box_position=[0.7, -0.2])
    assert isinstance(cfg, PushConfig)
    assert cfg.box_size == (0.05, 0.05, 0.05)
    assert cfg.box_position == (0.7, -0.2)
    assert cfg.initial_states() == {"gripper": "open"}
    press = make_config("press", states={"light": "on"})
    assert press.initial_states() == {"gripper": "open", "light": "on"}
