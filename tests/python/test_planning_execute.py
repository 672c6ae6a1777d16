"""Closed-loop task execution on Baxter in PyBullet: plan, run the learned skills through
the C++ step, perceive, replan when the world disagrees."""

from __future__ import annotations

from pathlib import Path

import pytest

from a2l.lfd.library import learn_recipe, make_skill_scene
from a2l.planning import TableRegions, grasp_skill, gripper_skill, press_skills
from a2l.planning.execute import execute_task, perceive_state


@pytest.fixture(scope="module")
def world(tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("skills")
    grasp = learn_recipe("grasp", out).bundle
    press = learn_recipe("press", out).bundle
    skills = [grasp_skill(), *press_skills("light", ("on", "off"), learned_under={}),
              gripper_skill("open")]
    bundles = {"grasp": grasp, "press-light-on": press, "press-light-off": press}
    scene = make_skill_scene("grasp", 0, scene="task", states={"light": "on"})
    yield scene, skills, bundles
    scene.close()


GOAL = "(and (light-off) (holding block))"


def _start(scene) -> None:
    scene.reset()
    assert scene.ground_truth()["states"]["light"] == "on"


def test_perceived_state_names_regions_light_and_gripper(world) -> None:
    scene, _skills, _bundles = world
    _start(scene)
    regions = TableRegions(scene.config.table_center, scene.config.table_size)
    state = perceive_state(scene, regions)
    assert state.states == {"light": "on", "gripper": "open"}
    assert state.holding is None and state.buttons == ("button",)
    assert state.movables["block"] == regions.region_of(scene.config.block_position)
    assert "(hand-empty)" in state.facts()


def test_press_then_grasp_reaches_the_goal(world, tmp_path: Path) -> None:
    scene, skills, bundles = world
    _start(scene)
    res = execute_task(scene, skills, bundles, GOAL, tmp_path)
    assert res.success, res.report()
    assert [s.step.name for s in res.steps] == ["press-light-off", "grasp"]
    assert res.replans == 0 and all(s.as_expected for s in res.steps)
    assert scene.ground_truth()["states"]["light"] == "off"
    assert (tmp_path / "plan0-plan-pyperplan.txt").exists()


def test_light_switched_back_on_behind_the_robot_is_replanned(world, tmp_path: Path) -> None:
    scene, skills, bundles = world
    _start(scene)

    def fault(k: int, step, scn) -> None:
        if k == 0:  # right after the press, someone switches the light back on
            assert step.name == "press-light-off"
            scn.perturb("toggle", state="light")

    res = execute_task(scene, skills, bundles, GOAL, tmp_path, after_step=fault)
    assert res.success, res.report()
    assert res.replans >= 1
    assert not res.steps[0].as_expected
    assert "(light-on)" in res.steps[0].perceived
    names = [s.step.name for s in res.steps]
    assert names.count("press-light-off") == 2 and names[-1] == "grasp"


def test_impossible_goal_ends_in_a_clear_failure_report(world, tmp_path: Path) -> None:
    scene, skills, bundles = world
    _start(scene)
    res = execute_task(scene, skills, bundles, "(and (light-off) (at block far-left))",
                       tmp_path)
    assert not res.success
    assert res.unmet == ["(light-off)", "(at block far-left)"]
    assert res.last_skill is None and res.replans == 0
    assert "unsolvable" in res.message
    assert "(at block far-left)" in res.report()


def test_a_world_that_keeps_undoing_the_press_ends_in_a_failure_report(world,
                                                                       tmp_path: Path) -> None:
    scene, skills, bundles = world
    _start(scene)

    def undo(_k: int, step, scn) -> None:
        if step.name == "press-light-off":
            scn.perturb("toggle", state="light")

    res = execute_task(scene, skills, bundles, GOAL, tmp_path, max_replans=1, after_step=undo)
    assert not res.success
    assert res.unmet == ["(light-off)", "(holding block)"]
    assert res.last_skill == "(press-light-off button)" and res.replans == 1
    assert [s.stop for s in res.steps] == ["effect_produced"] * 2
    assert "gave up" in res.message and "(light-off)" in res.report()
