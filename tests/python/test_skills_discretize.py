"""Discretization: bins against scalar re-derivations of docs/bundle_format.md's formulas."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from a2l.skills import (
    Discretizer,
    DistanceBins,
    EffectDiscretizer,
    HighLevelState,
    InclinationBins,
    MovementRepertoire,
    OffsetBins,
    OrientationBins,
)


def _ref_distance(r: np.ndarray, low: float, high: float, n: int) -> int:
    d = math.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2)
    return min(max(math.floor((d - low) / (high - low) * n), 0), n - 1)


def _ref_orientation(r: np.ndarray, n: int) -> int:
    w = 2 * math.pi / n
    theta = math.atan2(r[1], r[0])
    return math.floor(math.fmod(theta + math.pi + w / 2, 2 * math.pi) / w) % n


def _ref_inclination(r: np.ndarray, n: int) -> int:
    phi = math.atan2(math.hypot(r[0], r[1]), r[2])
    return min(math.floor(phi / math.pi * n), n - 1)


@pytest.mark.parametrize("n_dist,n_orient,n_incl", [(3, 16, 8), (5, 24, 4), (4, 32, 1)])
def test_context_bins_match_the_bundle_formulas(n_dist: int, n_orient: int, n_incl: int) -> None:
    rng = np.random.default_rng(n_orient)
    obj = rng.uniform(-1, 1, (2000, 3))
    eef = obj + rng.normal(0, 0.15, (2000, 3))
    disc = Discretizer(
        DistanceBins(n_dist, 0.05, 0.20), OrientationBins(n_orient), InclinationBins(n_incl)
    )
    bins = disc.context_bins(eef, obj)
    r = eef - obj
    assert bins["distance"].tolist() == [_ref_distance(x, 0.05, 0.20, n_dist) for x in r]
    assert bins["orientation"].tolist() == [_ref_orientation(x, n_orient) for x in r]
    assert bins["inclination"].tolist() == [_ref_inclination(x, n_incl) for x in r]
    for b, n in ((bins["distance"], n_dist), (bins["orientation"], n_orient)):
        assert set(b.tolist()) == set(range(n))  # every bin is reachable


def test_distance_saturates_at_both_ends() -> None:
    b = DistanceBins(3, 0.05, 0.20)
    d = np.array([0.0, 0.049, 0.05, 0.0999, 0.1001, 0.19, 0.2, 5.0])
    eef = np.stack([d, 0 * d, 0 * d], axis=1)
    assert b.bins(eef, np.zeros_like(eef)).tolist() == [0, 0, 0, 0, 1, 2, 2, 2]


def test_orientation_sections_are_centred_on_minus_pi_plus_k_w() -> None:
    n = 16
    w = 2 * math.pi / n
    k = np.arange(n)
    for off in (0.0, 0.49 * w, -0.49 * w):
        theta = -math.pi + k * w + off
        eef = np.stack([np.cos(theta), np.sin(theta), 0 * theta], axis=1)
        assert OrientationBins(n).bins(eef, np.zeros_like(eef)).tolist() == k.tolist()


def test_inclination_from_vertical() -> None:
    eef = np.array([[0, 0, 1.0], [1.0, 0, 0], [0, 0, -1.0], [1.0, 0, 1.0]])
    assert InclinationBins(8).bins(eef, np.zeros_like(eef)).tolist() == [0, 4, 7, 2]


def test_offset_strips_tell_in_front_of_a_face_from_beside_it() -> None:
    """3 offset bins of half-width h: edges at ±h, saturated beyond (the formula of a
    distance bin, applied to dx or dy); the points of docs/framework.md's aliased cell."""
    x = OffsetBins.strip("x", 0.045)
    y = OffsetBins.strip("y", 0.0525)
    assert (x.name, x.kind, x.low, x.high) == ("offset_x", "offset_x", -0.135, 0.135)
    obj = np.array([0.6, -0.1, 0.05])
    rel = np.array([[0.041, 0.141, 0.0], [0.059, 0.091, 0.0], [-0.046, 0.0, 0.0],
                    [-0.044, 0.05, 0.3], [9.0, -9.0, 0.0], [0.0, 0.0525, 0.0]])
    assert x.bins(obj + rel, np.tile(obj, (6, 1))).tolist() == [1, 2, 0, 1, 2, 1]
    assert y.bins(obj + rel, np.tile(obj, (6, 1))).tolist() == [2, 2, 1, 1, 0, 2]
    # the same as the distance formula on the signed offset
    rng = np.random.default_rng(3)
    r = rng.normal(0, 0.1, (500, 3))
    five = OffsetBins("y", 5, -0.2, 0.1)
    assert five.bins(r, np.zeros_like(r)).tolist() == [
        min(max(math.floor((v + 0.2) / 0.3 * 5), 0), 4) for v in r[:, 1]]
    disc = Discretizer(inclination=None, offsets=(x, y))
    assert disc.variable_names == ["effect", "distance", "orientation", "offset_x", "offset_y",
                                   "move"]
    assert disc.to_json()["offset_y"] == {"kind": "offset_y", "n_bins": 3, "low": -0.1575,
                                          "high": 0.1575}
    with pytest.raises(ValueError, match="axis"):
        OffsetBins("z")
    with pytest.raises(ValueError, match="odd"):
        OffsetBins.strip("x", 0.045, 4)
    with pytest.raises(ValueError, match="offset_x: need finite low < high"):
        OffsetBins("x", 3, 0.1, 0.1)


