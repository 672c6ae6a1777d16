"""Discretization of interactions: context bins, movements, effects, high-level states.

The context bins follow ``docs/bundle_format.md`` to the letter, because the C++ runtime
(``a2l::Discretizer``) bins the live context with the same formulas and must agree bin for
bin. All vectors are expressed in the robot's base frame (x forward, y left, z up).

========================  ================================================================
variable                  bin
========================  ================================================================
``distance``              d = ‖object − eef‖; clamp(floor((d − low)/(high − low)·n), 0, n−1)
``orientation``           θ = atan2(dy, dx) of (eef − object); w = 2π/n;
                          floor(((θ + π + w/2) mod 2π)/w) mod n (bin k centred on −π + k·w)
``inclination``           φ = atan2(√(dx² + dy²), dz) of (eef − object); min(floor(φ/π·n), n−1)
``move``                  signs of the end-effector step per axis, with a dead-band:
                          26 directions in 3-D, 8 in the plane
``effect``                object displacement: axis effect when the dominant axis moved more
                          than ``ratio`` × the other, else a diagonal; ``none`` below a threshold
high-level state          index of its value name
========================  ================================================================

A non-finite input (NaN, inf) gives bin ``-1`` (the runtime's *unknown context*).

The angles use the C library's ``atan2`` (through :func:`math.atan2`), the function the C++
runtime calls: numpy's vectorised ``arctan2`` may differ from it in the last bit, which is
enough to move a point lying exactly on a bin boundary into the neighbouring bin.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from a2l.data.schema import (
    EEF_COLUMNS,
    EFFECT_DISPLACEMENT_COLUMNS,
    MOVE_COLUMNS,
    OBJECT_COLUMNS,
    check_columns,
)
from a2l.skills.spec import VariableSpec

__all__ = [
    "AXIS_EFFECTS",
    "DIAGONAL_EFFECTS",
    "Discretizer",
    "DistanceBins",
    "EffectDiscretizer",
    "HighLevelState",
    "InclinationBins",
    "MovementRepertoire",
    "OrientationBins",
]

#: The 4 axis effects, in this order: object moved +y, −y, −x, +x.
AXIS_EFFECTS = ("left", "right", "close", "far")
#: The 4 diagonal effects (8-effect mode), after the axis effects.
DIAGONAL_EFFECTS = ("close_left", "close_right", "far_left", "far_right")


def _as_points(a: np.ndarray | Sequence[float], what: str) -> np.ndarray:
    """`a` as a float64 array of shape (n, 3) (a single (3,) point becomes (1, 3))."""
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{what} must have shape (n, 3) or (3,), got {np.shape(a)}")
    return arr


_atan2_ufunc = np.frompyfunc(math.atan2, 2, 1)


def _atan2(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Element-wise C-library atan2 (bit-identical to ``std::atan2`` in the runtime)."""
    return np.asarray(_atan2_ufunc(y, x), dtype=np.float64).reshape(np.shape(y))


def _relative(eef: np.ndarray, obj: np.ndarray) -> np.ndarray:
    e = _as_points(eef, "eef")
    o = _as_points(obj, "object")
    if e.shape != o.shape:
        raise ValueError(f"eef and object shapes differ: {e.shape} vs {o.shape}")
    return e - o


@dataclass(frozen=True)
class DistanceBins:
    """Equal bins of the eef→object distance over [low, high], saturating at both ends.

    Parameters
    ----------
    n_bins : int
        Number of bins (default 3, METHOD.md).
    low, high : float
        Range in metres (default [0.05, 0.20]); distances outside fall in the end bins.
    name : str
        Variable name in the dataset and the network.
    """

    n_bins: int = 3
    low: float = 0.05
    high: float = 0.20
    name: str = "distance"

    def __post_init__(self) -> None:
        if not 1 <= self.n_bins <= 1024:
            raise ValueError(f"{self.name}: n_bins must be in [1, 1024], got {self.n_bins}")
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(f"{self.name}: need finite low < high, got [{self.low}, {self.high}]")

    def bins(self, eef: np.ndarray, obj: np.ndarray) -> np.ndarray:
        """Distance bins.

        Parameters
        ----------
        eef, obj : ndarray, shape (n, 3) or (3,)
            End-effector and object positions (m).

        Returns
        -------
        ndarray of int64, shape (n,)
            Bin in [0, n_bins), or -1 where an input is not finite.
        """
        r = _relative(eef, obj)
        d = np.sqrt(r[:, 0] * r[:, 0] + r[:, 1] * r[:, 1] + r[:, 2] * r[:, 2])
        with np.errstate(invalid="ignore"):
            x = np.floor((d - self.low) / (self.high - self.low) * self.n_bins)
            b = np.clip(x, 0, self.n_bins - 1)
        out = np.full(d.shape, -1, dtype=np.int64)
        ok = np.isfinite(d)
        out[ok] = b[ok].astype(np.int64)
        return out

    def spec(self) -> VariableSpec:
        """The bundle variable of this discretization."""
        return VariableSpec(self.name, "distance", self.n_bins, low=self.low, high=self.high)


