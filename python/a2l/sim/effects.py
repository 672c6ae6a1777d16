"""Effects: the discrete change of an object between two instants (METHOD.md).

Push effects are classified by the C++ ``a2l._core.classify_effect`` (the function the C++
runtime and the skills use), so that there is one definition of them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from a2l import _core

__all__ = ["PUSH_EFFECTS_4", "PUSH_EFFECTS_8", "push_effect"]

#: Push effects along the axes of the world frame (x forward, y to the robot's left):
#: ``far`` = +x, ``close`` = -x, ``left`` = +y, ``right`` = -y.
PUSH_EFFECTS_4: tuple[str, ...] = ("far", "close", "left", "right")
#: The 4 axis effects and the 4 diagonals.
PUSH_EFFECTS_8: tuple[str, ...] = PUSH_EFFECTS_4 + (
    "far_left", "far_right", "close_left", "close_right",
)

#: Effect names in the order of ``a2l._core.classify_effect``'s indices.
_CORE_NAMES: tuple[str, ...] = ("left", "right", "close", "far", "close_left", "close_right",
                                "far_left", "far_right")


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
    d3 = np.zeros(3)
    d3[: d.shape[0]] = d
    index = _core.classify_effect(d3, n_effects, threshold, ratio)
    return "none" if index < 0 else _CORE_NAMES[index]