def test_non_finite_context_is_unknown() -> None:
    eef = np.array([[np.nan, 0, 0], [np.inf, 0, 0], [0.1, 0, 0]])
    bins = Discretizer().context_bins(eef, np.zeros_like(eef))
    for b in bins.values():
        assert b.tolist()[:2] == [-1, -1]
        assert b[2] >= 0


@pytest.mark.parametrize("planar,n", [(False, 26), (True, 8)])
def test_repertoire_round_trip(planar: bool, n: int) -> None:
    rep = MovementRepertoire(planar=planar, step=0.05)
    assert rep.n_moves == n == len(set(rep.labels))
    assert len({tuple(d) for d in rep.directions}) == n
    assert not (rep.directions == 0).all(axis=1).any()
    if planar:
        assert (rep.directions[:, 2] == 0).all()
    disp = rep.displacement(np.arange(n))
    np.testing.assert_allclose(np.linalg.norm(disp, axis=1), 0.05)
    assert rep.discretize(disp).tolist() == list(range(n))
    assert rep.labels[:4] == ("+x", "-x", "+y", "-y")


def test_movement_dead_band() -> None:
    rep = MovementRepertoire(dead_band=0.002)
    steps = np.array(
        [
            [0.05, 0.001, 0.0],  # small y inside the absolute dead-band
            [0.05, 0.01, 0.0],  # y below tan(22.5°) of x
            [0.05, 0.03, 0.0],  # a diagonal
            [0.0, 0.0, 0.0],  # no movement
            [0.001, -0.001, 0.0005],  # all inside the dead-band
            [np.nan, 0.05, 0.0],
            [-0.03, 0.03, -0.03],
        ]
    )
    labels = [rep.labels[i] if i >= 0 else None for i in rep.discretize(steps)]
    assert labels == ["+x", "+x", "+x+y", None, None, None, "-x+y-z"]
    planar = MovementRepertoire(planar=True)
    assert planar.discretize(np.array([[0, 0, 0.05], [0.05, 0, 0.05]])).tolist() == [-1, 0]


def test_effects_4_and_8() -> None:
    disp = np.array(
        [
            [0.05, 0.001, 0],
            [-0.05, 0.0, 0],
            [0.0, 0.05, 0],
            [0.01, -0.05, 0],
            [0.05, 0.02, 0],
            [-0.03, -0.03, 0],
            [0.05, 0.01, 0],
            [0.005, 0.005, 0.3],
        ]
    )
    e4 = EffectDiscretizer(4)
    assert [e4.values[i] if i >= 0 else None for i in e4.discretize(disp)] == [
        "far",
        "close",
        "left",
        "right",
        "far",
        "close",
        "far",
        None,
    ]
    e8 = EffectDiscretizer(8, ratio=3.0)
    assert [e8.values[i] if i >= 0 else None for i in e8.discretize(disp)] == [
        "far",
        "close",
        "left",
        "right",
        "far_left",
        "close_right",
        "far",
        None,
    ]
    assert e8.values[:4] == ("left", "right", "close", "far")


