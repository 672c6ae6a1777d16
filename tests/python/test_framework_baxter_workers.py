"""A short push experiment on the Baxter scene (PyBullet) gives identical results with one
worker (rollouts in this process, after whatever it ran before) and two worker processes
(rollouts split between them, each with its own history of episodes): every episode starts
bitwise the same (a2l.sim.bodies), through the public ``run_push_experiment``."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

from a2l.experiments.push import run_push_experiment
from a2l.framework import FrameworkConfig


def _config() -> FrameworkConfig:
    # 2 starts, 2 iterations, few tries: small, but every phase runs (babbling, learning,
    # validation, extension and effect-directed babbling). Rollouts read the simulator's
    # truth; the scene is told so and renders no camera frame.
    return FrameworkConfig(
        scene="bullet",
        max_iterations=2,
        seed=0,
        scene_config={"context_source": "ground_truth"},
        discretization={"n_effects": 4},
        starts={"n_starts": 2},
        babbling={"try_cap": 40},
        directed={"try_cap": 8},
    )


def _outcome(run_dir: Path) -> dict[str, Any]:
    m = json.loads((run_dir / "metrics.json").read_text())
    # wall times (the iteration's and the held-out rollouts') are the only fields that may differ
    iterations = [{k: v for k, v in it.items() if k not in ("wall_s", "heldout_wall_s")}
                  for it in m["iterations"]]
    return {"iterations": json.dumps(iterations, sort_keys=True),
            "final_score": m["final_score"],
            "bundle": (run_dir / "skills" / "push.a2lb").read_bytes(),
            "dataset": pd.read_parquet(run_dir / "dataset.parquet")}


@pytest.mark.slow
def test_baxter_run_same_results_with_one_and_two_workers(tmp_path: Path) -> None:
    runs = {}
    for workers in (1, 2):
        out = tmp_path / f"workers-{workers}"
        m = run_push_experiment(_config(), out=out, workers=workers, quiet=True, plots=False)
        assert m["workers"] == workers
        runs[workers] = _outcome(out)
    one, two = runs[1], runs[2]
    assert len(json.loads(one["iterations"])) == 2
    assert len(one["dataset"]) > 0 and one["final_score"] > 0  # the box was pushed
    assert one["iterations"] == two["iterations"]
    assert one["final_score"] == two["final_score"]
    assert one["bundle"] == two["bundle"]
    pd.testing.assert_frame_equal(one["dataset"], two["dataset"], check_exact=True)
