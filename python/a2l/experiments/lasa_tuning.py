"""Settings of the DS and of the DMP chosen on a tuning split of the LASA shapes
(:mod:`a2l.experiments.lasa`).

Both methods get the same budget: :data:`DS_CANDIDATES` and :data:`DMP_CANDIDATES` have the
same number of settings, each scored on the same tuning shapes under the held-out protocol
(learn from demonstrations 1-4, DTW on 5-7; :mod:`a2l.experiments.lasa_methods`); the
setting with the smallest mean DTW is kept. Nothing in either method is random, so "the same
seeds" is the same data: the same shapes, demonstrations and starts. The tuning shapes are
drawn with the tuning seed (:data:`TUNING_SEED`), apart from the seeds of the evaluation's
random starts; the results are reported on the other shapes, the tuning shapes marked.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from a2l.experiments.lasa_config import LasaConfig
from a2l.experiments.lasa_methods import (
    dmp_reproductions,
    ds_reproductions,
    fit_ds,
    load_lasa_shape,
    scores,
    split,
)

__all__ = ["DMP_CANDIDATES", "DS_CANDIDATES", "TUNING_SEED", "TuningShape", "tune_shape",
           "tuning_split"]

#: Seed of the tuning split: a tuning seed (``docs/seeds.md``); the evaluation's random
#: starts use ``LasaConfig.seed`` (evaluation seeds from 1000).
TUNING_SEED = 0

#: The DS's candidate settings (LasaConfig fields; beta/mu None = the schedules).
DS_CANDIDATES: tuple[dict[str, Any], ...] = tuple(
    {"beta": beta, "mu": mu, "arrival": arrival}
    for beta in (None, 0.5) for mu in (None, 0.6) for arrival in (1e-2, 1e-3))
#: The DMP's candidate settings: basis functions per dimension and ridge regularisation.
DMP_CANDIDATES: tuple[dict[str, Any], ...] = tuple(
    {"dmp_weights": w, "dmp_regularisation": r} for w in (10, 20, 50, 100) for r in (0.0, 0.1))


def tuning_split(shapes: list[str], n: int, seed: int = TUNING_SEED) -> list[str]:
    """`n` of `shapes` drawn with `seed` (sorted): the shapes the settings are chosen on."""
    if not 0 <= n < len(shapes):
        raise ValueError(f"tuning_shapes must be in [0, {len(shapes)}), got {n}")
    pick = np.random.default_rng(seed).choice(len(shapes), size=n, replace=False)
    return sorted(shapes[i] for i in pick)


@dataclass(frozen=True)
class TuningShape:
    """One tuning shape, as a worker scores the candidates on it (:func:`tune_shape`).

    Attributes
    ----------
    name : str
        The shape (:func:`a2l.experiments.lasa_methods.lasa_shapes`).
    config : a2l.experiments.lasa_config.LasaConfig
        The benchmark's parameters; each DS candidate replaces its ``beta``, ``mu`` and
        ``arrival``.
    """

    name: str
    config: LasaConfig


def tune_shape(task: TuningShape) -> dict[str, list[float]]:
    """Held-out DTW of every candidate on one shape.

    Returns
    -------
    dict
        ``{"ds": [DTW per DS candidate], "dmp": [DTW per DMP candidate]}``.
    """
    cfg = task.config
    demos, durations = load_lasa_shape(task.name)
    train, train_t, test, test_t = split(demos, durations, "heldout")
    ds_dtw = []
    for cand in DS_CANDIDATES:
        c = replace(cfg, **cand)
        ds, _ = fit_ds(train, train_t, c.fit_parameters(), c.arrival, {})
        ds_dtw.append(scores(ds_reproductions(ds, test, test_t), test, test_t)["dtw"])
    dmp_dtw = [scores(dmp_reproductions(train, train_t, test, c["dmp_weights"],
                                        c["dmp_regularisation"]), test, test_t)["dtw"]
               for c in DMP_CANDIDATES]
    return {"ds": ds_dtw, "dmp": dmp_dtw}


def choose(per_shape: dict[str, dict[str, list[float]]]) -> dict[str, Any]:
    """The candidates with the smallest mean held-out DTW over the tuning shapes.

    Returns
    -------
    dict
        ``{"ds": settings, "dmp": settings, "ds_dtw": [mean per candidate],
        "dmp_dtw": [...]}``.
    """
    ds_mean = np.mean([v["ds"] for v in per_shape.values()], axis=0)
    dmp_mean = np.mean([v["dmp"] for v in per_shape.values()], axis=0)
    return {"ds": DS_CANDIDATES[int(np.argmin(ds_mean))],
            "dmp": DMP_CANDIDATES[int(np.argmin(dmp_mean))],
            "ds_dtw": ds_mean.tolist(), "dmp_dtw": dmp_mean.tolist()}
