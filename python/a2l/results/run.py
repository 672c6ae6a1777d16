"""``a2l results``: run the named experiments on the current commit, write ``docs/results/``
and copy its tables into the README and the docs' marked blocks.

Each run of an entry (:mod:`a2l.results.catalog`) is an ``a2l`` command in a child process,
writing ``<out>/<entry>/<key>/``; when it ends, ``<key>.done.json`` records its command,
commit, date and wall time. A run with that record is not made again, so an interrupted
``full`` profile continues where it stopped (an interrupted push run continues from its last
iteration). Then every entry with all its runs done gets ``docs/results/<name>.md``: its
table inside a marked block (the source the README's block copies), the provenance of each
run (command, commit, clean or dirty tree, date, wall time), the machine and its figures.
"""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from a2l.atomic import atomic_write_text
from a2l.errors import ConfigError
from a2l.progress import ProgressBars
from a2l.results.blocks import block, fill_blocks, pages_with_blocks, read_blocks
from a2l.results.catalog import PROFILES, Entry, Run, entries
from a2l.results.provenance import git_state, machine, utc_now, utc_seconds
from a2l.rundir import read_json, write_json

__all__ = ["PAGES", "copy_blocks", "pages_dir", "run_results", "sources", "write_entry"]

#: Where each profile's pages go, under ``docs/results/``: the full profile's are the
#: published ones (the README and the docs copy their tables); the quick profile's, a check
#: of the pipeline, go to their own folder (ignored by git) and are copied nowhere, so that
#: they never replace a full-profile page.
PAGES = {"full": "", "quick": "quick"}


def _pages_rel(profile: str) -> str:
    """The folder of `profile`'s pages, relative to the repository (:data:`PAGES`)."""
    return "/".join(part for part in ("docs", "results", PAGES[profile]) if part)


def pages_dir(root: Path, profile: str) -> Path:
    """The folder of `profile`'s pages in repository `root` (:data:`PAGES`)."""
    return Path(root) / _pages_rel(profile)


def _up(profile: str) -> str:
    """The relative path from `profile`'s pages to ``docs/``."""
    return "../" * _pages_rel(profile).count("/")


def _command(run: Run, run_dir: Path, workers: int) -> list[str]:
    """The ``a2l`` words of `run` into `run_dir` (``--resume`` when it was started)."""
    if run.resume and (run_dir / "config.json").is_file():
        return ["experiment", "push", "--resume", str(run_dir), "--workers", str(workers),
                "--quiet"]
    return [*run.args, "--out", str(run_dir), "--workers", str(workers)]


def _done_path(root: Path, entry: Entry, run: Run) -> Path:
    return root / entry.name / f"{run.key}.done.json"


def _make_run(entry: Entry, run: Run, root: Path, workers: int, state: dict[str, Any]
              ) -> dict[str, Any]:
    """Make one run in a child process (its output in ``<key>.log``); its record."""
    run_dir = root / entry.name / run.key
    run_dir.parent.mkdir(parents=True, exist_ok=True)
    words = _command(run, run_dir, workers)
    log = root / entry.name / f"{run.key}.log"
    resumed = run_dir.is_dir() and any(run_dir.iterdir())  # an earlier part's work
    t0 = time.perf_counter()
    started, load = utc_now(), os.getloadavg()[0]
    with open(log, "w") as f:
        proc = subprocess.run([sys.executable, "-m", "a2l.cli", *words], stdout=f,
                              stderr=subprocess.STDOUT, check=False)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        tail = "\n".join(log.read_text().splitlines()[-15:])
        raise RuntimeError(f"results {entry.name}/{run.key}: `a2l {shlex.join(words)}` "
                           f"exited with {proc.returncode}; the end of {log}:\n{tail}")
    record = {"command": shlex.join(["a2l", *run.args, "--out", f"DIR/{run.key}",
                                     "--workers", str(workers)]),
              "commit": state["commit"], "short": state["short"], "dirty": state["dirty"],
              "started": started, "load": load, "wall_s": wall, "workers": workers,
              "resumed": resumed, "seed_use": _seed_use(run_dir)}
    write_json(_done_path(root, entry, run), record)
    return record


