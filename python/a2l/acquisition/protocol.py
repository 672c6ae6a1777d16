"""The ask/tell protocol every acquisition strategy follows (as pyribs' schedulers do).

A strategy proposes candidates (:meth:`Strategy.ask`: trajectories, or the tasks that play
them), somebody evaluates them where it likes (in this process, on workers, on Dask), and
the strategy is told what came out (:meth:`Strategy.tell`), in the order it asked. It never
evaluates anything itself, so the same strategy runs alone (:func:`drive`) or inside the
framework's loop, and what it learns is only what it is told.

A strategy whose candidates do not depend on the outcomes (only whether it goes on does:
random babbling, effect-directed trajectories) can say so with ``asks_ahead = True``: it
may then be asked again before it is told, and gives the candidates that follow.
:func:`drive_ahead` uses that to keep workers busy while outcomes travel back: the next
round is evaluated while the strategies are told the previous one, and what a strategy
was asked past the point where it is done is dropped, so it ends exactly as with
:func:`drive`.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Sequence
from typing import Any, Protocol, runtime_checkable

__all__ = ["Strategy", "drive", "drive_ahead"]


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
          batch: int, *, told: Callable[[Sequence[Any]], Any] | None = None,
          on_batch: Callable[[Sequence[Any], Sequence[Any]], None] | None = None) -> Strategy:
    """Ask, evaluate and tell in batches of `batch` until the strategy is done.

    Each batch is asked, evaluated, told, then handed to `on_batch`, in that order: the
    strategy's random draws are those of a loop written by hand the same way.

    Parameters
    ----------
    strategy : Strategy
        The strategy to run.
    evaluate : callable
        ``evaluate(candidates) -> outcomes``, e.g. ``lambda c: executor.map(task, c)``.
    batch : int
        Candidates asked at a time.
    told : callable, optional
        What the strategy is told of a batch's outcomes: ``told(outcomes)``, e.g. the
        descriptors of evaluations that carry more; default: the outcomes themselves.
    on_batch : callable, optional
        ``on_batch(asked, outcomes)`` after each batch is told (records, progress bars).

    Returns
    -------
    Strategy
        The same strategy, done.

    Raises
    ------
    ValueError
        ``batch < 1``, or `evaluate` returned a number of outcomes other than asked.
    RuntimeError
        The strategy is not done but asks for nothing.
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
        strategy.tell(asked, outcomes if told is None else told(outcomes))
        if on_batch:
            on_batch(asked, outcomes)
    return strategy


def drive_ahead(strategies: Sequence[Any], submit: Callable[[list[tuple[Any, Any]]], Any],
                batch: int, ahead: int = 1,
                on_round: Callable[[], None] | None = None) -> None:
    """Drive ask-ahead strategies together, with `ahead` rounds evaluated in advance.

    Each round asks every strategy not yet done for `batch` candidates and submits them all
    at once; rounds are told in order, each strategy its own part, unless it is done by
    then (the part is dropped). With ``ahead = 0`` this is :func:`drive` for several
    strategies at once; with more, the next rounds run while a round's outcomes come back,
    at the cost of evaluating up to `ahead` batches per strategy that are dropped (less:
    when a strategy is done, its part of the rounds in flight is given up where it has not
    started, if the submission has a ``drop(flags)`` method, as
    :meth:`a2l.parallel.Pending.drop`). Either way every strategy is asked and told exactly
    what :func:`drive` would ask and tell it.

    Parameters
    ----------
    strategies : sequence of Strategy
        Each with ``asks_ahead = True`` (see the module's docstring).
    submit : callable
        ``submit([(strategy, candidate), ...])`` -> an object whose ``result()`` returns
        the outcomes in that order (e.g. :meth:`a2l.parallel.Executor.submit`; the outcome
        of a candidate given up may be None).
    batch : int
        Candidates asked of each strategy per round.
    ahead : int
        Rounds submitted beyond the one waited for (0: none).
    on_round : callable, optional
        Called after each round is told (progress bars).

    Raises
    ------
    TypeError
        A strategy that cannot be asked ahead.
    RuntimeError
        A strategy not done that has nothing left to ask.
    """
    if batch < 1:
        raise ValueError(f"batch must be >= 1, got {batch}")
    if ahead < 0:
        raise ValueError(f"ahead must be >= 0, got {ahead}")
    for s in strategies:
        if not getattr(s, "asks_ahead", False):
            raise TypeError(f"{type(s).__name__} cannot be asked ahead (asks_ahead is not True)")
    inflight: deque[tuple[list[tuple[Any, list[Any]]], Any]] = deque()

    def launch() -> bool:
        asks = [(s, s.ask(batch)) for s in strategies if not s.done]
        asks = [(s, asked) for s, asked in asks if asked]
        if asks:
            inflight.append((asks, submit([(s, c) for s, asked in asks for c in asked])))
        return bool(asks)

    while True:
        while len(inflight) <= ahead and launch():
            pass
        if not inflight:
            break
        asks, pending = inflight.popleft()
        outcomes = pending.result()
        n = sum(len(asked) for _, asked in asks)
        if len(outcomes) != n:
            raise ValueError(f"evaluate returned {len(outcomes)} outcomes for {n} candidates")
        k = 0
        for s, asked in asks:
            if not s.done:
                s.tell(asked, outcomes[k:k + len(asked)])
            k += len(asked)
        # what the rounds in flight asked of strategies done by now will be dropped: give
        # it up where it has not run yet (a2l.parallel.Pending.drop)
        for later_asks, later in inflight:
            if hasattr(later, "drop"):
                later.drop([s.done for s, asked in later_asks for _ in asked])
        if on_round:
            on_round()
    for s in strategies:
        if not s.done:
            raise RuntimeError(f"{type(s).__name__} is not done but asked for nothing")
