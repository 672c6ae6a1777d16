"""Demonstrations: end-effector trajectories, their frame and high-level states, and files.

One schema for CSV and Parquet (the same columns in both): one row per
sample, several demonstrations per file.

========  ========  ==================================================================
column    type      meaning
========  ========  ==================================================================
demo      int       demonstration index (rows of one demonstration are contiguous)
t         float     time in seconds, strictly increasing within a demonstration
x, y      float     position in `frame` (the target, usually the object, at the origin)
z         float     optional: present for 3-D demonstrations, absent for 2-D ones
frame     str       name of the frame the positions are expressed in (one per demo)
states    str       JSON object of the high-level states the demonstration was given
                    under, e.g. ``{"light": "on"}`` (one per demo; ``{}`` if none)
========  ========  ==================================================================
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from a2l.atomic import atomic_write_bytes

__all__ = ["COLUMNS", "Demonstration", "load_demonstrations", "save_demonstrations"]

#: The schema's columns, in file order (``z`` only for 3-D demonstrations).
COLUMNS = ("demo", "t", "x", "y", "z", "frame", "states")
_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Demonstration:
    """One demonstrated trajectory.

    Parameters
    ----------
    positions : array (N, d), d in {2, 3}
        Positions in `frame`, the target at the end.
    times : array (N,)
        Strictly increasing times (s).
    frame : str
        The frame the positions are expressed in (e.g. ``"object"``).
    states : dict of str to str
        The high-level states the demonstration was given under.
    """

    positions: np.ndarray
    times: np.ndarray
    frame: str = "object"
    states: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        p = np.asarray(self.positions, dtype=float)
        t = np.asarray(self.times, dtype=float)
        if p.ndim != 2 or p.shape[1] not in (2, 3):
            raise ValueError(f"positions must have shape (N, 2) or (N, 3), got {p.shape}")
        if p.shape[0] < 2:
            raise ValueError(f"a demonstration needs at least 2 samples, got {p.shape[0]}")
        if t.shape != (p.shape[0],):
            raise ValueError(f"times must have shape ({p.shape[0]},), got {t.shape}")
        if not (np.all(np.isfinite(p)) and np.all(np.isfinite(t))):
            raise ValueError("positions or times have non-finite values")
        if np.any(np.diff(t) <= 0):
            raise ValueError("times must be strictly increasing")
        if not isinstance(self.frame, str) or not self.frame:
            raise ValueError("frame must be a non-empty string")
        states = dict(self.states)
        for k, v in states.items():
            if not (isinstance(k, str) and isinstance(v, str)):
                raise ValueError(f"states must map str to str, got {k!r}: {v!r}")
        p.setflags(write=False)
        t.setflags(write=False)
        object.__setattr__(self, "positions", p)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "states", states)

    @property
    def dim(self) -> int:
        """Dimension d of the positions."""
        return int(self.positions.shape[1])

    @property
    def duration(self) -> float:
        """``times[-1] - times[0]`` (s)."""
        return float(self.times[-1] - self.times[0])

    def arc_length(self) -> np.ndarray:
        """Cumulative path length at each sample, shape (N,), starting at 0."""
        seg = np.linalg.norm(np.diff(self.positions, axis=0), axis=1)
        return np.concatenate([[0.0], np.cumsum(seg)])

    def resample(self, n: int, by: str = "time") -> Demonstration:
        """The demonstration linearly resampled at `n` samples.

        Parameters
        ----------
        n : int
            Number of samples (>= 2).
        by : {"time", "arclength"}
            Equal steps in time, or equal steps in path length (times interpolated too).
        """
        if n < 2:
            raise ValueError(f"n must be >= 2, got {n}")
        if by == "time":
            base = self.times
        elif by == "arclength":
            base = self.arc_length()
            if base[-1] <= 0:
                raise ValueError("cannot resample by arc length: the path has no length")
            keep = np.concatenate([[True], np.diff(base) > 0])   # drop repeated positions
            base = base[keep]
            pos, times = self.positions[keep], self.times[keep]
            s = np.linspace(base[0], base[-1], n)
            new_t = np.interp(s, base, times)
            new_p = np.column_stack([np.interp(s, base, pos[:, k]) for k in range(self.dim)])
            return Demonstration(new_p, new_t, self.frame, self.states)
        else:
            raise ValueError(f"by must be 'time' or 'arclength', got {by!r}")
        s = np.linspace(base[0], base[-1], n)
        new_p = np.column_stack([np.interp(s, base, self.positions[:, k])
                                 for k in range(self.dim)])
        return Demonstration(new_p, s, self.frame, self.states)

    def to_frame(self, demo: int = 0) -> pd.DataFrame:
        """The rows of this demonstration in the file schema (see the module docstring)."""
        data: dict[str, object] = {"demo": np.full(len(self.times), demo, dtype=np.int64),
                                   "t": self.times}
        for k in range(self.dim):
            data[_AXES[k]] = self.positions[:, k]
        data["frame"] = self.frame
        data["states"] = json.dumps(self.states, sort_keys=True)
        return pd.DataFrame(data)


def _frame_of(demos: list[Demonstration]) -> pd.DataFrame:
    if not demos:
        raise ValueError("no demonstration to save")
    if len({d.dim for d in demos}) != 1:
        raise ValueError("all demonstrations in one file must have the same dimension")
    return pd.concat([d.to_frame(i) for i, d in enumerate(demos)], ignore_index=True)


def _format(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return "csv"
    if suffix in (".parquet", ".pq"):
        return "parquet"
    raise ValueError(f"'{path}': unknown demonstration file type '{suffix}' "
                     "(use .csv or .parquet)")


def save_demonstrations(path: str | os.PathLike[str],
                        demos: Demonstration | list[Demonstration]) -> Path:
    """Write demonstrations to a CSV or Parquet file (by extension), atomically."""
    path = Path(path)
    fmt = _format(path)
    frame = _frame_of([demos] if isinstance(demos, Demonstration) else list(demos))
    if fmt == "csv":
        data = frame.to_csv(index=False, float_format="%.17g").encode()
    else:
        import io

        buf = io.BytesIO()
        frame.to_parquet(buf, index=False)
        data = buf.getvalue()
    atomic_write_bytes(path, data)
    return path


def load_demonstrations(path: str | os.PathLike[str]) -> list[Demonstration]:
    """Read the demonstrations of a CSV or Parquet file written in the schema above.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        Naming the file and the problem: unknown type, unreadable content, a missing column,
        a non-numeric or non-finite value, times not increasing, a demonstration whose frame
        or states change between rows, malformed states JSON.
    """
    path = Path(path)
    fmt = _format(path)
    if not path.is_file():
        raise FileNotFoundError(f"demonstration file '{path}' does not exist")
    try:
        frame = pd.read_csv(path) if fmt == "csv" else pd.read_parquet(path)
    except Exception as exc:  # pandas/pyarrow raise many types for unreadable files
        raise ValueError(f"'{path}': cannot read as {fmt}: {exc}") from exc
    missing = [c for c in ("demo", "t", "x", "y", "frame", "states") if c not in frame.columns]
    if missing:
        raise ValueError(f"'{path}': missing column(s) {missing} (schema: {list(COLUMNS)})")
    if frame.empty:
        raise ValueError(f"'{path}': no rows")
    axes = [a for a in _AXES if a in frame.columns]
    for col in ["demo", "t", *axes]:
        if not pd.api.types.is_numeric_dtype(frame[col]):
            raise ValueError(f"'{path}': column '{col}' is not numeric")
    demos = []
    for key, rows in frame.groupby("demo", sort=False):
        where = f"'{path}', demo {key}"
        for col in ("frame", "states"):
            if rows[col].nunique(dropna=False) != 1:
                raise ValueError(f"{where}: column '{col}' changes within the demonstration")
        try:
            states = json.loads(str(rows["states"].iloc[0]))
        except json.JSONDecodeError as exc:
            raise ValueError(f"{where}: 'states' is not valid JSON: {exc}") from exc
        if not isinstance(states, dict):
            raise ValueError(f"{where}: 'states' must be a JSON object")
        try:
            demos.append(Demonstration(rows[axes].to_numpy(dtype=float),
                                       rows["t"].to_numpy(dtype=float),
                                       str(rows["frame"].iloc[0]),
                                       {str(k): str(v) for k, v in states.items()}))
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from exc
    return demos
