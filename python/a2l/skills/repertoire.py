"""The movement repertoire: discrete end-effector movements as sign patterns of a step, and
actions (open, close, stay).

A step becomes one of 26 directions in 3-D (8 in the table plane) by the signs of its
components, with a dead-band (see :class:`MovementRepertoire`); their default order and labels
are the C++ core's (:func:`default_directions`, :func:`direction_label`). After the directions, a
repertoire may hold actions (``docs/bundle_format.md``, ``movements.actions``): ``open`` and
``close`` the gripper, ``stay`` (hold still one movement's duration); they displace nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from a2l import _core
from a2l.skills.bins import as_points
from a2l.skills.spec import ACTIONS

__all__ = ["MovementRepertoire", "default_directions", "direction_label"]


def default_directions(planar: bool = False) -> np.ndarray:
    """The default directions in table order (``a2l::default_directions``, the C++ core's
    definition): axis moves first (+x, -x, +y, -y, +z, -z), then the diagonals.

    Returns
    -------
    ndarray of int64, shape (26, 3), or (8, 3) if `planar`
        Sign vectors (read-only).
    """
    dirs = np.array(_core.default_directions(planar), dtype=np.int64, order="C")
    dirs.setflags(write=False)
    return dirs


def direction_label(d: Sequence[int]) -> str:
    """The label of sign vector `d` (3,): ``"+x"``, ``"-x+y"``, ... (``a2l::direction_label``)."""
    return str(_core.direction_label(np.asarray(d, dtype=np.int32)))


@dataclass(frozen=True)
class MovementRepertoire:
    """The discrete movements: sign patterns of an end-effector step, then actions.

    A step ``d`` (3,) becomes the direction ``s`` with ``s_i = sign(d_i)``, except that a
    component is 0 when ``|d_i| <= dead_band`` or ``|d_i| < relative_dead_band · max_j |d_j|``.
    The default relative dead-band tan(22.5°) makes the planar case the nearest of the 8
    directions by angle. A movement's displacement is ``step · s / ‖s‖``. Movement
    ``n_directions + j`` is the action ``actions[j]`` (no displacement).

    Parameters
    ----------
    step : float
        Length of every movement (m), default 0.05.
    directions : array_like of int, shape (n_directions, 3), optional
        Sign vectors (entries in {-1, 0, 1}, not all 0, no repeat); default: the 26 directions
        of 3-D (8 in the plane if `planar`), axis moves first.
    labels : sequence of str, optional
        One name per direction (default ``"+x"``, ``"-x+y"``, ...); the actions' names may
        follow.
    actions : sequence of str
        Actions after the directions, from ``("open", "close", "stay")``, each at most once.
    planar : bool
        8 directions in the table plane (z ignored) instead of 26 in 3-D.
    dead_band : float
        Absolute dead-band (m); components at or below it count as 0.
    relative_dead_band : float
        Relative dead-band in [0, 1).

    Attributes
    ----------
    directions : ndarray of int64, shape (n_directions, 3)
        Sign patterns in table order: +x, -x, +y, -y, (+z, -z,) then diagonals.
    labels : tuple of str
        One name per movement: the directions' (``"+x"``, ``"-x+y"``, ...), then the actions'.
    actions : tuple of str
        The actions, in movement order after the directions.
    """

    step: float = 0.05
    directions: np.ndarray | None = field(default=None, repr=False, compare=False)
    labels: tuple[str, ...] | None = None
    actions: tuple[str, ...] = ()
    planar: bool = False
    dead_band: float = 1e-3
    relative_dead_band: float = math.tan(math.pi / 8)
    name: str = "move"

    def __post_init__(self) -> None:
        if not (self.step > 0 and math.isfinite(self.step)):
            raise ValueError(f"{self.name}: step must be a positive length, got {self.step}")
        if self.dead_band < 0:
            raise ValueError(f"{self.name}: dead_band must be >= 0, got {self.dead_band}")
        if not 0 <= self.relative_dead_band < 1:
            raise ValueError(
                f"{self.name}: relative_dead_band must be in [0, 1), got {self.relative_dead_band}"
            )
        if self.directions is None:
            dirs = default_directions(self.planar)
        else:
            dirs = np.array(self.directions, dtype=np.int64)
            if dirs.ndim != 2 or dirs.shape[1] != 3 or len(dirs) == 0:
                raise ValueError(
                    f"{self.name}: directions must have shape (n >= 1, 3), got {dirs.shape}"
                )
            bad = np.flatnonzero((np.abs(dirs) > 1).any(axis=1) | ~dirs.any(axis=1))
            if bad.size:
                raise ValueError(
                    f"{self.name}: directions[{bad[0]}] = {dirs[bad[0]].tolist()}: entries must "
                    "be signs in {-1, 0, 1}, not all zero"
                )
            if len({tuple(d) for d in dirs.tolist()}) != len(dirs):
                raise ValueError(f"{self.name}: directions repeat a sign vector")
        dirs.setflags(write=False)
        actions = tuple(str(a) for a in self.actions)
        for j, a in enumerate(actions):
            if a not in ACTIONS:
                raise ValueError(f"{self.name}: actions[{j}] = {a!r} is not one of {ACTIONS}")
            if a in actions[:j]:
                raise ValueError(f"{self.name}: actions[{j}] = {a!r} repeats an action")
        names = (
            [direction_label(d) for d in dirs] if self.labels is None else list(self.labels)
        )
        if len(names) == len(dirs) + len(actions) and tuple(names[len(dirs) :]) == actions:
            names = names[: len(dirs)]
        if len(names) != len(dirs):
            raise ValueError(
                f"{self.name}: {len(names)} labels for {len(dirs)} directions "
                f"(and actions {list(actions)})"
            )
        labels = (*(str(x) for x in names), *actions)
        if len(set(labels)) != len(labels):
            raise ValueError(f"{self.name}: labels must be unique, got {labels}")
        object.__setattr__(self, "directions", dirs)
        object.__setattr__(self, "actions", actions)
        object.__setattr__(self, "labels", labels)

    @property
    def n_directions(self) -> int:
        """Number of directions (the first movements)."""
        return len(self.directions)  # type: ignore[arg-type]

    @property
    def direction_labels(self) -> tuple[str, ...]:
        """The directions' labels (the bundle's ``movements.labels``)."""
        return self.labels[: self.n_directions]  # type: ignore[index]

    def is_action(self, index: int) -> bool:
        """True if movement `index` is an action (not a displacement)."""
        if not 0 <= index < self.n_moves:
            raise IndexError(f"{self.name}: movement {index} is outside [0, {self.n_moves})")
        return index >= self.n_directions

    def action(self, index: int) -> str | None:
        """The action of movement `index`, or None for a direction."""
        return self.actions[index - self.n_directions] if self.is_action(index) else None

    def index_of(self, label: str) -> int:
        """Index of the movement named `label` (a direction's label or an action's name).

        Raises
        ------
        KeyError
            No movement has that label.
        """
        try:
            return self.labels.index(label)  # type: ignore[union-attr]
        except ValueError:
            raise KeyError(f"{self.name}: no movement {label!r} in {self.labels}") from None

    @property
    def n_moves(self) -> int:
        """Number of movements: directions (8 or 26 by default) and actions."""
        return len(self.labels)  # type: ignore[arg-type]

    def discretize(self, displacement: np.ndarray) -> np.ndarray:
        """Movement index of each step.

        Parameters
        ----------
        displacement : ndarray, shape (n, 3) or (3,)
            End-effector displacements (or velocities).

        Returns
        -------
        ndarray of int64, shape (n,)
            Index into :attr:`directions` (never an action), or -1 where the step is inside
            the dead-band on every axis (no movement), not finite, or not a direction of a
            repertoire given its own `directions`.
        """
        d = as_points(displacement, "displacement").copy()
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
        lut[dcode] = np.arange(self.n_directions)
        out = lut[code]
        out[~np.isfinite(d).all(axis=1)] = -1
        return out

    def displacement(self, index: int | np.ndarray) -> np.ndarray:
        """Displacement of movement(s) `index`.

        Returns
        -------
        ndarray of float64, shape (3,) or (n, 3)
            ``step · d / ‖d‖``; zero for an action.
        """
        idx = np.asarray(index)
        if ((idx < 0) | (idx >= self.n_moves)).any():
            raise IndexError(f"{self.name}: movement index outside [0, {self.n_moves})")
        d = np.vstack([self.directions, np.zeros((len(self.actions), 3), np.int64)])
        d = d[idx].astype(np.float64)
        norm = np.linalg.norm(d, axis=-1, keepdims=True)
        return self.step * np.divide(d, norm, out=np.zeros_like(d), where=norm > 0)
