"""The one configuration of the demonstration -> skill pipeline (:class:`LfDConfig`).

Every LfD skill (:data:`a2l.lfd.library.SKILLS`) is learned with :data:`DEFAULT` unless a
caller overrides fields. The grid and discretization values are the ones the
parametrization study (``a2l experiment parametrization``) selected; the study's report
says how.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from a2l.checks import check_count, check_length
from a2l.errors import ConfigError
from a2l.skills.discretization import DiscretizationConfig

__all__ = ["DEFAULT", "LFD_DISCRETIZATION", "LfDConfig"]

#: The discretization of the demonstrated skills (the parametrization study's choice):
#: 2 cm movements, 16 orientation sections x 4 distance bins over [0.05, 0.20] m. Each skill
#: sets its own ``planar`` and ``n_effects`` (:meth:`LfDConfig.skill_discretization`).
LFD_DISCRETIZATION = DiscretizationConfig(step=0.02, n_orient=16, n_dist=4)


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
    discretization : DiscretizationConfig
        The bins and the movement length (``step``: the scene moves by it too), the
        package's one discretization configuration (:data:`LFD_DISCRETIZATION`; a mapping of
        some of its fields changes those). Its ``planar`` and ``n_effects`` are each
        skill's own.
    smoothing : bool
        Neighbour smoothing (``docs/method.md``) in the C++ step.
    n_demos : int
        Demonstrations per skill.
    maps : int
        Elementary maps K of each diffeomorphic DS.
    path_length : float
        Longest path a skill is expected to take (m): its step cap is
        ``ceil(path_length / discretization.step)``.
    """

    resolution: float = 0.01
    tube: float = 0.06
    blend: float = 0.02
    discretization: DiscretizationConfig = LFD_DISCRETIZATION
    smoothing: bool = False
    n_demos: int = 12
    maps: int = 60
    path_length: float = 1.0

    def __post_init__(self) -> None:
        d = self.discretization
        if isinstance(d, Mapping):
            known = [f.name for f in fields(DiscretizationConfig)]
            bad = sorted(set(d) - set(known))
            if bad:
                raise ConfigError("discretization", f"unknown field(s) {bad}; the fields of "
                                  f"discretization: {', '.join(known)}")
            object.__setattr__(self, "discretization", replace(LFD_DISCRETIZATION, **d))
        elif not isinstance(d, DiscretizationConfig):
            raise ConfigError("discretization", f"expected a DiscretizationConfig or a "
                              f"mapping of its fields, got {d!r}")
        for name in ("resolution", "tube", "path_length"):
            check_length("", name, getattr(self, name))
        check_length("", "blend", self.blend, allow_zero=True)
        for name in ("n_demos", "maps"):
            check_count("", name, getattr(self, name))
        if not isinstance(self.smoothing, bool):
            raise ConfigError("smoothing", f"must be True or False, got {self.smoothing!r}")

    @property
    def step(self) -> float:
        """The movement length (m): ``discretization.step``."""
        return self.discretization.step

    @property
    def step_cap(self) -> int:
        """Most movements of a run: ``ceil(path_length / discretization.step)``."""
        return int(math.ceil(self.path_length / self.step - 1e-9))

    def skill_discretization(self, planar: bool = True, n_effects: int = 4
                             ) -> DiscretizationConfig:
        """The discretization of a skill learned with this configuration: this one with the
        skill's `planar` and `n_effects`."""
        return replace(self.discretization, planar=planar, n_effects=n_effects)

    def with_(self, changes: Mapping[str, Any] | None = None, **kwargs: Any) -> LfDConfig:
        """A copy with fields changed, by name (``maps=20``) or dotted name
        (``{"discretization.step": 0.03}``); an unknown field is an error naming it."""
        top: dict[str, Any] = {}
        disc: dict[str, Any] = {}
        known = {f.name for f in fields(self)}
        sub = {f.name for f in fields(DiscretizationConfig)}
        for path, value in {**(changes or {}), **kwargs}.items():
            head, _, rest = path.partition(".")
            if head == "discretization" and rest in sub:
                disc[rest] = value
            elif not rest and head in known:
                top[head] = value
            else:
                hint = (f" (it is discretization.{path} now)" if path in sub else "")
                raise ConfigError(path, f"LfDConfig has no field {path!r}{hint}; known: "
                                  f"{sorted(known)}, discretization.<{', '.join(sorted(sub))}>")
        if disc:
            top["discretization"] = replace(top.get("discretization", self.discretization),
                                            **disc)
        return replace(self, **top)

    def to_json(self) -> dict[str, Any]:
        """The fields as a JSON-able dict (the discretization as a nested dict, its
        ``dist_edges`` a list: what a ``config.json`` holds and reads back)."""
        d = asdict(self)
        d["discretization"]["dist_edges"] = list(self.discretization.dist_edges)
        return d


#: The configuration every skill uses (selected by the parametrization study).
DEFAULT = LfDConfig()