def test_high_level_state_unknown_value() -> None:
    light = HighLevelState("light", ("off", "on"))
    assert light.discretize(["on", "off", "dim"]).tolist() == [1, 0, -1]
    with pytest.raises(ValueError, match="unique"):
        HighLevelState("light", ("on", "on"))


def test_bad_configuration_is_named() -> None:
    with pytest.raises(ValueError, match="distance.*low < high"):
        DistanceBins(3, 0.2, 0.05)
    with pytest.raises(ValueError, match="orientation.*n_bins"):
        OrientationBins(0)
    with pytest.raises(ValueError, match="n_effects"):
        EffectDiscretizer(6)
    with pytest.raises(ValueError, match="unique"):
        Discretizer(high_level=(HighLevelState("distance", ("a",)),))


def _raw(n: int = 50, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    obj = np.tile([0.7, 0.0, 0.04], (n, 1))
    eef = obj + rng.normal(0, 0.1, (n, 3))
    mv = rng.choice([-0.05, 0.0, 0.05], (n, 3))
    eff = rng.normal(0, 0.05, (n, 3))
    return pd.DataFrame(
        {
            "episode": np.arange(n) // 5,
            "step": np.arange(n) % 5,
            **{f"eef_{a}": eef[:, i] for i, a in enumerate("xyz")},
            **{f"obj_{a}": obj[:, i] for i, a in enumerate("xyz")},
            **{f"move_d{a}": mv[:, i] for i, a in enumerate("xyz")},
            **{f"effect_d{a}": eff[:, i] for i, a in enumerate("xyz")},
            "light": rng.choice(["off", "on"], n),
        }
    )


def test_discretize_dataset() -> None:
    raw = _raw()
    disc = Discretizer(high_level=(HighLevelState("light", ("off", "on")),))
    out = disc.discretize(raw)
    assert list(out.columns) == [
        "effect",
        "distance",
        "orientation",
        "inclination",
        "light",
        "move",
    ]
    for c, states in disc.state_names().items():
        assert list(out[c].cat.categories) == states
    mv = disc.movements.discretize(raw[["move_dx", "move_dy", "move_dz"]].to_numpy())
    ef = disc.effects.discretize(raw[["effect_dx", "effect_dy", "effect_dz"]].to_numpy())
    keep = (mv >= 0) & (ef >= 0)
    assert out.attrs["dropped_rows"] == int((~keep).sum()) > 0
    assert len(out) == int(keep.sum())
    assert out["move"].cat.codes.tolist() == mv[keep].tolist()
    assert out["light"].astype(str).tolist() == raw["light"][keep].tolist()


def test_discretize_dataset_errors_name_the_problem() -> None:
    disc = Discretizer(high_level=(HighLevelState("light", ("off", "on")),))
    with pytest.raises(ValueError, match="eef_y"):
        disc.discretize(_raw().drop(columns=["eef_y"]))
    with pytest.raises(ValueError, match="light"):
        disc.discretize(_raw().drop(columns=["light"]))
    with pytest.raises(ValueError, match="effect"):
        disc.discretize(_raw().drop(columns=["effect_dx"]))
    bad = _raw().assign(light="dim")
    with pytest.raises(ValueError, match="'light'.*dim"):
        disc.discretize(bad)
    named = _raw().drop(columns=["effect_dx", "effect_dy", "effect_dz"]).assign(effect="up")
    with pytest.raises(ValueError, match="unknown effect.*up"):
        disc.discretize(named)
    named["effect"] = "left"
    assert (disc.discretize(named)["effect"] == "left").all()
