"""``a2l results``: the README's and the docs' result tables are the generated ones of
``docs/results/`` (a number edited by hand fails), every run of the catalog is a valid
command on evaluation seeds, and a results page records its commit, clean or dirty."""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
from pathlib import Path
from typing import Any

import pytest

from a2l.results.blocks import block, fill_blocks, pages_with_blocks, read_blocks, stale_blocks
from a2l.results.catalog import CONTEXTS, ENTRIES, PROFILES, by_context, entries
from a2l.results.provenance import git_state, utc_seconds
from a2l.results.run import copy_blocks, run_results, sources
from a2l.rundir import read_json, write_json
from a2l.seeds import is_tuning

ROOT = Path(__file__).parents[2]
DOCS = ROOT / "docs" / "results"


def _edit_a_number(text: str, name: str) -> str:
    """`text` with the first digit inside block `name` changed."""
    m = re.search(rf"<!-- results:{name} -->\n", text)
    assert m is not None
    i = m.end() + re.search(r"\d", text[m.end():]).start()  # type: ignore[union-attr]
    return text[:i] + str((int(text[i]) + 1) % 10) + text[i + 1:]


def test_the_readme_and_the_docs_show_the_generated_tables() -> None:
    """Every block of the README and of docs/ is a copy of its docs/results/ table, every
    generated table is shown somewhere, and the README shows some."""
    src = sources(DOCS)
    pages = {p.stem for p in DOCS.glob("*.md") if p.name != "README.md"}
    assert pages <= {e.name for e in ENTRIES}, "a docs/results/ page is no catalog entry"
    assert set(src) == pages, "a docs/results/ page without its block"
    shown: dict[str, str] = {}
    for page in pages_with_blocks(ROOT):
        text = page.read_text()
        assert stale_blocks(text, src) == [], f"{page}: a results block differs from " \
            "docs/results/ (`a2l results --no-run` copies the generated tables)"
        shown.update(read_blocks(text))
    assert set(shown) == set(src), "a generated table is shown nowhere"
    assert read_blocks((ROOT / "README.md").read_text()), "the README shows no generated table"


def test_a_number_edited_by_hand_fails() -> None:
    src = sources(DOCS)
    for page in pages_with_blocks(ROOT):
        text = page.read_text()
        for name in read_blocks(text):
            assert stale_blocks(_edit_a_number(text, name), src) == [name], (page, name)


def test_every_page_names_the_commands_that_made_it() -> None:
    from a2l.cli import parse

    for page in sorted(DOCS.glob("*.md")):
        if page.name == "README.md":
            continue
        text = page.read_text()
        commands = re.findall(r"\| `(a2l [^`]+)` \|", text)
        assert commands, page
        for cmd in commands:
            parse(shlex.split(cmd.replace("DIR/", "runs/x/"))[1:])
        assert re.search(r"at commit [0-9a-f]{7}", text), page


def test_blocks_are_read_filled_and_checked() -> None:
    text = "intro\n" + block("a", "old\n") + "\nmiddle\n" + block("b", "x") + "\nend\n"
    assert read_blocks(text) == {"a": "old\n", "b": "x\n"}
    filled = fill_blocks(text, {"a": "| 1 |\n", "b": "| 2 |\n"})
    assert read_blocks(filled) == {"a": "| 1 |\n", "b": "| 2 |\n"}
    assert filled.startswith("intro\n") and filled.endswith("\nend\n")
    assert stale_blocks(filled, {"a": "| 1 |\n", "b": "| 2 |\n"}) == []
    assert stale_blocks(filled, {"a": "| 1 |\n", "b": "| 3 |\n"}) == ["b"]
    assert stale_blocks(filled, {"a": "| 1 |\n"}) == ["b"]
    with pytest.raises(KeyError, match=r"\['b'\] have no generated table"):
        fill_blocks(text, {"a": ""})
    with pytest.raises(ValueError, match="appears twice"):
        read_blocks(block("a", "1") + "\n" + block("a", "2"))
    with pytest.raises(ValueError, match="not closed"):
        read_blocks("<!-- results:c -->\n| 1 |\n")


