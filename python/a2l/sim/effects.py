"""Effects: the discrete change of an object between two instants (METHOD.md)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["PUSH_EFFECTS_4", "PUSH_EFFECTS_8", "push_effect"]

#: Push effects along the axes of the world frame (x forward, y to the robot's left):
#: ``far`` = +x, ``close`` = -x, ``left`` = +y, ``right`` = -y.
PUSH_EFFECTS_4: tuple[str, ...] = ("far", "close", "left", "right")
#: The 4 axis effects and the 4 diagonals.
PUSH_EFFECTS_8: tuple[str, ...] = PUSH_EFFECTS_4 + (
    "far_left", "far_right", "close_left", "close_right",
)


def push_effect(displacement: ArrayLike, n_effects: int = 8, threshold: float = 0.01,
                ratio: float = 3.0) -> str:
    """Name the push effect of an object's planar displacement.

    Parameters
    ----------
    displacement : array_like, shape (2,) or (3,)
        Object displacement (m) in the world frame; z is ignored.
    n_effects : {4, 8}
        4: the dominant axis only; 8: an axis effect when the dominant axis moved more than
        `ratio` times the other, else a diagonal.
    threshold : float
        Below this planar distance (m) the effect is ``"none"``.
    ratio : float
        Dominance ratio of an axis effect (METHOD.md: 3).

    Returns
    -------
    str
        One of :data:`PUSH_EFFECTS_8` (or :data:`PUSH_EFFECTS_4`), or ``"none"``.
    """
    d = np.asarray(displacement, dtype=float).reshape(-1)
    if d.shape[0] not in (2, 3) or not np.all(np.isfinite(d)):
        raise ValueError(f"displacement must be 2 or 3 finite numbers, got {displacement!r}")
    if n_effects not in (4, 8):
        raise ValueError(f"n_effects must be 4 or 8, got {n_effects}")
    dx, dy = float(d[0]), float(d[1])
    if np.hypot(dx, dy) < threshold:
        return "none"
    x_name = "far" if dx > 0 else "close"
    y_name = "left" if dy > 0 else "right"
    if n_effects == 4:
        return x_name if abs(dx) >= abs(dy) else y_name
    if abs(dx) > ratio * abs(dy):
        return x_name
    if abs(dy) > ratio * abs(dx):
        return y_name
    return f"{x_name}_{y_name}"
