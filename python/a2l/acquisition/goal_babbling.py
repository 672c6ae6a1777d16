"""Random goal babbling (IMGEP in its simplest form, Forestier & Oudeyer; ``docs/method.md``) and
random motor babbling over the same trajectory encoding, behind the ask/tell protocol.

Both are told the same outcomes as NovEB, image descriptors, so the three strategies see
the world the same way and differ only in how they choose the next trajectory.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["GoalBabbling", "RandomTrajectories"]


def _check_outcomes(outcomes: ArrayLike, n: int) -> NDArray[np.float64]:
    if not isinstance(outcomes, np.ndarray) or outcomes.dtype.kind != "f" \
            or outcomes.ndim != 2:
        raise TypeError("a babbling strategy is told image descriptors only: a float array of "
                        f"shape (n, d), got {type(outcomes).__name__}")
    if len(outcomes) != n:
        raise ValueError(f"{len(outcomes)} outcomes for {n} genotypes")
    return outcomes


class RandomTrajectories:
    """Random motor babbling: uniform genotypes in [0, 1]^n_genes.

    Parameters
    ----------
    n_genes : int
        Genotype length.
    seed : int
        Seed of the draws.
    budget : int
        Evaluations after which the strategy is done.
    """

    def __init__(self, n_genes: int, seed: int, budget: int) -> None:
        if n_genes < 1 or budget < 1:
            raise ValueError(f"n_genes and budget must be >= 1, got {n_genes}, {budget}")
        self.n_genes, self.budget = int(n_genes), int(budget)
        self.rng = np.random.default_rng(seed)
        self.asked = 0
        self.told = 0

    @property
    def done(self) -> bool:
        """The evaluation budget is spent."""
        return self.told >= self.budget

    def ask(self, n: int) -> list[NDArray[np.float64]]:
        """At most `n` uniform genotypes."""
        n = max(0, min(n, self.budget - self.asked))
        self.asked += n
        return [self.rng.random(self.n_genes) for _ in range(n)]

    def tell(self, asked: Sequence[ArrayLike], outcomes: ArrayLike) -> None:
        """Count the evaluations (random babbling learns nothing from them)."""
        _check_outcomes(outcomes, len(asked))
        self.told += len(asked)


class GoalBabbling(RandomTrajectories):
    """Random goal babbling with a nearest-neighbour inverse model.

    The first `bootstrap` genotypes are uniform. Then each one is: a goal drawn uniformly in
    the box of the outcomes seen so far, enlarged by `enlarge` of its size on each side;
    the genotype whose outcome was nearest to the goal; that genotype plus Gaussian noise
    of standard deviation `sigma` (clipped to [0, 1]).

    Parameters
    ----------
    n_genes : int
        Genotype length.
    seed : int
        Seed of the draws.
    budget : int
        Evaluations after which the strategy is done.
    bootstrap : int
        Uniform genotypes first.
    sigma : float
        Exploration noise, in genotype units.
    enlarge : float
        Share of the outcome box added on each side where goals are drawn.
    """

    def __init__(self, n_genes: int, seed: int, budget: int, bootstrap: int = 20,
                 sigma: float = 0.05, enlarge: float = 0.1) -> None:
        super().__init__(n_genes, seed, budget)
        if bootstrap < 1:
            raise ValueError(f"bootstrap must be >= 1, got {bootstrap}")
        if sigma <= 0 or enlarge < 0:
            raise ValueError(f"need sigma > 0 and enlarge >= 0, got {sigma}, {enlarge}")
        self.bootstrap, self.sigma, self.enlarge = int(bootstrap), float(sigma), float(enlarge)
        self.genotypes: list[NDArray[np.float64]] = []
        self.outcomes: list[NDArray[np.float64]] = []

    def ask(self, n: int) -> list[NDArray[np.float64]]:
        """At most `n` genotypes, from the memory as it is now."""
        n = max(0, min(n, self.budget - self.asked))
        out = []
        if len(self.outcomes) < self.bootstrap:
            for _ in range(n):
                out.append(self.rng.random(self.n_genes))
        else:
            seen = np.array(self.outcomes)
            lo, hi = seen.min(axis=0), seen.max(axis=0)
            pad = self.enlarge * (hi - lo)
            for _ in range(n):
                goal = self.rng.uniform(lo - pad, hi + pad)
                nearest = int(np.argmin(np.sum((seen - goal) ** 2, axis=1)))
                g = self.genotypes[nearest] + self.rng.normal(0.0, self.sigma, self.n_genes)
                out.append(np.clip(g, 0.0, 1.0))
        self.asked += n
        return out

    def tell(self, asked: Sequence[ArrayLike], outcomes: ArrayLike) -> None:
        """Remember each (genotype, outcome) pair."""
        o = _check_outcomes(outcomes, len(asked))
        for g, y in zip(asked, o, strict=True):
            self.genotypes.append(np.asarray(g, dtype=float))
            self.outcomes.append(np.asarray(y, dtype=float))
        self.told += len(asked)