@pytest.mark.parametrize("profile", PROFILES)
def test_every_run_is_a_command_on_evaluation_seeds(profile: str) -> None:
    from a2l.cli import parse

    assert [e.name for e in ENTRIES if not e.evaluation] == ["demo"]
    for entry in ENTRIES:
        assert entry.runs["full"], entry.name  # every table is published (quick: a check)
        for run in entry.runs[profile]:
            path, ns, _ = parse([*run.args, "--out", "x", "--workers", "2"])
            if not entry.evaluation:  # the demo: `make demo`'s own command and seed
                assert path[0] == "demo" and ns.seed == 0, run
                continue
            assert path[0] == "experiment", run
            seeds = []
            for flag in ("seed", "first_seed"):
                if flag in ns and ns[flag] is not None:
                    seeds.append(int(ns[flag]))
            if "seeds" in ns and isinstance(ns.seeds, str):
                seeds += [int(s) for s in re.split(r"[-,]", ns.seeds)]
            assert seeds, f"{entry.name}/{run.key}: no seed given (defaults may be tuning " \
                "seeds)"
            assert not any(is_tuning(s, path[1]) for s in seeds), (entry.name, run.key, seeds)
    with pytest.raises(KeyError, match="unknown results table"):
        entries(["push-virtual", "nonsense"])


def test_tables_per_context_are_joined_side_by_side() -> None:
    cam = "| skill | success |\n|---|---|\n| push | 8/10 |\n| grasp | 10/10 |\n"
    gt = "| skill | success |\n|---|---|\n| push | 9/10 |\n| grasp | 10/10 |\n"
    rows = by_context([cam, gt]).splitlines()
    assert rows[0] == "| context | skill | success |" and rows[1] == "|---|---|---|"
    assert rows[2:] == [f"| {CONTEXTS[0]} | push | 8/10 |", f"| {CONTEXTS[0]} | grasp | 10/10 |",
                        f"| {CONTEXTS[1]} | push | 9/10 |", f"| {CONTEXTS[1]} | grasp | 10/10 |"]
    with pytest.raises(ValueError, match="different headers"):
        by_context([cam, gt.replace("success", "rate")])
    with pytest.raises(ValueError, match="one per context"):
        by_context([cam])
    # every side-by-side entry runs each of its commands once per context: the camera run,
    # then the same command with the truth (a preset's baseline runs, with the camera only,
    # come after them)
    for entry in ENTRIES:
        for every in entry.runs.values():
            runs = [r for r in every if "--preset" not in r.args]
            if any("ground_truth" in r.args for r in runs):
                assert len(runs) % 2 == 0, entry.name
                for cam_run, gt_run in zip(runs[::2], runs[1::2], strict=True):
                    assert cam_run.args + ("--context_source", "ground_truth") == gt_run.args
                    assert gt_run.key == f"{cam_run.key}-gt", entry.name


