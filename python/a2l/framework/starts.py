"""Where rollouts start: the training starts' layout and the held-out starts' draws.

The training starts are a fixed layout around the object
(:meth:`~a2l.framework.config.FrameworkConfig.start_offsets`, whose ring orders its radii by
:func:`spread_ranks`); the held-out starts are drawn from a seed stream of their own
(:data:`HELDOUT_STREAM`, :func:`heldout_offsets`), and a start the arm cannot reach is
replaced by a redraw from a stream of its own (:func:`heldout_redraw`). The configuration's
methods (:meth:`~a2l.framework.config.FrameworkConfig.heldout_offsets`,
:meth:`~a2l.framework.config.FrameworkConfig.heldout_redraw`) draw them with its fields.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["HELDOUT_REDRAWS", "HELDOUT_STREAM", "heldout_offsets", "heldout_redraw",
           "spread_ranks"]

#: Tag of the held-out starts' seed stream: their generator is seeded by
#: ``(seed, HELDOUT_STREAM)``, a sequence no training draw (``(seed, iteration, phase,
#: index)``) uses.
HELDOUT_STREAM = 0x68656C64


def spread_ranks(n: int) -> np.ndarray:
    """A permutation of ``0 .. n-1``, shape (n,): the indices ordered by their bit-reversed
    value (van der Corput), so consecutive entries are far apart."""
    bits = max(1, (n - 1).bit_length())
    rev = [int(format(i, f"0{bits}b")[::-1], 2) for i in range(n)]
    ranks = np.empty(n, dtype=float)
    ranks[np.argsort(rev, kind="stable")] = np.arange(n)
    return ranks


#: Most redraws of one held-out start the arm cannot reach (:func:`heldout_redraw`).
HELDOUT_REDRAWS = 20


def heldout_redraw(seed: int, start: int, attempt: int, r_low: float, r_high: float
                   ) -> np.ndarray:
    """Replacement `attempt` (1, 2, ...) for held-out start `start` of the run seeded `seed`
    when the arm cannot reach it, shape (3,): the same distribution as
    :func:`heldout_offsets` (uniform angle, distance uniform in ``[r_low, r_high]``) from a
    stream of its own, ``(seed, HELDOUT_STREAM, start, attempt)``, so a redraw depends on
    neither the other starts nor the worker."""
    if attempt < 1:
        raise ValueError(f"attempt: must be >= 1, got {attempt}")
    rng = np.random.default_rng(np.random.SeedSequence([seed, HELDOUT_STREAM, start, attempt]))
    a = rng.uniform(0.0, 2 * np.pi)
    r = rng.uniform(r_low, r_high)
    return np.array([r * np.cos(a), r * np.sin(a), 0.0])


@functools.lru_cache(maxsize=16)
def _heldout_offsets(seed: int, n: int, r_low: float, r_high: float) -> np.ndarray:
    # cached: every held-out task asks for its run's starts
    rng = np.random.default_rng(np.random.SeedSequence([seed, HELDOUT_STREAM]))
    a = rng.uniform(0.0, 2 * np.pi, n)
    r = rng.uniform(r_low, r_high, n)
    return np.stack([r * np.cos(a), r * np.sin(a), np.zeros(n)], axis=1)


def heldout_offsets(seed: int, n: int, r_low: float, r_high: float) -> np.ndarray:
    """`n` held-out end-effector start positions relative to the object, shape (n, 3):
    uniform angle, distance uniform in ``[r_low, r_high]``, from the generator seeded with
    ``(seed, HELDOUT_STREAM)`` (a fresh copy: the draw is cached)."""
    return _heldout_offsets(seed, n, r_low, r_high).copy()
