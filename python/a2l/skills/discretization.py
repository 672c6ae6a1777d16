"""The one discretization configuration (:class:`DiscretizationConfig`): bins of the context
variables, the movement repertoire and the effects, and the :class:`Discretizer` they make.

Both configurations of the package hold one as their ``discretization`` part:
:class:`a2l.framework.FrameworkConfig` (the push experiment; ``--discretization.n_orient``
on the command line) and :class:`a2l.lfd.config.LfDConfig` (demonstrated skills), so the two
build their discretizers the same way. A value out of its domain is refused when the part is
made (:class:`a2l.errors.ConfigError` naming ``discretization.<field>``).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from a2l.checks import check_count, check_edges, check_length, check_odd_or_zero, check_range
from a2l.errors import ConfigError
from a2l.skills.bins import DistanceBins, InclinationBins, OffsetBins, OrientationBins
from a2l.skills.discretizer import Discretizer
from a2l.skills.effects import EffectDiscretizer
from a2l.skills.repertoire import MovementRepertoire

__all__ = ["DiscretizationConfig"]


@dataclass(frozen=True)
class DiscretizationConfig:
    """The discretization of a skill's dataset (defaults: the push experiment's).

    Attributes
    ----------
    n_effects : {4, 8}
        Push effects of the effect variable.
    effect_threshold : float
        Smallest object displacement that counts as an effect (m).
    planar : bool
        8 planar movements instead of 26 in 3-D.
    step : float
        Movement length (m).
    n_orient, n_dist, n_incl : int
        Bins of the context variables (``n_incl = 0`` leaves inclination out).
    dist_low, dist_high : float
        Range of the distance bins (m).
    dist_edges : tuple of float
        Explicit interior edges of the distance bins (m; finite, > 0, strictly increasing),
        e.g. ``(0.07, 0.10, 0.15)``: d < 0.07, [0.07, 0.10), [0.10, 0.15), d >= 0.15, bins
        finer near the object. Empty (default): ``n_dist`` equal bins over [dist_low,
        dist_high]. Given, the edges win: ``len(dist_edges) + 1`` bins, ``n_dist`` is
        ignored (dist_low and dist_high are still checked and written to the bundle). On the
        command line ``0.07,0.10,0.15`` or ``[0.07,0.10,0.15]``.
    n_offset : int
        Bins of each planar offset of the end-effector from the object (0: none; odd).
    offset_half_x, offset_half_y : float
        Half-width of an offset bin (m).
    """

    n_effects: int = 4
    effect_threshold: float = 0.01
    planar: bool = True
    step: float = 0.05
    n_orient: int = 16
    n_dist: int = 3
    n_incl: int = 0
    dist_low: float = 0.05
    dist_high: float = 0.20
    dist_edges: tuple[float, ...] = ()
    n_offset: int = 0
    offset_half_x: float = 0.045
    offset_half_y: float = 0.0525

    def __post_init__(self) -> None:
        own = "discretization"
        if isinstance(self.dist_edges, list):  # from JSON (config.json, --set)
            object.__setattr__(self, "dist_edges", tuple(self.dist_edges))
        check_edges(own, "dist_edges", self.dist_edges)
        object.__setattr__(self, "dist_edges", tuple(float(x) for x in self.dist_edges))
        if self.n_effects not in (4, 8) or isinstance(self.n_effects, bool):
            raise ConfigError(f"{own}.n_effects", f"must be 4 or 8, got {self.n_effects!r}")
        for name in ("n_orient", "n_dist"):
            check_count(own, name, getattr(self, name))
        check_count(own, "n_incl", self.n_incl, minimum=0)
        check_odd_or_zero(own, "n_offset", self.n_offset)
        for name in ("effect_threshold", "step", "offset_half_x", "offset_half_y",
                     "dist_high"):
            check_length(own, name, getattr(self, name))
        check_length(own, "dist_low", self.dist_low, allow_zero=True)
        check_range(own, "dist_low", "dist_high", self.dist_low, self.dist_high, strict=True)
        if not isinstance(self.planar, bool):
            raise ConfigError(f"{own}.planar", f"must be true or false, got {self.planar!r}")

    def distance_bins(self) -> DistanceBins:
        """The distance bins: between ``dist_edges`` when given, else ``n_dist`` equal bins
        over [dist_low, dist_high]."""
        return DistanceBins(n_bins=self.n_dist, low=self.dist_low, high=self.dist_high,
                            edges=self.dist_edges)

    def discretizer(self) -> Discretizer:
        """The discretizer of these parameters (built once per set of values: rollouts ask
        for it for every task)."""
        return _discretizer(self)

    def context_names(self) -> list[str]:
        """The context variables' names (``distance``, ``orientation``, ...), in order."""
        return [b.name for b in self.discretizer().context]


@functools.lru_cache(maxsize=16)
def _discretizer(c: DiscretizationConfig) -> Discretizer:
    offsets = ((OffsetBins.strip("x", c.offset_half_x, c.n_offset),
                OffsetBins.strip("y", c.offset_half_y, c.n_offset)) if c.n_offset else ())
    return Discretizer(
        distance=c.distance_bins(),
        orientation=OrientationBins(n_bins=c.n_orient),
        inclination=InclinationBins(n_bins=c.n_incl) if c.n_incl > 0 else None,
        offsets=offsets,
        movements=MovementRepertoire(planar=c.planar, step=c.step),
        effects=EffectDiscretizer(n_effects=c.n_effects, threshold=c.effect_threshold),
    )
