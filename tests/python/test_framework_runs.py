"""Whole push experiments through the ``a2l experiment push`` command (virtual scene):
a run killed in the middle of an iteration and resumed ends exactly as an uninterrupted run,
and one worker, two local worker processes and a local Dask cluster give the same results.

The runs are small (2 start positions, 2 iterations): the properties do not depend on the
size, and the second iteration (babbling directed at the stuck pairs, learning on a few
thousand rows) still takes seconds, long enough to be killed in. Rollouts are small tasks, so
the Dask run is the slowest of the module.
"""

from __future__ import annotations

import json
import shlex
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

from a2l.cli import parse
from a2l.cli.parser import config_from
from a2l.framework import FrameworkConfig

#: The command line of every run of this module (except the output options).
ARGS = ["--scene", "virtual", "--effects", "4", "--seed", "0", "--starts", "2",
        "--iterations", "2", "--quiet"]


def _command(*args: str) -> list[str]:
    return [sys.executable, "-m", "a2l.cli", "experiment", "push", *args]


def _run(*args: str, timeout: float = 600) -> subprocess.CompletedProcess[str]:
    proc = subprocess.run(_command(*args), capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, proc.stderr
    return proc


def _outcome(run_dir: Path) -> dict[str, Any]:
    """What must not depend on interruption or workers: metrics (but wall times), the final
    bundle's bytes and the final dataset."""
    m = json.loads((run_dir / "metrics.json").read_text())
    iterations = [{k: v for k, v in it.items() if k not in ("wall_s", "heldout_wall_s")}
                  for it in m["iterations"]]
    return {
        # JSON text: NaN (no success) compares equal to NaN.
        "iterations": json.dumps(iterations, sort_keys=True),
        "final_score": m["final_score"],
        "bundle": (run_dir / "skills" / "push.a2lb").read_bytes(),
        "dataset": pd.read_parquet(run_dir / "dataset.parquet"),
    }


def _assert_same(a: dict[str, Any], b: dict[str, Any]) -> None:
    assert a["iterations"] == b["iterations"]
    assert a["final_score"] == b["final_score"]
    assert a["bundle"] == b["bundle"]
    pd.testing.assert_frame_equal(a["dataset"], b["dataset"], check_exact=True)


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An uninterrupted run with one worker (rollouts in the command's own process)."""
    out = tmp_path_factory.mktemp("framework-runs") / "reference"
    _run(*ARGS, "--out", str(out), "--workers", "1")
    return out


def test_reference_run_is_complete_and_rerunnable(reference: Path) -> None:
    m = json.loads((reference / "metrics.json").read_text())
    assert [it["iteration"] for it in m["iterations"]] == [0, 1]
    # Iteration 1 (the one the resume test kills) extended the dataset.
    assert m["iterations"][1]["dataset_size"] > m["iterations"][0]["dataset_size"] > 0
    # config.json's command reruns the same configuration.
    cfg = json.loads((reference / "config.json").read_text())
    path, ns, _ = parse(shlex.split(cfg["command"])[1:])
    framework = FrameworkConfig.from_dict(cfg["framework"])
    assert path == ("experiment", "push") and config_from(ns, FrameworkConfig) == framework
    assert (framework.scene, framework.discretization.n_effects, framework.seed,
            framework.max_iterations, framework.starts.n_starts) == ("virtual", 4, 0, 2, 2)


@pytest.mark.slow
def test_killed_mid_iteration_and_resumed_ends_as_uninterrupted(reference: Path,
                                                                 tmp_path: Path) -> None:
    out = tmp_path / "killed"
    first = out / "checkpoints" / "iter_000" / "state.json"
    proc = subprocess.Popen(_command(*ARGS, "--out", str(out)), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 300
        while not first.is_file():
            assert proc.poll() is None, f"the run ended before its first checkpoint: " \
                                        f"{proc.stderr.read() if proc.stderr else ''}"
            assert time.monotonic() < deadline, "no checkpoint after 300 s"
            time.sleep(0.005)
        # Iteration 0's checkpoint exists: the run is in iteration 1 (seconds long), which
        # has no checkpoint yet (asserted below). Kill it now, with no chance to clean up.
        assert proc.poll() is None, "the run ended before it could be killed"
        proc.kill()
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == -9
    assert not (out / "metrics.json").exists()
    done = sorted(p.name for p in (out / "checkpoints").glob("iter_*"))
    assert done == ["iter_000"], done      # killed in iteration 1, before its checkpoint

    _run("--resume", str(out), "--quiet")
    _assert_same(_outcome(out), _outcome(reference))
    assert sorted(p.name for p in (out / "checkpoints").glob("iter_*")) == [
        "iter_000", "iter_001"]


@pytest.mark.slow
def test_two_local_workers_give_the_same_results(reference: Path, tmp_path: Path) -> None:
    out = tmp_path / "two-workers"
    _run(*ARGS, "--out", str(out), "--workers", "2")
    assert json.loads((out / "metrics.json").read_text())["workers"] == 2
    _assert_same(_outcome(out), _outcome(reference))


@pytest.fixture
def dask_cluster() -> Iterator[str]:
    """A local Dask cluster of two worker processes over loopback: its scheduler address."""
    from dask.distributed import LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address=None)
    try:
        yield cluster.scheduler_address
    finally:
        cluster.close()


@pytest.mark.slow
def test_dask_cluster_gives_the_same_results(reference: Path, tmp_path: Path,
                                             dask_cluster: str) -> None:
    assert dask_cluster.startswith("tcp://127.0.0.1:")
    out = tmp_path / "dask"
    _run(*ARGS, "--out", str(out), "--cluster", dask_cluster)
    assert json.loads((out / "metrics.json").read_text())["cluster"] == dask_cluster
    _assert_same(_outcome(out), _outcome(reference))


def test_dask_worker_threads_do_not_share_a_scene(tmp_path: Path) -> None:
    """A Dask worker runs tasks in several threads: babbling and validation there give the
    rollouts of one process (each thread has its own scene and skill state)."""
    from dask.distributed import LocalCluster

    from a2l.acquisition.interactions import interaction_rows
    from a2l.framework import acquire, generate_skill, validate
    from a2l.parallel import Executor

    cfg = FrameworkConfig(scene="virtual", seed=3, discretization={"n_effects": 4})
    bundle = tmp_path / "iter_000.a2lb"
    with Executor(workers=1) as local:
        babbled = acquire(cfg, local, 0).rollouts
        generate_skill(cfg, interaction_rows(babbled, cfg.discretization.discretizer()), bundle)
        validated = validate(cfg, local, bundle)
    cluster = LocalCluster(n_workers=1, threads_per_worker=2, processes=True,
                           host="127.0.0.1", dashboard_address=None)
    try:
        with Executor(cluster=cluster.scheduler_address) as remote:
            babbled_d = acquire(cfg, remote, 0).rollouts
            validated_d = validate(cfg, remote, bundle)
    finally:
        cluster.close()
    for a, b in zip([*babbled, *validated], [*babbled_d, *validated_d], strict=True):
        assert (a.start, a.moves, a.effect, a.wanted, a.outcome, a.stop) == (
            b.start, b.moves, b.effect, b.wanted, b.outcome, b.stop)
        assert (a.eef == b.eef).all() and (a.obj == b.obj).all()
