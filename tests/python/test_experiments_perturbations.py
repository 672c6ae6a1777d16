"""``a2l experiment perturbations``: each perturbation really happens, metrics schema,
1 vs 2 workers identical, bad arguments named."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from a2l.experiments.perturbations import (
    CONDITIONS,
    DEFAULT_SEED,
    HOLD_RANGE,
    MOVE_RANGE,
    PerturbationTrial,
    draw_perturbation,
    run_perturbations,
    trial_task,
)
from a2l.lfd.config import DEFAULT
from a2l.lfd.library import learn_recipe

SKILL = "push_right"
SEEDS = (DEFAULT_SEED,)


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> str:
    return str(learn_recipe(SKILL, tmp_path_factory.mktemp("skills")).bundle)


@pytest.fixture(scope="module")
def runs(bundle: str, tmp_path_factory: pytest.TempPathFactory) -> dict[int, Path]:
    """The experiment on one skill and two seeds, with one and with two workers."""
    out = {}
    for workers in (1, 2):
        d = tmp_path_factory.mktemp(f"w{workers}")
        run_perturbations(d, [SKILL], trials=len(SEEDS), seed=SEEDS[0], workers=workers,
                          bundles={SKILL: bundle}, quiet=True, plots=workers == 1)
        out[workers] = d
    return out


def test_draws_are_mid_action_in_range_and_seeded() -> None:
    for seed in range(200):
        for movements in (2, 3, 7, 20):
            m = draw_perturbation("move_object", seed, movements, 0.2)
            assert 1 <= m.after <= movements - 1
            assert math.ceil(movements / 3) <= m.after <= max(math.ceil(movements / 3),
                                                              math.floor(2 * movements / 3))
            assert MOVE_RANGE[0] <= m.distance <= MOVE_RANGE[1]
            h = draw_perturbation("hold", seed, movements, 0.2)
            assert HOLD_RANGE[0] - 1e-9 <= h.hold_s <= HOLD_RANGE[1] + 1e-9
            assert h.hold_s == pytest.approx(0.2 * h.hold_steps)
    assert draw_perturbation("hold", 7, 9, 0.2) == draw_perturbation("hold", 7, 9, 0.2)
    assert draw_perturbation("move_object", 1, 1, 0.2).after == 0  # no middle to a 1-step run
    angles = {round(draw_perturbation("move_object", s, 6, 0.2).angle, 3) for s in range(50)}
    assert len(angles) == 50 and max(angles) - min(angles) > 5  # all around the circle


def test_each_perturbation_happens(bundle: str) -> None:
    rows = trial_task(PerturbationTrial(SKILL, bundle, "table", SEEDS[0], "press", CONDITIONS,
                                        DEFAULT))
    by = {r["condition"]: r for r in rows}
    assert list(by) == list(CONDITIONS)
    assert not by["none"]["applied"]
    base = by["none"]["eef"]
    for cond in CONDITIONS[1:]:
        r = by[cond]
        assert r["applied"], cond
        # mid-action, and the run is the unperturbed one up to the instant
        assert 1 <= r["after"] < by["none"]["movements"]
        assert r["prefix_identical"]
        assert np.allclose(r["eef"][: r["after"] + 1], base[: r["after"] + 1], atol=1e-6)
    # the object really moved by 3-5 cm (ground truth right before and after)
    assert MOVE_RANGE[0] - 1e-3 <= by["move_object"]["displacement_m"] <= MOVE_RANGE[1] + 1e-3
    # the arm stayed still for every held movement: 1-2 s, within 2 mm
    h = by["hold"]
    assert h["hold_s"] == pytest.approx(h["hold_planned_s"]) and h["held_observed"] >= 1
    assert HOLD_RANGE[0] - 1e-9 <= h["hold_s"] <= HOLD_RANGE[1] + 1e-9
    assert h["hold_drift_m"] < 0.002
    held = h["eef"][h["after"]: h["after"] + h["held_observed"] + 1]
    assert np.max(np.linalg.norm(held - held[0], axis=1)) < 0.002
    assert h["movements"] > by["none"]["movements"]  # the held commands are steps too
    # the light flipped; the push does not depend on it: the very same run
    t = by["toggle_light"]
    assert (t["light_before"], t["light_after"]) == ("off", "on")
    assert t["same_as_none"] and np.allclose(t["eef"], base, atol=1e-6)


@pytest.mark.slow
def test_metrics_schema_and_report(runs: dict[int, Path]) -> None:
    m = json.loads((runs[1] / "metrics.json").read_text())
    assert m["context_source"] == "perceived"  # the camera, by default
    assert m["trial_seeds"] == [SEEDS[0], SEEDS[-1]]
    assert m["demonstration_seeds"] == [0, 2 * DEFAULT.n_demos - 1]
    assert set(m["skills"]) == {SKILL}
    for cond in CONDITIONS:
        e = m["skills"][SKILL][cond]
        for key in ("context", "ds"):
            assert 0.0 <= e[key] <= 1.0
            assert e["successes"][key] == round(e[key] * len(SEEDS))
        assert e["mean_steps"] >= 1 and e["trials"] == len(SEEDS)
        assert 0.0 <= e["fisher_p"] <= 1.0 and isinstance(e["differ"], bool)
        if cond != "none":
            assert e["applied"] == {"context": len(SEEDS), "ds": len(SEEDS)}
    assert m["skills"][SKILL]["toggle_light"]["light_flipped"] == 2 * len(SEEDS)
    lo, hi = m["skills"][SKILL]["move_object"]["displacement_m"]
    assert MOVE_RANGE[0] - 1e-3 <= lo <= hi <= MOVE_RANGE[1] + 1e-3
    trials = pd.read_csv(runs[1] / "trials.csv")
    assert len(trials) == len(CONDITIONS) * 2 * len(SEEDS)
    report = (runs[1] / "report.md").read_text()
    assert "| push_right | toggle_light |" in report and f"{SEEDS[0]}-{SEEDS[-1]}" in report
    assert "Context: camera (perceived)." in report
    config = json.loads((runs[1] / "config.json").read_text())
    assert config["context_source"] == "perceived"
    assert "--context_source perceived" in config["command"]
    for cond in CONDITIONS:
        assert (runs[1] / "plots" / f"{SKILL}_{cond}.png").stat().st_size > 1000
    with np.load(runs[1] / "trajectories.npz") as z:
        assert z[f"{SKILL}/hold/table/{SEEDS[0]}/eef"].shape[1] == 3


@pytest.mark.slow
def test_one_and_two_workers_give_identical_results(runs: dict[int, Path]) -> None:
    one, two = (json.loads((runs[w] / "metrics.json").read_text()) for w in (1, 2))
    for cond, e in one["skills"][SKILL].items():
        f = two["skills"][SKILL][cond]
        for key in ("context", "ds", "mean_steps", "mean_steps_ds", "successes", "stops",
                    "failed_seeds", "applied", "fisher_p"):
            assert e[key] == f[key], (cond, key)
    # every column, positions included, and the trajectories are bitwise equal: a rollout does
    # not depend on which trials its worker ran before (test_sim_exact_start.py)
    a, b = (pd.read_csv(runs[w] / "trials.csv") for w in (1, 2))
    assert a.equals(b)
    with np.load(runs[1] / "trajectories.npz") as za, np.load(runs[2] / "trajectories.npz") as zb:
        assert sorted(za.files) == sorted(zb.files)
        assert all(np.array_equal(za[k], zb[k], equal_nan=True) for k in za.files)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"skills": ["push_sideways"]}, "--skills: unknown skill"),
    ({"conditions": ["earthquake"]}, "--conditions: unknown condition"),
    ({"trials": 0}, "--trials: must be >= 1"),
    ({"workers": 0}, "--workers: must be >= 1"),
    ({"seed": 3}, "--seed: trial seeds 3.. overlap the demonstration seeds "
                  f"0..{2 * DEFAULT.n_demos - 1}"),
])
def test_bad_arguments_are_named(tmp_path: Path, kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        run_perturbations(tmp_path / "run", **{"skills": [SKILL], **kwargs}, quiet=True)
    assert not (tmp_path / "run").exists()  # nothing written


def test_cli_names_the_bad_argument(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    from a2l.cli import main

    (tmp_path / "file").write_text("")
    for argv, expect in (
        (["--trials", "0"], "argument --trials: must be >= 1"),
        (["--skills", "push_sideways"], "argument --skills: unknown skill(s) ['push_sideways']"),
        (["--out", str(tmp_path / "file")], "argument --out: "),
    ):
        args = ["experiment", "perturbations", "--out", str(tmp_path / "r"), *argv]
        with pytest.raises(SystemExit) as exc:
            main(args)
        assert exc.value.code == 2
        assert expect in capsys.readouterr().err


def test_light_dependent_skill_is_judged_by_the_new_light_state(tmp_path: Path) -> None:
    from a2l.experiments.perturbation_trials import light_effects, skill_scene
    from a2l.experiments.perturbations import skill_cfg
    from a2l.lfd.library import SKILLS

    cfg = skill_cfg("grasp_light")
    recipe = SKILLS["grasp_light"]
    assert light_effects(recipe, cfg) == {"off": "grasped", "on": "away"}
    assert light_effects(SKILLS["grasp"], skill_cfg("grasp")) is None
    assert skill_scene(SKILLS["grasp"]) == "grasp_light"  # a lamp to switch
    assert skill_scene(SKILLS[SKILL]) == "press"
    bundle = learn_recipe("grasp_light", tmp_path, cfg).bundle
    rows = trial_task(PerturbationTrial("grasp_light", str(bundle), "table", SEEDS[0],
                                        "grasp_light", ("none", "toggle_light"), cfg))
    none, toggled = rows
    assert none["light_dependent"] and toggled["applied"]
    start = toggled["light_before"]
    assert toggled["light_after"] == {"off": "on", "on": "off"}[start]
    assert none["expected_effect"] == {"off": "grasped", "on": "away"}[start]
    assert toggled["expected_effect"] == {"off": "away", "on": "grasped"}[start]
    assert not toggled["same_as_none"]  # the behaviour switched
