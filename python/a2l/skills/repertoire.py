"""The movement repertoire: discrete end-effector movements as sign patterns of a step.

A step becomes one of 26 directions in 3-D (8 in the table plane) by the signs of its
components, with a dead-band (see :class:`MovementRepertoire`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from a2l.skills.bins import _as_points

__all__ = ["MovementRepertoire"]


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
