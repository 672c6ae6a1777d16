"""The demonstrated skills on another robot than Baxter: learned for the Panda (the bundles
record it), tried in its scenes from held-out trial seeds by ``a2l experiment lfd-skills
--robot panda``; a Baxter scene refuses them; the refusals of a robot that cannot."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from a2l.errors import A2LValueError, ConfigError
from a2l.experiments.lfd_skills import resolve_scene, run_lfd_skills
from a2l.lfd.library import learn_recipe, make_skill_scene, reset_for_trial
from a2l.robot import robot_entry, urdf_sha256
from a2l.rollout.run import run_skill

SKILLS = ("push_far", "grasp", "press")


@pytest.fixture(scope="module")
def panda_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    """The experiment on the Panda: a push, the grasp and the press, 2 held-out trials
    each, the context from the simulator (the camera loses the block under the Panda's
    hand: docs/lfd.md)."""
    out = tmp_path_factory.mktemp("lfd-panda") / "run"
    metrics = run_lfd_skills(out, list(SKILLS), trials=2, robot="panda", quiet=True,
                             context_source="ground_truth")
    return out, metrics


def test_the_skills_learned_for_the_panda_succeed_on_it(
        panda_run: tuple[Path, dict[str, Any]]) -> None:
    out, metrics = panda_run
    assert metrics["scene"] == "bullet" and metrics["robot"] == "panda"
    for name in SKILLS:
        s = metrics["skills"][name]
        assert (s["successes"], s["trials"]) == (2, 2), (name, s)
    config = json.loads((out / "config.json").read_text())
    assert config["robot"] == "panda" and "--robot panda" in config["command"]
    assert "(bullet, robot panda, table" in (out / "report.md").read_text()


def test_a_bundle_records_its_robot_and_another_robots_scene_refuses_it(
        panda_run: tuple[Path, dict[str, Any]]) -> None:
    from a2l.skills import load_bundle

    bundle = panda_run[0] / "skills" / "push_far.a2lb"
    panda = robot_entry("panda")
    assert load_bundle(bundle).robot == {
        "name": "panda", "urdf_sha256": urdf_sha256(panda.urdf),
        "base_link": "panda_link0", "tip_link": "panda_hand_tcp"}
    with make_skill_scene("push_far", 0) as scene:  # Baxter's
        reset_for_trial(scene, "push_far", 1000)
        with pytest.raises(A2LValueError, match="learned for robot 'panda'.* not for 'baxter'"):
            run_skill(scene, bundle, "far")


def test_a_robot_that_cannot_is_refused_by_name(tmp_path: Path) -> None:
    with pytest.raises(A2LValueError, match="skill 'grasp' closes the gripper, and robot "
                       "'ur5' has none"):
        learn_recipe("grasp", tmp_path, robot="ur5")
    assert not list(tmp_path.iterdir())  # refused before learning anything
    with pytest.raises(A2LValueError, match="unknown robot 'kuka'"):
        learn_recipe("push_far", tmp_path, robot="kuka")
    with pytest.raises(A2LValueError, match="the virtual scene has no robot"):
        make_skill_scene("push_far", scene="virtual", robot="panda")
    with pytest.raises(ConfigError, match="skill 'grasp_light' closes the gripper"):
        run_lfd_skills(tmp_path / "r", ["push_far", "grasp_light"], robot="ur5", quiet=True)
    assert resolve_scene(None, "baxter") == "bullet" and resolve_scene(None, "ur5") == "bullet"
    assert resolve_scene("baxter", "baxter") == "bullet"  # the earlier name of Baxter's
    for scene, robot, message in (("baxter", "panda", "scene 'baxter' is Baxter's"),
                                  ("virtual", "panda", "the virtual scene has no robot"),
                                  (None, "kuka", "unknown robot 'kuka'")):
        with pytest.raises(ConfigError, match=message):
            resolve_scene(scene, robot)


def test_the_virtual_scene_learns_for_no_robot(tmp_path: Path) -> None:
    """A run in the virtual scene learns bundles for no robot (as before robots were data),
    which any arm's scene takes."""
    from a2l.skills import load_bundle

    metrics = run_lfd_skills(tmp_path / "v", ["push_far"], trials=1, scene="virtual",
                             quiet=True)
    assert metrics["robot"] is None
    assert load_bundle(tmp_path / "v" / "skills" / "push_far.a2lb").robot is None
    assert np.isfinite(metrics["skills"]["push_far"]["mean_movements"])


def test_a_start_out_of_a_small_arms_reach_is_a_failed_trial(tmp_path: Path) -> None:
    """The SO-101's scene is scaled by about a half, the demonstrations' starts are not: a
    grasp trial's start above the block is out of its reach, a failure (not a crash) that
    the report explains."""
    from a2l.experiments.lfd_skills import LfdTrial, scale_note, trial_task
    from a2l.lfd.manipulation_skills import CONFIG

    row = trial_task(LfdTrial("grasp", str(tmp_path / "unused.a2lb"), 1000, "bullet",
                              "table", CONFIG, robot="so101"))
    assert (row["success"], row["stop"], row["movements"]) == (False, "start_unreachable", 0)
    assert "Robot so101's scene is scaled by 0.52" in scale_note("bullet", "so101")[0]
    assert scale_note("bullet", "panda") == [] == scale_note("bullet", "baxter")


def test_perturbations_and_parametrization_run_on_the_panda(tmp_path: Path) -> None:
    """``perturbations --robot panda``: the skill learned for the Panda (its bundle says so),
    tried in the Panda's scene with the object moved mid-action; ``parametrization --robot
    panda``: a one-cell study learns and tries it there."""
    from a2l.experiments.parametrization import run_parametrization
    from a2l.experiments.perturbations import DEFAULT_SEED, run_perturbations
    from a2l.skills import load_bundle

    m = run_perturbations(tmp_path / "pert", ["push_far"], trials=1, seed=DEFAULT_SEED,
                          conditions=["none", "move_object"], quiet=True, plots=False,
                          context_source="ground_truth", robot="panda")
    assert m["robot"] == "panda"
    assert load_bundle(m["learning"]["push_far"]["bundle"]).robot["name"] == "panda"
    config = json.loads((tmp_path / "pert" / "config.json").read_text())
    assert "--robot panda" in config["command"]
    rows = m["skills"]["push_far"]
    assert rows, m["skills"]
    # the trials ran in the Panda's scene: the object starts where the trial's reset puts it
    trials = np.load(tmp_path / "pert" / "trajectories.npz")
    obj = trials[f"push_far/none/table/{DEFAULT_SEED}/obj"]
    with make_skill_scene("push_far", scene=m["scenes"]["push_far"], robot="panda") as scene:
        home = reset_for_trial(scene, "push_far", DEFAULT_SEED)["object"]
    np.testing.assert_allclose(obj[0][:2], home[:2], atol=0.005)

    p = run_parametrization(tmp_path / "param", ["push_far"],
                            {"resolution": (0.02,), "step": (0.05,), "n_orient": (16,),
                             "n_dist": (3,), "smoothing": (False,)},
                            trials=2, quiet=True, robot="panda")
    assert p["scene"] == "bullet" and p["robot"] == "panda" and p["cells"] == 1
    assert "--robot panda" in json.loads((tmp_path / "param" / "config.json").read_text())[
        "command"]
    with pytest.raises(ConfigError, match="scene 'baxter' is Baxter's"):
        run_parametrization(tmp_path / "bad", ["push_far"], scene="baxter", robot="panda",
                            quiet=True)