def test_the_push_table_puts_camera_and_truth_runs_side_by_side() -> None:
    """The Baxter push table groups its runs by the source their metrics name (runs that
    name none read the camera, the default)."""
    def run(seed: int, source: str | None) -> dict[str, object]:
        it = {"accepted": True, "success_rate": {"left": 1.0}, "heldout_success_rate":
              {"left": 0.5}, "robot_movements_total": 10}
        return {"scene": "baxter", "n_effects": 4, "seed": seed, "iterations": [it],
                "final_score": 100.0, "heldout_score": 75.0,
                **({"context_source": source} if source else {})}

    (entry,) = entries(["push-baxter"])
    rows = entry.table([run(1000, "ground_truth"), run(1001, None), run(1002, "perceived")])
    body = rows.splitlines()[2:]
    assert [r.split(" | ")[0] for r in body] == [f"| {CONTEXTS[0]}"] * 2 + [f"| {CONTEXTS[1]}"]
    assert [r.split(" | ")[3] for r in body] == ["1001", "1002", "1000"]
    # the thesis preset's runs (their metrics name it) come last, labelled
    rows = entry.table([{**run(1003, "perceived"), "preset": "thesis"}, run(1003, "perceived"),
                        run(1003, "ground_truth")])
    assert [r.split(" | ")[0] for r in rows.splitlines()[2:]] == [
        f"| {CONTEXTS[0]}", f"| {CONTEXTS[1]}", f"| {CONTEXTS[0]}, `--preset thesis`"]
    # every full-profile push table has the thesis preset's runs beside the defaults'
    for name in ("push-baxter", "push-virtual"):
        (entry,) = entries([name])
        assert any(r.args[2:4] == ("--preset", "thesis") for r in entry.runs["full"]), name


def test_a_run_is_told_a_presets_by_its_configuration() -> None:
    from a2l.framework import FrameworkConfig
    from a2l.framework.presets import preset_of

    thesis = FrameworkConfig.preset("thesis", scene="bullet", seed=1003)
    assert preset_of(json.loads(json.dumps(thesis.to_dict()))) == "thesis"
    assert preset_of(FrameworkConfig(scene="bullet").to_dict()) is None
    # a field the preset pins changed: no longer the preset
    assert preset_of(thesis.with_({"skill.align": 0.05}).to_dict()) is None


def _git(root: Path, *args: str) -> None:
    subprocess.run(["git", "-C", str(root), *args], check=True, capture_output=True)


def _empty_repo(root: Path) -> None:
    """A git repository at `root` with ``docs/`` and one empty commit."""
    (root / "docs").mkdir(parents=True)
    _git(root, "init", "-q")
    _git(root, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "--allow-empty",
         "-m", "empty")


def _done_sweeps(out: Path, rows: list[dict[str, Any]], seed_use: Any,
                 **done: Any) -> None:
    """The full profile's two push-virtual runs done in `out` (the defaults' sweep and the
    thesis preset's, the same `rows`), their done records `done`."""
    from a2l.experiments.sweep import summarize_sweep

    for key, extra in (("sweep", {}), ("sweep-thesis", {"preset": "thesis"})):
        run_dir = out / "push-virtual" / key
        write_json(run_dir / "metrics.json",
                   {"rows": rows, "summary": summarize_sweep(rows), **extra})
        write_json(run_dir / "config.json", {"seed_use": seed_use})
        write_json(out / "push-virtual" / f"{key}.done.json", {**done, "seed_use": seed_use})


