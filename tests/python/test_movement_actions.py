"""Movement actions (open, close, stay) in the repertoire: the Python MovementRepertoire, the
bundle's ``movements.actions`` (written and read back, run by the C++ step), a dataset's
``action`` column, the export's movement order, and Baxter's scene carrying them out."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from a2l import A2LValueError, BundleError, _core
from a2l.sim import make_scene
from a2l.skills import (
    Discretizer,
    DistanceBins,
    HighLevelState,
    MovementRepertoire,
    PolicyTable,
    SkillSpec,
    VariableSpec,
    load_bundle,
    make_skill_spec,
    save_bundle,
)

AXES = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]


def test_repertoire_holds_directions_then_actions() -> None:
    rep = MovementRepertoire(0.03, AXES, ["+x", "-x", "+y", "-y", "+z", "-z"], ("close", "stay"))
    assert rep.n_moves == 8 and rep.n_directions == 6
    assert rep.labels[-2:] == ("close", "stay") and rep.direction_labels[0] == "+x"
    assert rep.index_of("close") == 6 and rep.index_of("-z") == 5
    assert rep.is_action(7) and not rep.is_action(5)
    assert rep.action(6) == "close" and rep.action(0) is None
    disp = rep.displacement(np.arange(8))
    np.testing.assert_allclose(disp[0], [0.03, 0.0, 0.0])
    np.testing.assert_array_equal(disp[6:], 0.0)
    # A displacement is never discretized into an action.
    assert rep.discretize(np.array([[0.0, 0.0, -0.1], [0.0, 0.0, 0.0]])).tolist() == [5, -1]
    # The default repertoire is unchanged (26 directions, no action).
    assert MovementRepertoire().n_moves == 26 and MovementRepertoire(planar=True).actions == ()
    with pytest.raises(KeyError, match="no movement 'open'"):
        rep.index_of("open")
    with pytest.raises(ValueError, match=r"actions\[0\] = 'grip'"):
        MovementRepertoire(actions=("grip",))
    with pytest.raises(ValueError, match=r"actions\[1\] = 'open' repeats"):
        MovementRepertoire(actions=("open", "open"))
    with pytest.raises(ValueError, match=r"directions\[1\]"):
        MovementRepertoire(0.05, [[1, 0, 0], [0, 0, 0]])


def _grasp_light_spec() -> SkillSpec:
    """effect(1) x distance(3) x light(2); light off approaches (-x) then closes, light on
    moves away (+x) then stays."""
    variables = [
        VariableSpec("effect", "effect", 1, values=("grasped",)),
        VariableSpec("distance", "distance", 3, low=0.05, high=0.20),
        VariableSpec("light", "high_level", 2, values=("off", "on")),
    ]
    rep = MovementRepertoire(0.05, AXES, None, ("open", "close", "stay"))
    chosen = [[rep.index_of("close"), 0], [1, 0], [1, rep.index_of("stay")]]
    post = np.full((1, 3, 2, rep.n_moves), 0.1 / (rep.n_moves - 1))
    argmax = np.zeros((1, 3, 2), dtype=np.int32)
    for d in range(3):
        for light in range(2):
            post[0, d, light, chosen[d][light]] = 0.9
            argmax[0, d, light] = chosen[d][light]
    return SkillSpec("grasp_light", variables, np.array(AXES), post, argmax,
                     labels=list(rep.direction_labels), actions=list(rep.actions))


def test_bundle_actions_round_trip_and_drive_the_cpp_step(tmp_path: Path) -> None:
    path = save_bundle(_grasp_light_spec(), tmp_path / "g.a2lb")
    spec = load_bundle(path)
    assert spec.actions == ["open", "close", "stay"] and spec.posterior.shape == (1, 3, 2, 9)
    skill = _core.load_bundle(path)
    assert skill.movements.actions == ["open", "close", "stay"]
    assert skill.movements.labels[6:] == ["open", "close", "stay"]
    state = _core.SkillState(skill)
    obj = np.array([0.6, -0.2, 0.1])
    near = skill.context(obj + [0.03, 0, 0], obj, "grasped", {"light": "off"})
    out = _core.step(skill, state, near)
    assert out.status == _core.Status.ok and out.action == _core.MovementAction.close
    np.testing.assert_array_equal(out.displacement, 0.0)
    far_on = skill.context(obj + [0.22, 0, 0], obj, "grasped", {"light": "on"})
    assert _core.step(skill, state, far_on).action == _core.MovementAction.stay


def test_bundle_refuses_bad_actions(tmp_path: Path) -> None:
    spec = _grasp_light_spec()
    spec.actions = ["open", "close", "grip"]
    with pytest.raises(BundleError, match=r"movements\.actions\[2\]: unknown action 'grip'"):
        save_bundle(spec, tmp_path / "bad.a2lb")
    spec.actions = ["open", "close"]  # the table has one more movement
    with pytest.raises(BundleError, match=r"arrays\.posterior\.shape"):
        save_bundle(spec, tmp_path / "bad.a2lb")
    assert not (tmp_path / "bad.a2lb").exists()


def test_dataset_action_column_and_export_order() -> None:
    rep = MovementRepertoire(0.05, AXES, None, ("close",))
    disc = Discretizer(distance=DistanceBins(3, 0.05, 0.20), orientation=None, inclination=None,
                       movements=rep, high_level=(HighLevelState("light", ("off", "on")),))
    raw = pd.DataFrame({
        "episode": [0, 0, 0], "step": [0, 1, 2],
        "eef_x": [0.2, 0.15, 0.1], "eef_y": 0.0, "eef_z": 0.0,
        "obj_x": 0.0, "obj_y": 0.0, "obj_z": 0.0,
        "move_dx": [-0.05, -0.05, 0.0], "move_dy": 0.0, "move_dz": 0.0,
        "effect": "left", "light": "off", "action": [None, "", "close"],
    })
    data = disc.discretize(raw)
    assert data["move"].tolist() == ["-x", "-x", "close"]
    with pytest.raises(ValueError, match=r"action\(s\) \['open'\]"):
        disc.discretize(raw.assign(action=[None, None, "open"]))
    # A table whose movement states list the action first: the bundle puts it last.
    states = ["close", *rep.direction_labels]
    values = np.full((4, 7), 1.0 / 7)
    values[0] = [0.7, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05]  # "close" most probable
    values[1] = [0.05, 0.05, 0.7, 0.05, 0.05, 0.05, 0.05]  # "-x"
    table = PolicyTable("move", states, ["effect"], {"effect": list(disc.effects.values)},
                        values, np.array([0, 2, -1, -1], dtype=np.int32))
    spec = make_skill_spec(table, disc, name="g")
    assert spec.actions == ["close"] and spec.labels == list(rep.direction_labels)
    assert spec.argmax.tolist() == [6, 1, -1, -1]
    np.testing.assert_allclose(spec.posterior[0, 6], 0.7)
    np.testing.assert_array_equal(spec.directions, AXES)


def test_baxter_scene_carries_out_the_actions() -> None:
    with make_scene("grasp", seed=0) as scene:
        before = scene.eef_position()
        assert scene.ground_truth()["states"]["gripper"] == "open"
        assert scene.execute("close")
        assert scene.ground_truth()["states"]["gripper"] == "closed"
        res = scene.execute("stay")
        assert res and res.status == "ok"
        assert np.linalg.norm(scene.eef_position() - before) < 0.01  # held still
        assert scene.execute("open")
        assert scene.ground_truth()["states"]["gripper"] == "open"
        with pytest.raises(A2LValueError, match="unknown action 'grip'"):
            scene.execute("grip")
    with make_scene("virtual", seed=0) as scene, pytest.raises(A2LValueError, match="no gripper"):
        scene.execute("close")
