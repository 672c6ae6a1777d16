"""The seed registry (``a2l.seeds``, ``docs/seeds.md``): tuning seeds 0-999 and evaluation
seeds from 1000 on, an entry for every experiment, and a run on a tuning seed says so in its
``config.json`` and its ``report.md`` (one on evaluation seeds does not)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from a2l import seeds
from a2l.seeds import (
    EVALUATION_FIRST,
    REGISTRY,
    format_seeds,
    mark_report,
    seed_record,
    seed_use,
)


def test_the_split_and_its_edges() -> None:
    assert EVALUATION_FIRST == 1000
    assert seeds.is_tuning(0) and seeds.is_tuning(999)
    assert not seeds.is_tuning(1000)
    assert seed_use([0, 5]) == "tuning"
    assert seed_use([1000, 1029]) == "evaluation"
    assert seed_use([999, 1000]) == "mixed"
    with pytest.raises(ValueError, match="seed: must be >= 0"):
        seeds.is_tuning(-1)
    # seeds looked at before a choice are tuning seeds of their experiment only
    assert seeds.is_tuning(1001, "push") and not seeds.is_tuning(1001, "babbling")
    assert seeds.is_tuning(1009, "push") and not seeds.is_tuning(1010, "push")
    assert not seeds.is_tuning(1001) and seed_use([1001, 1010], "push") == "mixed"
    record = seed_record("sweep", [1000, 1010])
    assert (record["use"], record["tuning"], record["evaluation"]) == ("mixed", "1000", "1010")
    assert "1000-1009, looked at before a choice" in mark_report("# T\n", record)
    with pytest.raises(ValueError, match="below its block"):
        seeds.ExperimentSeeds("x", "y", (1003, 1100), "z", looked_at=(1003,))
    with pytest.raises(ValueError, match="none given"):
        seed_use([])


def test_format_seeds_writes_ranges() -> None:
    assert format_seeds([5, 0, 1, 2, 7, 8]) == "0-2, 5, 7-8"
    assert format_seeds(range(1000, 1020)) == "1000-1019"
    assert format_seeds([]) == "-"


def test_every_experiment_has_an_entry_with_evaluation_seeds_only_above_the_split() -> None:
    from a2l.cli import build_parser

    _, commands = build_parser()
    experiments = {path[1] for path in commands if path[0] == "experiment"}
    assert experiments and experiments <= set(REGISTRY), experiments - set(REGISTRY)
    for entry in REGISTRY.values():
        assert EVALUATION_FIRST <= entry.evaluation[0] <= entry.evaluation[1]
    with pytest.raises(ValueError, match="must lie at or above 1000"):
        seeds.ExperimentSeeds("x", "y", (999, 1100), "z")
    with pytest.raises(KeyError, match="no seed registry entry"):
        seed_record("nonsense", [1000])


def test_docs_list_every_registry_entry_and_the_split() -> None:
    text = (Path(__file__).parents[2] / "docs" / "seeds.md").read_text()
    assert "0–999" in text and "1000" in text
    for name, entry in REGISTRY.items():
        first, last = entry.evaluation
        assert f"| `{name}` |" in text, name
        assert f"{first}–{last}" in text, name


def test_mark_report_puts_the_note_under_the_title_and_leaves_evaluation_runs_alone() -> None:
    text = "# Title\n\nbody\n"
    marked = mark_report(text, seed_record("tasks", [3, 4]))
    lines = marked.split("\n")
    assert lines[0] == "# Title"
    assert lines[2].startswith("**Tuning seeds**: this run uses seed(s) 3-4")
    assert "tasks: 7000-7999" in lines[2]
    assert mark_report(text, seed_record("tasks", [7000, 7001])) == text
    mixed = mark_report(text, seed_record("tasks", [999, 1000]))
    assert "seed(s) 999," in mixed


@pytest.mark.parametrize("seed, tuning", [(3, True), (1010, False)])
def test_a_push_run_on_a_tuning_seed_says_so_in_its_report(tmp_path: Path, seed: int,
                                                          tuning: bool) -> None:
    from a2l.experiments.push import run_push_experiment
    from a2l.framework import FrameworkConfig

    cfg = FrameworkConfig(
        scene="virtual",
        seed=seed,
        max_iterations=1,
        discretization={"n_effects": 4},
        starts={"n_starts": 2},
        heldout={"n_starts": 0},
    )
    run_push_experiment(cfg, tmp_path / "run", quiet=True, plots=False)
    config = json.loads((tmp_path / "run" / "config.json").read_text())
    report = (tmp_path / "run" / "report.md").read_text()
    assert config["seed_use"]["use"] == ("tuning" if tuning else "evaluation")
    assert config["seed_use"]["seeds"] == str(seed)
    assert ("**Tuning seeds**" in report) == tuning
    if tuning:
        assert "not an evaluation result" in report


@pytest.mark.parametrize(("seed", "eval_seed"), [(0, 500), (500, 501), (1000, 500),
                                                  (1001, 500), (1002, 1502), (1502, 1503)])
def test_panda_gym_evaluates_a_looked_at_learning_seed_on_the_tuning_episodes(
        seed: int, eval_seed: int) -> None:
    # learning seeds 1000 and 1001 were looked at before the transit: tuning seeds, judged
    # on the tuning episodes (500); an evaluation seed on 1502 (never the learning seed)
    from a2l.experiments.panda_gym import PandaGymConfig

    assert seeds.is_tuning(seed, "panda-gym") == (eval_seed < 1000)
    assert PandaGymConfig(seed=seed).evaluation_seed == eval_seed
