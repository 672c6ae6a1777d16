"""``a2l experiment tasks`` on a short configuration: one seed per task, with and without its
fault."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

import a2l.planning.execute
from a2l.cli import main
from a2l.experiments.task_trials import fault_hook
from a2l.experiments.tasks import TASKS, TaskTrial, run_tasks, trial_task
from a2l.experiments.tasks_report import summarise
from a2l.planning import PlanStep, TableRegions


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("tasks") / "run"
    metrics = run_tasks(out, trials=1, seed=7100, quiet=True)
    return out, metrics


@pytest.mark.slow
def test_metrics_schema_and_every_task_reached_with_and_without_its_fault(run) -> None:
    out, metrics = run
    assert json.loads((out / "metrics.json").read_text()) == json.loads(json.dumps(metrics))
    assert set(metrics["tasks"]) == set(TASKS)
    # the skills and the planner's state read the camera by default, and the report says so
    assert metrics["context_source"] == "perceived"
    assert "Context: camera (perceived)." in (out / "report.md").read_text()
    for name, m in metrics["tasks"].items():
        for key in ("success_rate", "success_rate_with_faults", "mean_replans", "plan_ms",
                    "transit_ms", "wall_s"):
            assert m[key] is not None, (name, key)
        assert m["success_rate"] == 1.0 and m["success_rate_with_faults"] == 1.0, \
            (name, m["failures"])
        assert m["plan_ms"] > 0 and m["transit_ms"] > 0
        assert min(m["plan_lengths"]) >= 3, name


@pytest.mark.slow
def test_each_fault_was_injected_and_replanned(run) -> None:
    out, _metrics = run
    rows = pd.read_csv(out / "trials.csv", keep_default_na=False)
    assert len(rows) == 2 * len(TASKS)
    clean, faulty = rows[~rows["fault"]], rows[rows["fault"]]
    assert (clean["fault_injected"] == "").all() and (clean["replans"] == 0).all()
    kinds = {r.task: r.fault_injected.split("@")[0] for r in faulty.itertuples()}
    assert kinds == {n: t.fault for n, t in TASKS.items()}
    assert faulty["fault_applied"].all() and (faulty["fault_not_applied"] == "").all()
    assert (faulty["replans"] >= 1).all()
    # a fault costs skills (press again, grasp again) or none (the block moved before
    # the grasp: grasped where it is now); never fewer than the plan without it
    assert (faulty["skills_run"] >= clean.set_index("task").loc[faulty["task"],
                                                                 "skills_run"].values).all()
    # every plan written where a user can rerun it
    for r in rows.itertuples():
        d = out / "plans" / f"{r.task}-{r.seed}{'-fault' if r.fault else ''}"
        assert (d / "plan0-plan-pyperplan.txt").exists()
    text = (out / "report.md").read_text()
    assert "| light-off-place-right |" in text and (out / "tasks.png").stat().st_size > 0


def test_bad_arguments_are_usage_errors(tmp_path: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["experiment", "tasks", "--out", str(tmp_path / "x"), "--tasks", "nope"])
    assert exc.value.code == 2
    assert "--tasks: unknown task(s) ['nope']" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["experiment", "tasks", "--out", str(tmp_path / "y"), "--seed", "3"])
    assert exc.value.code == 2 and "demonstration seeds" in capsys.readouterr().err
    for robot, message in (("nobot", "--robot: unknown robot 'nobot'"),
                           ("ur5", "--robot: robot 'ur5' has no gripper")):
        with pytest.raises(SystemExit) as exc:
            main(["experiment", "tasks", "--out", str(tmp_path / robot), "--robot", robot])
        assert exc.value.code == 2 and message in capsys.readouterr().err


@pytest.mark.slow
def test_an_applied_fault_leaves_the_world_disagreeing_with_the_plan(run) -> None:
    out, _metrics = run
    rows = pd.read_csv(out / "trials.csv", keep_default_na=False, dtype={"as_planned": str})
    for r in rows[rows["fault"]].itertuples():
        k = int(r.fault_injected.split("@")[1].split(":")[0])
        # the step the fault followed carried out as planned (else no fault), and what was
        # perceived after the fault is not what the plan predicted
        assert r.as_planned[k] == "0", (r.task, r.fault_injected, r.as_planned)
    clean = rows[~rows["fault"]]
    assert all(set(a) == {"1"} for a in clean["as_planned"])


def test_a_fault_that_leaves_the_world_as_planned_is_not_applied() -> None:
    from a2l.lfd.library import make_skill_scene

    scene = make_skill_scene("grasp", 0, scene="task", states={"light": "off"})
    try:
        regions = TableRegions(tuple(scene.config.table_center),
                               tuple(scene.config.table_size))
        rng = np.random.default_rng(0)
        # "drop" after a grasp while the gripper is open and holds nothing: opening it
        # changes no fact, so the fault is not applied
        fired: list[str] = []
        unchanged: list[str] = []
        hook = fault_hook(TASKS["tidy-light-on"], rng, regions, "(light-on)", fired, unchanged)
        hook(1, PlanStep("grasp", ("block",)), scene)
        assert fired == [] and unchanged == ["drop@1:(grasp block)"]
        # "light back on" after the press switched it off: applied
        hook = fault_hook(TASKS["light-off-place-right"], rng, regions, "(light-off)", fired,
                          unchanged)
        hook(2, PlanStep("press-light-off", ("button",)), scene)
        assert fired == ["light_on@2:(press-light-off button)"]
        assert scene.ground_truth()["states"]["light"] == "on"
    finally:
        scene.close()


def test_a_fault_after_a_failed_step_is_not_applied_and_counted_apart(
        run, monkeypatch: pytest.MonkeyPatch) -> None:
    out, _metrics = run
    bundles = {"grasp": str(next((out / "skills").glob("grasp*.a2lb"))),
               "press-light-on": str(next((out / "skills").glob("press*.a2lb"))),
               "press-light-off": str(next((out / "skills").glob("press*.a2lb")))}
    real = a2l.planning.execute.run_skill

    def press_fails(scene, bundle, effect, **kwargs):
        # the press skill ends at once without touching the button: the step fails in
        # the world (the light stays on)
        if effect == "pressed":
            return SimpleNamespace(stop="step_cap")
        return real(scene, bundle, effect, **kwargs)

    monkeypatch.setattr(a2l.planning.execute, "run_skill", press_fails)
    row = trial_task(TaskTrial("light-off-place-right", 7100, True, bundles,
                               str(out / "failed-press"), max_replans=1))
    # the old hook fired on the step's name and switched the light off itself: a success
    assert not row["success"] and "(light-off)" in row["unmet"]
    assert row["fault_injected"] == "" and not row["fault_applied"]
    assert row["fault_not_applied"] == "the step it follows never carried out as planned"
    assert row["stops"].count("press-light-off:step_cap") == 2
    m = summarise(pd.DataFrame([row]))["light-off-place-right"]
    assert m["faults_not_applied"] == 1 and m["trials_with_faults"] == 0
    assert m["success_rate_with_faults"] is None and m["success_rate_fault_not_applied"] == 0.0
