"""``a2l experiment sweep``: the push experiment over seeds writes the iterations each seed
needed to reach score 100 (the table of docs/framework.md), resumes, and names bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from a2l.cli import main
from a2l.experiments.sweep import (
    iterations_to_full_score,
    parse_overrides,
    parse_seeds,
    summarize_sweep,
)

#: Small runs: 2 starts, at most 3 iterations (the property does not depend on the size).
SMALL = ["--scene", "virtual", "--effects", "4", "--starts", "2", "--iterations", "3",
         "--quiet"]


def test_parse_seeds() -> None:
    assert parse_seeds("0-3") == [0, 1, 2, 3]
    assert parse_seeds("5,0-1, 9") == [5, 0, 1, 9]
    for bad, msg in (("a-3", "expected e.g."), ("3-1", "empty range"), ("-2", "expected"),
                     ("1,1", "twice"), ("", "expected")):
        with pytest.raises(ValueError, match=msg):
            parse_seeds(bad)


def test_parse_overrides() -> None:
    assert parse_overrides(["directed_per_pair=20", "waypoint_aim=0.06",
                            "directed_mode=random", "directed_try_cap=null"]) == {
        "directed_per_pair": 20, "waypoint_aim": 0.06, "directed_mode": "random",
        "directed_try_cap": None}
    with pytest.raises(ValueError, match="no field 'per_pair'.*directed_per_pair"):
        parse_overrides(["per_pair=3"])
    with pytest.raises(ValueError, match="FIELD=VALUE"):
        parse_overrides(["directed_per_pair"])
    with pytest.raises(ValueError, match="--seeds"):
        parse_overrides(["seed=3"])


def test_iterations_to_full_score_and_summary() -> None:
    its = [{"iteration": 0, "score": 30.0}, {"iteration": 1, "score": 100.0},
           {"iteration": 2, "score": 100.0}]
    assert iterations_to_full_score(its) == 2
    assert iterations_to_full_score(its[:1]) is None
    rows = [{"seed": s, "iterations_to_100": n} for s, n in enumerate([2, 4, None, 3, 8])]
    assert summarize_sweep(rows) == {"runs": 5, "reached": 4, "within": 3,
                                     "reached_within": 2, "min": 2, "max": 8,
                                     "median": 3.5, "mean": 4.25}


def test_sweep_writes_the_table_and_resumes(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sweep"
    args = ["experiment", "sweep", *SMALL, "--seeds", "0-1", "--set", "directed_per_pair=20",
            "--out", str(out)]
    assert main(args) == 0
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["seeds"] == [0, 1] and cfg["overrides"] == {"directed_per_pair": 20}
    assert cfg["framework"]["directed_per_pair"] == 20 and cfg["framework"]["n_starts"] == 2
    assert "--set directed_per_pair=20" in cfg["command"]
    m = json.loads((out / "metrics.json").read_text())
    assert [r["seed"] for r in m["rows"]] == [0, 1]
    for row in m["rows"]:
        # Independently of the sweep: each seed's own run directory.
        run = json.loads((out / f"seed_{row['seed']:03d}" / "metrics.json").read_text())
        assert run["seed"] == row["seed"]
        scores = [it["score"] for it in run["iterations"]]
        first = next((i + 1 for i, s in enumerate(scores) if s >= 100.0), None)
        assert row["iterations_to_100"] == first
        assert row["final_score"] == max(scores) == run["final_score"]
        assert row["iterations_run"] == len(scores) <= 3
    assert m["summary"]["runs"] == 2
    report = (out / "report.md").read_text()
    assert "| seed | iterations to 100 |" in report and "directed_per_pair = 20" in report
    # Run again: finished seeds are read back, not rerun.
    stamp = (out / "seed_000" / "metrics.json").stat().st_mtime_ns
    capsys.readouterr()
    assert main(args) == 0
    assert (out / "seed_000" / "metrics.json").stat().st_mtime_ns == stamp
    assert json.loads((out / "metrics.json").read_text()) == m
    # Another configuration in the same directory is refused.
    with pytest.raises(SystemExit) as exc:
        main(["experiment", "sweep", *SMALL, "--seeds", "0-2", "--out", str(out)])
    assert exc.value.code == 2
    assert "another configuration" in capsys.readouterr().err


@pytest.mark.parametrize(("args", "message"), [
    (["--seeds", "x"], "--seeds"),
    (["--set", "nope=1"], "no field 'nope'"),
    (["--set", "directed_per_pair=-3"], "--set"),
])
def test_sweep_bad_arguments(args: list[str], message: str, tmp_path: Path,
                             capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["experiment", "sweep", *args, "--out", str(tmp_path / "s")])
    assert exc.value.code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "s").exists()