@dataclass(frozen=True)
class OrientationBins:
    """Sections of the planar angle of (eef − object), offset by half a section.

    Parameters
    ----------
    n_bins : int
        Number of sections (default 16); bin k is centred on θ = −π + k·2π/n_bins.
    name : str
        Variable name.
    """

    n_bins: int = 16
    name: str = "orientation"

    def __post_init__(self) -> None:
        if not 1 <= self.n_bins <= 1024:
            raise ValueError(f"{self.name}: n_bins must be in [1, 1024], got {self.n_bins}")

    def bins(self, eef: np.ndarray, obj: np.ndarray) -> np.ndarray:
        """Orientation bins.

        Parameters
        ----------
        eef, obj : ndarray, shape (n, 3) or (3,)
            End-effector and object positions (m).

        Returns
        -------
        ndarray of int64, shape (n,)
            Bin in [0, n_bins), or -1 where an input is not finite.
        """
        r = _relative(eef, obj)
        w = 2.0 * math.pi / self.n_bins
        theta = _atan2(r[:, 1], r[:, 0])
        with np.errstate(invalid="ignore"):
            # theta + pi + w/2 > 0, so numpy's mod equals C's fmod here.
            x = np.floor(np.mod(theta + math.pi + w / 2.0, 2.0 * math.pi) / w)
        ok = np.isfinite(r).all(axis=1)
        out = np.full(theta.shape, -1, dtype=np.int64)
        out[ok] = np.mod(x[ok].astype(np.int64), self.n_bins)
        return out

    def spec(self) -> VariableSpec:
        """The bundle variable of this discretization."""
        return VariableSpec(self.name, "orientation", self.n_bins)


@dataclass(frozen=True)
class InclinationBins:
    """Sections of the angle from vertical of (eef − object), over [0, π].

    Parameters
    ----------
    n_bins : int
        Number of sections (default 8); 0 is the end-effector straight above the object.
    name : str
        Variable name.
    """

    n_bins: int = 8
    name: str = "inclination"

    def __post_init__(self) -> None:
        if not 1 <= self.n_bins <= 1024:
            raise ValueError(f"{self.name}: n_bins must be in [1, 1024], got {self.n_bins}")

    def bins(self, eef: np.ndarray, obj: np.ndarray) -> np.ndarray:
        """Inclination bins.

        Parameters
        ----------
        eef, obj : ndarray, shape (n, 3) or (3,)
            End-effector and object positions (m).

        Returns
        -------
        ndarray of int64, shape (n,)
            Bin in [0, n_bins), or -1 where an input is not finite.
        """
        r = _relative(eef, obj)
        phi = _atan2(np.sqrt(r[:, 0] * r[:, 0] + r[:, 1] * r[:, 1]), r[:, 2])
        with np.errstate(invalid="ignore"):
            x = np.minimum(np.floor(phi / math.pi * self.n_bins), self.n_bins - 1)
        ok = np.isfinite(r).all(axis=1)
        out = np.full(phi.shape, -1, dtype=np.int64)
        out[ok] = x[ok].astype(np.int64)
        return out

    def spec(self) -> VariableSpec:
        """The bundle variable of this discretization."""
        return VariableSpec(self.name, "inclination", self.n_bins)


def _direction_label(d: Sequence[int]) -> str:
    return "".join(("+" if s > 0 else "-") + ax for s, ax in zip(d, "xyz", strict=True) if s)


