"""``a2l experiment sweep``: the push experiment over seeds writes the iterations each seed
needed to reach score 100 (the table of docs/framework.md), resumes, and names bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from a2l.cli import main
from a2l.cli.args import parse_overrides, parse_seeds
from a2l.experiments.sweep import (
    headline_table,
    iterations_to_full_score,
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
    assert parse_overrides(["directed.per_pair=20", "directed.waypoint_aim=0.06",
                            "directed.mode=random", "directed.try_cap=null"]) == {
        "directed.per_pair": 20, "directed.waypoint_aim": 0.06, "directed.mode": "random",
        "directed.try_cap": None}
    with pytest.raises(ValueError, match="no field 'per_pair'.*directed.per_pair"):
        parse_overrides(["per_pair=3"])
    with pytest.raises(ValueError, match="is renamed: it is 'directed.per_pair' now"):
        parse_overrides(["directed_per_pair=3"])
    with pytest.raises(ValueError, match="FIELD=VALUE"):
        parse_overrides(["directed.per_pair"])
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
    # the published one-row table leads with the held-out success rate's mean and lowest
    for r, h in zip(rows, [1.0, 0.96875, None, 0.9375, 1.0], strict=True):
        r["heldout_success"] = h
    head, _, row = headline_table({"rows": rows, "summary": summarize_sweep(rows)}).split("\n")
    assert head.startswith("| seeds | held-out success rate (mean, lowest) |")
    assert row == "| 0–4 (5) | 97.7 % (lowest 93.8 %) | 4 of 5 | 2 of 5 | 3.5 (2–8) |"


def test_sweep_writes_the_table_and_resumes(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sweep"
    args = ["experiment", "sweep", *SMALL, "--seeds", "0-1", "--set", "directed.per_pair=20",
            "--out", str(out)]
    assert main(args) == 0
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["seeds"] == [0, 1] and cfg["overrides"] == {"directed.per_pair": 20}
    assert cfg["framework"]["directed"]["per_pair"] == 20
    assert cfg["framework"]["starts"]["n_starts"] == 2
    assert "--set directed.per_pair=20" in cfg["command"]
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
    assert "| seed | held-out success | iterations to 100 |" in report
    assert "directed.per_pair = 20" in report
    for row in m["rows"]:  # the final skill's held-out success rate, as its run has it
        run = json.loads((out / f"seed_{row['seed']:03d}" / "metrics.json").read_text())
        assert row["heldout_success"] == run["heldout_success"]
        assert f"| {row['seed']} | {row['heldout_success']:.0%} |" in report
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
    (["--set", "directed.per_pair=-3"], "--set"),
    (["--set", "directed_per_pair=3"], "is renamed: it is 'directed.per_pair' now"),
])
def test_sweep_bad_arguments(args: list[str], message: str, tmp_path: Path,
                             capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["experiment", "sweep", *args, "--out", str(tmp_path / "s")])
    assert exc.value.code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "s").exists()


def _seed_outcome(run: Path) -> tuple[str, bytes]:
    """A seed's metrics (but wall times and the workers it ran on) and final bundle."""
    m = json.loads((run / "metrics.json").read_text())
    its = [{k: v for k, v in it.items() if k not in ("wall_s", "heldout_wall_s")}
           for it in m["iterations"]]
    return json.dumps([its, m["final_score"]], sort_keys=True), \
        (run / "skills" / "push.a2lb").read_bytes()


@pytest.mark.slow
def test_seeds_run_at_once_give_the_results_of_seeds_one_by_one(tmp_path: Path) -> None:
    """With 2 workers, 2 seeds run at once, each in a worker process of its own: every
    seed's metrics, bundle and row are those of the sweep run one seed after the other; a
    sweep continued at once (a finished seed read back, two run) gives them again."""
    one, two = tmp_path / "one", tmp_path / "two"
    args = ["experiment", "sweep", *SMALL, "--seeds", "0-2"]
    assert main([*args, "--out", str(one)]) == 0
    assert main([*args, "--workers", "2", "--out", str(two)]) == 0

    def rows(d: Path) -> list[dict]:
        return [{k: v for k, v in r.items() if k != "wall_s"}
                for r in json.loads((d / "metrics.json").read_text())["rows"]]

    assert rows(two) == rows(one) and [r["seed"] for r in rows(one)] == [0, 1, 2]
    for seed in (0, 1, 2):
        sub = f"seed_{seed:03d}"
        assert _seed_outcome(two / sub) == _seed_outcome(one / sub)
        assert json.loads((two / sub / "metrics.json").read_text())["workers"] == 1
    # seeds 0 and 2 left unfinished (their metrics gone): resumed at once, seed 1 read back
    for seed in (0, 2):
        (two / f"seed_{seed:03d}" / "metrics.json").unlink()
    assert main([*args, "--workers", "2", "--out", str(two)]) == 0
    assert rows(two) == rows(one)
    for seed in (0, 1, 2):
        sub = f"seed_{seed:03d}"
        assert _seed_outcome(two / sub) == _seed_outcome(one / sub)
