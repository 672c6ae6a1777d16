"""Vectorised numpy reference of the diffeomorphic DS (tests and the speed ratio).

The C++ core (:class:`a2l._core.DiffeoDS`) is the implementation the skills use; this module
computes the same quantities with numpy, vectorised over points, so that tests can compare
the two and benchmarks can measure what the C++ evaluation gains.

Convention (docs/bundle_format.md, docs/method.md): ``C = psi_{K-1} o ... o psi_0``
with ``psi_i(x) = x + exp(-rho_i^2 ||x - c_i||^2) v_i``; ``Phi = C`` (direction
``"to_demo"``) or ``Phi = C^{-1}`` (``"to_line"``); the DS is
``xdot = speed * J_Phi(y) (target - y)`` with ``y = Phi^{-1}(x)``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "INVERSE_ITERATIONS",
    "SQRT_E_HALF",
    "ref_forward",
    "ref_inverse",
    "ref_jacobian",
    "ref_velocity",
]

#: The invertibility bound: psi is a diffeomorphism when rho * ||v|| < sqrt(e / 2).
SQRT_E_HALF = float(np.sqrt(np.e / 2.0))
#: Fixed iteration bound of the safeguarded Newton solve of one map's inverse.
INVERSE_ITERATIONS = 60


def _points(x: np.ndarray, d: int) -> tuple[np.ndarray, bool]:
    a = np.asarray(x, dtype=float)
    single = a.ndim == 1
    a = np.atleast_2d(a)
    if a.ndim != 2 or a.shape[1] != d:
        raise ValueError(f"points must have shape ({d},) or (M, {d}), got {np.shape(x)}")
    if not np.all(np.isfinite(a)):
        raise ValueError("points are not finite")
    return a, single


def _check_direction(direction: str) -> None:
    if direction not in ("to_demo", "to_line"):
        raise ValueError(f"direction must be 'to_demo' or 'to_line', got {direction!r}")


def _apply(a: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
           rhos: np.ndarray) -> np.ndarray:
    """The maps applied in index order to points a (M, d)."""
    y = a.copy()
    for c, v, r in zip(centers, vectors, rhos, strict=True):
        diff = y - c
        y += np.exp(-(r * r) * np.einsum("ij,ij->i", diff, diff))[:, None] * v
    return y


def _apply_jacobian(a: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
                    rhos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The maps applied to points a (M, d) and their Jacobian: ((M, d), (M, d, d))."""
    m, d = a.shape
    y = a.copy()
    jac = np.broadcast_to(np.eye(d), (m, d, d)).copy()
    for c, v, r in zip(centers, vectors, rhos, strict=True):
        diff = y - c
        w = np.exp(-(r * r) * np.einsum("ij,ij->i", diff, diff))
        # J_psi = I - 2 rho^2 w v (y - c)^T ; J <- J_psi @ J
        g = (-2.0 * r * r * w)[:, None] * diff               # (M, d)
        jac += v[None, :, None] * np.einsum("ik,ikj->ij", g, jac)[:, None, :]
        y += w[:, None] * v
    return y, jac


def _undo(a: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
          rhos: np.ndarray) -> np.ndarray:
    """The maps undone in reverse index order for points a (M, d)."""
    x = a.copy()
    for i in range(len(rhos) - 1, -1, -1):
        x = _inverse_one(x, centers[i], vectors[i], float(rhos[i]))
    return x


def ref_forward(x: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
                rhos: np.ndarray, direction: str = "to_demo") -> np.ndarray:
    """``Phi(x)`` for x (d,) or (M, d) -> same shape (to_line: the maps undone)."""
    _check_direction(direction)
    a, single = _points(x, centers.shape[1])
    y = (_apply if direction == "to_demo" else _undo)(a, centers, vectors, rhos)
    return y[0] if single else y


def ref_jacobian(x: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
                 rhos: np.ndarray, direction: str = "to_demo") -> np.ndarray:
    """``J_Phi(x)``: x (d,) -> (d, d); x (M, d) -> (M, d, d) (to_line: ``J_C(Phi(x))^-1``)."""
    _check_direction(direction)
    a, single = _points(x, centers.shape[1])
    if direction == "to_demo":
        jac = _apply_jacobian(a, centers, vectors, rhos)[1]
    else:
        jac = np.linalg.inv(_apply_jacobian(_undo(a, centers, vectors, rhos), centers,
                                            vectors, rhos)[1])
    return jac[0] if single else jac


def _inverse_one(y: np.ndarray, c: np.ndarray, v: np.ndarray, r: float) -> np.ndarray:
    """Invert one map for points y (M, d): x with x + exp(-r^2||x-c||^2) v = y."""
    z = y - c
    r2 = r * r
    zz = np.einsum("ij,ij->i", z, z)
    zv = z @ v
    vv = float(v @ v)
    lo = np.zeros(len(y))
    hi = np.ones(len(y))
    k = np.exp(-r2 * zz)             # the weight at y: a first guess in [0, 1]
    for _ in range(INVERSE_ITERATIONS):
        q = zz - 2.0 * k * zv + k * k * vv          # ||z - k v||^2
        e = np.exp(-r2 * q)
        g = k - e
        neg = g < 0
        lo = np.where(neg, k, lo)
        hi = np.where(neg, hi, k)
        dg = 1.0 + e * (2.0 * r2) * (k * vv - zv)      # g'(k) > 0 under the bound
        step = k - g / dg
        inside = (step > lo) & (step < hi)
        k_new = np.where(g == 0, k, np.where(inside, step, 0.5 * (lo + hi)))
        done = np.max(np.abs(k_new - k)) <= 1e-16   # converged everywhere (k in [0, 1])
        k = k_new
        if done:
            break
    return y - k[:, None] * v


def ref_inverse(y: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
                rhos: np.ndarray, direction: str = "to_demo") -> np.ndarray:
    """``Phi^{-1}(y)`` for y (d,) or (M, d) -> same shape (to_demo: the maps undone in
    reverse order; to_line: the maps applied)."""
    _check_direction(direction)
    a, single = _points(y, centers.shape[1])
    x = (_undo if direction == "to_demo" else _apply)(a, centers, vectors, rhos)
    return x[0] if single else x


def ref_velocity(x: np.ndarray, target: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
                 rhos: np.ndarray, speed: float, direction: str = "to_demo") -> np.ndarray:
    """DS velocity ``speed * J_Phi(y) (target - y)``, ``y = Phi^{-1}(x)``; (d,) or (M, d).

    to_line: ``speed * J_C(x)^-1 (target - C(x))`` with C the maps applied (one sweep, one
    d x d solve per point)."""
    _check_direction(direction)
    a, single = _points(x, centers.shape[1])
    if direction == "to_demo":
        y = _undo(a, centers, vectors, rhos)
        jac = _apply_jacobian(y, centers, vectors, rhos)[1]
        out = speed * np.einsum("ijk,ik->ij", jac, target - y)
    else:
        y, jac = _apply_jacobian(a, centers, vectors, rhos)
        out = np.linalg.solve(jac, (speed * (target - y))[:, :, None])[:, :, 0]
    return out[0] if single else out
