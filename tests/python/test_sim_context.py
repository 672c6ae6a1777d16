"""The context reader's low-level state against hand-computed values and the skills'
discretizer (both must read the same angles)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from a2l.sim import low_level_state
from a2l.skills.bins import InclinationBins, OrientationBins


@pytest.mark.parametrize(
    ("eef", "obj", "orientation", "inclination"),
    [
        ((0.5, 0.0, 0.0), (0.6, 0.0, 0.0), math.pi, math.pi / 2),  # eef in front (-x)
        ((0.6, 0.1, 0.0), (0.6, 0.0, 0.0), math.pi / 2, math.pi / 2),  # eef on the left
        ((0.6, 0.0, 0.1), (0.6, 0.0, 0.0), 0.0, 0.0),  # eef straight above
        ((0.7, 0.0, -0.1), (0.6, 0.0, 0.0), 0.0, 3 * math.pi / 4),  # behind and below
    ],
)
def test_low_level_state_values(eef: tuple, obj: tuple, orientation: float,
                                inclination: float) -> None:
    s = low_level_state(eef, obj)
    assert np.allclose(s.vector, np.subtract(obj, eef))
    assert s.distance == pytest.approx(np.linalg.norm(np.subtract(obj, eef)))
    assert s.orientation == pytest.approx(orientation)
    assert s.inclination == pytest.approx(inclination)


def test_angles_bin_like_the_skills_discretizer(rng: np.random.Generator) -> None:
    eef = rng.uniform(-0.3, 0.3, (500, 3))
    obj = rng.uniform(-0.3, 0.3, (500, 3))
    orient, incl = OrientationBins(n_bins=16), InclinationBins(n_bins=8)
    w = 2 * math.pi / 16
    for e, o, ob, ib in zip(eef, obj, orient.bins(eef, obj), incl.bins(eef, obj), strict=True):
        s = low_level_state(e, o)
        assert int(((s.orientation + math.pi + w / 2) % (2 * math.pi)) // w) % 16 == ob
        assert min(int(s.inclination / math.pi * 8), 7) == ib
