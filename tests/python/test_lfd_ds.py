"""The diffeomorphic DS: fit, C++ evaluation against the numpy reference, bundle files."""

from __future__ import annotations

import numpy as np
import pytest

from a2l.errors import BundleError
from a2l.lfd import Demonstration, DiffeoDS
from a2l.lfd.fit import fit_diffeo, line_source, mean_demonstration
from a2l.lfd.reference import (
    SQRT_E_HALF,
    ref_forward,
    ref_inverse,
    ref_jacobian,
    ref_velocity,
)


def _curve(d: int = 2, n: int = 400) -> np.ndarray:
    """An S-shaped demonstration ending at (1, -2[, 0.5])."""
    s = np.linspace(0.0, 1.0, n)
    pts = [30 * np.cos(3 * s) * (1 - s) + 1, 20 * np.sin(4 * s) * (1 - s) - 2]
    if d == 3:
        pts.append(10 * np.sin(2 * s) * (1 - s) + 0.5)
    return np.column_stack(pts)


@pytest.fixture(scope="module", params=[(2, "to_demo"), (3, "to_demo"), (2, "to_line"),
                                        (3, "to_line")], ids=lambda p: f"{p[0]}d-{p[1]}")
def fitted(request: pytest.FixtureRequest) -> tuple[DiffeoDS, np.ndarray]:
    d, direction = request.param
    x = _curve(d)
    return DiffeoDS.fit(x, K=60, beta=0.5, mu=0.6, duration=2.0, direction=direction), x


def _maps(ds: DiffeoDS) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return ds.centers, ds.vectors, ds.rhos


def test_fit_matches_the_demonstration_and_respects_the_bound(fitted):
    ds, x = fitted
    assert ds.dim == x.shape[1] and 1 <= ds.n_maps <= 60
    assert np.allclose(ds.target, x[-1])
    # every map within mu * sqrt(e/2): invertible with margin
    assert np.all(ds.rhos * np.linalg.norm(ds.vectors, axis=1) <= 0.6 * SQRT_E_HALF + 1e-12)
    # Phi maps the line onto the demonstration, up to the reported residual, which is small
    # (to_line: Phi = C^-1, the pullback fit measures the same demonstration-space error)
    err = np.linalg.norm(ds.forward(line_source(x)) - x, axis=1)
    assert err.max() == pytest.approx(ds.metadata["max_error"], rel=1e-6, abs=1e-9)
    assert err.mean() < 0.05 * np.ptp(x, axis=0).max()
    # the end point is matched: the target is a fixed point of Phi
    assert np.allclose(ds.forward(ds.target), ds.target, atol=1e-9)


@pytest.mark.parametrize("direction", ["to_demo", "to_line"])
def test_fit_reduces_the_error_with_more_maps(direction):
    x = _curve(2)
    errs = [fit_diffeo(x, K=k, mu=0.6, direction=direction).max_error for k in (5, 40, 150)]
    assert errs[0] > errs[1] > errs[2]


def test_to_line_fit_measures_the_reproduction_error_and_matches_the_end_point():
    """The pullback fit's max_error is Phi(source)'s distance to the demonstration, Phi
    evaluated by the C++ DS (the maps stored in the order C applies them), and Phi keeps
    the target fixed exactly."""
    x = _curve(3)
    res = fit_diffeo(x, K=40, mu=0.6, direction="to_line")
    ds = DiffeoDS.from_maps(res.target, res.centers, res.vectors, res.rhos, direction="to_line")
    err = np.linalg.norm(ds.forward(line_source(x)) - x, axis=1)
    assert err.max() == pytest.approx(res.max_error, rel=1e-6)
    assert np.abs(ds.forward(res.target) - res.target).max() < 1e-9
    # its reproduction from the demonstration's start follows the demonstration to its end
    rep = ds.rollout(x[0], 0.01, 3000, "exact")
    assert np.linalg.norm(rep[-1] - x[-1]) < 1e-6 * np.ptp(x)
    gap = np.linalg.norm(x[:, None, :] - rep[None, :, :], axis=2).min(axis=1)
    assert gap.mean() < 0.05 * np.ptp(x)


