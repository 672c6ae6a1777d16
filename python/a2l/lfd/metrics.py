"""Trajectory metrics of the LASA benchmark: DTW, swept error area, velocity RMSE.

Conventions (said in the LASA report):

- **DTW** is the *mean* point distance along the optimal dynamic-time-warping alignment
  (``dtaidistance`` computes the alignment): ``mean_k ||a[i_k] - b[j_k]||``, in data units.
- **Swept error area** (SEA): both trajectories are resampled to the same number of
  samples on their own normalised time; SEA sums, over consecutive samples, the area of the
  quadrilateral ``a_t, a_{t+1}, b_{t+1}, b_t`` (as two triangles), in squared units.
- **Velocity RMSE**: ``sqrt(mean_t ||a'(t) - b'(t)||^2)`` with velocities by finite differences
  (``numpy.gradient``) on the same time-aligned samples, in units per second.
"""

from __future__ import annotations

import numpy as np

__all__ = ["dtw_mean_distance", "resample_time", "swept_error_area", "velocity_rmse"]


def resample_time(traj: np.ndarray, n: int) -> np.ndarray:
    """`traj` (M, d) resampled linearly to `n` samples on its normalised time, (n, d)."""
    traj = np.asarray(traj, dtype=float)
    if len(traj) == n:
        return traj
    u = np.linspace(0.0, 1.0, len(traj))
    s = np.linspace(0.0, 1.0, n)
    return np.column_stack([np.interp(s, u, traj[:, k]) for k in range(traj.shape[1])])


def dtw_mean_distance(a: np.ndarray, b: np.ndarray) -> float:
    """Mean point distance along the DTW alignment of `a` (M, d) and `b` (N, d)."""
    from dtaidistance import dtw_ndim

    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    path = np.asarray(dtw_ndim.warping_path(a, b, use_c=True))
    return float(np.linalg.norm(a[path[:, 0]] - b[path[:, 1]], axis=1).mean())


def _triangle_area(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    u, v = q - p, r - p
    if p.shape[1] == 2:
        return 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    return 0.5 * np.linalg.norm(np.cross(u, v), axis=1)


def swept_error_area(a: np.ndarray, b: np.ndarray) -> float:
    """Swept error area between `a` (M, d) and `b` (N, d), time-aligned (see module)."""
    b = np.asarray(b, dtype=float)
    a = resample_time(a, len(b))
    a0, a1, b0, b1 = a[:-1], a[1:], b[:-1], b[1:]
    return float(np.sum(_triangle_area(a0, a1, b1) + _triangle_area(a0, b1, b0)))


def velocity_rmse(a: np.ndarray, b: np.ndarray, duration: float) -> float:
    """Velocity RMSE between `a` and `b` over `duration` seconds, time-aligned (see module)."""
    b = np.asarray(b, dtype=float)
    a = resample_time(a, len(b))
    dt = duration / (len(b) - 1)
    va = np.gradient(a, dt, axis=0)
    vb = np.gradient(b, dt, axis=0)
    return float(np.sqrt(np.mean(np.sum((va - vb) ** 2, axis=1))))