def _repertoire(planar: bool) -> np.ndarray:
    signs = (1, -1, 0)
    if planar:
        dirs = [(x, y, 0) for x, y in itertools.product(signs, repeat=2)]
    else:
        dirs = list(itertools.product(signs, repeat=3))
    dirs = [d for d in dirs if any(d)]

    # Axis moves first (+x, -x, +y, -y, +z, -z), then the diagonals.
    def key(d: tuple[int, ...]) -> tuple[int, ...]:
        nz = sum(1 for s in d if s)
        return (nz, *(abs(s) == 0 for s in d), *(-s for s in d))

    return np.array(sorted(dirs, key=key), dtype=np.int64)


@dataclass(frozen=True)
class MovementRepertoire:
    """The discrete movements: sign patterns of an end-effector step.

    A step ``d`` (3,) becomes the direction ``s`` with ``s_i = sign(d_i)``, except that a
    component is 0 when ``|d_i| <= dead_band`` or ``|d_i| < relative_dead_band · max_j |d_j|``.
    The default relative dead-band tan(22.5°) makes the planar case the nearest of the 8
    directions by angle. A movement's displacement is ``step · s / ‖s‖``.

    Parameters
    ----------
    planar : bool
        8 directions in the table plane (z ignored) instead of 26 in 3-D.
    step : float
        Length of every movement (m), default 0.05.
    dead_band : float
        Absolute dead-band (m); components at or below it count as 0.
    relative_dead_band : float
        Relative dead-band in [0, 1).

    Attributes
    ----------
    directions : ndarray of int64, shape (n_moves, 3)
        Sign patterns in table order: +x, -x, +y, -y, (+z, -z,) then diagonals.
    labels : tuple of str
        Names such as ``"+x"`` or ``"-x+y"``, one per direction.
    """

    planar: bool = False
    step: float = 0.05
    dead_band: float = 1e-3
    relative_dead_band: float = math.tan(math.pi / 8)
    name: str = "move"
    directions: np.ndarray = field(init=False, repr=False, compare=False)
    labels: tuple[str, ...] = field(init=False, compare=False)

    def __post_init__(self) -> None:
        if not (self.step > 0 and math.isfinite(self.step)):
            raise ValueError(f"{self.name}: step must be a positive length, got {self.step}")
        if self.dead_band < 0:
            raise ValueError(f"{self.name}: dead_band must be >= 0, got {self.dead_band}")
        if not 0 <= self.relative_dead_band < 1:
            raise ValueError(
                f"{self.name}: relative_dead_band must be in [0, 1), got {self.relative_dead_band}"
            )
        dirs = _repertoire(self.planar)
        dirs.setflags(write=False)
        object.__setattr__(self, "directions", dirs)
        object.__setattr__(self, "labels", tuple(_direction_label(d) for d in dirs))

    @property
    def n_moves(self) -> int:
        """Number of movements (8 or 26)."""
        return len(self.labels)

    def discretize(self, displacement: np.ndarray) -> np.ndarray:
        """Movement index of each step.

        Parameters
        ----------
        displacement : ndarray, shape (n, 3) or (3,)
            End-effector displacements (or velocities).

        Returns
        -------
        ndarray of int64, shape (n,)
            Index into :attr:`directions`, or -1 where the step is inside the dead-band on
            every axis (no movement) or not finite.
        """
        d = _as_points(displacement, "displacement").copy()
        if self.planar:
            d[:, 2] = 0.0
        a = np.abs(d)
        with np.errstate(invalid="ignore"):
            amax = a.max(axis=1, keepdims=True)
            keep = (a > self.dead_band) & (a >= self.relative_dead_band * amax)
        s = np.where(keep, np.sign(d), 0).astype(np.int64)
        code = (s[:, 0] + 1) * 9 + (s[:, 1] + 1) * 3 + (s[:, 2] + 1)
        lut = np.full(27, -1, dtype=np.int64)
        dcode = (
            (self.directions[:, 0] + 1) * 9
            + (self.directions[:, 1] + 1) * 3
            + (self.directions[:, 2] + 1)
        )
        lut[dcode] = np.arange(self.n_moves)
        out = lut[code]
        out[~np.isfinite(d).all(axis=1)] = -1
        return out

    def displacement(self, index: int | np.ndarray) -> np.ndarray:
        """Displacement of movement(s) `index`.

        Returns
        -------
        ndarray of float64, shape (3,) or (n, 3)
            ``step · d / ‖d‖``.
        """
        d = self.directions[np.asarray(index)].astype(np.float64)
        return self.step * d / np.linalg.norm(d, axis=-1, keepdims=True)


