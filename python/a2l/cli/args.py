"""Shared pieces of the ``a2l`` command: the usage error and the argument checks."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from a2l.errors import ConfigError
from a2l.framework.config import FLAT_NAMES, FrameworkConfig, field_paths


class UsageError(ConfigError):
    """A bad command-line argument found after parsing (exit code 2, no traceback).

    Parameters
    ----------
    argument : str
        The argument at fault (``--resume``...).
    message : str
        What is wrong with it.
    """

    def __init__(self, argument: str, message: str) -> None:
        super().__init__(argument, message)
        self.args = (f"argument {argument}: {message}",)
        self.argument = argument

    def __str__(self) -> str:
        return str(self.args[0])


def comma_list(text: str | None) -> list[str] | None:
    """Names given as ``"a, b,c"``: stripped, empty ones dropped; None when nothing was given."""
    return [x.strip() for x in text.split(",") if x.strip()] if text else None


def check_cluster(address: str | None) -> None:
    """Fail early, as a usage error, if the Dask scheduler at `address` is unreachable."""
    if address is None:
        return
    # imported here: parsing and --help do not load this command's stack
    from a2l.parallel import Executor

    try:
        Executor(cluster=address).close()
    except ConnectionError as exc:  # the Executor's message names the address
        raise UsageError("--cluster", str(exc)) from None
    except (OSError, ValueError, TypeError) as exc:  # e.g. a malformed address
        raise UsageError("--cluster", f"cannot reach a Dask scheduler at {address!r}: "
                         f"{exc}") from None


def parse_seeds(text: str) -> list[int]:
    """Seeds from ``"0-29"``, ``"0,3,7"`` or a mix (``"0-4,9"``), in the given order.

    Raises
    ------
    UsageError
        Malformed text, a negative seed, an empty range or a seed given twice.
    """
    seeds: list[int] = []
    for part in text.split(","):
        part = part.strip()
        try:
            if "-" in part:
                lo, hi = (int(x) for x in part.split("-", 1))
                if hi < lo:
                    raise ValueError(f"empty range {part!r}")
                seeds.extend(range(lo, hi + 1))
            else:
                seeds.append(int(part))
        except ValueError as exc:
            raise UsageError("--seeds", f"expected e.g. '0-29' or '0,3,7', got {text!r} ({exc})"
                             ) from None
    if any(s < 0 for s in seeds):
        raise UsageError("--seeds", f"must be >= 0, got {text!r}")
    if len(set(seeds)) != len(seeds):
        raise UsageError("--seeds", f"a seed is given twice in {text!r}")
    return seeds


def parse_overrides(items: Sequence[str]) -> dict[str, Any]:
    """``FIELD=VALUE`` strings as FrameworkConfig fields by their dotted names
    (``directed.per_pair=20``); VALUE is read as JSON (numbers, ``true``, ``null``), else
    kept as text.

    Raises
    ------
    UsageError
        An item without ``=``, or a field FrameworkConfig does not have (the message lists
        its fields; a field of the flat form of earlier versions names its name now), or one
        the sweep sets itself (``seed``).
    """
    fields = set(field_paths(FrameworkConfig))
    out: dict[str, Any] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise UsageError("--set", f"expected FIELD=VALUE, got {item!r}")
        if name in FLAT_NAMES:
            raise UsageError("--set", f"{name!r} is renamed: it is {FLAT_NAMES[name]!r} now")
        if name not in fields:
            raise UsageError("--set", f"FrameworkConfig has no field {name!r}; its fields: "
                             f"{', '.join(field_paths(FrameworkConfig))}")
        if name == "seed":
            raise UsageError("--set", "'seed' is set by --seeds")
        try:
            out[name] = json.loads(value)
        except json.JSONDecodeError:
            out[name] = value
    return out


def check_out(out: Path | None, *run_files: str, resume: bool = False) -> None:
    """Fail early, as a usage error, when `out` is a file, or a directory that holds a run:
    one of `run_files` (glob patterns relative to it, e.g. ``metrics.json``) is there.
    `resume`: the message says how to continue the run (``--resume``)."""
    if out is None:
        return
    if out.exists() and not out.is_dir():
        raise UsageError("--out", f"'{out}' exists and is not a directory")
    if any(any(out.glob(pattern)) for pattern in run_files):
        hint = f"continue it with --resume {out}, or " if resume else ""
        raise UsageError("--out", f"'{out}' already holds a run; {hint}choose another "
                         "directory")


def check_record(path: Path, argument: str = "--record") -> None:
    """Fail early, as a usage error, unless a Rerun recording can be written at `path`
    (``.rrd``, an existing directory, ``rerun-sdk`` installed: the ``ros`` extra)."""
    if path.suffix != ".rrd":
        raise UsageError(argument, f"'{path}': a Rerun recording ends in .rrd")
    if not path.resolve().parent.is_dir():
        raise UsageError(argument, f"'{path}': its directory does not exist")
    try:
        import rerun  # noqa: F401
    except ImportError:
        raise UsageError(argument, "rerun-sdk is not installed: pip install 'a2l[ros]'"
                         ) from None
