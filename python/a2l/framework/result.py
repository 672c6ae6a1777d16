"""What a whole A2L run returns (:class:`FrameworkResult`, from
:func:`a2l.framework.run_framework`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import pandas as pd

__all__ = ["FrameworkResult"]


@dataclass(frozen=True)
class FrameworkResult:
    """The outcome of :func:`a2l.framework.run_framework`.

    Attributes
    ----------
    iterations : list of dict
        Each iteration's metrics (:class:`a2l.framework.IterationResult` as a dict: score,
        success rates, false positives, dataset size, accepted, wall time).
    final_score : float
        The accepted skill's score on the training starts (0-100).
    bundle : str
        Path of the accepted skill bundle.
    dataset : pandas.DataFrame
        The accepted dataset (raw rows, :mod:`a2l.data.schema`).
    validation : pandas.DataFrame
        The accepted iteration's validation rollouts
        (:func:`a2l.acquisition.interactions.rollouts_table`).
    heldout : list of dict
        Each iteration's held-out metrics (:func:`a2l.framework.heldout_metrics`, plus
        ``heldout_wall_s``), apart from ``iterations``: the held-out rollouts run after the
        iteration's own metrics are taken and decide nothing (no acceptance, no stuck pair,
        no draw of training).
    heldout_score, heldout_success : float or None
        The accepted skill's held-out score and success rate (a false positive a failure);
        None without held-out starts.
    heldout_success_rate : dict or None
        The accepted skill's held-out success rate per effect name.
    heldout_validation : pandas.DataFrame
        The accepted skill's held-out rollouts (empty without held-out starts).
    movements : list of dict
        Each iteration's robot movements per phase and their running totals (the discrete
        movements the scene executed, counted from the rollouts told to the run, so the
        same with 1 and 2 workers); empty for a run resumed from a checkpoint written before
        they were counted.
    """

    iterations: list[dict[str, Any]]
    final_score: float
    bundle: str
    dataset: pd.DataFrame
    validation: pd.DataFrame
    heldout: list[dict[str, Any]] = field(default_factory=list)
    heldout_score: float | None = None
    heldout_success: float | None = None
    heldout_success_rate: dict[str, float] | None = None
    heldout_validation: pd.DataFrame = field(default_factory=pd.DataFrame)
    movements: list[dict[str, Any]] = field(default_factory=list)
