"""The manipulation skills through the LfD pipeline (grasp, press, grasp_light): phases and
their rows, then skills learned from scripted demonstrations and run in closed loop through
the C++ step on Baxter from held-out trial seeds (no demonstration used them)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from a2l.lfd.library import SKILLS, learn_recipe, make_skill_scene, reset_for_trial, skill_config
from a2l.lfd.manipulation import GRASP_POINT, demonstrate
from a2l.lfd.manipulation_skills import (
    CONFIG,
    N_INCLINATION,
    manipulation_discretizer,
    phase_rows,
    skill_phases,
)
from a2l.lfd.skill import fit_fields
from a2l.rollout.effect_tests import RETREAT, light_test
from a2l.rollout.run import run_skill

HELD_OUT = range(1000, 1004)


@pytest.fixture(scope="module")
def bundles(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("manip")
    return {name: learn_recipe(name, out).bundle for name in ("grasp", "press", "grasp_light")}


def test_phases_follow_the_segments_states() -> None:
    phases = skill_phases("grasp_light", demonstrate("grasp_light", 4, seed=0))
    by_name = {p.name: p for p in phases}
    assert set(by_name) == {"reach", "lift", "retreat"}
    assert by_name["reach"].when == {"light": "off", "gripper": "open"}
    assert by_name["reach"].end_action == "close" and by_name["lift"].end_action is None
    assert by_name["retreat"].when == {"light": "on"}
    assert by_name["retreat"].end_action == "stay"
    assert np.allclose(by_name["reach"].target, GRASP_POINT)
    assert np.linalg.norm(by_name["retreat"].target - RETREAT) < 0.01
    (press,) = skill_phases("press", demonstrate("press", 2, seed=0))
    assert press.name == "press" and press.when == {} and press.end_action is None
    assert skill_config("grasp") is CONFIG and SKILLS["grasp"].effect == "grasped"


def test_reach_rows_close_at_the_grasp_point_and_cover_every_bin_near_the_block() -> None:
    (reach, _lift) = sorted(skill_phases("grasp", demonstrate("grasp", 4, seed=0)),
                            key=lambda p: p.name != "reach")
    rows = phase_rows(reach, fit_fields(reach.segments, CONFIG), "grasped", CONFIG)
    eef = rows[["eef_x", "eef_y", "eef_z"]].to_numpy()
    close = rows["action"] == "close"
    assert close.any() and (rows["gripper"] == "open").all()
    assert np.all(np.linalg.norm(eef[close] - GRASP_POINT, axis=1) <= 0.015 + 1e-9)
    assert np.all(np.linalg.norm(eef[~close] - GRASP_POINT, axis=1) > 0.015 - 1e-9)
    # moves of one step along the DS; straight down above the grasp point
    moves = rows[["move_dx", "move_dy", "move_dz"]].to_numpy()[~close]
    assert np.allclose(np.linalg.norm(moves, axis=1), CONFIG.step)
    above = np.linalg.norm(eef[~close] - (GRASP_POINT + [0, 0, 0.05]), axis=1) < 0.004
    assert above.any() and np.all(moves[above][:, 2] < -0.8 * CONFIG.step)
    # every orientation x inclination section of the first distance bin has rows
    disc = manipulation_discretizer("grasp", CONFIG)
    bins = disc.context_bins(eef, np.zeros_like(eef))
    first = bins["distance"] == 0
    seen = set(zip(bins["orientation"][first], bins["inclination"][first], strict=True))
    assert len(seen) == CONFIG.discretization.n_orient * N_INCLINATION


@pytest.mark.parametrize("name", [pytest.param("grasp", marks=pytest.mark.slow), "press"])
def test_learned_skill_reproduces_its_effect_on_held_out_seeds(name: str, bundles) -> None:
    recipe = SKILLS[name]
    with make_skill_scene(name, 0) as scene:
        for seed in HELD_OUT:
            reset_for_trial(scene, name, seed)
            run = run_skill(scene, bundles[name], recipe.effect,
                            object_name=recipe.object_name)
            assert run.success, (name, seed, run.stop, [s.label for s in run.steps])
            if name == "grasp":
                labels = [s.label for s in run.steps]
                # approach, close once, then lift: up moves only after the close
                k = labels.index("close")
                assert labels.count("close") == 1 and labels[k + 1:-1]
                assert all("+z" in lab for lab in labels[k + 1:-1])


def test_the_light_decides_what_the_grasp_does_even_mid_action(bundles) -> None:
    name = "grasp_light"
    by_light = SKILLS[name].extra["effect_by_light"]
    assert by_light == {"off": "grasped", "on": "away"}
    with make_skill_scene(name, 0) as scene:
        # the light switched on after 3 movements of a grasp: the skill turns to the
        # retreat, waits there, and the block is not taken
        for seed in HELD_OUT[:2]:
            reset_for_trial(scene, name, seed)
            if scene.ground_truth()["states"]["light"] == "on":
                scene.perturb("toggle", state="light")
                scene.start_episode()

            def switch(k: int, _step: object) -> None:
                if k == 2:
                    scene.perturb("toggle", state="light")

            run = run_skill(scene, bundles[name], "grasped", on_step=switch,
                            object_name="block", effect_test=light_test(by_light))
            assert run.success, (seed, run.stop, [s.label for s in run.steps])
            assert run.steps[0].states["light"] == "off"
            assert run.steps[-1].states["light"] == "on"
            assert "close" not in [s.label for s in run.steps]
            block = np.asarray(scene.ground_truth()["objects"]["block"])
            assert np.linalg.norm(scene.eef_position() - block - RETREAT) <= 0.04
            # then it waits: once at the retreat pose the table says stay, and stays
            more = run_skill(scene, bundles[name], "grasped", max_steps=5,
                             effect_test=lambda _pr: (False, False), object_name="block")
            labels = [s.label for s in more.steps[:5]]
            assert "stay" in labels, labels
            first = labels.index("stay")
            assert first <= 2 and set(labels[first:]) == {"stay"}, labels
            assert np.allclose(more.eef[first], more.eef[-1], atol=0.002)
        # the light off all along: a grasp
        reset_for_trial(scene, name, HELD_OUT[2])
        if scene.ground_truth()["states"]["light"] == "on":
            scene.perturb("toggle", state="light")
            scene.start_episode()
        run = run_skill(scene, bundles[name], "grasped", object_name="block")
        assert run.success and "close" in [s.label for s in run.steps]
        assert scene.observe_effect(since="episode", source="ground_truth") == "grasped"


@pytest.mark.parametrize("name", ["grasp", "grasp_light"])
def test_ds_phases_grasp_and_turn_away_without_the_table(name: str, bundles) -> None:
    """The DS phases alone (no table) grasp, and turn away when the light says so. Read
    from the ground truth: with the camera, the DS alone misses grasp seed 1001
    (workspace_limit after 14 reach steps), a known gap of the DS baseline with the camera
    (the table succeeds there, test_learned_skill_reproduces_its_effect_on_held_out_seeds)."""
    recipe = SKILLS[name]
    by_light = recipe.extra.get("effect_by_light")
    with make_skill_scene(name, 0, context_source="ground_truth") as scene:
        for seed in HELD_OUT[:2]:
            reset_for_trial(scene, name, seed)
            light = scene.ground_truth()["states"].get("light", "off")
            run = run_skill(scene, bundles[name], recipe.effect, mode="ds",
                            object_name=recipe.object_name,
                            effect_test=light_test(by_light) if by_light else None)
            assert run.success, (name, seed, light, run.stop, [s.label for s in run.steps])
            labels = [s.label for s in run.steps if s.label]
            phases = {lab.split(":")[1] for lab in labels if lab.startswith("ds:")}
            if light == "off":
                assert labels.count("close") == 1 and phases == {"reach", "lift"}
            else:
                assert "close" not in labels and phases == {"retreat"}
