"""Progress bars on the terminal (``rich``), silent when quiet: the one progress helper.

:class:`ProgressBars` shows one bar per named task (label, bar, done/total, elapsed time and
an optional info text), added on its first update; :func:`progress_bar` is the common case
of a single bar, yielding an ``on_done(n)`` callback::

    with progress_bar("trials", len(tasks), quiet) as on_done:
        run(tasks, on_done=on_done)  # on_done is None when quiet

``rich`` is imported only when a bar is shown.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import Any

__all__ = ["ProgressBars", "progress_bar"]


class ProgressBars:
    """Named progress bars (a context manager; nothing is shown when `quiet`).

    Parameters
    ----------
    quiet : bool
        Show nothing: every method does nothing.
    """

    def __init__(self, quiet: bool = False) -> None:
        self.quiet = quiet
        self._rich: Any = None
        self._tasks: dict[str, Any] = {}

    def __enter__(self) -> ProgressBars:
        if not self.quiet:
            # imported here: rich costs an import only when a bar is shown
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

            self._rich = Progress("[bold]{task.description}", BarColumn(), MofNCompleteColumn(),
                                  TimeElapsedColumn(), "{task.fields[info]}")
            self._rich.start()
        return self

    def __exit__(self, *exc: object) -> None:
        if self._rich is not None:
            self._rich.stop()
            self._rich = None
        self._tasks.clear()

    def update(self, label: str, done: int, total: int | None = None, info: str = "") -> None:
        """Set bar `label` (added on first use) to `done` of `total`, with an info text.

        Parameters
        ----------
        label : str
            The bar's name, shown in bold.
        done : int
            Items done.
        total : int, optional
            Items in all (kept from the previous update when None).
        info : str
            Text shown after the elapsed time.
        """
        if self._rich is None:
            return
        if label not in self._tasks:
            self._tasks[label] = self._rich.add_task(label, total=total, info=info)
        self._rich.update(self._tasks[label], completed=done, total=total, info=info)

    def counter(self, label: str, total: int) -> Callable[[int], None] | None:
        """An ``on_done(n)`` callback setting bar `label` to `n` of `total` (None when quiet)."""
        if self._rich is None:
            return None
        self.update(label, 0, total)
        return lambda n: self.update(label, n, total)

    def print(self, text: str) -> None:
        """Print a line above the bars (nothing when quiet)."""
        if self._rich is not None:
            self._rich.console.print(text)

    def clear(self) -> None:
        """Remove every bar (the next updates add new ones)."""
        if self._rich is not None:
            for task in self._tasks.values():
                self._rich.remove_task(task)
        self._tasks.clear()


@contextlib.contextmanager
def progress_bar(label: str, total: int, quiet: bool = False
                 ) -> Iterator[Callable[[int], None] | None]:
    """One progress bar over `total` items; yields its ``on_done(n)`` callback.

    Parameters
    ----------
    label : str
        The bar's name.
    total : int
        Items in all.
    quiet : bool
        Show nothing and yield None.

    Yields
    ------
    callable or None
        ``on_done(n)``: `n` items are done; None when quiet.
    """
    with ProgressBars(quiet) as bars:
        yield bars.counter(label, total)
