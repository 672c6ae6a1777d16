"""Run directories: ``runs/<name>-<timestamp>/`` with config, metrics, plots, checkpoints.

Everything is written atomically (a temporary file in the same directory, then a rename),
so an interrupted run never leaves a half-written file behind, and nothing already saved is
lost.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import os
import shlex
import shutil
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from a2l.atomic import atomic_write_text

__all__ = [
    "command_line",
    "latest_checkpoint",
    "make_run_dir",
    "read_json",
    "save_checkpoint",
    "write_json",
]

CHECKPOINTS = "checkpoints"


def make_run_dir(name: str, out: str | os.PathLike[str] | None = None) -> Path:
    """Create the run directory: `out` if given, else ``runs/<name>-<YYYYmmdd-HHMMSS>``."""
    if out is None:
        stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
        out = Path("runs") / f"{name}-{stamp}"
    path = Path(out)
    path.mkdir(parents=True, exist_ok=True)
    return path


def write_json(path: str | os.PathLike[str], obj: Any) -> None:
    """Write `obj` as indented JSON, atomically."""
    atomic_write_text(path, json.dumps(obj, indent=2, sort_keys=False, default=_json_default))


def read_json(path: str | os.PathLike[str]) -> Any:
    """Read a JSON file; a malformed one raises ``ValueError`` naming it."""
    try:
        return json.loads(Path(path).read_text())
    except json.JSONDecodeError as exc:
        raise ValueError(f"malformed JSON in '{path}': {exc}") from exc


def _json_default(o: Any) -> Any:
    import numpy as np

    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON-serializable: {type(o).__name__}")


def save_checkpoint(run_dir: str | os.PathLike[str], iteration: int, state: dict[str, Any],
                    frames: dict[str, pd.DataFrame]) -> Path:
    """Save the state after `iteration` as ``checkpoints/iter_NNN/`` (all or nothing).

    The directory is written under a temporary name, then renamed, so a checkpoint either
    exists whole or not at all.

    Parameters
    ----------
    state : dict
        JSON-able state (``state.json``).
    frames : dict of str to DataFrame
        Tables saved as ``<name>.parquet``.
    """
    root = Path(run_dir) / CHECKPOINTS
    root.mkdir(parents=True, exist_ok=True)
    final = root / f"iter_{iteration:03d}"
    tmp = Path(tempfile.mkdtemp(dir=root, prefix=f".iter_{iteration:03d}."))
    try:
        for name, df in frames.items():
            df.to_parquet(tmp / f"{name}.parquet", index=False)
        (tmp / "state.json").write_text(json.dumps(state, indent=1, default=_json_default))
        if final.exists():
            shutil.rmtree(final)
        os.replace(tmp, final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return final


def latest_checkpoint(run_dir: str | os.PathLike[str]
                      ) -> tuple[int, dict[str, Any], dict[str, pd.DataFrame]] | None:
    """The newest complete checkpoint: (iteration, state, frames), or None."""
    root = Path(run_dir) / CHECKPOINTS
    if not root.is_dir():
        return None
    done = sorted(p for p in root.glob("iter_*") if (p / "state.json").is_file())
    if not done:
        return None
    last = done[-1]
    state = read_json(last / "state.json")
    frames = {p.stem: pd.read_parquet(p) for p in last.glob("*.parquet")}
    return int(last.name.split("_")[1]), state, frames


def command_line(words: Sequence[Any], config: Any, skip: Sequence[str] = (),
                 prefix: str = "") -> str:
    """The command that reproduces a run (kept in its ``config.json``): `words`, then
    ``--<prefix>field VALUE`` for every field of the dataclass `config` (None: none) but
    `skip` (VALUE as JSON where it is not a plain string), a field that is a dataclass
    itself (a part) as ``--<prefix>field.sub VALUE`` per field of it: the options ``a2l``
    makes of the fields. Every field is given, so the command does not depend on the
    defaults of the version that reads it."""
    return shlex.join([str(w) for w in words] + _options(config, skip, prefix))


def _options(config: Any, skip: Sequence[str], prefix: str) -> list[str]:
    out: list[str] = []
    for f in dataclasses.fields(config) if config is not None else ():
        if not f.init or f.name in skip:
            continue
        value = getattr(config, f.name)
        if dataclasses.is_dataclass(value):
            out += _options(value, (), f"{prefix}{f.name}.")
            continue
        text = value if isinstance(value, str) else json.dumps(
            list(value) if isinstance(value, tuple) else value)
        out += [f"--{prefix}{f.name}", text]
    return out