def _tree_state(root: Path, docs: Path) -> dict[str, Any]:
    """:func:`git_state` of `root`, not counting what ``a2l results`` writes itself: the
    files under `docs` and, in the pages with blocks, the blocks' contents (a page changed
    only there is as committed)."""
    state = git_state(root)
    rel = str(docs.resolve().relative_to(root.resolve()))
    pages = {str(p.resolve().relative_to(root.resolve())) for p in pages_with_blocks(root, rel)}

    def own(path: str) -> bool:
        if path.startswith(rel + "/") or path == rel + "/":
            return True
        if path not in pages:
            return False
        shown = subprocess.run(["git", "-C", str(root), "show", f"HEAD:{path}"],
                               capture_output=True, text=True, check=False)
        if shown.returncode != 0:
            return False
        strip = {name: "" for name in read_blocks((root / path).read_text())}
        try:
            return fill_blocks(shown.stdout, {**strip, **{
                n: "" for n in read_blocks(shown.stdout)}}) == fill_blocks(
                (root / path).read_text(), strip)
        except (KeyError, ValueError):
            return False

    changed = [c for c in state["changed"] if not own(c)]
    return {**state, "changed": changed, "dirty": state["commit"] is None or bool(changed)}


def _seed_use(run_dir: Path) -> Any:
    cfg = run_dir / "config.json"
    return read_json(cfg).get("seed_use") if cfg.is_file() else None


def seeds_caption(seeds: list[dict[str, Any]]) -> str:
    """The seeds of a page's runs (their ``seed_use`` records) for its caption: one mention per
    use, its distinct ranges in run order (the runs of a side-by-side table share theirs),
    e.g. ``"evaluation seeds 1000, 1001, 1002"``; ``"not recorded"`` without any."""
    by_use: dict[str, dict[str, None]] = {}
    for s in seeds:
        by_use.setdefault(s["use"], {})[str(s["seeds"])] = None
    return "; ".join(f"{use} seeds {', '.join(ranges)}" for use, ranges in by_use.items()
                     ) or "not recorded"


