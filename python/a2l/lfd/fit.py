"""Fast diffeomorphic matching (Perrin & Schlehuber-Caissier 2016), in numpy.

From a demonstration ``X`` (N, d) ending at the target, the fit builds
``Phi = psi_{K-1} o ... o psi_0`` mapping the straight line from ``X[0]`` to the target
(the *line space*) onto ``X``:

1. Normalise: ``x_n = (x - target) / s`` with one scalar ``s`` (the largest per-axis standard
   deviation), so that the maps stay isotropic; the maps are converted back to the original
   units at the end (``c = target + s c_n``, ``v = s v_n``, ``rho = rho_n / s``).
2. Source: the line point matched with ``X[j]`` is ``(1 - tau_j) X[0]`` where ``tau_j`` is the
   demonstration's arc-length fraction at ``j`` (a documented choice: arc length rather than
   time spreads the source evenly where the demonstration lingers, at its start and end).
3. K - 1 times: take the point ``j`` of largest error ``e = ||X_j - current_j||^2``, put the map
   at ``c = current_j`` with ``v = beta (X_j - c)``, and choose ``rho`` by a bounded
   golden-section search on ``[0, mu sqrt(e/2) / ||v||]`` (so ``rho ||v|| <= mu sqrt(e/2)``:
   invertible) minimising the mean squared residual over all points plus ``reg * rho^2``.
   The residual after a candidate map has a closed form (``|a - w v|^2 = |a|^2 - 2 w a.v +
   w^2 |v|^2``), so one cost evaluation costs O(N).
4. The last map matches the end point (``beta = 1`` at the last point), so
   ``Phi(target) = target``.

Fitting stops early when every error is below ``tol`` (fewer than K maps).

``direction="to_line"`` fits maps whose composition ``C`` carries the demonstration onto
the line, so that ``Phi = C^{-1}`` and the DS's velocity is explicit (``a2l._core.DiffeoDS``,
direction ``"to_line"``: no scalar solves per query). It is fitted by *pullback*, so that the
error it reduces is the reproduction's, in the demonstration's space: the points
``q = C^{-1}(source)`` start on the line and each new map ``psi`` is applied *first*
(``C <- C o psi``), which moves them by ``psi^{-1}``. Each step takes the point ``j`` of largest
``||X_j - q_j||``, puts the map at ``c = q_j + u`` with ``v = -u``, ``u = beta (X_j - q_j)``
(so ``psi(c) = q_j``: ``psi^{-1}`` moves ``q_j`` exactly by ``u``, and its displacement peaks
there), chooses ``rho`` by the same golden-section search on the cost with the first-order
weights ``exp(-rho^2 ||q - q_j||^2)``, then moves every ``q`` by the exact ``psi^{-1}`` (one
scalar solve per point within reach of the map). The maps are stored in the order ``C``
applies them (the last fitted first). On the 30 LASA shapes this matches the demonstrations
as well as ``to_demo`` (``docs/experiments/lasa.md``) except where the greedy gets stuck between two
parts of the curve (GShape). ``direction="auto"`` fits both and keeps the one whose
fitted curve is closer to the demonstration (the smaller mean distance
``||Phi(source) - X||``, :attr:`FitResult.mean_error`; ``to_line`` on a tie).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from a2l import _core
from a2l.lfd.reference import SQRT_E_HALF

__all__ = [
    "BETA_SCHEDULE",
    "DIRECTIONS",
    "FIT_DIRECTIONS",
    "MU_SCHEDULE",
    "FitResult",
    "fit_diffeo",
    "line_source",
    "mean_demonstration",
    "schedule",
    "speed_gain",
]

#: beta over the maps in the original implementation (``schlepil/diffeo``): the inverses of
#: its division coefficients 3, 3, 2.5, 2, 1.66, 1.33, 1.1 at 7 equally spaced maps.
BETA_SCHEDULE = tuple(1.0 / np.array([3.0, 3.0, 2.5, 2.0, 1.66, 1.33, 1.1]))
#: mu over the maps used by the LASA benchmark: the original implementation's safety
#: coefficients (0.9, 0.9, 0.9, 0.85, 0.8, 0.75, 0.75) lowered by 0.1, which keeps the DS
#: less stiff (selected on LASA itself: see ``docs/experiments/lasa.md``).
MU_SCHEDULE = (0.8, 0.8, 0.8, 0.75, 0.7, 0.65, 0.65)

#: The two ways the maps can go (``a2l._core.DiffeoDS``'s ``direction``).
DIRECTIONS = ("to_demo", "to_line")
#: What :func:`fit_diffeo` accepts: a direction, or ``"auto"`` (both fitted, the one with the
#: smaller mean error kept).
FIT_DIRECTIONS = (*DIRECTIONS, "auto")

_GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


@dataclass(frozen=True)
class FitResult:
    """The fitted maps, in the demonstration's units.

    Attributes
    ----------
    target : array (d,)
    centers, vectors : arrays (n_maps, d)
    rhos : array (n_maps,)
    scale : float
        The normalisation scale ``s``.
    max_error : float
        Largest distance between ``Phi(source)`` and the demonstration after the fit, in the
        demonstration's units (either direction: ``to_line`` measures ``C^{-1}(source)``).
    direction : str
        ``"to_demo"`` (the maps compose to ``Phi``) or ``"to_line"`` (to ``Phi^{-1}``).
    mean_error : float
        Mean of the same distances over the demonstration's points (what ``"auto"``
        compares).
    alternative : dict or None
        ``"auto"`` only: the other direction's ``{"direction", "mean_error", "max_error"}``.
    """

    target: np.ndarray
    centers: np.ndarray
    vectors: np.ndarray
    rhos: np.ndarray
    scale: float
    max_error: float
    direction: str = "to_demo"
    mean_error: float = float("nan")
    alternative: dict[str, float | str] | None = None


def _as_trajectory(points: np.ndarray) -> np.ndarray:
    x = np.asarray(points, dtype=float)
    if x.ndim != 2 or x.shape[1] not in (2, 3):
        raise ValueError(f"trajectory must have shape (N, 2) or (N, 3), got {x.shape}")
    if x.shape[0] < 2:
        raise ValueError(f"trajectory needs at least 2 points, got {x.shape[0]}")
    if not np.all(np.isfinite(x)):
        raise ValueError("trajectory has non-finite values")
    return x


def line_source(points: np.ndarray) -> np.ndarray:
    """The line-space points matched with `points` (N, d): ``target + (1 - tau) (x0 - target)``.

    ``tau`` is the arc-length fraction along `points` (uniform if the path has no length).
    """
    x = _as_trajectory(points)
    seg = np.linalg.norm(np.diff(x, axis=0), axis=1)
    total = seg.sum()
    if total > 0:
        tau = np.concatenate([[0.0], np.cumsum(seg)]) / total
    else:
        tau = np.linspace(0.0, 1.0, len(x))
    return x[-1] + (1.0 - tau)[:, None] * (x[0] - x[-1])


def mean_demonstration(trajectories: list[np.ndarray], n: int | None = None) -> np.ndarray:
    """Time-aligned mean of several demonstrations (each (N_i, d), uniform in time).

    Each is resampled linearly to `n` points (default: the longest length) on its own
    normalised time [0, 1], then the points are averaged.
    """
    trajs = [_as_trajectory(t) for t in trajectories]
    if not trajs:
        raise ValueError("no demonstration given")
    d = trajs[0].shape[1]
    if any(t.shape[1] != d for t in trajs):
        raise ValueError("demonstrations have different dimensions")
    n = n or max(len(t) for t in trajs)
    s = np.linspace(0.0, 1.0, n)
    out = np.zeros((n, d))
    for t in trajs:
        u = np.linspace(0.0, 1.0, len(t))
        out += np.column_stack([np.interp(s, u, t[:, k]) for k in range(d)])
    return out / len(trajs)


def schedule(values: tuple[float, ...], n: int) -> np.ndarray:
    """`values` at equally spaced anchors, linearly interpolated over `n` maps, shape (n,)."""
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    anchors = np.linspace(0.0, max(n - 1, 1), len(values))
    return np.interp(np.arange(n, dtype=float), anchors, np.asarray(values, dtype=float))


def speed_gain(duration: float, fraction: float = 0.01) -> float:
    """Gain ``k`` of ``ydot = -k (y - target)`` so that a reproduction lasts `duration`.

    In line space the distance to the target decays as ``exp(-k t)``; the gain makes it reach
    `fraction` (1 %) of its start at ``t = duration``: ``k = ln(1 / fraction) / duration``.
    """
    if not (np.isfinite(duration) and duration > 0):
        raise ValueError(f"duration must be finite and > 0, got {duration}")
    return float(np.log(1.0 / fraction) / duration)


def _golden_min(a2: float, r2: np.ndarray, av: np.ndarray, vv: float, n: int, hi: float,
                reg: float, iterations: int) -> float:
    """argmin over rho in [0, hi] of mean ||a - w v||^2 + reg rho^2, w = exp(-rho^2 r2)."""

    def cost(rho: float) -> float:
        w = np.exp(-(rho * rho) * r2)
        return (a2 - 2.0 * float(w @ av) + vv * float(w @ w)) / n + reg * rho * rho

    lo = 0.0
    c = hi - _GOLDEN * (hi - lo)
    d = lo + _GOLDEN * (hi - lo)
    fc, fd = cost(c), cost(d)
    for _ in range(iterations):
        if fc < fd:
            hi, d, fd = d, c, fc
            c = hi - _GOLDEN * (hi - lo)
            fc = cost(c)
        else:
            lo, c, fc = c, d, fd
            d = lo + _GOLDEN * (hi - lo)
            fd = cost(d)
    return 0.5 * (lo + hi)


def _undo_map(q: np.ndarray, c: np.ndarray, v: np.ndarray, rho: float) -> np.ndarray:
    """``psi^{-1}(q)`` for ``psi(y) = y + exp(-rho^2 ||y - c||^2) v``, q (M, d) -> (M, d).

    The C++ inverse of a one-map DS (``a2l._core.DiffeoDS.inverse``: per point a scalar
    equation in the weight, bracketed Halley; points beyond the map's reach are not moved):
    the fit moves its points with the very solve a velocity query uses.
    """
    one = _core.DiffeoDS(c, c[None, :], v[None, :], np.array([rho]), 1.0)
    return np.asarray(one.inverse(q))


def _fit_forward(cur: np.ndarray, goal: np.ndarray, betas: np.ndarray, mus: np.ndarray,
                 regularisation: float, tol: float, iterations: int) -> tuple[list, list, list,
                                                                              np.ndarray]:
    """The paper's greedy: maps at the moving points `cur` (N, d) carry them onto `goal`;
    `cur` is updated in place. Returns centers, vectors, rhos and the residual (N, d)."""
    n = len(goal)
    centers: list[np.ndarray] = []
    vectors: list[np.ndarray] = []
    rhos: list[float] = []
    res = goal - cur                                   # residual (N, d)
    err = np.einsum("ij,ij->i", res, res)

    def add_map(j: int, b: float, m: float) -> None:
        c = cur[j].copy()
        v = b * res[j]
        vn = float(np.sqrt(v @ v))
        if vn == 0.0:
            return
        diff = cur - c
        r2 = np.einsum("ij,ij->i", diff, diff)
        av = res @ v
        rho = _golden_min(float(err.sum()), r2, av, vn * vn, n, m * SQRT_E_HALF / vn,
                          regularisation, iterations)
        w = np.exp(-(rho * rho) * r2)
        cur[:] += w[:, None] * v
        res[:] -= w[:, None] * v
        err[:] += w * (w * (vn * vn) - 2.0 * av)       # |a - w v|^2
        centers.append(c)
        vectors.append(v)
        rhos.append(rho)

    for i in range(len(betas)):
        j = int(np.argmax(err))
        if err[j] < tol * tol:
            break
        add_map(j, float(betas[i]), float(mus[i]))
    add_map(n - 1, 1.0, float(mus[-1]))
    return centers, vectors, rhos, res


def _fit_pullback(q: np.ndarray, goal: np.ndarray, betas: np.ndarray, mus: np.ndarray,
                  regularisation: float, tol: float, iterations: int) -> tuple[list, list, list,
                                                                               np.ndarray]:
    """The pullback greedy of ``to_line`` (module docstring): maps applied first move the
    pulled-back source `q` (N, d) onto `goal` by their inverses; `q` is updated in place.
    Returns centers, vectors, rhos in the order C applies them, and the residual (N, d)."""
    n = len(goal)
    centers: list[np.ndarray] = []
    vectors: list[np.ndarray] = []
    rhos: list[float] = []

    def add_map(j: int, b: float, m: float, res: np.ndarray) -> None:
        u = b * res[j]                                 # what psi^{-1} does to q_j
        un = float(np.sqrt(u @ u))
        if un == 0.0:
            return
        diff = q - q[j]
        r2 = np.einsum("ij,ij->i", diff, diff)
        rho = _golden_min(float(np.einsum("ij,ij->", res, res)), r2, res @ u, un * un, n,
                          m * SQRT_E_HALF / un, regularisation, iterations)
        c, v = q[j] + u, -u                            # psi(c) = q_j
        q[:] = _undo_map(q, c, v, rho)
        centers.append(c)
        vectors.append(v)
        rhos.append(rho)

    for i in range(len(betas)):
        res = goal - q
        err = np.einsum("ij,ij->i", res, res)
        j = int(np.argmax(err))
        if err[j] < tol * tol:
            break
        add_map(j, float(betas[i]), float(mus[i]), res)
    add_map(n - 1, 1.0, float(mus[-1]), goal - q)      # psi^{-1}(q_end) = target exactly
    return centers[::-1], vectors[::-1], rhos[::-1], goal - q


def fit_diffeo(trajectory: np.ndarray, K: int = 150, beta: float | np.ndarray = 0.5,
               mu: float | np.ndarray = 0.9,
               regularisation: float = 1e-4, tol: float = 1e-6,
               search_iterations: int = 30, source: np.ndarray | None = None,
               direction: str = "to_demo") -> FitResult:
    """Fit the maps of a diffeomorphism between the line space and `trajectory`.

    Parameters
    ----------
    trajectory : array (N, d), d in {2, 3}
        The demonstration; its last point is the target.
    K : int
        Maximum number of maps (the last one matches the end point).
    beta : float in (0, 1], or array (K - 1,)
        Fraction of the largest error that one map corrects (per map if an array).
    mu : float in (0, 1), or array (K,)
        Safety factor of the invertibility bound: ``rho ||v|| <= mu sqrt(e/2)`` (per map
        if an array; the last entry is the end-point map's).
    regularisation : float
        Weight of ``rho^2`` (normalised units) in the search's cost.
    tol : float
        Stop when every error is below it (normalised units).
    search_iterations : int
        Golden-section iterations per map.
    source : array (N, d), optional
        The line-space points matched with `trajectory` (default :func:`line_source`).
    direction : {"to_demo", "to_line", "auto"}
        ``"to_demo"``: the paper's greedy, the maps move the source onto `trajectory` (they
        compose to ``Phi``); ``"to_line"``: the pullback greedy, the maps compose to
        ``Phi^{-1}`` (explicit velocity queries); ``"auto"``: both are fitted and the one
        with the smaller mean error (:attr:`FitResult.mean_error`, ``to_line`` on a tie) is
        returned; its ``direction`` says which, ``alternative`` has the other's errors.

    Returns
    -------
    FitResult
        In the demonstration's units; ``max_error`` is measured in its space either way.
    """
    x = _as_trajectory(trajectory)
    if K < 1:
        raise ValueError(f"K must be >= 1, got {K}")
    betas = np.broadcast_to(np.asarray(beta, dtype=float), (K - 1,))
    mus = np.broadcast_to(np.asarray(mu, dtype=float), (K,))
    if not np.all((betas > 0) & (betas <= 1)):
        raise ValueError(f"beta must be in (0, 1], got {beta}")
    if not np.all((mus > 0) & (mus < 1)):
        raise ValueError(f"mu must be in (0, 1), got {mu}")
    if direction not in FIT_DIRECTIONS:
        raise ValueError(f"direction must be one of {FIT_DIRECTIONS}, got {direction!r}")
    target = x[-1].copy()
    scale = float(np.max(np.std(x, axis=0)))
    if not scale > 0:
        raise ValueError("trajectory is a single point: nothing to fit")
    goal = (x - target) / scale
    src = line_source(x) if source is None else np.asarray(source, dtype=float)
    if src.shape != x.shape:
        raise ValueError(f"source must have the trajectory's shape {x.shape}, got {src.shape}")

    def fit(way: str) -> FitResult:
        fitter = _fit_pullback if way == "to_line" else _fit_forward
        cs, vs, rs, res = fitter((src - target) / scale, goal, betas, mus, regularisation,
                                 tol, search_iterations)
        d = x.shape[1]
        c = np.asarray(cs).reshape(-1, d)
        v = np.asarray(vs).reshape(-1, d)
        r = np.asarray(rs, dtype=float)
        dist = np.sqrt(np.einsum("ij,ij->i", res, res)) * scale
        return FitResult(target=target, centers=target + scale * c, vectors=scale * v,
                         rhos=r / scale, scale=scale, max_error=float(dist.max()),
                         direction=way, mean_error=float(dist.mean()))

    if direction != "auto":
        return fit(direction)
    line, demo = fit("to_line"), fit("to_demo")
    best, other = (demo, line) if demo.mean_error < line.mean_error else (line, demo)
    return replace(best, alternative={"direction": other.direction,
                                      "mean_error": other.mean_error,
                                      "max_error": other.max_error})
