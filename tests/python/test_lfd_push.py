"""LfD part 2, push: scripted demonstrations -> vector-field dataset -> skill -> closed loop.

The acceptance test of the demonstrated skills: a skill learned from a scripted demonstration
reproduces its effect in the virtual scene, on held-out trial seeds (1000-1019: no
demonstration and no tuning used them). The full Baxter figures are ``a2l experiment
lfd-skills`` (docs/experiments/).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.lfd.dataset import grid_points, skill_discretizer, vector_field_rows
from a2l.lfd.demonstrators import PUSH_DIRECTIONS, PushDemonstrator
from a2l.lfd.library import SKILLS, learn_recipe, make_skill_scene, reset_for_trial
from a2l.lfd.skill import fit_fields
from a2l.rollout.effect_tests import EFFECT_TESTS
from a2l.rollout.run import run_skill
from a2l.skills import load_bundle, load_ds_phases
from a2l.skills.ds_bundle import load_ds_bundle

HELD_OUT = range(1000, 1020)


@pytest.fixture(scope="module")
def bundles(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("lfd")
    return {name: learn_recipe(name, out).bundle for name in SKILLS
            if name.startswith("push_")}


def test_demonstrator_is_seeded_and_goes_around_the_object():
    dem = PushDemonstrator("right")
    a, b, c = dem.path(3), dem.path(3), dem.path(4)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)
    for seed in range(10):
        p = dem.path(seed)
        u = dem.approach
        start = p[0, :2]
        r = float(np.hypot(*start))
        angle = math.degrees(math.acos(np.clip(start @ u / r, -1, 1)))
        assert dem.r_low - 1e-9 <= r <= dem.r_high + 1e-9
        assert angle <= dem.spread_deg + 1e-6
        np.testing.assert_allclose(p[-1, :2], -dem.depth * u, atol=1e-12)
        assert np.all(p[:, 2] == 0.0)
        # before the push (the part on the approach side), the path keeps clear of the box
        # (half-extents 0.035 x 0.0425): the end-effector only meets it from the approach side
        before = p[(p[:, :2] @ u) > dem.pre_push - 1e-9]
        lateral = np.abs(before[:, :2] @ np.array([-u[1], u[0]]))
        along = before[:, :2] @ u
        assert np.all((along > 0.06) | (lateral < 0.02))
    d = dem.demonstrate(0, {"light": "off"})
    assert d.frame == "object" and d.states == {"light": "off"}
    assert np.all(np.diff(d.times) > 0)


def test_demonstrator_rejects_bad_parameters():
    with pytest.raises(ValueError, match="unknown push effect"):
        PushDemonstrator("up")
    with pytest.raises(ValueError, match="approach_shape"):
        PushDemonstrator("far", approach_shape="zigzag")
    with pytest.raises(ValueError, match="n must be >= 1"):
        PushDemonstrator("far").demonstrations(0)


def test_config_validates_and_derives_the_step_cap():
    assert DEFAULT.step_cap == math.ceil(DEFAULT.path_length / DEFAULT.step)
    assert LfDConfig(discretization={"step": 0.02}).step_cap == 50
    with pytest.raises(ValueError, match="resolution"):
        LfDConfig(resolution=0.0)
    with pytest.raises(ValueError, match="LfDConfig has no field 'grid'"):
        DEFAULT.with_(grid=3)
    with pytest.raises(ValueError, match=r"it is discretization.step now"):
        DEFAULT.with_(step=0.03)
    with pytest.raises(ValueError, match=r"^discretization.step: must be a positive length"):
        DEFAULT.with_({"discretization.step": -1.0})
    assert DEFAULT.with_({"discretization.n_orient": 8}).discretization.n_orient == 8


def test_grid_stays_around_the_demonstrations():
    demos = PushDemonstrator("far").demonstrations(3, seed=7)
    pts, nearest = grid_points(demos, 0.01, 0.03)
    assert pts.shape[1] == 3 and len(pts) == len(nearest) > 100
    assert np.all(pts[:, 2] == 0.0)  # planar demonstrations: a planar grid
    allp = np.vstack([d.positions for d in demos])
    dist = np.min(np.linalg.norm(pts[:, None, :] - allp[None, :, :], axis=2), axis=1)
    assert dist.max() <= 0.03 + 0.01  # within the tube (demos sampled every resolution/2)
    assert set(np.unique(nearest)) <= {0, 1, 2}


def test_dataset_goes_through_the_babbling_discretizer():
    from a2l.framework.config import FrameworkConfig

    cfg = DEFAULT
    disc = skill_discretizer(cfg)
    babbling = FrameworkConfig(discretization={
        "n_effects": 4, "planar": True, "step": cfg.step,
        "n_orient": cfg.discretization.n_orient,
        "n_dist": cfg.discretization.n_dist}).discretization.discretizer()
    assert disc is babbling  # the very same object, from the same function
    demos = PushDemonstrator("left").demonstrations(2, seed=1)
    rows = vector_field_rows(fit_fields(demos, cfg.with_(maps=20)), demos, "left", cfg,
                             {"light": "off"})
    assert set(rows["effect"]) == {"left"} and set(rows["light"]) == {"off"}
    steps = np.linalg.norm(rows[["move_dx", "move_dy", "move_dz"]].to_numpy(), axis=1)
    assert np.allclose(steps[steps > 0], cfg.step)
    discrete = disc.discretize(rows.drop(columns="light"))
    assert 0 < len(discrete) <= len(rows)
    # the field carries the end-effector towards the push: from the approach side the most
    # frequent movement is +y (the box should go left)
    near_axis = rows[(rows.eef_y < -0.08) & (rows.eef_x.abs() < 0.02)]
    moves = disc.movements.discretize(near_axis[["move_dx", "move_dy", "move_dz"]].to_numpy())
    assert np.bincount(moves[moves >= 0]).argmax() == disc.movements.labels.index("+y")


def test_bundle_holds_the_table_and_the_ds(bundles):
    path = bundles["push_right"]
    spec = load_bundle(path)
    names = [v.name for v in spec.variables]
    assert names[0] == "effect" and "orientation" in names
    assert spec.step == DEFAULT.step and spec.step_cap == DEFAULT.step_cap
    assert spec.extra["lfd"]["behaviours"][0]["effect"] == "right"
    assert spec.extra["lfd"]["behaviours"][0]["n_demonstrations"] == DEFAULT.n_demos
    phases = load_ds_phases(path)
    assert [p.name for p in phases] == ["push_right"] and phases[0].when == {}
    assert phases[0].end_action is None
    ds, meta = load_ds_bundle(path)
    assert ds.dim == 3 and meta["lfd"]["rows"] > 100
    # the target sits beyond the object along the push (-y for right)
    assert np.asarray(ds.target)[1] < -0.05
    # other effects were never demonstrated: their rows are uniform (unknown context)
    e = [v.values for v in spec.variables if v.name == "effect"][0]
    assert np.all(spec.argmax[list(e).index("left")] == -1)
    assert np.any(spec.argmax[list(e).index("right")] >= 0)


@pytest.mark.parametrize("name", ["push_right", "push_left", "push_close", "push_far"])
def test_acceptance_skill_from_demonstrations_reproduces_its_effect_in_virtual_scene(
        bundles, name):
    """Acceptance: held-out trials in the virtual scene, through the C++ step."""
    recipe = SKILLS[name]
    with make_skill_scene(name, 0, scene="virtual") as scene:
        runs = []
        for seed in HELD_OUT:
            reset_for_trial(scene, name, seed)
            runs.append(run_skill(scene, bundles[name], recipe.effect))
    wins = sum(r.success for r in runs)
    assert wins >= 18, f"{name}: {wins}/20 ({[r.stop for r in runs]})"
    d = np.asarray(PUSH_DIRECTIONS[recipe.effect])
    for r in runs:
        if r.success:
            assert r.stop == "effect_produced"
            assert r.produced[:2] @ d >= 0.05
        assert r.eef.shape == r.obj.shape == (len(r.steps), 3)


def test_run_skill_reports_each_step_and_excludes_perturbations(bundles):
    seen = []
    with make_skill_scene("push_far", 0, scene="virtual") as scene:
        reset_for_trial(scene, "push_far", 1000)

        def on_step(k, step):
            seen.append((k, step.status, step.label))
            if k == 0:  # the box is moved by hand: not the robot's doing
                scene.perturb("move_object", delta=(0.03, 0.0))

        run = run_skill(scene, bundles["push_far"], "far", on_step=on_step)
    assert seen and seen[0][0] == 0 and all(s == "ok" for _, s, _ in seen)
    assert run.statuses[:-1] == ["ok"] * (len(run.steps) - 1)
    assert run.success and run.stop == "effect_produced"
    # the 3 cm teleport is not in the produced displacement; the run still pushed 5 cm
    total = run.obj[-1] - run.obj[0]
    assert total[0] - run.produced[0] == pytest.approx(0.03, abs=1e-9)


def test_run_skill_stops_on_the_cpp_status_and_checks_its_inputs(bundles, tmp_path):
    with make_skill_scene("push_right", 0, scene="virtual") as scene:
        reset_for_trial(scene, "push_right", 1000)
        # wanted effect never demonstrated by this skill: the C++ step finds a uniform row
        run = run_skill(scene, bundles["push_right"], "far")
        assert not run.success and run.stop == "unknown_context" and len(run.steps) == 1
        reset_for_trial(scene, "push_right", 1000)
        run = run_skill(scene, bundles["push_right"], "right", max_steps=1)
        assert run.stop == "max_steps" and run.movements == 1
        with pytest.raises(ValueError, match="mode"):
            run_skill(scene, bundles["push_right"], "right", mode="dmp")
        with pytest.raises(ValueError, match="no effect test"):
            run_skill(scene, bundles["push_right"], "spun")
    with make_skill_scene("push_right", 0, scene="virtual", step=0.03) as scene:
        with pytest.raises(ValueError, match="moves by 0.03 m"):
            run_skill(scene, bundles["push_right"], "right")
    assert set(EFFECT_TESTS) >= set(PUSH_DIRECTIONS)


def test_ds_mode_runs_the_bundle_ds_phase_through_the_cpp_step(bundles):
    with make_skill_scene("push_far", 0, scene="virtual") as scene:
        reset_for_trial(scene, "push_far", 1001)
        run = run_skill(scene, bundles["push_far"], "far", mode="ds")
    assert run.mode == "ds" and run.movements >= 1
    assert all(s.label == "ds:push_far" for s in run.steps if s.status == "ok")
    steps = np.linalg.norm(np.diff(run.eef, axis=0), axis=1)
    assert np.all(steps <= DEFAULT.step + 1e-9)


def test_push_on_baxter(bundles):
    """One held-out push on Baxter in PyBullet, the context read from the camera by default
    (the figures: a2l experiment lfd-skills)."""
    with make_skill_scene("push_far", 0) as scene:
        assert scene.config.context_source == "perceived"
        reset_for_trial(scene, "push_far", 1000)
        run = run_skill(scene, bundles["push_far"], "far")
    assert run.success, run.statuses
    assert run.produced[0] >= 0.05


def test_parametrization_selects_by_success_then_movements_then_table():
    import pandas as pd

    from a2l.experiments.parametrization import select_default

    base = {"resolution": 0.01, "step": 0.05, "n_orient": 16, "n_dist": 3, "smoothing": False}
    cells = pd.DataFrame([
        {**base, "success_rate": 0.9, "movements_per_action": 3.0},
        {**base, "n_orient": 8, "success_rate": 0.9, "movements_per_action": 3.0},
        {**base, "step": 0.02, "success_rate": 0.9, "movements_per_action": 7.0},
        {**base, "n_dist": 5, "success_rate": 0.8, "movements_per_action": 2.0},
    ])
    chosen = select_default(cells)
    assert chosen["n_orient"] == 8 and chosen["step"] == 0.05  # tie on success: smaller table
    assert chosen["success_rate"] == 0.9


def test_parametrization_runs_cells_and_writes_its_report(tmp_path):
    """A 2-cell study in the virtual scene, through the worker task (1 process)."""
    import json
    import shlex

    from a2l.experiments.parametrization import run_parametrization

    m = run_parametrization(tmp_path / "p", ["push_far"],
                            {"resolution": (0.02,), "step": (0.05,), "n_orient": (8, 16),
                             "n_dist": (3,), "smoothing": (False,)},
                            trials=3, scene="virtual", quiet=True)
    assert m["cells"] == 2 and m["selected"]["n_orient"] in (8, 16)
    saved = json.loads((tmp_path / "p" / "metrics.json").read_text())
    assert saved["selected"] == m["selected"]
    report = (tmp_path / "p" / "report.md").read_text()
    assert report.count("| push_far |") == 2
    assert (tmp_path / "p" / "parametrization.png").stat().st_size > 1000
    # config.json's command runs the same study: its parse gives the same grid and skills
    from a2l.cli import parse
    from a2l.cli.lfd import grid_of

    config = json.loads((tmp_path / "p" / "config.json").read_text())
    path, ns, _ = parse(shlex.split(config["command"])[1:])
    assert path == ("experiment", "parametrization") and ns.skills == "push_far"
    assert {k: list(v) for k, v in grid_of(ns).items()} == config["grid"] == {
        "resolution": [0.02], "step": [0.05], "n_orient": [8, 16], "n_dist": [3],
        "smoothing": [False]}


def test_lfd_skills_reads_the_camera_by_default_and_names_its_source(tmp_path):
    """The experiment's default context is the camera: the command line, the function and
    the scenes; a ground-truth run says so in its report (virtual scene: 2 trials)."""
    import inspect
    import json

    from a2l.cli import parse
    from a2l.experiments.lfd_skills import evaluate, run_lfd_skills

    _, ns, _ = parse(["experiment", "lfd-skills", "--out", str(tmp_path / "x")])
    assert ns.context_source == "perceived"
    for fn in (run_lfd_skills, evaluate):
        assert inspect.signature(fn).parameters["context_source"].default == "perceived"
    m = run_lfd_skills(tmp_path / "gt", ["push_far"], trials=2, scene="virtual", quiet=True,
                       context_source="ground_truth")
    assert m["context_source"] == "ground_truth"
    assert "context: ground truth" in (tmp_path / "gt" / "report.md").read_text()
    config = json.loads((tmp_path / "gt" / "config.json").read_text())
    assert config["context_source"] == "ground_truth"
    assert "--context_source ground_truth" in config["command"]


def test_a_worker_with_another_package_refuses_to_run():
    from a2l.experiments.lfd_skills import LfdTrial, trial_task

    with pytest.raises(RuntimeError, match="imported a2l from"):
        trial_task(LfdTrial("push_far", "x", 0, "virtual", "table", DEFAULT,
                            package="/elsewhere/a2l"))


@pytest.mark.parametrize("argv, message", [
    (["lfd-skills", "--trials", "0"], "--trials: must be >= 1"),
    (["lfd-skills", "--skills", "nope"], "unknown skill(s) ['nope']"),
    (["lfd-skills", "--seed", "-1"], "--seed: must be >= 0"),
    (["parametrization", "--seed", "-3"], "--seed: must be >= 0"),
    (["parametrization", "--workers", "0"], "--workers: must be >= 1"),
    (["parametrization", "--steps", "0.02,x"], "--steps: expected comma-separated numbers"),
    (["parametrization", "--smoothing", "maybe"], "--smoothing: expected on and/or off"),
])
def test_experiment_commands_name_a_bad_option(tmp_path, capsys, argv, message):
    from a2l.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["experiment", *argv, "--out", str(tmp_path / "run")])
    assert exc.value.code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "run").exists()