def write_entry(entry: Entry, profile: str, root: Path, docs: Path, mach: str) -> Path:
    """Write ``docs/<name>.md`` (and its figures) from the finished runs under `root`."""
    runs = entry.runs[profile]
    records = [read_json(_done_path(root, entry, r)) for r in runs]
    run_dirs = [root / entry.name / r.key for r in runs]
    table = entry.tabulate(run_dirs)
    commits = sorted({(r["short"], r["dirty"]) for r in records})
    where = ", ".join(f"{c}{' (dirty tree)' if d else ''}" for c, d in commits)
    dates = sorted(r["started"] for r in records)
    wall = sum(r["wall_s"] for r in records)
    parts = [r.key for r, rec, d in zip(runs, records, run_dirs, strict=True)
             if _resumed(rec, d)]
    if parts:
        wall_text = (f"{wall:.0f} s wall (for {', '.join(parts)}: the last part, "
                     "resumed from an earlier one's work)")
    else:
        wall_text = f"{wall:.0f} s wall"
    seeds = [r["seed_use"] for r in records if r.get("seed_use")]
    seed_text = seeds_caption(seeds)
    body = (f"{table}\n\n*Generated by `a2l results --profile {profile}` at commit {where}, "
            f"{dates[0][:10]}; {seed_text}; {wall_text}; commands and machine: "
            f"{_pages_rel(profile)}/{entry.name}.md.*\n")
    fig_dir = docs / entry.name
    figures = []
    for rel in entry.figures:
        src = run_dirs[0] / rel
        if src.is_file():
            fig_dir.mkdir(parents=True, exist_ok=True)
            dst = fig_dir / Path(rel).name
            shutil.copyfile(src, dst)
            figures.append(f"![{Path(rel).stem}]({entry.name}/{dst.name})")
    lines = [f"# {entry.title}", "",
             "Written by `a2l results`; do not edit (the README and the docs copy the block "
             "below, and a test compares them).", "", block(entry.name, body), "",
             "| run | command | commit | started | load at start | wall (s) | seeds |",
             "|---|---|---|---|---|---|---|"]
    for run, rec in zip(runs, records, strict=True):
        s = rec.get("seed_use") or {}
        lines.append(f"| {run.key} | `{rec['command']}` | {rec['short']}"
                     f"{' (dirty tree)' if rec['dirty'] else ''} | {rec['started']} | "
                     f"{_load(rec)} | {rec['wall_s']:.0f}"
                     f"{' (last part)' if run.key in parts else ''} | "
                     f"{s.get('use', '?')} {s.get('seeds', '')} |")
    lines += ["", f"Machine: {mach}. Load at start: the 1-minute load average as the run "
              "started (above the number of cores, other jobs shared them: wall times are "
              "upper bounds).", "",
              f"Seeds: see [seeds.md]({_up(profile)}seeds.md); `DIR` is the run's output "
              "directory.", ""]
    lines += [f"{f}\n" for f in figures]
    if entry.details is not None:
        lines += entry.details(run_dirs, fig_dir)
    page = docs / f"{entry.name}.md"
    atomic_write_text(page, "\n".join(lines))
    return page


def _resumed(rec: dict[str, Any], run_dir: Path) -> bool:
    """Whether the recorded part of a run resumed the work of an earlier, interrupted part
    (its wall time is then the last part's). Records written before the runner said so
    are judged by the run directory: a file in it older than the record's start (a
    minute's margin: ``started`` is to the minute) was an earlier part's."""
    if "resumed" in rec:
        return bool(rec["resumed"])
    start = utc_seconds(rec["started"])
    return any(p.stat().st_mtime < start - 60 for p in run_dir.rglob("*") if p.is_file())


def _load(rec: dict[str, Any]) -> str:
    return "not recorded" if rec.get("load") is None else f"{rec['load']:.1f}"


def sources(docs: Path) -> dict[str, str]:
    """Every generated block of ``docs/results/*.md``: name -> content."""
    out: dict[str, str] = {}
    for page in sorted(Path(docs).glob("*.md")):
        out.update(read_blocks(page.read_text()))
    return out


def copy_blocks(root: Path, docs: Path) -> list[Path]:
    """Copy every generated block into the pages that include it; the pages changed."""
    src = sources(docs)
    changed = []
    for page in pages_with_blocks(root, str(Path(docs).resolve().relative_to(
            Path(root).resolve()))):
        text = page.read_text()
        new = fill_blocks(text, src)
        if new != text:
            atomic_write_text(page, new)
            changed.append(page)
    return changed


