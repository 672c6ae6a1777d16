"""Effects: names of the object displacement in the table plane.

The dominant axis decides the effect (``left``, ``right``, ``close``, ``far``); in 8-effect
mode a displacement whose axes are within ``ratio`` of each other is a diagonal; a planar
displacement below a threshold is no effect (index -1).

There is one implementation of the classification: the C++ ``a2l::classify_effect``, which
the scenes, ``a2l-run`` and :func:`a2l.sim.effects.push_effect` call;
:class:`EffectDiscretizer` calls it for all displacements at once through
``a2l._core.classify_effects``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from a2l import _core
from a2l.skills.bins import _as_points
from a2l.skills.spec import VariableSpec

__all__ = ["AXIS_EFFECTS", "DIAGONAL_EFFECTS", "EffectDiscretizer"]

#: The 4 axis effects, in this order: object moved +y, −y, −x, +x.
AXIS_EFFECTS = ("left", "right", "close", "far")
#: The 4 diagonal effects (8-effect mode), after the axis effects.
DIAGONAL_EFFECTS = ("close_left", "close_right", "far_left", "far_right")


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
        return _core.classify_effects(d, self.n_effects, self.threshold, self.ratio).astype(
            np.int64
        )

    def spec(self) -> VariableSpec:
        """The bundle variable of the wanted effect."""
        return VariableSpec(self.name, "effect", len(self.values), values=self.values)
