"""Where rollouts start: the training starts' layout, each iteration's fresh validation
starts and the held-out starts' draws.

The training starts are a fixed layout around the object
(:meth:`~a2l.framework.config.FrameworkConfig.start_offsets`, whose ring orders its radii by
:func:`spread_ranks`). The fresh validation starts are drawn anew each iteration from the
training seed stream (:data:`FRESH_PHASE`, :func:`fresh_offsets`); the held-out starts from a
stream of their own (:data:`HELDOUT_STREAM`, :func:`heldout_offsets`), so the two never
share a draw. A drawn start the arm cannot reach is replaced by a redraw from a stream of its
own (:func:`fresh_redraw`, :func:`heldout_redraw`). The configuration's methods
(:meth:`~a2l.framework.config.FrameworkConfig.start_offset`,
:meth:`~a2l.framework.config.FrameworkConfig.heldout_offsets`, ...) draw them with its
fields.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["FRESH_PHASE", "HELDOUT_REDRAWS", "HELDOUT_STREAM", "fresh_offsets",
           "fresh_redraw", "heldout_offsets", "heldout_redraw", "ring_draw", "spread_ranks"]

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


#: Phase tag of the fresh validation starts in the training seed stream: iteration `i`'s are
#: drawn by a generator seeded ``(seed, i, FRESH_PHASE)``, the stream of every training draw
#: (``(seed, iteration, phase, index)``, :func:`a2l.framework.loop.phase_seed`), at a phase
#: no other draw uses (acquisition 0, extension 1, stuck pairs 2, 3, ...).
FRESH_PHASE = 0x66726573


def ring_draw(entropy: list[int], n: int, r_low: float, r_high: float) -> np.ndarray:
    """`n` positions on the ring around the object, shape (n, 3): uniform angle, distance
    uniform in ``[r_low, r_high]``, z 0, from the generator seeded with `entropy`."""
    rng = np.random.default_rng(np.random.SeedSequence(entropy))
    a = rng.uniform(0.0, 2 * np.pi, n)
    r = rng.uniform(r_low, r_high, n)
    return np.stack([r * np.cos(a), r * np.sin(a), np.zeros(n)], axis=1)


def fresh_offsets(seed: int, iteration: int, n: int, r_low: float, r_high: float
                  ) -> np.ndarray:
    """The `n` fresh validation starts of iteration `iteration` of the run seeded `seed`,
    relative to the object, shape (n, 3) (:func:`ring_draw` from ``(seed, iteration,
    FRESH_PHASE)``): start positions no earlier iteration validated from."""
    return ring_draw([seed, iteration, FRESH_PHASE], n, r_low, r_high)


def fresh_redraw(seed: int, iteration: int, start: int, attempt: int, r_low: float,
                 r_high: float) -> np.ndarray:
    """Replacement `attempt` (1, 2, ...) for fresh start `start` of iteration `iteration`
    when the arm cannot reach it, shape (3,): the same distribution, from ``(seed,
    iteration, FRESH_PHASE, start, attempt)``."""
    if attempt < 1:
        raise ValueError(f"attempt: must be >= 1, got {attempt}")
    return ring_draw([seed, iteration, FRESH_PHASE, start, attempt], 1, r_low, r_high)[0]


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
    return ring_draw([seed, HELDOUT_STREAM, start, attempt], 1, r_low, r_high)[0]


@functools.lru_cache(maxsize=16)
def _heldout_offsets(seed: int, n: int, r_low: float, r_high: float) -> np.ndarray:
    # cached: every held-out task asks for its run's starts
    return ring_draw([seed, HELDOUT_STREAM], n, r_low, r_high)


def heldout_offsets(seed: int, n: int, r_low: float, r_high: float) -> np.ndarray:
    """`n` held-out end-effector start positions relative to the object, shape (n, 3):
    uniform angle, distance uniform in ``[r_low, r_high]``, from the generator seeded with
    ``(seed, HELDOUT_STREAM)`` (a fresh copy: the draw is cached)."""
    return _heldout_offsets(seed, n, r_low, r_high).copy()
