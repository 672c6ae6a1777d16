"""NovEB: novelty-driven evolutionary babbling (``docs/method.md``; thesis chapter 4), with DEAP.

Genotypes are trajectory parameters in [0, 1] (:class:`a2l.acquisition.trajectory.
WaypointEncoding`); the behaviour of a genotype is a descriptor of the camera image after
its movement (:func:`a2l.acquisition.images.image_descriptor`). Novelty is the mean
distance to the ``k`` nearest neighbours among the population, the new generation and the
archive; a behaviour whose novelty exceeds the adaptive threshold enters the archive
(:class:`ArchiveThreshold`); a (μ + λ) selection on novelty keeps the population.

The strategy is told descriptors only (:meth:`NovEB.tell` refuses anything but a float
array of them): it cannot see where objects are, only how images changed.
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from deap import base, creator, tools
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.distance import cdist

__all__ = ["ArchiveThreshold", "NovEB", "NovEBConfig", "novelty"]

if not hasattr(creator, "NovEBFitness"):
    creator.create("NovEBFitness", base.Fitness, weights=(1.0,))
    creator.create("NovEBIndividual", list, fitness=creator.NovEBFitness)


def novelty(behaviours: ArrayLike, reference: ArrayLike, k: int = 15,
            self_in_reference: bool = True) -> NDArray[np.float64]:
    """Mean distance of each behaviour to its `k` nearest neighbours in `reference`.

    Distances are root-mean-square differences (Euclidean over the square root of the
    dimension), so a threshold does not depend on the image size.

    Parameters
    ----------
    behaviours : array_like, shape (n, d)
        Descriptors to score.
    reference : array_like, shape (m, d)
        The behaviours they are compared with.
    k : int
        Neighbours (fewer when `reference` is smaller).
    self_in_reference : bool
        Row ``i`` of `behaviours` is also row ``i`` of `reference` (the first `n` rows);
        its zero distance to itself is not a neighbour.

    Returns
    -------
    ndarray, shape (n,)
    """
    b = np.atleast_2d(np.asarray(behaviours, dtype=float))
    r = np.atleast_2d(np.asarray(reference, dtype=float))
    if b.shape[1] != r.shape[1]:
        raise ValueError(f"descriptors of dimension {b.shape[1]} vs reference {r.shape[1]}")
    if k < 1:
        raise ValueError(f"k must be >= 1, got {k}")
    d = cdist(b, r) / np.sqrt(b.shape[1])
    if self_in_reference:
        d[np.arange(len(b)), np.arange(len(b))] = np.inf
    m = r.shape[0] - (1 if self_in_reference else 0)
    if m < 1:
        return np.zeros(len(b))
    kk = min(k, m)
    nearest = np.partition(d, kk - 1, axis=1)[:, :kk]
    return nearest.mean(axis=1)


@dataclass
class ArchiveThreshold:
    """The adaptive archive threshold (Lehman & Stanley's rule as usually implemented).

    Multiplied by `raise_factor` after a generation in which `raise_after` or more
    behaviours entered the archive; by `lower_factor` after `lower_after` generations in a
    row with none; never below `floor`.
    """

    value: float = 0.02
    raise_after: int = 4
    raise_factor: float = 1.2
    lower_after: int = 10
    lower_factor: float = 0.95
    floor: float = 1e-3
    idle: int = 0

    def __post_init__(self) -> None:
        if not (self.value > 0 and self.floor > 0 and self.raise_factor > 1
                and 0 < self.lower_factor < 1 and self.raise_after >= 1
                and self.lower_after >= 1):
            raise ValueError(f"bad archive threshold parameters: {self}")

    def update(self, admitted: int) -> float:
        """Adapt to the number of behaviours `admitted` in the last generation; the new
        value."""
        if admitted >= self.raise_after:
            self.value *= self.raise_factor
        if admitted == 0:
            self.idle += 1
            if self.idle >= self.lower_after:
                self.value = max(self.floor, self.value * self.lower_factor)
                self.idle = 0
        else:
            self.idle = 0
        return self.value


@dataclass(frozen=True)
class NovEBConfig:
    """NovEB's parameters.

    Attributes
    ----------
    mu, lambda_ : int
        Population and offspring sizes of the (μ + λ) selection.
    k : int
        Nearest neighbours of the novelty.
    threshold : float
        Initial archive threshold (RMS descriptor distance).
    cx_prob : float
        Probability that an offspring is a simulated-binary crossover of two parents
        (otherwise a mutated copy of one).
    eta_cx, eta_mut : float
        Crowding degrees of DEAP's bounded SBX crossover and polynomial mutation.
    mut_gene_prob : float
        Probability that a gene mutates.
    """

    mu: int = 20
    lambda_: int = 20
    k: int = 15
    threshold: float = 0.02
    cx_prob: float = 0.3
    eta_cx: float = 10.0
    eta_mut: float = 10.0
    mut_gene_prob: float = 0.5


class NovEB:
    """Novelty-driven evolutionary babbling behind the ask/tell protocol.

    The first generation is `mu` uniform genotypes; each later one is `lambda_` offspring
    of the population. :meth:`ask` hands out the current generation (in pieces if asked
    so); when all of it has been told, the archive and the population are updated.

    Parameters
    ----------
    n_genes : int
        Genotype length.
    seed : int
        Seed of every draw (DEAP's operators draw from a private :class:`random.Random`
        state seeded from it, the global one is left alone).
    budget : int
        Evaluations after which the strategy is done.
    config : NovEBConfig, optional
    """

    def __init__(self, n_genes: int, seed: int, budget: int,
                 config: NovEBConfig | None = None) -> None:
        self.cfg = config or NovEBConfig()
        if n_genes < 1 or budget < 1:
            raise ValueError(f"n_genes and budget must be >= 1, got {n_genes}, {budget}")
        self.n_genes, self.budget = int(n_genes), int(budget)
        self.rng = np.random.default_rng(seed)
        self._py = random.Random(int(self.rng.integers(2**63)))
        self.threshold = ArchiveThreshold(value=self.cfg.threshold)
        self.population: list[Any] = []
        self.archive: list[NDArray[np.float64]] = []
        self.generation = 0
        self.told = 0
        self.history: list[dict[str, float]] = []
        self._pending: list[Any] = []
        self._asked = 0
        self._told_gen: list[tuple[Any, NDArray[np.float64]]] = []

    @property
    def done(self) -> bool:
        """The evaluation budget is spent."""
        return self.told >= self.budget

    def _individual(self, genes: Sequence[float]) -> Any:
        return creator.NovEBIndividual(float(g) for g in genes)

    def _new_generation(self) -> list[Any]:
        c = self.cfg
        if not self.population:
            return [self._individual(self.rng.random(self.n_genes)) for _ in range(c.mu)]
        state = random.getstate()
        random.setstate(self._py.getstate())
        try:
            out = []
            for _ in range(c.lambda_):
                if self.rng.random() < c.cx_prob and len(self.population) > 1:
                    i, j = self.rng.choice(len(self.population), 2, replace=False)
                    a = self._individual(self.population[i])
                    b = self._individual(self.population[j])
                    child, _ = tools.cxSimulatedBinaryBounded(a, b, c.eta_cx, 0.0, 1.0)
                else:
                    child = self._individual(
                        self.population[int(self.rng.integers(len(self.population)))])
                (child,) = tools.mutPolynomialBounded(child, c.eta_mut, 0.0, 1.0,
                                                      c.mut_gene_prob)
                out.append(self._individual(np.clip(child, 0.0, 1.0)))
            self._py.setstate(random.getstate())
        finally:
            random.setstate(state)
        return out

    def ask(self, n: int) -> list[NDArray[np.float64]]:
        """At most `n` genotypes of the current generation, shape (n_genes,) each."""
        if self.done or n < 1:
            return []
        if self._asked == len(self._pending):
            if self._told_gen:
                raise RuntimeError("NovEB: tell the outcomes of the current generation "
                                   "before asking for the next")
            self._pending = self._new_generation()
            self._asked = 0
        n = min(n, len(self._pending) - self._asked, self.budget - self.told - self._asked)
        out = self._pending[self._asked: self._asked + n]
        self._asked += n
        return [np.array(ind, dtype=float) for ind in out]

    def tell(self, asked: Sequence[ArrayLike], outcomes: ArrayLike) -> None:
        """The behaviour descriptors of the genotypes `asked`.

        Parameters
        ----------
        asked : sequence of genotypes
            As returned by :meth:`ask`, in order.
        outcomes : ndarray of float, shape (len(asked), d)
            Their image descriptors, and nothing else.
        """
        if not isinstance(outcomes, np.ndarray) or outcomes.dtype.kind != "f" \
                or outcomes.ndim != 2:
            raise TypeError("NovEB is told image descriptors only: a float array of shape "
                            f"(n, d), got {type(outcomes).__name__}")
        if len(outcomes) != len(asked):
            raise ValueError(f"{len(outcomes)} descriptors for {len(asked)} genotypes")
        start = len(self._told_gen)
        for i, (g, d) in enumerate(zip(asked, outcomes, strict=True)):
            ind = self._pending[start + i]
            if not np.allclose(np.asarray(g, dtype=float), np.asarray(ind, dtype=float)):
                raise ValueError("NovEB: outcomes told out of ask order")
            self._told_gen.append((ind, np.asarray(d, dtype=float)))
        self.told += len(asked)
        if len(self._told_gen) == self._asked and (self._asked == len(self._pending)
                                                  or self.done):
            self._close_generation()

    def _close_generation(self) -> None:
        new = [ind for ind, _ in self._told_gen]
        new_b = np.array([d for _, d in self._told_gen])
        for ind, d in self._told_gen:
            ind.behaviour = d
        pool = self.population + new
        pool_b = np.array([ind.behaviour for ind in pool])
        ref = np.vstack([pool_b, *([np.array(self.archive)] if self.archive else [])])
        nov = novelty(pool_b, ref, self.cfg.k, self_in_reference=True)
        new_nov = nov[len(self.population):]
        admitted = 0
        for d, v in zip(new_b, new_nov, strict=True):
            if v > self.threshold.value:
                self.archive.append(d)
                admitted += 1
        for ind, v in zip(pool, nov, strict=True):
            ind.fitness.values = (float(v),)
        self.population = tools.selBest(pool, self.cfg.mu)
        self.history.append({"generation": self.generation, "admitted": admitted,
                             "threshold": self.threshold.value,
                             "mean_novelty": float(np.mean(new_nov))})
        self.threshold.update(admitted)
        self.generation += 1
        self._told_gen = []
        self._pending = []
        self._asked = 0
