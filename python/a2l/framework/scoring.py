"""Scoring an iteration: the outcomes of a validation rollout, the success rate (the share of
rollouts that produced the wanted effect: a false positive is a failure, :func:`success_of`),
the score of ``docs/method.md`` (:func:`score_of`, which counts a false positive as a point)
and the metrics of one iteration (:class:`IterationResult`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from a2l.acquisition.interactions import Rollout
from a2l.framework.config import FrameworkConfig

__all__ = ["FAIL", "FALSE_POSITIVE", "SUCCESS", "FreshValidation", "IterationResult",
           "heldout_metrics", "iteration_metrics", "miss_counts", "outcome_of", "score_of",
           "success_of"]

#: Outcomes of one validation rollout.
SUCCESS, FALSE_POSITIVE, FAIL = "success", "false_positive", "fail"


def outcome_of(true_effect: int, wanted: int) -> str:
    """A validation rollout's outcome, judged by what happened to the object (its true
    effect, :attr:`a2l.acquisition.interactions.Rollout.true_effect`), not by what the robot saw:
    `SUCCESS` for the wanted effect, `FALSE_POSITIVE` for another one, `FAIL` for none."""
    if true_effect == wanted:
        return SUCCESS
    return FALSE_POSITIVE if true_effect >= 0 else FAIL


def score_of(rollouts: Sequence[Rollout], n_effects: int, n_starts: int) -> float:
    """The score: Σ(4·success + 1·false positive) / (4·n_effects·n_starts) · 100."""
    points = sum(4 if r.outcome == SUCCESS else 1 if r.outcome == FALSE_POSITIVE else 0
                 for r in rollouts)
    return 100.0 * points / (4 * n_effects * n_starts)


def success_of(rollouts: Sequence[Rollout]) -> float:
    """The success rate: the share of `rollouts` that produced their wanted effect (a false
    positive is a failure), in [0, 1]; NaN without rollouts."""
    return float(np.mean([r.outcome == SUCCESS for r in rollouts])) if rollouts else float("nan")


def miss_counts(rollouts: Sequence[Rollout]) -> dict[str, int]:
    """How the rollouts that did not succeed ended: ``{"false_positive": n, <stop>: n}``,
    a fail counted by its stop (``unknown_context``, ``step_cap``, ``unreachable``, ...,
    ``""`` when the step never stopped the run), and ``"with_fallback"``: misses in which
    the skill took at least one fallback movement (a cell without data)."""
    out: dict[str, int] = {}
    for r in rollouts:
        if r.outcome == SUCCESS:
            continue
        key = FALSE_POSITIVE if r.outcome == FALSE_POSITIVE else (r.stop or "none")
        out[key] = out.get(key, 0) + 1
        if r.fallbacks:
            out["with_fallback"] = out.get("with_fallback", 0) + 1
    return out


@dataclass(frozen=True)
class FreshValidation:
    """An iteration's validation from its fresh starts (``validation.starts = "fresh"``).

    Attributes
    ----------
    success : float
        The candidate skill's success rate there.
    accepted_success : float or None
        The success rate there of the skill accepted before (None at iteration 0): the
        candidate is accepted when ``success`` is not lower.
    misses : dict
        How the candidate's misses there ended (:func:`miss_counts`).
    """

    success: float
    accepted_success: float | None
    misses: dict[str, int]


@dataclass
class IterationResult:
    """Metrics of one iteration (one entry of ``metrics.json``'s ``iterations``):
    ``success``, the success rate over every (training start, effect) pair, leads;
    ``success_rate`` per effect; ``score`` as ``docs/method.md`` defines it (the thesis'
    figure, on the training starts); ``fresh_success`` and ``fresh_accepted_success``: the
    candidate's and the skill accepted before's success rates from the iteration's fresh
    starts (:class:`FreshValidation`; None with ``validation.starts = "fixed"``), which
    decide acceptance then."""

    iteration: int
    success: float
    score: float
    success_rate: dict[str, float]
    false_positives: int
    mean_movements: float
    dataset_size: int
    accepted: bool
    wall_s: float
    fresh_success: float | None = None
    fresh_accepted_success: float | None = None
    fresh_misses: dict[str, int] | None = None


def iteration_metrics(cfg: FrameworkConfig, it: int, val: Sequence[Rollout], size: int,
                      accepted: bool, wall: float, fresh: FreshValidation | None = None
                      ) -> IterationResult:
    """The metrics of iteration `it` from its validation rollouts `val` from the training
    starts (dataset of `size` rows, `accepted` or not, `wall` seconds) and its `fresh`
    validation (None: none)."""
    rate = _success_rates(cfg, val)
    moves = [len(r.moves) for r in val if r.outcome == SUCCESS]
    return IterationResult(
        iteration=it, success=success_of(val),
        score=score_of(val, cfg.discretization.n_effects, cfg.starts.n_starts), success_rate=rate,
        false_positives=sum(r.outcome == FALSE_POSITIVE for r in val),
        mean_movements=float(np.mean(moves)) if moves else float("nan"),
        dataset_size=size, accepted=accepted, wall_s=wall,
        fresh_success=fresh.success if fresh else None,
        fresh_accepted_success=fresh.accepted_success if fresh else None,
        fresh_misses=fresh.misses if fresh else None)


def heldout_metrics(cfg: FrameworkConfig, it: int, held: Sequence[Rollout]) -> dict[str, Any]:
    """The held-out metrics of iteration `it` from its rollouts `held` from the
    ``cfg.heldout.n_starts`` held-out starts: ``{"iteration", "heldout_success" (overall
    success rate, :func:`success_of`), "heldout_success_rate": {effect: rate},
    "heldout_score", "heldout_false_positives", "heldout_misses"}`` (the score as
    :func:`score_of`, over the held-out starts; the misses as :func:`miss_counts`)."""
    return {"iteration": it,
            "heldout_success": success_of(held),
            "heldout_success_rate": _success_rates(cfg, held),
            "heldout_score": score_of(held, cfg.discretization.n_effects, cfg.heldout.n_starts),
            "heldout_false_positives": sum(r.outcome == FALSE_POSITIVE for r in held),
            "heldout_misses": miss_counts(held)}


def _success_rates(cfg: FrameworkConfig, rollouts: Sequence[Rollout]) -> dict[str, float]:
    """Share of the rollouts wanting each effect that produced it, by effect name."""
    names = cfg.discretization.discretizer().effects.values
    return {names[e]: float(np.mean([r.outcome == SUCCESS for r in rollouts if r.wanted == e]))
            for e in range(cfg.discretization.n_effects)}