@dataclass(frozen=True)
class EffectDiscretizer:
    """Effect names from object displacements in the table plane.

    With 4 effects, the dominant axis decides (``far`` = +x, ``close`` = −x, ``left`` = +y,
    ``right`` = −y). With 8, it decides only when it moved more than `ratio` × the other
    axis; otherwise the effect is the diagonal (``close_left`` …). A planar displacement
    shorter than `threshold` is no effect.

    Parameters
    ----------
    n_effects : {4, 8}
        Number of effects.
    threshold : float
        Smallest planar displacement that counts as an effect (m).
    ratio : float
        Dominance ratio for an axis effect in 8-effect mode (default 3).
    name : str
        Variable name.
    """

    n_effects: int = 4
    threshold: float = 0.01
    ratio: float = 3.0
    name: str = "effect"

    def __post_init__(self) -> None:
        if self.n_effects not in (4, 8):
            raise ValueError(f"{self.name}: n_effects must be 4 or 8, got {self.n_effects}")
        if not self.threshold >= 0:
            raise ValueError(f"{self.name}: threshold must be >= 0, got {self.threshold}")
        if not self.ratio >= 1:
            raise ValueError(f"{self.name}: ratio must be >= 1, got {self.ratio}")

    @property
    def values(self) -> tuple[str, ...]:
        """Effect names in index order."""
        return AXIS_EFFECTS if self.n_effects == 4 else AXIS_EFFECTS + DIAGONAL_EFFECTS

    def discretize(self, displacement: np.ndarray) -> np.ndarray:
        """Effect index of each object displacement.

        Parameters
        ----------
        displacement : ndarray, shape (n, 3) or (3,)
            Object displacements (m); z is ignored.

        Returns
        -------
        ndarray of int64, shape (n,)
            Index into :attr:`values`, or -1 for no effect (or a non-finite input).
        """
        d = _as_points(displacement, "displacement")
        dx, dy = d[:, 0], d[:, 1]
        ax, ay = np.abs(dx), np.abs(dy)
        x_axis = np.where(dx > 0, 3, 2)  # far / close
        y_axis = np.where(dy > 0, 0, 1)  # left / right
        out = np.where(ax >= ay, x_axis, y_axis)
        if self.n_effects == 8:
            diag = 4 + np.where(dx > 0, 2, 0) + np.where(dy > 0, 0, 1)
            axis_wins = (ax > self.ratio * ay) | (ay > self.ratio * ax)
            out = np.where(axis_wins, out, diag)
        with np.errstate(invalid="ignore"):
            moved = np.hypot(dx, dy) >= self.threshold
        return np.where(moved & np.isfinite(d[:, :2]).all(axis=1), out, -1).astype(np.int64)

    def spec(self) -> VariableSpec:
        """The bundle variable of the wanted effect."""
        return VariableSpec(self.name, "effect", len(self.values), values=self.values)


@dataclass(frozen=True)
class HighLevelState:
    """A discrete high-level state (light, gripper, colour) and its value names.

    Parameters
    ----------
    name : str
        Variable (and dataset column) name.
    values : tuple of str
        Value names in index order.
    """

    name: str
    values: tuple[str, ...]

    def __post_init__(self) -> None:
        vals = tuple(str(v) for v in self.values)
        if not vals or len(set(vals)) != len(vals):
            raise ValueError(f"{self.name}: values must be non-empty and unique, got {vals}")
        object.__setattr__(self, "values", vals)

    def discretize(self, column: Sequence[str] | np.ndarray) -> np.ndarray:
        """Value index of each entry, -1 where the value is not one of :attr:`values`.

        Returns
        -------
        ndarray of int64, shape (n,)
        """
        lut = {v: i for i, v in enumerate(self.values)}
        return np.array([lut.get(str(v), -1) for v in column], dtype=np.int64)

    def spec(self) -> VariableSpec:
        """The bundle variable of this state."""
        return VariableSpec(self.name, "high_level", len(self.values), values=self.values)


