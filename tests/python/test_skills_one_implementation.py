"""One implementation of the context bins and of the effect classification.

The Python learning side (:mod:`a2l.skills.bins`, :mod:`a2l.skills.effects`) calls the C++
functions the runtime uses (``a2l::Discretizer::context_bin`` and ``a2l::classify_effect``,
vectorised as ``a2l._core.context_bins`` and ``a2l._core.classify_effects``). The numpy code
they replaced is kept here, verbatim, as the reference: on 100,000 points (random, on bin
edges, NaN, inf, overflowing, the object exactly at the end-effector) both agree bin for bin,
so datasets and bundles learned before are unchanged.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from a2l import _core
from a2l.errors import A2LValueError
from a2l.skills import (
    Discretizer,
    DistanceBins,
    EffectDiscretizer,
    InclinationBins,
    OrientationBins,
)
from a2l.skills.bins import context_bins

N = 100_000

# --- the numpy implementation before b6c53fc (reference only) ---------------------------

_atan2_ufunc = np.frompyfunc(math.atan2, 2, 1)


def _atan2(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    return np.asarray(_atan2_ufunc(y, x), dtype=np.float64).reshape(np.shape(y))


def ref_distance(r: np.ndarray, n: int, low: float, high: float) -> np.ndarray:
    with np.errstate(invalid="ignore", over="ignore"):
        d = np.sqrt(r[:, 0] * r[:, 0] + r[:, 1] * r[:, 1] + r[:, 2] * r[:, 2])
        x = np.floor((d - low) / (high - low) * n)
        b = np.clip(x, 0, n - 1)
    out = np.full(d.shape, -1, dtype=np.int64)
    ok = np.isfinite(d)
    out[ok] = b[ok].astype(np.int64)
    return out


def ref_orientation(r: np.ndarray, n: int) -> np.ndarray:
    w = 2.0 * math.pi / n
    theta = _atan2(r[:, 1], r[:, 0])
    with np.errstate(invalid="ignore"):
        x = np.floor(np.mod(theta + math.pi + w / 2.0, 2.0 * math.pi) / w)
    ok = np.isfinite(r).all(axis=1)
    out = np.full(theta.shape, -1, dtype=np.int64)
    out[ok] = np.mod(x[ok].astype(np.int64), n)
    return out


def ref_inclination(r: np.ndarray, n: int) -> np.ndarray:
    with np.errstate(over="ignore"):
        phi = _atan2(np.sqrt(r[:, 0] * r[:, 0] + r[:, 1] * r[:, 1]), r[:, 2])
    with np.errstate(invalid="ignore"):
        x = np.minimum(np.floor(phi / math.pi * n), n - 1)
    ok = np.isfinite(r).all(axis=1)
    out = np.full(phi.shape, -1, dtype=np.int64)
    out[ok] = x[ok].astype(np.int64)
    return out


def ref_effect(d: np.ndarray, n_effects: int, threshold: float, ratio: float) -> np.ndarray:
    dx, dy = d[:, 0], d[:, 1]
    ax, ay = np.abs(dx), np.abs(dy)
    x_axis = np.where(dx > 0, 3, 2)
    y_axis = np.where(dy > 0, 0, 1)
    out = np.where(ax >= ay, x_axis, y_axis)
    if n_effects == 8:
        diag = 4 + np.where(dx > 0, 2, 0) + np.where(dy > 0, 0, 1)
        with np.errstate(invalid="ignore", over="ignore"):
            axis_wins = (ax > ratio * ay) | (ay > ratio * ax)
        out = np.where(axis_wins, out, diag)
    with np.errstate(invalid="ignore", over="ignore"):
        moved = np.hypot(dx, dy) >= threshold
    return np.where(moved & np.isfinite(d[:, :2]).all(axis=1), out, -1).astype(np.int64)


# --- points ------------------------------------------------------------------------------


def context_points(seed: int, n_dist: int, n_orient: int, n_incl: int, low: float,
                   high: float) -> tuple[np.ndarray, np.ndarray]:
    """N (eef, object) pairs: a fifth random, the rest on the bin edges of each variable, at
    the object, or with non-finite or overflowing coordinates."""
    rng = np.random.default_rng(seed)
    k = N // 8
    obj = rng.uniform(-1.0, 1.0, (N, 3))
    obj[rng.random(N) < 0.3] = 0.0  # exact relative vectors where the object is at 0
    rel = rng.normal(0.0, 0.2, (N, 3))
    # distance edges, along a random axis and in a random direction
    edges = low + (high - low) * rng.integers(0, n_dist + 1, k) / n_dist
    rel[:k] = 0.0
    rel[np.arange(k), rng.integers(0, 3, k)] = edges * rng.choice([-1.0, 1.0], k)
    # orientation edges (theta = -pi + (j + 1/2) w) and centres, at random heights
    w = 2 * math.pi / n_orient
    theta = -math.pi + (rng.integers(0, 2 * n_orient, k) / 2.0 + 0.5) * w
    rho = rng.uniform(0.01, 0.3, k)
    rel[k:2 * k] = np.c_[rho * np.cos(theta), rho * np.sin(theta), rng.normal(0, 0.1, k)]
    # axis directions: theta exactly 0, +-pi/2, pi, and -0.0 components
    axes = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1],
                     [-0.0, 0.5, 0], [0.5, -0.0, 0], [-0.5, -0.0, 0], [0, 0, -0.0]])
    rel[2 * k:3 * k] = axes[rng.integers(0, len(axes), k)] * rng.uniform(0.01, 0.3, (k, 1))
    # inclination edges (phi = j pi / n)
    phi = rng.integers(0, n_incl + 1, k) * math.pi / n_incl
    az = rng.uniform(-math.pi, math.pi, k)
    rel[3 * k:4 * k] = 0.1 * np.c_[np.sin(phi) * np.cos(az), np.sin(phi) * np.sin(az),
                                   np.cos(phi)]
    eef = obj + rel
    # the object exactly at the end-effector
    eef[4 * k:5 * k] = obj[4 * k:5 * k]
    # non-finite coordinates, in the eef or the object
    bad = np.array([np.nan, np.inf, -np.inf])
    i = np.arange(5 * k, 6 * k)
    which = rng.integers(0, 2, k)
    for j, row in enumerate(i):
        (eef if which[j] else obj)[row, rng.integers(0, 3)] = bad[rng.integers(0, 3)]
    # finite positions whose difference overflows, or whose squared norm does
    big = np.finfo(np.float64).max
    eef[6 * k:6 * k + k // 2] = [big, 0.0, 0.0]
    obj[6 * k:6 * k + k // 2] = [-big, 0.0, 0.0]
    eef[6 * k + k // 2:7 * k] = [1e200, 1e200, 0.0]
    obj[6 * k + k // 2:7 * k] = 0.0
    return eef, obj


@pytest.mark.parametrize(("n_dist", "n_orient", "n_incl", "low", "high", "seed"), [
    (3, 16, 8, 0.05, 0.20, 0),
    (5, 12, 6, 0.02, 0.31, 1),
    (1, 1, 1, 0.0, 0.1, 2),
    (7, 32, 9, 0.1, 0.3, 3),
])
def test_context_bins_equal_the_old_numpy_bins(n_dist: int, n_orient: int, n_incl: int,
                                               low: float, high: float, seed: int) -> None:
    eef, obj = context_points(seed, n_dist, n_orient, n_incl, low, high)
    disc = Discretizer(distance=DistanceBins(n_dist, low, high),
                       orientation=OrientationBins(n_orient), inclination=InclinationBins(n_incl))
    with np.errstate(invalid="ignore", over="ignore"):
        r = eef - obj
    expected = {
        "distance": ref_distance(r, n_dist, low, high),
        "orientation": ref_orientation(r, n_orient),
        "inclination": ref_inclination(r, n_incl),
    }
    got = disc.context_bins(eef, obj)
    for name, ref in expected.items():
        bad = np.flatnonzero(got[name] != ref)
        assert bad.size == 0, (name, bad[:5], got[name][bad[:5]], ref[bad[:5]], r[bad[:5]])
        assert got[name].dtype == np.int64
    # every kind of point was met: all bins, and unknown contexts
    for b in disc.context:
        assert set(np.unique(got[b.name])) == {-1, *range(b.n_bins)}
    # one variable at a time, and the object exactly at the end-effector
    assert np.array_equal(disc.distance.bins(eef, obj), expected["distance"])
    p = np.array([0.7, -0.1, 0.04])
    assert [b.bins(p, p)[0] for b in disc.context] == [0, n_orient // 2 % n_orient, 0]


def test_context_bins_equal_the_runtime_discretizer() -> None:
    eef, obj = context_points(7, 3, 16, 8, 0.05, 0.20)
    variables = [DistanceBins(), OrientationBins(), InclinationBins()]
    got = context_bins(eef, obj, variables)
    assert got.shape == (N, 3)
    for i in range(0, N, 97):  # the scalar C++ function, one point at a time
        for j, v in enumerate(variables):
            one = _core.context_bins(eef[i], obj[i], [v.core_variable()])
            assert one.shape == (1, 1) and one[0, 0] == got[i, j], (i, j)


@pytest.mark.parametrize("edges", [(0.07, 0.10, 0.15), (0.1,), (0.02, 0.05, 0.08, 0.3)])
def test_distance_edges_bin_the_number_of_edges_at_or_below(edges: tuple[float, ...]) -> None:
    """Explicit edges: the bin of d is the number of edges <= d (numpy's searchsorted on the
    same d), on random points, on every edge and just below it, NaN, inf and overflow; the
    C++ scalar step of the runtime (Discretizer.discretize of a loaded variable) agrees."""
    eef, obj = context_points(5, 3, 16, 8, 0.05, 0.20)
    k = N // 7
    rng = np.random.default_rng(6)
    on = np.asarray(edges)[rng.integers(0, len(edges), k)]
    on[::2] = np.nextafter(on[::2], 0.0)  # just below an edge
    obj[:k] = 0.0
    eef[:k] = 0.0
    eef[np.arange(k), rng.integers(0, 3, k)] = on * rng.choice([-1.0, 1.0], k)  # d == |on|
    bins = DistanceBins(edges=edges)
    assert bins.n_bins == len(edges) + 1
    got = bins.bins(eef, obj)
    with np.errstate(invalid="ignore", over="ignore"):
        r = eef - obj
        d = np.sqrt(r[:, 0] * r[:, 0] + r[:, 1] * r[:, 1] + r[:, 2] * r[:, 2])
    ref = np.where(np.isfinite(d), np.searchsorted(edges, d, side="right"), -1)
    assert np.array_equal(got, ref), np.flatnonzero(got != ref)[:5]
    assert set(np.unique(got)) == {-1, *range(len(edges) + 1)}
    core = bins.core_variable()
    assert core == ("distance", len(edges) + 1, 0.05, 0.20, tuple(edges))
    for i in range(0, N, 211):  # one point at a time, as the runtime's step bins it
        one = _core.context_bins(eef[i], obj[i], [core])
        assert one[0, 0] == got[i], i
    # without edges, the 4-tuple and the equal bins of before
    assert DistanceBins().core_variable() == ("distance", 3, 0.05, 0.20)


def test_bad_distance_edges_are_named() -> None:
    bad = {(0.1, 0.07): r"variables\[0\]\.edges\[1\]: 0\.07",
           (0.0,): r"variables\[0\]\.edges\[0\]: 0 ",
           (math.nan,): r"variables\[0\]\.edges\[0\]: nan"}
    for edges, message in bad.items():
        with pytest.raises(A2LValueError, match=message):
            _core.context_bins(np.zeros(3), np.ones(3),
                               [("distance", len(edges) + 1, 0.05, 0.2, edges)])
        with pytest.raises(ValueError, match="edges must be finite, > 0 and strictly increasing"):
            DistanceBins(edges=edges)
    with pytest.raises(A2LValueError, match=r"variables\[0\]\.n_bins: 3, but 1 edges make 2"):
        _core.context_bins(np.zeros(3), np.ones(3), [("distance", 3, 0.05, 0.2, (0.1,))])
    with pytest.raises(A2LValueError, match=r"variables\[1\]\.edges: only a distance"):
        _core.context_bins(np.zeros(3), np.ones(3), [("distance", 3, 0.05, 0.2, ()),
                                                     ("offset_x", 2, -0.1, 0.1, (0.05,))])
    with pytest.raises(A2LValueError, match=r"variables\[0\]: must be \(kind, n_bins, low, "):
        _core.context_bins(np.zeros(3), np.ones(3), [("distance", 3, 0.05)])
    with pytest.raises(A2LValueError, match=r"variables\[0\]: kind must be a str"):
        _core.context_bins(np.zeros(3), np.ones(3), [("distance", 3, 0.05, 0.2, "x")])


@pytest.mark.parametrize("n_effects", [4, 8])
def test_effects_equal_the_old_numpy_effects(n_effects: int) -> None:
    rng = np.random.default_rng(11 + n_effects)
    d = rng.normal(0.0, 0.05, (N, 3))
    k = N // 6
    d[:k] *= 0.1  # around the threshold
    d[k:2 * k, :2] = rng.choice([-1.0, 1.0], (k, 2)) * [0.75, 0.25]  # |dx| = 3 |dy| exactly
    d[2 * k:3 * k, :2] = rng.choice([-1.0, 1.0], (k, 2)) * 0.02  # |dx| = |dy|
    d[3 * k:3 * k + 100, :2] = [[0.01, 0.0], [0.0, -0.01], [0.0, 0.0], [-0.0, 0.02],
                                [0.0, 0.0]] * 20  # threshold itself, zero, -0.0
    d[4 * k:4 * k + 300] = np.nan
    d[4 * k + 300:4 * k + 600, 0] = np.inf
    d[4 * k + 600:4 * k + 900, 1] = -np.inf
    d[4 * k + 900:4 * k + 1200, :2] = np.finfo(np.float64).max
    e = EffectDiscretizer(n_effects=n_effects)
    got = e.discretize(d)
    ref = ref_effect(d, n_effects, e.threshold, e.ratio)
    assert got.dtype == np.int64
    assert np.array_equal(got, ref), np.flatnonzero(got != ref)[:5]
    assert set(np.unique(got)) == {-1, *range(n_effects)}
    # the scalar C++ function the scenes and a2l-run call agrees
    assert [_core.classify_effect(x, n_effects) for x in d[::101]] == got[::101].tolist()


def test_the_python_names_call_the_cpp_functions(monkeypatch: pytest.MonkeyPatch) -> None:
    eef = np.array([[0.1, 0.0, 0.0]])
    obj = np.zeros((1, 3))

    def boom(*args: object, **kwargs: object) -> None:
        raise RuntimeError("the C++ function was called")

    monkeypatch.setattr(_core, "context_bins", boom)
    for b in (DistanceBins(), OrientationBins(), InclinationBins()):
        with pytest.raises(RuntimeError, match="C.. function was called"):
            b.bins(eef, obj)
    with pytest.raises(RuntimeError, match="C.. function was called"):
        Discretizer().context_bins(eef, obj)
    monkeypatch.setattr(_core, "classify_effects", boom)
    with pytest.raises(RuntimeError, match="C.. function was called"):
        EffectDiscretizer().discretize(eef)
    monkeypatch.undo()
    assert EffectDiscretizer().discretize(eef).tolist() == [3]  # far
    assert Discretizer().context_bins(eef, obj)["distance"].tolist() == [1]


def test_bad_arguments_are_named() -> None:
    with pytest.raises(A2LValueError, match=r"variables\[1\]: kind must be"):
        _core.context_bins(np.zeros(3), np.ones(3), [("distance", 3, 0.0, 1.0), ("effect", 4,
                                                                                 0.0, 0.0)])
    with pytest.raises(A2LValueError, match=r"variables\[0\]: need finite low < high"):
        _core.context_bins(np.zeros(3), np.ones(3), [("distance", 3, 1.0, 1.0)])
    with pytest.raises(A2LValueError, match=r"variables\[0\]: n_bins must be in \[1, 1024\]"):
        _core.context_bins(np.zeros(3), np.ones(3), [("orientation", 0, 0.0, 0.0)])
    with pytest.raises(A2LValueError, match="shapes differ"):
        _core.context_bins(np.zeros((2, 3)), np.ones((3, 3)), [])
    with pytest.raises(A2LValueError, match=r"eef must have shape \(n, 3\)"):
        _core.context_bins(np.zeros((2, 2)), np.ones((2, 2)), [])
    with pytest.raises(A2LValueError, match="n_effects must be 4 or 8"):
        _core.classify_effects(np.zeros((2, 3)), 5)
    with pytest.raises(ValueError, match="eef and object shapes differ"):
        DistanceBins().bins(np.zeros((2, 3)), np.zeros((3, 3)))
