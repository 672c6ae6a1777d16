"""Discrete movements: the validation of a direction, and the outcome of one movement.

The directions themselves (their default order and labels) are the C++ core's, read by
:mod:`a2l.skills.repertoire` (:func:`~a2l.skills.repertoire.default_directions`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from a2l.errors import A2LValueError

__all__ = ["MoveResult", "as_direction"]

def as_direction(movement: Any) -> NDArray[np.float64]:
    """Validate a movement (3 signs in {-1, 0, 1}, not all 0); return it as floats (3,)."""
    try:
        d = tuple(movement)
    except TypeError as exc:
        raise A2LValueError(f"a movement is a 3-tuple of signs in {{-1, 0, 1}}, got "
                            f"{movement!r}") from exc
    if len(d) != 3 or any(v not in (-1, 0, 1) for v in d) or d == (0, 0, 0):
        raise A2LValueError(f"a movement is a 3-tuple of signs in {{-1, 0, 1}}, not all 0; "
                            f"got {movement!r}")
    return np.asarray(d, dtype=float)


@dataclass(frozen=True)
class MoveResult:
    """Outcome of :meth:`Scene.execute`; true when the movement was carried out.

    Attributes
    ----------
    carried_out : bool
        The end-effector reached the target within the tolerance.
    status : str
        ``"ok"``, ``"unreachable"`` (no IK solution within the joint limits or the arm
        would swing around), ``"joint_limit"``, ``"workspace_limit"`` (target outside the
        workspace bounds: nothing moved), ``"blocked"`` (the arm moved but something
        stopped it short of the target) or ``"held"`` (a hold perturbation kept it still).
    message : str
        Why, for a human; empty when ``ok``.
    target : ndarray, shape (3,)
        Where the end-effector was sent.
    reached : ndarray, shape (3,)
        Where it is after the movement.
    """

    carried_out: bool
    status: str
    message: str
    target: NDArray[np.float64]
    reached: NDArray[np.float64]

    def __bool__(self) -> bool:
        return self.carried_out
