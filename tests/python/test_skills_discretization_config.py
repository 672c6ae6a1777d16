"""One discretization configuration (a2l.skills.discretization) shared by the push
experiment's FrameworkConfig and the LfD skills' LfDConfig."""

from __future__ import annotations

import dataclasses

from a2l.framework import FrameworkConfig
from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.lfd.dataset import skill_discretizer
from a2l.skills.discretization import DiscretizationConfig


def test_framework_config_holds_the_one_discretization_part() -> None:
    cfg = FrameworkConfig(discretization={"n_effects": 8, "n_orient": 24, "n_dist": 4,
                                          "n_incl": 3, "n_offset": 3, "step": 0.03})
    d = cfg.discretization
    assert d == DiscretizationConfig(n_effects=8, n_orient=24, n_dist=4, n_incl=3, n_offset=3,
                                     step=0.03)
    # no field of the part is declared again in the composed configuration
    assert not {f.name for f in dataclasses.fields(d)} & {
        f.name for f in dataclasses.fields(FrameworkConfig)}
    assert DiscretizationConfig(n_effects=8, n_orient=24, n_dist=4, n_incl=3, n_offset=3,
                                step=0.03).discretizer() is d.discretizer()  # built once
    assert d.context_names() == ["distance", "orientation", "inclination", "offset_x",
                                 "offset_y"]


def test_lfd_config_uses_the_same_configuration() -> None:
    cfg = LfDConfig(discretization={"step": 0.03, "n_orient": 8})
    assert isinstance(cfg.discretization, DiscretizationConfig)
    d = cfg.skill_discretization(planar=False, n_effects=8)
    lfd = DEFAULT.discretization
    assert d == DiscretizationConfig(n_effects=8, planar=False, step=0.03, n_orient=8,
                                     n_dist=lfd.n_dist, dist_low=lfd.dist_low,
                                     dist_high=lfd.dist_high)
    # one class declares the discretization's fields: LfDConfig holds it as a part
    assert not {f.name for f in dataclasses.fields(DiscretizationConfig)} & {
        f.name for f in dataclasses.fields(LfDConfig)}
    # the LfD discretizer is the framework's of the same values, the very same object
    fw = FrameworkConfig(discretization=DEFAULT.discretization)
    assert skill_discretizer(DEFAULT) is fw.discretization.discretizer()
