"""Where a result comes from: the commit (and whether the tree was clean), the machine, the
date; recorded beside every table ``a2l results`` writes."""

from __future__ import annotations

import datetime as _dt
import os
import platform
import subprocess
from pathlib import Path
from typing import Any

__all__ = ["git_state", "machine", "provenance", "utc_now", "utc_seconds"]


def git_state(root: str | os.PathLike[str] = ".") -> dict[str, Any]:
    """The commit checked out in `root` and whether its tree is clean.

    Returns
    -------
    dict
        ``{"commit": full hash or None (not a git tree), "short": 7-character hash or
        "unknown", "dirty": bool, "changed": paths changed or untracked (at most 20)}``;
        ignored files (``runs/``, build trees) do not count.
    """
    def git(*args: str) -> str:
        return subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True,
                              check=True).stdout

    try:
        commit = git("rev-parse", "HEAD").strip()
        changed = [line[3:] for line in git("status", "--porcelain").splitlines() if line]
    except (OSError, subprocess.CalledProcessError):
        return {"commit": None, "short": "unknown", "dirty": True, "changed": []}
    return {"commit": commit, "short": commit[:7], "dirty": bool(changed),
            "changed": changed[:20]}


def machine() -> str:
    """One line naming the CPU, cores, memory, OS and Python of this machine (the stamp of
    every generated results page and benchmark section)."""
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
    return (f"{cpu}, {os.cpu_count()} cores{mem}; {platform.system()} {platform.release()}; "
            f"Python {platform.python_version()}")


def utc_now() -> str:
    """The time now, UTC, to the minute (``2026-12-03 08:40 UTC``)."""
    return _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")


def utc_seconds(text: str) -> float:
    """A time written by :func:`utc_now` in seconds since the epoch."""
    return _dt.datetime.strptime(text, "%Y-%m-%d %H:%M UTC").replace(
        tzinfo=_dt.timezone.utc).timestamp()


def provenance(root: str | os.PathLike[str] = ".") -> dict[str, Any]:
    """:func:`git_state` with the machine and the date."""
    return {**git_state(root), "machine": machine(), "date": utc_now()}
