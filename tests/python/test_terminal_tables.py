"""The tables the commands print stay readable at 80 columns and in a file or a pipe: every
header and every number whole, no line past 80 columns (:func:`a2l.progress.terminal_tables`).

The push experiment's table comes from a real short run (``a2l experiment push --scene
virtual --max_iterations 2 --seed 3``, about 10 s), printed by the command itself; the demo's
from the committed results page (``docs/results/demo.md``, written by ``a2l results`` from a
real demo) and from the demo's summary of that push run.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

from a2l.experiments.demo_report import summary_table
from a2l.experiments.push_report import headline_table, results_table
from a2l.progress import terminal_tables

ROOT = Path(__file__).resolve().parents[2]
NUMBER = re.compile(r"[-+]?\d[\d,]*(?:\.\d+)?%?")


def _table(markdown: str) -> tuple[list[str], list[list[str]]]:
    """The header and the rows of a Markdown table, bold markers dropped."""
    lines = [ln for ln in markdown.splitlines() if ln.startswith("|")]
    cells = [[c.strip().replace("**", "") for c in ln.strip().strip("|").split("|")]
             for k, ln in enumerate(lines) if k != 1]
    return cells[0], cells[1:]


def assert_whole(markdown: str, text: str, width: int = 80) -> None:
    """`text` (the terminal's rendering of the Markdown table `markdown`) holds every header
    whole on one line, every word and number of every cell whole, nothing cut, and no line
    past `width` columns."""
    head, rows = _table(markdown)
    assert "…" not in text
    assert all(len(line) <= width for line in text.splitlines()), text
    for h in head:
        assert any(h in line for line in text.splitlines()), (h, text)
    words = Counter(w for r in [head, *rows] for c in r for w in c.split())
    missing = words - Counter(text.split())
    assert not missing, (missing, text)
    numbers = Counter(n for r in rows for c in r for n in NUMBER.findall(c))
    assert numbers, markdown
    assert not numbers - Counter(NUMBER.findall(text)), text


@pytest.fixture(scope="module")
def push_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """A short push run through the command (not quiet), its output a pipe and no
    ``COLUMNS`` set: the run directory and what the command printed."""
    out = tmp_path_factory.mktemp("terminal-tables") / "run"
    env = {k: v for k, v in os.environ.items() if k != "COLUMNS"}
    done = subprocess.run([sys.executable, "-m", "a2l.cli", "experiment", "push", "--scene",
                           "virtual", "--max_iterations", "2", "--seed", "3", "--out",
                           str(out)], env=env, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    return out, done.stdout


@pytest.fixture(scope="module")
def push_metrics(push_run: tuple[Path, str]) -> dict[str, Any]:
    return json.loads((push_run[0] / "metrics.json").read_text())


@pytest.mark.slow
def test_the_push_command_prints_its_table_whole_into_a_file(
        push_run: tuple[Path, str], push_metrics: dict[str, Any]) -> None:
    lines = push_run[1].splitlines()
    start = 1 + max(k for k, ln in enumerate(lines) if re.match(r"iteration \d+: score", ln))
    end = next(k for k, ln in enumerate(lines) if re.match(r"held-out success \d", ln))
    text = "\n".join(lines[start:end])  # after the iterations' lines, before the results line
    table = results_table(push_metrics["iterations"])
    assert "held-out success" in table and len(push_metrics["iterations"]) == 2
    assert_whole(table, text)
    # one line per measure, the iterations' values beside it in order
    head, rows = _table(table)
    for j, h in enumerate(head[1:], start=1):
        values = [r[j] for r in rows]
        assert re.search(rf"^{re.escape(h)}\s+" + r"\s+".join(map(re.escape, values)) + "$",
                         text, flags=re.M), (h, values, text)
    # the report keeps its Markdown table as it was
    assert table in (push_run[0] / "report.md").read_text()


@pytest.mark.slow
@pytest.mark.parametrize("columns", [80, None, 120],
                         ids=["terminal-80", "not-a-terminal", "terminal-120"])
def test_the_push_and_demo_tables_at_the_terminals_width(
        push_metrics: dict[str, Any], monkeypatch: pytest.MonkeyPatch,
        columns: int | None) -> None:
    """At the terminal's width (`columns`), 80 when the output is not a terminal."""
    monkeypatch.delenv("COLUMNS", raising=False)

    def size(*_: Any) -> os.terminal_size:
        if columns is None:
            raise OSError("not a terminal")
        return os.terminal_size((columns, 24))

    monkeypatch.setattr(os, "get_terminal_size", size)
    its = push_metrics["iterations"]
    demo_md = (ROOT / "docs" / "results" / "demo.md").read_text()
    demo = demo_md.split("<!-- results:demo -->")[1].split("\n\n")[0].strip()
    summary = {"seed": 3, "workers": 1, "wall_s": push_metrics["wall_s"], "parts": {
        "experiment": {"scores": [m["score"] for m in its],
                       "success": push_metrics["final_success"],
                       "heldout_success": push_metrics["heldout_success"],
                       "rc": 0, "wall_s": push_metrics["wall_s"]}}}
    tables = {"push": results_table(its), "push, every row twice": results_table(its * 2),
              "push headline": headline_table([push_metrics]), "demo (docs/results)": demo,
              "demo summary of the push run": summary_table(summary)}
    for name, table in tables.items():
        assert max(map(len, table.splitlines())) > 80, name  # too wide as Markdown
        assert_whole(table, terminal_tables(table), width=columns or 80)


def test_a_table_that_fits_is_a_grid_and_the_text_around_it_stays() -> None:
    demo_md = (ROOT / "docs" / "results" / "demo.md").read_text()
    table = demo_md.split("<!-- results:demo -->")[1].split("\n\n")[0].strip()
    text = terminal_tables(f"# a report\n\n{table}\n\nafter the table", width=200)
    lines = text.splitlines()
    assert lines[:2] == ["# a report", ""] and lines[-2:] == ["", "after the table"]
    head, rows = _table(table)
    grid = lines[2:-2]
    assert grid[0].split() == " ".join(head).split() and set(grid[1]) == {"-", " "}
    assert len(grid) == 2 + len(rows)  # one line per row when nothing wraps
    assert_whole(table, text, width=200)
