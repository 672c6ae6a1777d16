"""The ask/tell protocol every acquisition strategy follows (as pyribs' schedulers do).

A strategy proposes candidates (:meth:`Strategy.ask`: trajectories, or the tasks that play
them), somebody evaluates them where it likes (in this process, on workers, on Dask), and
the strategy is told what came out (:meth:`Strategy.tell`), in the order it asked. It never
evaluates anything itself, so the same strategy runs alone (:func:`drive`) or inside the
framework's loop, and what it learns is only what it is told.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Protocol, runtime_checkable

__all__ = ["Strategy", "drive"]


@runtime_checkable
class Strategy(Protocol):
    """An acquisition strategy.

    Attributes
    ----------
    done : bool
        True when the strategy wants no more evaluations (its target is met or its budget
        spent).
    """

    @property
    def done(self) -> bool: ...

    def ask(self, n: int) -> list[Any]:
        """At most `n` new candidates (fewer when the budget ends; none when done)."""
        ...

    def tell(self, asked: Sequence[Any], outcomes: Sequence[Any]) -> None:
        """The outcomes of the candidates `asked` (same order, same length)."""
        ...


def drive(strategy: Strategy, evaluate: Callable[[Sequence[Any]], Sequence[Any]],
          batch: int, on_batch: Callable[[Strategy], None] | None = None) -> Strategy:
    """Ask, evaluate and tell in batches of `batch` until the strategy is done.

    Parameters
    ----------
    strategy : Strategy
        The strategy to run.
    evaluate : callable
        ``evaluate(candidates) -> outcomes``, e.g. ``lambda c: executor.map(task, c)``.
    batch : int
        Candidates asked at a time.
    on_batch : callable, optional
        Called with the strategy after each batch is told (progress bars).

    Returns
    -------
    Strategy
        The same strategy, done.
    """
    if batch < 1:
        raise ValueError(f"batch must be >= 1, got {batch}")
    while not strategy.done:
        asked = strategy.ask(batch)
        if not asked:
            raise RuntimeError(f"{type(strategy).__name__} is not done but asked for nothing")
        outcomes = evaluate(asked)
        if len(outcomes) != len(asked):
            raise ValueError(f"evaluate returned {len(outcomes)} outcomes for {len(asked)} "
                             "candidates")
        strategy.tell(asked, outcomes)
        if on_batch:
            on_batch(strategy)
    return strategy
