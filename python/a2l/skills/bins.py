"""Context bins: distance, orientation, inclination and planar offsets of the end-effector to
the object.

The bins follow ``docs/bundle_format.md`` to the letter: the learning side and the C++
runtime (``a2l::Discretizer``) must agree bin for bin, so both call the same function. All
vectors are expressed in the robot's base frame (x forward, y left, z up).

==========================  ================================================================
variable                    bin
==========================  ================================================================
``distance``                d = ‖object − eef‖; clamp(floor((d − low)/(high − low)·n), 0, n−1),
                            or with explicit edges the number of edges ≤ d
``orientation``             θ = atan2(dy, dx) of (eef − object); w = 2π/n;
                            floor(((θ + π + w/2) mod 2π)/w) mod n (bin k centred on −π + k·w)
``inclination``             φ = atan2(√(dx² + dy²), dz) of (eef − object); min(floor(φ/π·n), n−1)
``offset_x``, ``offset_y``  dx (dy) of (eef − object), binned like the distance over [low, high]
==========================  ================================================================

A non-finite eef − object (NaN, inf, overflow) gives bin ``-1`` (the runtime's *unknown
context*).

There is one implementation of these formulas: the C++ ``a2l::Discretizer::context_bin``,
which the runtime's step calls; the classes here call it for all points at once through
``a2l._core.context_bins`` (:func:`context_bins`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from a2l import _core
from a2l.skills.spec import VariableSpec

__all__ = ["ContextBins", "CoreVariable", "DistanceBins", "InclinationBins", "OffsetBins",
           "OrientationBins", "as_points", "context_bins"]


#: One variable as :func:`a2l._core.context_bins` takes it: ``(kind, n_bins, low, high)``,
#: or ``(kind, n_bins, low, high, edges)`` for a distance with explicit edges.
CoreVariable = tuple[str, int, float, float] | tuple[str, int, float, float, tuple[float, ...]]


def as_points(a: np.ndarray | Sequence[float], what: str) -> np.ndarray:
    """`a` as a float64 array of shape (n, 3) (a single (3,) point becomes (1, 3))."""
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{what} must have shape (n, 3) or (3,), got {np.shape(a)}")
    return arr


def _pair(eef: np.ndarray, obj: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    e = as_points(eef, "eef")
    o = as_points(obj, "object")
    if e.shape != o.shape:
        raise ValueError(f"eef and object shapes differ: {e.shape} vs {o.shape}")
    return e, o


def context_bins(eef: np.ndarray, obj: np.ndarray, variables: Sequence[ContextBins]) -> np.ndarray:
    """Bins of several context variables at once, by the C++ runtime's bin math.

    Parameters
    ----------
    eef, obj : ndarray, shape (n, 3) or (3,)
        End-effector and object positions (m).
    variables : sequence of DistanceBins, OrientationBins, InclinationBins or OffsetBins
        The context discretizations.

    Returns
    -------
    ndarray of int64, shape (n, len(variables))
        Bin of each point and variable, -1 where eef − object is not finite.
    """
    e, o = _pair(eef, obj)
    core = [v.core_variable() for v in variables]
    return _core.context_bins(e, o, core).astype(np.int64)


class _Bins:
    """What the three context discretizations share: the bin-count check and :meth:`bins`,
    both through :func:`context_bins` (the C++ bin math)."""

    name: str
    n_bins: int

    def _check_n_bins(self) -> None:
        if not 1 <= self.n_bins <= 1024:
            raise ValueError(f"{self.name}: n_bins must be in [1, 1024], got {self.n_bins}")

    def bins(self, eef: np.ndarray, obj: np.ndarray) -> np.ndarray:
        """Bins of this variable.

        Parameters
        ----------
        eef, obj : ndarray, shape (n, 3) or (3,)
            End-effector and object positions (m).

        Returns
        -------
        ndarray of int64, shape (n,)
            Bin in [0, n_bins), or -1 where eef − object is not finite.
        """
        return context_bins(eef, obj, [self])[:, 0]  # type: ignore[list-item]


@dataclass(frozen=True)
class DistanceBins(_Bins):
    """Bins of the eef→object distance, saturating at both ends: equal bins over [low, high],
    or bins between explicit edges.

    Parameters
    ----------
    n_bins : int
        Number of equal bins (default 3); with `edges`, ``len(edges) + 1`` (set from them).
    low, high : float
        Range in metres (default [0.05, 0.20]); distances outside fall in the end bins. With
        `edges` they are still checked and written to a bundle but do not shape the bins.
    name : str
        Variable name in the dataset and the network.
    edges : tuple of float
        Interior bin edges (m), finite, > 0, strictly increasing (at most 1023); the bin of d
        is the number of edges ≤ d: ``(0.07, 0.10, 0.15)`` gives d < 0.07, [0.07, 0.10),
        [0.10, 0.15) and d ≥ 0.15. Empty (default): equal bins.
    """

    n_bins: int = 3
    low: float = 0.05
    high: float = 0.20
    name: str = "distance"
    edges: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if self.edges:
            edges = tuple(float(x) for x in self.edges)
            object.__setattr__(self, "edges", edges)
            object.__setattr__(self, "n_bins", len(edges) + 1)
            for k, x in enumerate(edges):
                if not (math.isfinite(x) and x > 0 and (k == 0 or x > edges[k - 1])):
                    raise ValueError(f"{self.name}: edges must be finite, > 0 and strictly "
                                     f"increasing, got {list(edges)}")
        self._check_n_bins()
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(f"{self.name}: need finite low < high, got [{self.low}, {self.high}]")

    def core_variable(self) -> CoreVariable:
        """``(kind, n_bins, low, high)``, with ``edges`` as a fifth item when there are any,
        as ``a2l._core.context_bins`` takes it."""
        if self.edges:
            return ("distance", self.n_bins, self.low, self.high, self.edges)
        return ("distance", self.n_bins, self.low, self.high)

    def spec(self) -> VariableSpec:
        """The bundle variable of this discretization."""
        return VariableSpec(self.name, "distance", self.n_bins, low=self.low, high=self.high,
                            edges=self.edges)


@dataclass(frozen=True)
class OrientationBins(_Bins):
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
        self._check_n_bins()

    def core_variable(self) -> CoreVariable:
        """``(kind, n_bins, low, high)``, as ``a2l._core.context_bins`` takes it."""
        return ("orientation", self.n_bins, 0.0, 0.0)

    def spec(self) -> VariableSpec:
        """The bundle variable of this discretization."""
        return VariableSpec(self.name, "orientation", self.n_bins)


@dataclass(frozen=True)
class InclinationBins(_Bins):
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
        self._check_n_bins()

    def core_variable(self) -> CoreVariable:
        """``(kind, n_bins, low, high)``, as ``a2l._core.context_bins`` takes it."""
        return ("inclination", self.n_bins, 0.0, 0.0)

    def spec(self) -> VariableSpec:
        """The bundle variable of this discretization."""
        return VariableSpec(self.name, "inclination", self.n_bins)


@dataclass(frozen=True)
class OffsetBins(_Bins):
    """Equal bins of the end-effector's offset from the object along the base frame's x or y
    axis (``dx`` or ``dy`` of eef − object) over [low, high], saturating at both ends.

    Distance and orientation sections are rings and wedges around the object's centre, so a
    cell near a box holds points beside a face and points in front of it, from which the
    same movement passes the box or hits it. Offset bins whose edges lie on the faces (e.g.
    3 bins over ``[-3h, 3h]``: edges at ``±h``, h = the box's half-size plus the
    end-effector's radius) tell the two apart (:meth:`strip`).

    Parameters
    ----------
    axis : {"x", "y"}
        The base-frame axis.
    n_bins : int
        Number of bins.
    low, high : float
        Range in metres; offsets outside fall in the end bins.
    name : str
        Variable name (default ``"offset_x"`` / ``"offset_y"``).
    """

    axis: str = "x"
    n_bins: int = 3
    low: float = -0.135
    high: float = 0.135
    name: str = ""

    def __post_init__(self) -> None:
        if self.axis not in ("x", "y"):
            raise ValueError(f"offset bins: axis must be 'x' or 'y', got {self.axis!r}")
        if not self.name:
            object.__setattr__(self, "name", f"offset_{self.axis}")
        self._check_n_bins()
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(f"{self.name}: need finite low < high, got [{self.low}, {self.high}]")

    @classmethod
    def strip(cls, axis: str, half_width: float, n_bins: int = 3) -> OffsetBins:
        """Bins of width ``2 · half_width`` centred on the object: the middle one (n_bins
        odd) is the strip ``|offset| < half_width`` in front of the object's faces across
        `axis`.

        Parameters
        ----------
        axis : {"x", "y"}
            The base-frame axis.
        half_width : float
            Half-width of a bin (m), > 0.
        n_bins : int
            Number of bins, odd (range ``[-n_bins · half_width, n_bins · half_width]``).
        """
        if not (math.isfinite(half_width) and half_width > 0):
            raise ValueError(f"offset_{axis}: half_width must be a positive length, got "
                             f"{half_width!r}")
        if n_bins < 1 or n_bins % 2 == 0:
            raise ValueError(f"offset_{axis}: n_bins must be odd, got {n_bins}")
        return cls(axis=axis, n_bins=n_bins, low=-n_bins * half_width,
                   high=n_bins * half_width)

    @property
    def kind(self) -> str:
        """The bundle kind: ``"offset_x"`` or ``"offset_y"``."""
        return f"offset_{self.axis}"

    def core_variable(self) -> CoreVariable:
        """``(kind, n_bins, low, high)``, as ``a2l._core.context_bins`` takes it."""
        return (self.kind, self.n_bins, self.low, self.high)

    def spec(self) -> VariableSpec:
        """The bundle variable of this discretization."""
        return VariableSpec(self.name, self.kind, self.n_bins, low=self.low, high=self.high)


#: A context discretization: what :func:`context_bins` and ``Discretizer.context`` hold.
ContextBins = DistanceBins | OrientationBins | InclinationBins | OffsetBins