def run_results(profile: str = "quick", out: str | os.PathLike[str] | None = None,
                root: str | os.PathLike[str] = ".", only: Sequence[str] | None = None,
                workers: int = 2, run: bool = True, quiet: bool = False) -> dict[str, Any]:
    """Run the entries of `profile` (those not done yet), write ``docs/results/`` and copy
    the blocks. A run whose record appears while earlier runs are made (another process
    made it into the same `out`) is not made again.

    Parameters
    ----------
    profile : {"quick", "full"}
    out : path, optional
        Where the runs go (default ``<root>/runs/results-<profile>``); rerunning with the
        same one continues.
    root : path
        The repository (its ``docs/results/``, README and docs are written).
    only : sequence of str, optional
        Entry names (default: all). A name whose table has no runs in `profile` is an error.
    workers : int
        Worker processes of each experiment.
    run : bool
        Make the runs; False: only rewrite the pages from the runs already done.
    quiet : bool
        No progress bar.

    Returns
    -------
    dict
        ``{"pages": [...], "missing": [entries with runs not done], "copied": [...],
        "dirty": bool}``.
    """
    if profile not in PROFILES:
        raise ValueError(f"profile: unknown {profile!r}; choose one of {PROFILES}")
    if workers < 1:
        raise ValueError(f"workers: must be >= 1, got {workers}")
    root = Path(root)
    base = Path(out) if out is not None else root / "runs" / f"results-{profile}"
    docs = pages_dir(root, profile)
    picked = entries(only)
    chosen = [e for e in picked if e.runs[profile]]  # a table of this profile
    none = [e.name for e in picked if not e.runs[profile]]
    if only is not None and none:
        raise ConfigError("only", f"{', '.join(none)}: no runs in the {profile} profile "
                          f"(tables of {', '.join(p for p in PROFILES if p != profile)} only)")
    state = _tree_state(root, pages_dir(root, "full"))
    todo = [(e, r) for e in chosen for r in e.runs[profile]
            if not _done_path(base, e, r).is_file()]
    if run and todo and state["dirty"]:
        print(f"a2l results: the tree is not clean ({', '.join(state['changed'][:5])}"
              f"{' ...' if len(state['changed']) > 5 else ''}): the tables will say "
              "'dirty tree'", file=sys.stderr)
    if run:
        with ProgressBars(quiet) as bars:
            for i, (entry, r) in enumerate(todo):
                bars.update(f"results ({profile})", i, len(todo),
                            f"{entry.name}/{r.key}: {' '.join(r.args[:2])}")
                if _done_path(base, entry, r).is_file():  # finished meanwhile by another
                    bars.print(f"{entry.name}/{r.key}: done meanwhile, not made again")
                    continue
                rec = _make_run(entry, r, base, workers, state)
                bars.print(f"{entry.name}/{r.key}: {rec['wall_s']:.0f} s")
            bars.update(f"results ({profile})", len(todo), len(todo), "done")
    mach = machine()
    pages, missing = [], []
    for entry in chosen:
        if all(_done_path(base, entry, r).is_file() for r in entry.runs[profile]):
            pages.append(write_entry(entry, profile, base, docs, mach))
        else:
            missing.append(entry.name)
    if pages:
        _write_index(docs, profile)
    copied = copy_blocks(root, docs) if profile == "full" else []
    return {"pages": [str(p) for p in pages], "missing": missing,
            "copied": [str(p) for p in copied], "dirty": state["dirty"]}


def _write_index(docs: Path, profile: str = "full") -> None:
    """``README.md`` of `profile`'s pages: the tables there and where they come from."""
    shown = ("The README and the docs include these tables between `<!-- results:NAME -->` "
             "markers; `a2l results` copies them there and `tests/python/test_results.py` "
             "fails when a copy differs." if profile == "full" else
             "These are the quick profile's pages (fewer seeds and trials), a check of the "
             "pipeline: nothing copies them; the published tables are the full profile's, "
             "one folder up.")
    lines = ["# Generated results" + ("" if profile == "full" else " (quick profile)"), "",
             f"Every table here is written by `a2l results --profile {profile}` (`make "
             f"results PROFILE={profile}`): it runs the experiments on the current commit, on "
             f"evaluation seeds ([seeds.md]({_up(profile)}seeds.md)), and writes one page per "
             "table with the commands, the commit, the machine, the date and the wall time. "
             + shown, "",
             "| table | what |", "|---|---|"]
    for page in sorted(docs.glob("*.md")):
        if page.name == "README.md":
            continue
        title = page.read_text().split("\n", 1)[0].lstrip("# ")
        lines.append(f"| [{page.stem}]({page.name}) | {title} |")
    atomic_write_text(docs / "README.md", "\n".join(lines) + "\n")
