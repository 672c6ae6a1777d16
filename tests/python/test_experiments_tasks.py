"""``a2l experiment tasks`` on a short configuration: one seed per task, with and without its
fault (issue 13, item 5)."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from a2l.cli import main
from a2l.experiments.tasks import TASKS, run_tasks


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("tasks") / "run"
    metrics = run_tasks(out, trials=1, seed=7100, quiet=True)
    return out, metrics


def test_metrics_schema_and_every_task_reached_with_and_without_its_fault(run) -> None:
    out, metrics = run
    assert json.loads((out / "metrics.json").read_text()) == json.loads(json.dumps(metrics))
    assert set(metrics["tasks"]) == set(TASKS)
    for name, m in metrics["tasks"].items():
        for key in ("success_rate", "success_rate_with_faults", "mean_replans", "plan_ms",
                    "transit_ms", "wall_s"):
            assert m[key] is not None, (name, key)
        assert m["success_rate"] == 1.0 and m["success_rate_with_faults"] == 1.0, \
            (name, m["failures"])
        assert m["plan_ms"] > 0 and m["transit_ms"] > 0
        assert min(m["plan_lengths"]) >= 3, name


def test_each_fault_was_injected_and_replanned(run) -> None:
    out, _metrics = run
    rows = pd.read_csv(out / "trials.csv", keep_default_na=False)
    assert len(rows) == 2 * len(TASKS)
    clean, faulty = rows[~rows["fault"]], rows[rows["fault"]]
    assert (clean["fault_injected"] == "").all() and (clean["replans"] == 0).all()
    kinds = {r.task: r.fault_injected.split("@")[0] for r in faulty.itertuples()}
    assert kinds == {n: t.fault for n, t in TASKS.items()}
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
