"""The one configuration of the demonstration -> skill pipeline (:class:`LfDConfig`).

Every LfD skill (:data:`a2l.lfd.library.SKILLS`) is learned with :data:`DEFAULT` unless a
caller overrides fields. The grid and discretization values are the ones the
parametrization study (``a2l experiment parametrization``) selected; the study's report
says how.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from a2l.skills.discretization import DiscretizationConfig

__all__ = ["DEFAULT", "LfDConfig"]


@dataclass(frozen=True)
class LfDConfig:
    """Parameters of the demonstration -> dataset -> skill pipeline.

    Attributes
    ----------
    resolution : float
        Spacing of the grid sampled around the demonstrations (m).
    tube : float
        Grid points farther than this from every demonstration are not sampled (m).
    blend : float
        0: a grid point takes the velocity of its nearest demonstration's DS; > 0: the
        DSs' unit velocities weighted by a Gaussian of this width (m) of the point's
        distance to each demonstration (:mod:`a2l.lfd.dataset`).
    step : float
        Movement length of the repertoire (m); the scene moves by it too.
    n_orient, n_dist : int
        Orientation sections and distance bins (the babbling path's discretizer).
    dist_low, dist_high : float
        Range of the distance bins (m).
    smoothing : bool
        Neighbour smoothing (``docs/method.md``) in the C++ step.
    n_demos : int
        Demonstrations per skill.
    maps : int
        Elementary maps K of each diffeomorphic DS.
    path_length : float
        Longest path a skill is expected to take (m): its step cap is
        ``ceil(path_length / step)``.
    """

    resolution: float = 0.01
    tube: float = 0.06
    blend: float = 0.02
    step: float = 0.02
    n_orient: int = 16
    n_dist: int = 4
    dist_low: float = 0.05
    dist_high: float = 0.20
    smoothing: bool = False
    n_demos: int = 12
    maps: int = 60
    path_length: float = 1.0

    def __post_init__(self) -> None:
        if not (isinstance(self.dist_low, (int, float)) and math.isfinite(self.dist_low)
                and self.dist_low >= 0):
            raise ValueError(f"LfDConfig.dist_low: must be a length >= 0, got "
                             f"{self.dist_low!r}")
        for name in ("resolution", "tube", "step", "dist_high", "path_length"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"LfDConfig.{name}: must be a positive length, got {v!r}")
        if self.dist_low >= self.dist_high:
            raise ValueError(f"LfDConfig.dist_low, dist_high: need low < high, got "
                             f"{self.dist_low}, {self.dist_high}")
        if not (isinstance(self.blend, (int, float)) and math.isfinite(self.blend)
                and self.blend >= 0):
            raise ValueError(f"LfDConfig.blend: must be a length >= 0, got {self.blend!r}")
        for name in ("n_orient", "n_dist", "n_demos", "maps"):
            v = getattr(self, name)
            if not isinstance(v, int) or isinstance(v, bool) or v < 1:
                raise ValueError(f"LfDConfig.{name}: must be a positive integer, got {v!r}")
        if not isinstance(self.smoothing, bool):
            raise ValueError(f"LfDConfig.smoothing: must be True or False, got "
                             f"{self.smoothing!r}")

    @property
    def step_cap(self) -> int:
        """Most movements of a run: ``ceil(path_length / step)``."""
        return int(math.ceil(self.path_length / self.step - 1e-9))

    def discretization(self, planar: bool = True, n_effects: int = 4) -> DiscretizationConfig:
        """The discretization of a skill learned with this configuration: the bins and step
        here, `planar` and `n_effects` of the skill, the push experiment's defaults else."""
        return DiscretizationConfig(n_effects=n_effects, planar=planar, step=self.step,
                                    n_orient=self.n_orient, n_dist=self.n_dist, n_incl=0,
                                    dist_low=self.dist_low, dist_high=self.dist_high)

    def with_(self, **changes: Any) -> LfDConfig:
        """A copy with some fields changed; an unknown field is an error naming it."""
        known = {f.name for f in fields(self)}
        bad = sorted(set(changes) - known)
        if bad:
            raise ValueError(f"unknown LfDConfig field(s) {bad}; known: {sorted(known)}")
        return replace(self, **changes)

    def to_json(self) -> dict[str, Any]:
        """The fields as a JSON-able dict."""
        return asdict(self)


#: The configuration every skill uses (selected by the parametrization study).
DEFAULT = LfDConfig()