def test_a_page_is_written_from_done_runs_and_copied_with_its_commit(tmp_path: Path) -> None:
    """A fake repository with a README block and a finished sweep run: ``--no-run`` writes
    ``docs/results/push-virtual.md`` with the table, the commit (dirty: the README was
    edited after the commit) and the command, and copies the table into the README."""
    root = tmp_path / "repo"
    _empty_repo(root)
    (root / "README.md").write_text("# r\n\n" + block("push-virtual", "typed 100\n") + "\n")
    _git(root, "add", "README.md")
    state = git_state(root)
    assert state["dirty"] and state["changed"] == ["README.md"]
    rows = [{"seed": 1000 + i, "iterations_to_100": n, "final_score": 100.0 if n else 90.0,
             "iterations_run": n or 3, "wall_s": 5.0, "heldout_success": h}
            for i, (n, h) in enumerate([(2, 1.0), (3, 0.875), (None, 0.75)])]
    out = tmp_path / "runs"
    _done_sweeps(out, rows, {"use": "evaluation", "seeds": "1000-1002"},
                 command="a2l experiment sweep --seeds 1000-1002", commit="f" * 40,
                 short="fffffff", dirty=True, started="2026-12-03 08:00 UTC", wall_s=15.0,
                 workers=2)
    done = run_results("full", out=out, root=root, only=["push-virtual"], run=False)
    assert done["missing"] == []
    page = (root / "docs" / "results" / "push-virtual.md").read_text()
    body = read_blocks(page)["push-virtual"]
    row = "| 1000–1002 (3) | 87.5 % (lowest 75.0 %) | 2 of 3 | 2 of 3 | 2.5 (2–3) |"
    assert f"| defaults {row}" in body and f"| `--preset thesis` {row}" in body
    assert "fffffff (dirty tree)" in body and "evaluation seeds 1000-1002" in body
    assert "`a2l experiment sweep --seeds 1000-1002`" in page
    readme = (root / "README.md").read_text()
    assert read_blocks(readme)["push-virtual"] == body and "typed 100" not in readme
    assert copy_blocks(root, root / "docs" / "results") == []  # nothing left to copy
    # the entry's runs not done: no page, the entry reported missing
    done = run_results("full", out=out, root=root, only=["tasks"], run=False)
    assert done["missing"] == ["tasks"] and done["pages"] == []
    # the quick profile's page of the same runs goes to its own folder, and nothing copies it
    readme = (root / "README.md").read_text()
    quick = run_results("quick", out=out, root=root, only=["push-virtual"], run=False)
    assert quick["pages"] == [str(root / "docs" / "results" / "quick" / "push-virtual.md")]
    assert quick["copied"] == [] and (root / "README.md").read_text() == readme
    assert (root / "docs" / "results" / "push-virtual.md").read_text() == page
    quick_page = Path(quick["pages"][0]).read_text()
    assert "--profile quick" in quick_page and "[seeds.md](../../seeds.md)" in quick_page


def test_a_run_made_in_parts_says_its_wall_time_is_the_last_parts(tmp_path: Path) -> None:
    """A run resumed from an interrupted part's work: its record times only the last part,
    and the page says so (told by the record, or, in records that do not say, by a file of
    the run directory older than the record's start)."""
    root = tmp_path / "repo"
    _empty_repo(root)
    rows = [{"seed": 1000, "iterations_to_100": 2, "final_score": 100.0, "iterations_run": 2,
             "wall_s": 5.0, "heldout_success": 1.0}]
    out = tmp_path / "runs"
    started = "2026-12-03 08:00 UTC"
    _done_sweeps(out, rows, {"use": "evaluation", "seeds": "1000"}, command="a2l x",
                 commit="f" * 40, short="fffffff", dirty=False, started=started,
                 wall_s=15.0, workers=2)

    def page() -> str:
        run_results("full", out=out, root=root, only=["push-virtual"], run=False)
        return (root / "docs" / "results" / "push-virtual.md").read_text()

    assert "last part" not in page()  # every file written after the start: one part
    old = utc_seconds(started) - 3600
    os.utime(out / "push-virtual" / "sweep" / "config.json", (old, old))
    text = page()
    assert "30 s wall (for sweep: the last part, resumed from an earlier one's work)" in text
    assert "| 15 (last part) |" in text and text.count("(last part)") == 1
    done = out / "push-virtual" / "sweep.done.json"
    write_json(done, {**read_json(done), "resumed": False})  # the record's word wins
    assert "last part" not in page()


def test_a_caption_names_each_seed_use_once_with_its_ranges() -> None:
    from a2l.results.run import seeds_caption

    ev = [{"use": "evaluation", "seeds": s} for s in ("1000", "1000", "1001", "1002")]
    assert seeds_caption(ev) == "evaluation seeds 1000, 1001, 1002"
    assert seeds_caption([{"use": "tuning", "seeds": "0"}, *ev[:1]]) == (
        "tuning seeds 0; evaluation seeds 1000")
    assert seeds_caption([]) == "not recorded"


def test_the_command_refuses_an_unknown_table_and_a_non_repository(tmp_path: Path) -> None:
    from a2l.cli import main

    for argv in (["results", "--only", "nonsense", "--no-run"],
                 ["results", "--root", str(tmp_path), "--no-run"]):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 2




