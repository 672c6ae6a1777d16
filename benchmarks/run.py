"""Run the benchmarks and rewrite BENCHMARKS.md.

Every ``benchmarks/bench_<area>.py`` is a section: it defines ``TITLE`` (str) and
``run() -> str`` returning Markdown (tables of figures measured in this run). Each section's
output is kept in ``benchmarks/sections/<area>.md`` so that ``--only AREA`` reruns one section
and keeps the others; BENCHMARKS.md is assembled from all of them under a header naming the
machine and the date. C++ benchmark binaries are found in ``$A2L_BENCH_BIN`` (the CMake build
tree, set by ``make bench``).

Usage: ``python benchmarks/run.py [--only AREA ...] [--out BENCHMARKS.md]``
"""

from __future__ import annotations

import argparse
import datetime as _dt
import hashlib
import importlib.metadata
import importlib.util
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from a2l.results.provenance import machine as machine_description

HERE = Path(__file__).resolve().parent
SECTIONS = HERE / "sections"


#: What run.py writes itself: not part of what was measured, so not "uncommitted changes".
OUTPUTS = ("benchmarks/sections", "BENCHMARKS.md")


def _git(cwd: Path, *args: str) -> str:
    return subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True,
                          check=True).stdout


def git_commit(cwd: Path = HERE) -> str:
    """The commit the measured code is, as a section's stamp.

    ``commit abc1234`` when the work tree (but run.py's own outputs, :data:`OUTPUTS`) is
    clean; otherwise ``uncommitted changes on top of abc1234 (diff sha256 0123abcd4567)``,
    the hash covering the diff against HEAD and the untracked files' names and contents, so
    two sections stamped alike were measured on the same tree. ``commit unknown`` outside
    a git checkout. `cwd`: any directory of the checkout.
    """
    try:
        root = Path(_git(cwd, "rev-parse", "--show-toplevel").strip())
        head = _git(root, "rev-parse", "--short", "HEAD").strip()
        exclude = [f":(exclude){p}" for p in OUTPUTS]
        diff = _git(root, "diff", "HEAD", "--binary", "--", ".", *exclude)
        untracked = _git(root, "ls-files", "--others", "--exclude-standard", "-z", "--", ".",
                         *exclude).split("\0")
    except (OSError, subprocess.CalledProcessError):
        return "commit unknown"
    untracked = sorted(u for u in untracked if u)
    if not diff and not untracked:
        return f"commit {head}"
    h = hashlib.sha256(diff.encode())
    for name in untracked:
        h.update(name.encode() + b"\0")
        try:
            h.update((root / name).read_bytes())
        except OSError:
            pass
    return f"uncommitted changes on top of {head} (diff sha256 {h.hexdigest()[:12]})"


def discover() -> dict[str, Path]:
    return {p.stem.removeprefix("bench_"): p for p in sorted(HERE.glob("bench_*.py"))}


def package_versions(names: tuple[str, ...]) -> str:
    """``name version`` of each installed distribution (``not installed`` if absent)."""
    out = []
    for n in names:
        try:
            out.append(f"{n} {importlib.metadata.version(n)}")
        except importlib.metadata.PackageNotFoundError:
            out.append(f"{n} not installed")
    return ", ".join(out)


def run_section(name: str, path: Path) -> str:
    """Run one section; its text under a stamp of date, machine, code and package versions.

    A section may define ``PACKAGES`` (tuple of distribution names): their installed
    versions are stamped, and ``package_versions`` gives them to its prose.
    """
    spec = importlib.util.spec_from_file_location(f"a2l_bench_{name}", path)
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    print(f"[bench] {name}: {mod.TITLE}", flush=True)
    code = git_commit()  # the code measured: stamped before the run, not after
    stamp = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    body = mod.run().strip()
    packages = getattr(mod, "PACKAGES", ())
    versions = f"; {package_versions(packages)}" if packages else ""
    return (
        f"## {mod.TITLE}\n\n_Measured {stamp} on {machine_description()}, "
        f"{code}{versions}._\n\n{body}\n"
    )


def atomic_write(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def assemble(sections: dict[str, Path], directory: Path = SECTIONS) -> str:
    """BENCHMARKS.md's text: a header, then each area's kept section
    (``<directory>/<area>.md``) in the order of `sections`, those never run left out.

    BENCHMARKS.md is only ever this: an edit made to it and not to its section file is lost
    at the next ``make bench`` (``tests/python/test_bench_provenance.py`` checks the two agree).
    """
    parts = [
        "# a2l benchmarks\n",
        "Written by `make bench` (`benchmarks/run.py`), but for the sections that say they were "
        "assembled by hand from a benchmark's own runs (each names the command that writes it "
        "whole); every figure below was measured on the "
        "machine named in its section, and ratios compare figures measured in the same run. "
        "This machine is shared and noisy: read medians and tails, not single runs.\n",
    ]
    for name in sections:
        f = directory / f"{name}.md"
        if f.is_file():
            parts.append(f.read_text())
    return "\n".join(parts)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", default=None, help="areas to rerun")
    parser.add_argument("--out", default=str(HERE.parent / "BENCHMARKS.md"))
    args = parser.parse_args()
    sections = discover()
    todo = sections if args.only is None else {k: sections[k] for k in args.only}
    unknown = set(args.only or []) - set(sections)
    if unknown:
        print(f"unknown benchmark areas: {sorted(unknown)}; known: {sorted(sections)}")
        return 2
    SECTIONS.mkdir(exist_ok=True)
    for name, path in todo.items():
        atomic_write(SECTIONS / f"{name}.md", run_section(name, path))
    atomic_write(Path(args.out), assemble(sections))
    print(f"[bench] wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