@dataclass(frozen=True)
class Discretizer:
    """Everything that turns a raw interaction dataset into discrete variables.

    Parameters
    ----------
    distance, orientation, inclination : bins or None
        Context discretizations; None leaves the variable out.
    movements : MovementRepertoire
        The movement repertoire (variable ``move``).
    effects : EffectDiscretizer
        The effect discretization (variable ``effect``).
    high_level : tuple of HighLevelState
        High-level states, read from dataset columns of the same names.
    """

    distance: DistanceBins | None = field(default_factory=DistanceBins)
    orientation: OrientationBins | None = field(default_factory=OrientationBins)
    inclination: InclinationBins | None = field(default_factory=InclinationBins)
    movements: MovementRepertoire = field(default_factory=MovementRepertoire)
    effects: EffectDiscretizer = field(default_factory=EffectDiscretizer)
    high_level: tuple[HighLevelState, ...] = ()

    def __post_init__(self) -> None:
        names = self.variable_names
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"variable names must be unique, repeated: {sorted(dup)}")

    @property
    def context(self) -> tuple[DistanceBins | OrientationBins | InclinationBins, ...]:
        """The low-level context discretizations in use."""
        return tuple(b for b in (self.distance, self.orientation, self.inclination) if b)

    @property
    def variable_names(self) -> list[str]:
        """Names of the discrete variables: effect, context, high-level states, move."""
        return [
            self.effects.name,
            *(b.name for b in self.context),
            *(h.name for h in self.high_level),
            self.movements.name,
        ]

    @property
    def evidence(self) -> list[str]:
        """The evidence variables of the action generator (every variable but ``move``)."""
        return self.variable_names[:-1]

    def state_names(self) -> dict[str, list[int] | list[str]]:
        """Every variable's states, in index order (ints for bins, names otherwise)."""
        out: dict[str, list[int] | list[str]] = {self.effects.name: list(self.effects.values)}
        for b in self.context:
            out[b.name] = list(range(b.n_bins))
        for h in self.high_level:
            out[h.name] = list(h.values)
        out[self.movements.name] = list(self.movements.labels)
        return out

    def variable_specs(self) -> dict[str, VariableSpec]:
        """Bundle variable of each evidence variable, by name."""
        specs = [self.effects.spec(), *(b.spec() for b in self.context)]
        specs += [h.spec() for h in self.high_level]
        return {s.name: s for s in specs}

    def context_bins(self, eef: np.ndarray, obj: np.ndarray) -> dict[str, np.ndarray]:
        """Low-level context bins.

        Parameters
        ----------
        eef, obj : ndarray, shape (n, 3) or (3,)
            End-effector and object positions (m).

        Returns
        -------
        dict of str to ndarray of int64, shape (n,)
            Bin of each context variable, -1 where an input is not finite.
        """
        return {b.name: b.bins(eef, obj) for b in self.context}

    def discretize(self, raw: pd.DataFrame) -> pd.DataFrame:
        """The discrete dataset of a raw interaction dataset (:mod:`a2l.data.schema`).

        Rows whose movement is in the dead-band, whose effect is ``none`` or whose context
        is not finite are dropped; their number is in ``result.attrs["dropped_rows"]``.

        Parameters
        ----------
        raw : pandas.DataFrame, shape (n_rows, n_columns)
            Raw dataset with the columns of :data:`a2l.data.schema.REQUIRED_COLUMNS`, either
            ``effect_dx, effect_dy, effect_dz`` or ``effect``, and a column per high-level
            state.

        Returns
        -------
        pandas.DataFrame, shape (n_kept, n_variables)
            One categorical column per variable of :attr:`variable_names`, with every state
            of :meth:`state_names` as categories (so unseen states stay known).

        Raises
        ------
        ValueError
            A column is missing (named), or an ``effect`` / high-level value is unknown.
        """
        check_columns(raw, ("episode", "step", *EEF_COLUMNS, *OBJECT_COLUMNS, *MOVE_COLUMNS))
        check_columns(raw, [h.name for h in self.high_level])
        eef = raw.loc[:, list(EEF_COLUMNS)].to_numpy(np.float64)
        obj = raw.loc[:, list(OBJECT_COLUMNS)].to_numpy(np.float64)
        cols: dict[str, np.ndarray] = {}
        if "effect" in raw.columns:
            lut = {v: i for i, v in enumerate(self.effects.values)}
            bad = sorted({str(v) for v in raw["effect"]} - set(lut) - {"none"})
            if bad:
                raise ValueError(
                    f"column 'effect' has unknown effect(s) {bad}; known: {self.effects.values}"
                )
            cols[self.effects.name] = np.array(
                [lut.get(str(v), -1) for v in raw["effect"]], dtype=np.int64
            )
        elif all(c in raw.columns for c in EFFECT_DISPLACEMENT_COLUMNS):
            disp = raw.loc[:, list(EFFECT_DISPLACEMENT_COLUMNS)].to_numpy(np.float64)
            cols[self.effects.name] = self.effects.discretize(disp)
        else:
            raise ValueError(
                "dataset is missing the effect: it needs column 'effect' or columns "
                f"{list(EFFECT_DISPLACEMENT_COLUMNS)}"
            )
        cols.update(self.context_bins(eef, obj))
        for h in self.high_level:
            idx = h.discretize(raw[h.name])
            if (idx < 0).any():
                bad = sorted({str(v) for v, i in zip(raw[h.name], idx, strict=True) if i < 0})
                raise ValueError(f"column {h.name!r} has unknown value(s) {bad}; known: {h.values}")
            cols[h.name] = idx
        move = raw.loc[:, list(MOVE_COLUMNS)].to_numpy(np.float64)
        cols[self.movements.name] = self.movements.discretize(move)
        keep = np.logical_and.reduce([c >= 0 for c in cols.values()])
        states = self.state_names()
        out = pd.DataFrame(
            {
                name: pd.Categorical.from_codes(cols[name][keep], categories=states[name])
                for name in self.variable_names
            },
            index=pd.RangeIndex(int(keep.sum())),
        )
        out.attrs["dropped_rows"] = int((~keep).sum())
        return out

    def to_json(self) -> dict[str, object]:
        """A JSON-able description (kept in a bundle's ``extra`` and in run configs)."""
        d: dict[str, object] = {}
        for b in self.context:
            d[b.name] = {"kind": b.spec().kind, "n_bins": b.n_bins}
            if isinstance(b, DistanceBins):
                d[b.name].update(low=b.low, high=b.high)  # type: ignore[union-attr]
        m = self.movements
        d["move"] = {
            "name": m.name,
            "planar": m.planar,
            "step": m.step,
            "dead_band": m.dead_band,
            "relative_dead_band": m.relative_dead_band,
        }
        e = self.effects
        d["effect"] = {
            "name": e.name,
            "n_effects": e.n_effects,
            "threshold": e.threshold,
            "ratio": e.ratio,
        }
        d["high_level"] = {h.name: list(h.values) for h in self.high_level}
        return d