def test_auto_direction_keeps_the_smaller_mean_error():
    x = _curve(2)
    line = fit_diffeo(x, K=40, mu=0.6, direction="to_line")
    demo = fit_diffeo(x, K=40, mu=0.6, direction="to_demo")
    auto = fit_diffeo(x, K=40, mu=0.6, direction="auto")
    best, other = (demo, line) if demo.mean_error < line.mean_error else (line, demo)
    assert auto.direction == best.direction and auto.mean_error == best.mean_error
    assert auto.alternative == {"direction": other.direction, "mean_error": other.mean_error,
                                "max_error": other.max_error}
    assert 0 < line.mean_error <= line.max_error
    # the mean error is the mean distance between the fitted curve and the demonstration
    ds = DiffeoDS.from_maps(line.target, line.centers, line.vectors, line.rhos,
                            direction="to_line")
    err = np.linalg.norm(ds.forward(line_source(x)) - x, axis=1)
    assert err.mean() == pytest.approx(line.mean_error, rel=1e-6)
    fitted = DiffeoDS.fit(x, K=40, mu=0.6, direction="auto")
    assert fitted.direction == best.direction
    assert fitted.metadata["direction_alternative"]["direction"] == other.direction
    with pytest.raises(ValueError, match="direction"):
        fit_diffeo(x, K=10, direction="sideways")


def test_fit_with_schedules_respects_each_maps_bound():
    from a2l.lfd.fit import BETA_SCHEDULE, MU_SCHEDULE, schedule

    mus = schedule(MU_SCHEDULE, 100)
    assert mus[0] == MU_SCHEDULE[0] and mus[-1] == MU_SCHEDULE[-1]
    res = fit_diffeo(_curve(2), K=100, beta=schedule(BETA_SCHEDULE, 99), mu=mus)
    k = len(res.rhos)
    used = np.concatenate([mus[: k - 1], mus[-1:]])
    assert np.all(res.rhos * np.linalg.norm(res.vectors, axis=1) <= used * SQRT_E_HALF + 1e-12)
    with pytest.raises(ValueError):
        fit_diffeo(_curve(2), K=10, mu=np.full(9, 0.5))     # one mu per map: 10 needed


def test_cpp_evaluation_agrees_with_the_numpy_reference(fitted):
    ds, x = fitted
    rng = np.random.default_rng(1)
    lo, hi = x.min(axis=0), x.max(axis=0)
    pts = rng.uniform(lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo), size=(300, ds.dim))
    c, v, r = _maps(ds)

    def close(a: np.ndarray, b: np.ndarray) -> None:
        # within 1e-9, relative to the magnitude for large values
        assert np.all(np.abs(a - b) <= 1e-9 * np.maximum(1.0, np.abs(b)))

    way = ds.direction
    close(ds.velocity(pts), ref_velocity(pts, ds.target, c, v, r, ds.speed, way))
    close(ds.forward(pts), ref_forward(pts, c, v, r, way))
    close(ds.inverse(pts), ref_inverse(pts, c, v, r, way))
    close(ds.jacobian(pts), ref_jacobian(pts, c, v, r, way))
    # far points, where most maps are skipped by the negligible-weight cutoff (exp(-40))
    far = rng.uniform(lo - 3.0 * (hi - lo), hi + 3.0 * (hi - lo), size=(300, ds.dim))
    close(ds.velocity(far), ref_velocity(far, ds.target, c, v, r, ds.speed, way))
    close(ds.inverse(far), ref_inverse(far, c, v, r, way))
    close(ds.forward(far), ref_forward(far, c, v, r, way))
    # single points keep their shape
    assert ds.velocity(pts[0]).shape == (ds.dim,)
    close(ds.velocity(pts[0]), ref_velocity(pts[0], ds.target, c, v, r, ds.speed, way))


def test_inverse_of_forward_is_the_identity(fitted):
    ds, x = fitted
    rng = np.random.default_rng(2)
    pts = rng.uniform(-80, 80, size=(500, ds.dim))
    assert np.abs(ds.inverse(ds.forward(pts)) - pts).max() < 1e-10
    c, v, r = _maps(ds)
    way = ds.direction
    assert np.abs(ref_inverse(ref_forward(pts, c, v, r, way), c, v, r, way) - pts).max() < 1e-10


def test_rollout_from_far_outside_the_data_converges(fitted):
    ds, x = fitted
    far = ds.target + 20 * np.ptp(x, axis=0)
    for method in ("rk4", "euler"):
        traj = ds.rollout(far, 0.01, 4000, method)
        assert traj.shape == (4000, ds.dim)
        assert np.linalg.norm(traj[-1] - ds.target) < 1e-3
        assert np.linalg.norm(traj[0] - far) == 0.0


