"""One discretization configuration (a2l.skills.discretization) shared by the push
experiment's FrameworkConfig and the LfD skills' LfDConfig."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from a2l.errors import ConfigError
from a2l.framework import FrameworkConfig
from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.lfd.dataset import skill_discretizer
from a2l.skills import DistanceBins
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


def test_dist_edges_give_the_distance_bins_and_win_over_n_dist() -> None:
    d = DiscretizationConfig(dist_edges=[0.07, 0.10, 0.15], n_dist=7)  # a list, as from JSON
    assert d.dist_edges == (0.07, 0.10, 0.15)
    bins = d.discretizer().distance
    assert (bins.n_bins, bins.edges) == (4, (0.07, 0.10, 0.15))
    eef = np.array([[0.069, 0, 0], [0.07, 0, 0], [0.1, 0, 0], [0.3, 0, 0]])
    assert bins.bins(eef, np.zeros_like(eef)).tolist() == [0, 1, 2, 3]
    assert DiscretizationConfig(dist_edges=(1, 2)).dist_edges == (1.0, 2.0)
    # default: no edges, the equal bins of n_dist over [dist_low, dist_high], as before
    plain = DiscretizationConfig()
    assert plain.dist_edges == () and plain.distance_bins() == DistanceBins(3, 0.05, 0.20)
    assert FrameworkConfig().to_dict()["discretization"]["dist_edges"] == []
    cfg = FrameworkConfig.from_dict({"discretization": {"dist_edges": [0.08, 0.12]}})
    assert cfg.discretization.dist_edges == (0.08, 0.12)
    assert FrameworkConfig.from_dict(json.loads(json.dumps(cfg.to_dict()))) == cfg


@pytest.mark.parametrize("edges", [(0.10, 0.07), (0.07, 0.07), (0.0, 0.1), (-0.05,),
                                   (0.07, math.nan), (math.inf,), (True,), ("0.07",), 0.07,
                                   tuple(0.001 * (k + 1) for k in range(1024))])
def test_bad_dist_edges_name_the_field(edges: object) -> None:
    with pytest.raises(ConfigError, match=r"discretization\.dist_edges: must be a list of at "
                       r"most 1023 bin edges \(lengths > 0, strictly increasing\)"):
        DiscretizationConfig(dist_edges=edges)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"discretization\.dist_edges"):
        FrameworkConfig(discretization={"dist_edges": edges})