def state_codes(column: pd.Series, states: Sequence, name: str) -> np.ndarray:
    """Index of each entry of `column` in `states`.

    Returns
    -------
    ndarray of int64, shape (n,)

    Raises
    ------
    ValueError
        An entry is missing or not one of `states` (the message names `name` and the values).
    """
    values = (
        column.astype(object).to_numpy()
        if isinstance(column.dtype, pd.CategoricalDtype)
        else (column.to_numpy())
    )
    codes = pd.Index(list(states), dtype=object).get_indexer(pd.Index(values, dtype=object))
    if (codes < 0).any():
        bad = sorted({str(v) for v in values[codes < 0]})
        raise ValueError(
            f"column {name!r} has missing value(s) or value(s) not in its states: {bad}"
        )
    return codes.astype(np.int64)


def as_state_names(df: pd.DataFrame, state_names: Mapping[str, Sequence] | None = None) -> dict:
    """State names of every column of `df`: `state_names` first, then categories, then the
    sorted observed values."""
    out: dict[str, list] = {}
    for c in df.columns:
        if state_names is not None and c in state_names:
            out[c] = list(state_names[c])
        elif isinstance(df[c].dtype, pd.CategoricalDtype):
            out[c] = list(df[c].cat.categories)
        else:
            out[c] = sorted(pd.unique(df[c].dropna()))
    return out
