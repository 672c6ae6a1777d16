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
import importlib.util
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
SECTIONS = HERE / "sections"


def machine_description() -> str:
    """One line naming the CPU, cores, memory, OS and Python of this machine."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal"):
                mem = f", {int(line.split()[1]) / 2**20:.0f} GiB RAM"
                break
    except OSError:
        pass
    return (
        f"{cpu}, {os.cpu_count()} cores{mem}; {platform.system()} {platform.release()}; "
        f"Python {platform.python_version()}"
    )


def git_commit() -> str:
    try:
        return subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=HERE, capture_output=True, text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def discover() -> dict[str, Path]:
    return {p.stem.removeprefix("bench_"): p for p in sorted(HERE.glob("bench_*.py"))}


def run_section(name: str, path: Path) -> str:
    spec = importlib.util.spec_from_file_location(f"a2l_bench_{name}", path)
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    print(f"[bench] {name}: {mod.TITLE}", flush=True)
    body = mod.run().strip()
    stamp = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    return (
        f"## {mod.TITLE}\n\n_Measured {stamp} on {machine_description()}, "
        f"commit {git_commit()}._\n\n{body}\n"
    )


def atomic_write(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(tmp, path)


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
    parts = [
        "# a2l benchmarks\n",
        "Written by `make bench` (`benchmarks/run.py`); every figure below was measured on the "
        "machine named in its section, and ratios compare figures measured in the same run. "
        "This machine is shared and noisy: read medians and tails, not single runs.\n",
    ]
    for name in sections:
        f = SECTIONS / f"{name}.md"
        if f.is_file():
            parts.append(f.read_text())
    atomic_write(Path(args.out), "\n".join(parts))
    print(f"[bench] wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