def test_what_a2l_results_writes_itself_does_not_make_the_tree_dirty(tmp_path: Path) -> None:
    """docs/results/ and the blocks' contents are the command's own output: a committed
    tree stays clean after they are written (a rerun continues as clean); any other change
    makes it dirty."""
    root = tmp_path / "repo"
    (root / "docs").mkdir(parents=True)
    (root / "README.md").write_text("# r\n\n" + block("push-virtual", "typed\n") + "\nend\n")
    (root / "docs" / "x.md").write_text("x\n")
    _git(root, "init", "-q")
    _git(root, "add", ".")
    _git(root, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "c")
    rows = [{"seed": 1000, "iterations_to_100": 2, "final_score": 100.0, "iterations_run": 2,
             "wall_s": 5.0}]
    out = tmp_path / "runs"
    _done_sweeps(out, rows, None, command="a2l experiment sweep --seeds 1000", commit="f" * 40,
                 short="fffffff", dirty=False, started="2026-12-03 08:00 UTC", wall_s=5.0,
                 workers=1)
    assert run_results("full", out=out, root=root, run=False)["dirty"] is False
    assert git_state(root)["dirty"]  # README's block and docs/results/ changed ...
    again = run_results("full", out=out, root=root, run=False)
    assert again["dirty"] is False  # ... but only by a2l results
    assert run_results("quick", out=out, root=root, run=False)["dirty"] is False
    (root / "README.md").write_text((root / "README.md").read_text() + "more\n")
    assert run_results("full", out=out, root=root, run=False)["dirty"] is True


def test_a_run_another_process_finished_meanwhile_is_not_made_again(tmp_path: Path,
                                                                     monkeypatch) -> None:
    """Runs of one table made by two processes into one ``--out`` (a long run beside the
    rest): the runner's to-do list is read at its start, and a run whose record appears
    later is skipped, not resumed over its finished record."""
    from a2l.results import run as runmod

    root = tmp_path / "repo"
    _empty_repo(root)
    out = tmp_path / "runs"
    robots = next(e for e in ENTRIES if e.name == "robots")
    keys = [r.key for r in robots.runs["full"]]
    made = []

    def make_run(entry, run, base, workers, state):
        made.append(run.key)
        if len(made) == 1:  # the other process finishes the table's last run meanwhile
            done = base / entry.name / f"{keys[-1]}.done.json"
            done.parent.mkdir(parents=True, exist_ok=True)
            done.write_text("{}")
        return {"wall_s": 0.0}

    monkeypatch.setattr(runmod, "_make_run", make_run)
    result = run_results("full", out=out, root=root, only=["robots"], quiet=True)
    assert made == keys[:-1]
    assert result["missing"] == ["robots"]  # the fake runs wrote no record of their own


def test_a_table_without_runs_in_a_profile_is_not_part_of_it(tmp_path: Path) -> None:
    """The PR2's push run (hours) has no quick form: the quick profile neither makes nor
    misses its table; the full profile misses it until its run is done."""
    root = tmp_path / "repo"
    _empty_repo(root)
    pr2 = next(e for e in ENTRIES if e.name == "robots-pr2")
    assert pr2.runs["quick"] == [] and len(pr2.runs["full"]) == 1
    quick = run_results("quick", out=tmp_path / "q", root=root, run=False)
    assert "robots-pr2" not in quick["missing"]
    assert not any(Path(p).stem == "robots-pr2" for p in quick["pages"])
    # asked for by name, it is an error, not a silent nothing
    with pytest.raises(ValueError, match=r"^only: robots-pr2: no runs in the quick profile"):
        run_results("quick", out=tmp_path / "q", root=root, only=["robots-pr2"], run=False)
    full = run_results("full", out=tmp_path / "f", root=root, only=["robots-pr2"], run=False)
    assert full["pages"] == [] and full["missing"] == ["robots-pr2"]
