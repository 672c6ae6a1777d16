"""Effects: names of the object displacement in the table plane.

The dominant axis decides the effect (``left``, ``right``, ``close``, ``far``); in 8-effect
mode a displacement whose axes are within ``ratio`` of each other is a diagonal; a planar
displacement below a threshold is no effect (index -1).

The C++ core owns the effect names, their order and the classification
(``cpp/include/a2l/effects.hpp``: ``a2l::effect_names``, ``a2l::classify_effect``, which the
C++ scenes and ``a2l-run`` call); this module reads them from ``a2l._core`` and is the one
Python home of the names and of the classification: :class:`EffectDiscretizer` (indices, for
many displacements at once through ``a2l._core.classify_effects``, or one) and
:func:`effect_name` (a name).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from a2l import _core
from a2l.skills.bins import as_points
from a2l.skills.spec import VariableSpec

__all__ = ["AXIS_EFFECTS", "DIAGONAL_EFFECTS", "EFFECT_DIRECTIONS", "EFFECT_NAMES",
           "EffectDiscretizer", "effect_name"]

#: The 8 push effects in index order (``a2l::effect_names``): the axis effects, then the
#: diagonals.
EFFECT_NAMES: tuple[str, ...] = tuple(_core.effect_names(8))
#: The 4 axis effects, in this order: object moved +y, −y, −x, +x.
AXIS_EFFECTS: tuple[str, ...] = tuple(_core.effect_names(4))
#: The 4 diagonal effects (8-effect mode), after the axis effects.
DIAGONAL_EFFECTS: tuple[str, ...] = EFFECT_NAMES[len(AXIS_EFFECTS):]
#: Effect name -> the planar direction (x, y) the object moves (``a2l::effect_direction``):
#: a unit axis for an axis effect, (±1, ±1) for a diagonal.
EFFECT_DIRECTIONS: dict[str, tuple[float, float]] = {
    e: (float(x), float(y)) for i, e in enumerate(EFFECT_NAMES)
    for x, y in [_core.effect_direction(i)]
}


def effect_name(displacement: ArrayLike, n_effects: int = 8,
                threshold: float = _core.EFFECT_THRESHOLD,
                ratio: float = _core.EFFECT_RATIO) -> str:
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
        Dominance ratio of an axis effect (3).

    Returns
    -------
    str
        One of :data:`EFFECT_NAMES` (the first 4 with 4 effects), or ``"none"``.

    Raises
    ------
    ValueError
        The displacement is not 2 or 3 finite numbers, or `n_effects` is neither 4 nor 8.
    """
    d = np.asarray(displacement, dtype=float).reshape(-1)
    if d.shape[0] not in (2, 3) or not np.all(np.isfinite(d)):
        raise ValueError(f"displacement must be 2 or 3 finite numbers, got {displacement!r}")
    if n_effects not in (4, 8):
        raise ValueError(f"n_effects must be 4 or 8, got {n_effects}")
    d3 = np.zeros(3)
    d3[: d.shape[0]] = d
    return str(_core.effect_name(_core.classify_effect(d3, n_effects, threshold, ratio)))


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
    threshold: float = _core.EFFECT_THRESHOLD
    ratio: float = _core.EFFECT_RATIO
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
        d = as_points(displacement, "displacement")
        return _core.classify_effects(d, self.n_effects, self.threshold, self.ratio).astype(
            np.int64
        )

    def classify(self, displacement: ArrayLike) -> int:
        """Effect index of one object displacement (3,) (z ignored): an index into
        :attr:`values`, or -1 for no effect (or a non-finite input)."""
        return int(_core.classify_effect(np.asarray(displacement, dtype=float), self.n_effects,
                                         self.threshold, self.ratio))

    def spec(self) -> VariableSpec:
        """The bundle variable of the wanted effect."""
        return VariableSpec(self.name, "effect", len(self.values), values=self.values)
