"""Scoring an iteration: the outcomes of a validation rollout, the score of ``docs/method.md``
(:func:`score_of`) and the metrics of one iteration (:class:`IterationResult`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from a2l.acquisition.rollout import Rollout
from a2l.framework.config import FrameworkConfig, discretizers

__all__ = ["FAIL", "FALSE_POSITIVE", "SUCCESS", "IterationResult", "heldout_metrics",
           "iteration_metrics", "score_of"]

#: Outcomes of one validation rollout.
SUCCESS, FALSE_POSITIVE, FAIL = "success", "false_positive", "fail"


def score_of(rollouts: Sequence[Rollout], n_effects: int, n_starts: int) -> float:
    """The score: Σ(4·success + 1·false positive) / (4·n_effects·n_starts) · 100."""
    points = sum(4 if r.outcome == SUCCESS else 1 if r.outcome == FALSE_POSITIVE else 0
                 for r in rollouts)
    return 100.0 * points / (4 * n_effects * n_starts)


@dataclass
class IterationResult:
    """Metrics of one iteration (one entry of ``metrics.json``'s ``iterations``)."""

    iteration: int
    score: float
    success_rate: dict[str, float]
    false_positives: int
    mean_movements: float
    dataset_size: int
    accepted: bool
    wall_s: float


def iteration_metrics(cfg: FrameworkConfig, it: int, val: Sequence[Rollout], size: int,
                      accepted: bool, wall: float) -> IterationResult:
    """The metrics of iteration `it` from its validation rollouts `val` (dataset of `size`
    rows, `accepted` or not, `wall` seconds)."""
    rate = _success_rates(cfg, val)
    moves = [len(r.moves) for r in val if r.outcome == SUCCESS]
    return IterationResult(
        iteration=it, score=score_of(val, cfg.n_effects, cfg.n_starts), success_rate=rate,
        false_positives=sum(r.outcome == FALSE_POSITIVE for r in val),
        mean_movements=float(np.mean(moves)) if moves else float("nan"),
        dataset_size=size, accepted=accepted, wall_s=wall)


def heldout_metrics(cfg: FrameworkConfig, it: int, held: Sequence[Rollout]) -> dict[str, Any]:
    """The held-out metrics of iteration `it` from its rollouts `held` from the
    ``cfg.heldout_starts`` held-out starts: ``{"iteration", "heldout_score",
    "heldout_success_rate": {effect: rate}, "heldout_false_positives"}`` (the score as
    :func:`score_of`, over the held-out starts)."""
    return {"iteration": it,
            "heldout_score": score_of(held, cfg.n_effects, cfg.heldout_starts),
            "heldout_success_rate": _success_rates(cfg, held),
            "heldout_false_positives": sum(r.outcome == FALSE_POSITIVE for r in held)}


def _success_rates(cfg: FrameworkConfig, rollouts: Sequence[Rollout]) -> dict[str, float]:
    """Share of the rollouts wanting each effect that produced it, by effect name."""
    names = discretizers(cfg).effects.values
    return {names[e]: float(np.mean([r.outcome == SUCCESS for r in rollouts if r.wanted == e]))
            for e in range(cfg.n_effects)}
