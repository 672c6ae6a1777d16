"""Context bins: distance, orientation and inclination of the end-effector to the object.

The bins follow ``docs/bundle_format.md`` to the letter, because the C++ runtime
(``a2l::Discretizer``) bins the live context with the same formulas and must agree bin for
bin. All vectors are expressed in the robot's base frame (x forward, y left, z up).

========================  ================================================================
variable                  bin
========================  ================================================================
``distance``              d = ‖object − eef‖; clamp(floor((d − low)/(high − low)·n), 0, n−1)
``orientation``           θ = atan2(dy, dx) of (eef − object); w = 2π/n;
                          floor(((θ + π + w/2) mod 2π)/w) mod n (bin k centred on −π + k·w)
``inclination``           φ = atan2(√(dx² + dy²), dz) of (eef − object); min(floor(φ/π·n), n−1)
========================  ================================================================

A non-finite input (NaN, inf) gives bin ``-1`` (the runtime's *unknown context*).

The angles use the C library's ``atan2`` (through :func:`math.atan2`), the function the C++
runtime calls: numpy's vectorised ``arctan2`` may differ from it in the last bit, which is
enough to move a point lying exactly on a bin boundary into the neighbouring bin.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from a2l.skills.spec import VariableSpec

__all__ = ["DistanceBins", "InclinationBins", "OrientationBins"]


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