def test_reproduction_follows_the_demonstration_and_lasts_as_long():
    x = _curve(2)
    demo = Demonstration(x, np.linspace(0.0, 3.0, len(x)))
    ds = DiffeoDS.fit(demo, K=150, mu=0.6)
    rep = ds.rollout(x[0], 3.0 / (len(x) - 1), len(x), "rk4")
    # 99 % of the line-space distance is covered at the demonstration's duration
    line_left = np.linalg.norm(ds.inverse(rep[-1]) - ds.target)
    assert line_left == pytest.approx(0.01 * np.linalg.norm(ds.inverse(x[0]) - ds.target),
                                      rel=1e-3)
    nearest = np.min(np.linalg.norm(rep[:, None, :] - x[None, :, :], axis=2), axis=1)
    assert nearest.mean() < 0.02 * np.ptp(x, axis=0).max()


def test_from_maps_refuses_a_map_breaking_the_bound_naming_it():
    target = np.zeros(2)
    centers = np.ones((5, 2))
    vectors = np.full((5, 2), 0.5)
    rhos = np.full(5, 1.0)
    rhos[3] = 1.01 * SQRT_E_HALF / np.linalg.norm(vectors[3])
    with pytest.raises(ValueError, match="3"):
        DiffeoDS.from_maps(target, centers, vectors, rhos)
    rhos[3] = 1.0
    rhos[2] = np.nan
    with pytest.raises(ValueError, match="2"):
        DiffeoDS.from_maps(target, centers, vectors, rhos)
    with pytest.raises(ValueError):
        DiffeoDS.from_maps(target, centers, vectors[:4], np.ones(5))
    ok = DiffeoDS.from_maps(target, centers, vectors, np.ones(5), speed=2.0)
    assert ok.n_maps == 5 and ok.speed == 2.0


def test_non_finite_query_is_refused(fitted):
    ds, _ = fitted
    bad = np.full(ds.dim, np.nan)
    with pytest.raises(ValueError):
        ds.velocity(bad)


def test_save_and_load_roundtrip(fitted, tmp_path):
    ds, _ = fitted
    path = ds.save(tmp_path / "ds.a2lb", name="curve")
    back = DiffeoDS.load(path)
    pts = np.random.default_rng(3).normal(size=(50, ds.dim)) * 10
    assert np.array_equal(back.velocity(pts), ds.velocity(pts))
    assert back.n_maps == ds.n_maps and back.speed == ds.speed
    assert back.direction == ds.direction
    assert back.metadata["K"] == 60


def test_load_refuses_a_corrupted_bundle(fitted, tmp_path):
    ds, _ = fitted
    path = ds.save(tmp_path / "ds.a2lb")
    data = bytearray(path.read_bytes())
    data[-8:] = b"\xff" * 8                     # clobber the last array bytes
    path.write_bytes(bytes(data))
    with pytest.raises(BundleError):
        DiffeoDS.load(path)


def test_several_demonstrations_fit_their_time_aligned_mean():
    x = _curve(2)
    demos = [Demonstration(x + off, np.linspace(0.0, 2.0 + k, len(x)))
             for k, off in enumerate((np.array([0.5, 0.0]), np.array([-0.5, 0.0])))]
    ds = DiffeoDS.fit(demos, K=80, mu=0.6)
    mean = mean_demonstration([d.positions for d in demos])
    assert np.allclose(mean, x)
    assert np.allclose(ds.target, x[-1])
    assert ds.metadata["duration"] == pytest.approx(2.5)
    assert ds.metadata["n_demonstrations"] == 2


def test_fit_refuses_bad_input():
    with pytest.raises(ValueError, match="shape"):
        DiffeoDS.fit(np.zeros((10, 4)))
    with pytest.raises(ValueError, match="non-finite"):
        DiffeoDS.fit(np.full((10, 2), np.nan))
    with pytest.raises(ValueError, match="mu"):
        DiffeoDS.fit(_curve(2), mu=1.0)
    with pytest.raises(ValueError, match="single point"):
        DiffeoDS.fit(np.ones((10, 2)))
    with pytest.raises(ValueError, match="direction"):
        DiffeoDS.fit(_curve(2), direction="backwards")
    with pytest.raises(ValueError, match="direction"):
        DiffeoDS.from_maps(np.zeros(2), np.ones((1, 2)), np.ones((1, 2)), np.ones(1),
                           direction="backwards")
