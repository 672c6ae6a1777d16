"""The parameters of the LASA handwriting benchmark (:mod:`a2l.experiments.lasa`):
:class:`LasaConfig`, shared by the experiment and its tuning
(:mod:`a2l.experiments.lasa_tuning`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from a2l.lfd.fit import BETA_SCHEDULE, FIT_DIRECTIONS, MU_SCHEDULE, schedule

__all__ = ["LasaConfig"]


@dataclass(frozen=True)
class LasaConfig:
    """Parameters of the LASA benchmark (all saved in ``config.json``).

    Attributes
    ----------
    K : int
        Maps per DS.
    beta, mu : float or None
        Constant fit parameters; None uses the schedules over the maps
        :data:`a2l.lfd.fit.BETA_SCHEDULE` and :data:`a2l.lfd.fit.MU_SCHEDULE`.
    regularisation : float
        Weight of rho^2 in the width search.
    n_starts : int
        Random starts per shape for the convergence test.
    tolerance : float
        A start converged when the integrated DS comes within this fraction of the
        demonstrations' scale (the largest side of their bounding box) of the target.
    enlarge : float
        The start box is the demonstrations' bounding box enlarged by this fraction.
    horizon : float
        Longest rollout of the convergence test, in demonstration durations.
    control_dt : float
        Euler step of the convergence test (s): the runtime's control period (1 kHz).
    arrival : float
        The speed gain's end fraction: in line space a reproduction is left with this
        fraction of its start distance to the target after the demonstrations' mean
        duration (:func:`a2l.lfd.fit.speed_gain`).
    dmp_weights : int
        Basis functions per dimension of the DMP baseline.
    dmp_regularisation : float
        Ridge regularisation of the DMP's weights (``movement_primitives``).
    grid : int
        Streamline grid size (grid x grid points) for the figure.
    query_points : int
        Query-timing points per demonstration, uniform in its bounding box.
    seed : int
        Seed of the random starts and query points (shape i uses seed + i).
    direction : str
        Which way the maps are fitted (:func:`a2l.lfd.fit.fit_diffeo`): ``"auto"`` (both,
        the smaller mean fit error kept), ``"to_line"`` (explicit velocity queries) or
        ``"to_demo"`` (the paper's: queries solve K scalar equations).
    tune : bool
        Choose the DS's beta, mu and arrival and the DMP's weights and regularisation on
        the tuning shapes first (:mod:`a2l.experiments.lasa_tuning`), overriding the
        values given here.
    tuning_shapes : int
        Size of the tuning split (drawn with :data:`a2l.experiments.lasa_tuning.TUNING_SEED`).
    """

    K: int = 150
    beta: float | None = None
    mu: float | None = None
    regularisation: float = 1e-5
    n_starts: int = 10_000
    tolerance: float = 0.01
    enlarge: float = 0.5
    horizon: float = 3.0
    control_dt: float = 1e-3
    arrival: float = 1e-3
    dmp_weights: int = 50
    dmp_regularisation: float = 0.0
    grid: int = 40
    query_points: int = 200
    seed: int = 0
    direction: str = "auto"
    tune: bool = True
    tuning_shapes: int = 10

    def validate(self) -> None:
        """Raise ValueError naming the first out-of-range parameter."""
        if self.K < 1:
            raise ValueError(f"K must be >= 1, got {self.K}")
        if self.beta is not None and not 0 < self.beta <= 1:
            raise ValueError(f"beta must be in (0, 1], got {self.beta}")
        if self.mu is not None and not 0 < self.mu < 1:
            raise ValueError(f"mu must be in (0, 1), got {self.mu}")
        for name in ("regularisation", "dmp_regularisation"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        for name in ("n_starts", "dmp_weights", "grid", "query_points"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)}")
        for name in ("tolerance", "enlarge", "horizon", "control_dt"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if not 0 < self.arrival < 1:
            raise ValueError(f"arrival must be in (0, 1), got {self.arrival}")
        if self.direction not in FIT_DIRECTIONS:
            raise ValueError(f"direction must be one of {FIT_DIRECTIONS}, got {self.direction!r}")
        if not 0 <= self.tuning_shapes < 30:
            raise ValueError(f"tuning_shapes must be in [0, 30), got {self.tuning_shapes}")

    def fit_parameters(self) -> dict[str, Any]:
        """Keyword arguments of :func:`a2l.lfd.fit.fit_diffeo` (K, beta, mu, regularisation,
        direction)."""
        beta = schedule(BETA_SCHEDULE, max(self.K - 1, 1)) if self.beta is None else self.beta
        mu = schedule(MU_SCHEDULE, self.K) if self.mu is None else self.mu
        return {"K": self.K, "beta": beta, "mu": mu, "regularisation": self.regularisation,
                "direction": self.direction}
