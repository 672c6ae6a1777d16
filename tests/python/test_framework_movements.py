"""Every iteration's metrics count the robot's discrete movements per phase (acquire, extend,
validate, validate_heldout) and in all: the count is the number of movements the scene
executed in a run with one worker, and the same with two worker processes (each rollout
carries its count back; rounds run ahead on workers and dropped are not counted)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from a2l.acquisition.interactions import Interactions
from a2l.experiments.push import results_table, run_push_experiment
from a2l.framework import FrameworkConfig, loop, run_framework
from a2l.parallel import Executor
from a2l.rollout.env import SceneEnv

#: A short virtual run: iteration 0 (acquisition) and 1 (extension with effect-directed
#: babbling for the stuck pairs), with held-out starts.
CFG = FrameworkConfig(scene="virtual", seed=0, max_iterations=2,
                      discretization={"n_effects": 4}, starts={"n_starts": 2},
                      heldout={"n_starts": 4})


class _SceneCount:
    """Counts ``SceneEnv.execute`` calls in this process, in all and per phase of the loop."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.total = 0
        self.phases: list[dict[str, int]] = []
        orig = SceneEnv.execute

        def execute(env: SceneEnv, direction: tuple[int, int, int]) -> bool:
            self.total += 1
            return orig(env, direction)

        monkeypatch.setattr(SceneEnv, "execute", execute)
        for name in ("acquire", "extend", "validate", "validate_heldout"):
            monkeypatch.setattr(loop, name, self._phase(name, getattr(loop, name)))

    def _phase(self, name: str, fn: Any) -> Any:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            before = self.total
            out = fn(*args, **kwargs)
            if name in ("acquire", "extend"):  # a new iteration begins
                self.phases.append(dict.fromkeys(loop.MOVEMENT_PHASES, 0))
            self.phases[-1][name] += self.total - before
            return out

        return wrapper


def _records(result: dict[str, Any]) -> list[dict[str, Any]]:
    return result.movements


def test_movements_are_those_the_scene_executed_with_one_and_two_workers(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    cfg = CFG
    with monkeypatch.context() as mp:
        count = _SceneCount(mp)
        with Executor(workers=1) as ex:
            one = run_framework(cfg, tmp_path / "one", ex)
    got = _records(one)
    assert [r["iteration"] for r in got] == [0, 1]
    assert [r["robot_movements"] for r in got] == count.phases
    assert got[-1]["robot_movements_total"] == count.total > 0
    assert got[0]["robot_movements"]["extend"] == got[1]["robot_movements"]["acquire"] == 0
    assert got[1]["robot_movements"]["extend"] > 0
    totals = [r["robot_movements_total"] for r in got]
    assert totals == [sum(got[0]["robot_movements"].values()),
                      totals[0] + sum(got[1]["robot_movements"].values())]
    assert [r["robot_movements_training"] for r in got][-1] == count.total - sum(
        r["robot_movements"]["validate_heldout"] for r in got)
    # validation plays every (start, effect) pair: at least one movement each
    assert (
        got[0]["robot_movements"]["validate"] >= cfg.starts.n_starts * cfg.discretization.n_effects
    )
    # two worker processes: rollouts elsewhere, rounds asked ahead; the same counts
    with Executor(workers=2) as ex:
        two = run_framework(cfg, tmp_path / "two", ex)
    assert _records(two) == got
    assert [m["score"] for m in two.iterations] == [m["score"] for m in one.iterations]


def test_first_acquisition_movements_are_recorded(tmp_path: Path) -> None:
    """A first acquisition (NovEB with ``--acquisition noveb``) reports its own movements,
    the tries it threw away included: they are iteration 0's ``acquire``."""
    cfg = CFG.with_({"max_iterations": 1, "heldout.n_starts": 0})

    def first(cfg_: FrameworkConfig, ex: Executor, it: int, progress: Any) -> Interactions:
        got = loop.acquire(cfg_, ex, it, progress)
        return Interactions(got.rollouts, got.movements + 1000)

    with Executor(workers=1) as ex:
        base = run_framework(cfg, tmp_path / "base", ex)
        other = run_framework(cfg, tmp_path / "other", ex, first_acquisition=first)
    a, b = base.movements[0], other.movements[0]
    assert b["robot_movements"]["acquire"] == a["robot_movements"]["acquire"] + 1000
    assert b["robot_movements_total"] == a["robot_movements_total"] + 1000
    assert b["robot_movements"]["validate_heldout"] == 0


def test_metrics_report_and_table_show_the_movements(tmp_path: Path) -> None:
    cfg = CFG
    m = run_push_experiment(cfg, tmp_path / "run", quiet=True, plots=False)
    on_disk = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert on_disk["iterations"] == json.loads(json.dumps(m["iterations"]))
    last = on_disk["iterations"][-1]
    assert set(last["robot_movements"]) == set(loop.MOVEMENT_PHASES)
    table = results_table(on_disk["iterations"])
    assert "| movements |" in table and f"| {last['robot_movements_total']:,} |" in table
    report = (tmp_path / "run" / "report.md").read_text()
    assert f"**{last['robot_movements_total']:,}** discrete movements" in report
    # resumed from its checkpoints, the run keeps the counts
    again = run_push_experiment(resume=tmp_path / "run", quiet=True, plots=False)
    assert [it["robot_movements_total"] for it in again["iterations"]] == [
        it["robot_movements_total"] for it in on_disk["iterations"]]
