"""What a command shows on the terminal: progress bars (``rich``), silent when quiet, the
one progress helper; and tables laid out to the terminal's width, the one table printer.

:class:`ProgressBars` shows one bar per named task (label, bar, done/total, elapsed time and
an optional info text), added on its first update; :func:`progress_bar` is the common case
of a single bar, yielding an ``on_done(n)`` callback::

    with progress_bar("trials", len(tasks), quiet) as on_done:
        run(tasks, on_done=on_done)  # on_done is None when quiet

``rich`` is imported only when a bar is shown.

:func:`print_tables` prints Markdown (a report's table, or a report) with each table laid
out by :func:`terminal_tables`: at 80 columns, or when the output is a file or a pipe, every
header and every number stays whole (the Markdown written to files is not touched).
"""

from __future__ import annotations

import contextlib
import re
import shutil
import textwrap
from collections.abc import Callable, Iterator
from typing import Any

__all__ = ["ProgressBars", "print_tables", "progress_bar", "terminal_tables", "terminal_width"]


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


# -- tables -------------------------------------------------------------------------------

#: Columns between two columns of a table laid out for the terminal.
GAP = 2
#: A cell up to this many characters is never wrapped (a number, a short phrase); a longer
#: one wraps at its spaces, to no fewer characters than this (nor than its longest word).
SHORT_CELL = 24
_SEPARATOR = re.compile(r"^\|?\s*:?-+:?\s*(\|\s*:?-+:?\s*)*\|?\s*$")


def terminal_width() -> int:
    """Columns to lay a table out in: the terminal's (``COLUMNS`` first, as
    :func:`shutil.get_terminal_size`), 80 when the output is not a terminal."""
    return max(20, shutil.get_terminal_size((80, 24)).columns)


def terminal_tables(markdown: str, width: int | None = None) -> str:
    """`markdown` with each of its tables laid out as plain text `width` columns wide (the
    other lines as they are): every header, word and number whole, never cut.

    A table is a grid of aligned columns under a rule, each header on one line, its long
    cells (past :data:`SHORT_CELL` characters) wrapped at their spaces when the natural
    widths do not fit. When even that does not fit, a table of fewer rows than columns (each
    row named by a distinct first cell, e.g. a run's iterations) is turned on its side: one
    line per column, the headers down the left and one column per row; any other table is
    cut into groups of columns that fit, each led again by the columns that name a row (the
    fewest leading columns telling the rows apart). Bold markers (``**``) are dropped. A
    column too wide for `width` on its own is left wider, not cut.

    Parameters
    ----------
    markdown : str
        Markdown text (a table, or a report holding tables).
    width : int, optional
        Columns of the output (default :func:`terminal_width`).

    Returns
    -------
    str
        The text to print.
    """
    width = terminal_width() if width is None else width
    lines, out, i = markdown.splitlines(), [], 0
    while i < len(lines):
        j = i
        while j < len(lines) and lines[j].lstrip().startswith("|"):
            j += 1
        if j - i >= 2 and _SEPARATOR.match(lines[i + 1].strip()):
            rows = [_cells(line) for k, line in enumerate(lines[i:j]) if k != 1]
            n = max(len(r) for r in rows)
            rows = [r + [""] * (n - len(r)) for r in rows]
            out += _layout(rows[0], rows[1:], width)
            i = j
        else:
            out.append(lines[i])
            i += 1
    return "\n".join(out)


def print_tables(markdown: str, width: int | None = None) -> None:
    """Print `markdown` with its tables laid out for the terminal (:func:`terminal_tables`):
    the one way a command prints a table."""
    print(terminal_tables(markdown, width), flush=True)


def _cells(line: str) -> list[str]:
    """The cells of one Markdown table row (escaped ``\\|`` kept as ``|``, bold dropped)."""
    line = line.strip().removeprefix("|")
    line = line[:-1] if line.endswith("|") and not line.endswith("\\|") else line
    return [c.replace("\\|", "|").replace("**", "").strip()
            for c in re.split(r"(?<!\\)\|", line)]


def _narrowest(text: str, short: int) -> int:
    """The fewest columns `text` may wrap to: all of it up to `short` characters, else down
    to `short` (or its longest word, when longer)."""
    if len(text) <= short:
        return len(text)
    return max(short, *(len(w) for w in text.split()))


def _layout(head: list[str], rows: list[list[str]], width: int, turned: bool = False
            ) -> list[str]:
    """Lines of the table `head` + `rows` in `width` columns (see :func:`terminal_tables`);
    `turned`: it is a table turned on its side, its first column the headers (kept whole)."""
    natural = [max(len(c) for c in col) for col in zip(head, *rows, strict=True)]
    least = [max([len(h), *(_narrowest(r[j], SHORT_CELL) for r in rows)])
             for j, h in enumerate(head)]
    if turned:
        least[0] = natural[0]
    if sum(least) + GAP * (len(head) - 1) <= width or len(head) <= 2:
        return _grid(head, rows, natural, least, width)
    keys = [r[0] for r in rows]
    if not turned and len(rows) < len(head) - 1 and len(set(keys)) == len(keys):
        side = [[h, *(r[j] for r in rows)] for j, h in enumerate(head)]
        return _layout(side[0], side[1:], width, turned=True)
    lead = _leading(rows, natural, width)
    groups: list[list[int]] = [[]]
    for j in range(lead, len(head)):
        used = sum(natural[k] + GAP for k in [*range(lead), *groups[-1]])
        if groups[-1] and used + natural[j] > width:
            groups.append([])
        groups[-1].append(j)
    out: list[str] = []
    for g in groups:
        cols = [*range(lead), *g]
        out += ([""] if out else []) + _grid(
            [head[k] for k in cols], [[r[k] for k in cols] for r in rows],
            [natural[k] for k in cols], [least[k] for k in cols], width)
    return out


def _leading(rows: list[list[str]], natural: list[int], width: int) -> int:
    """How many leading columns name a row (repeated in each group of columns): the fewest
    whose cells tell every row apart, if they take at most half of `width`; else one."""
    for k in range(1, len(natural)):
        if sum(natural[:k]) + GAP * k > width // 2:
            break
        if len({tuple(r[:k]) for r in rows}) == len(rows):
            return k
    return 1


def _grid(head: list[str], rows: list[list[str]], natural: list[int], least: list[int],
          width: int) -> list[str]:
    """Aligned columns under a rule, narrowed to fit `width` (the column holding the most
    text first, each down to `least`); numeric columns (most cells without a letter)
    right-aligned; a blank line between rows when a row takes more than one line."""
    widths = list(natural)
    text = [sum(len(r[j]) for r in rows) for j in range(len(head))]
    while sum(widths) + GAP * (len(widths) - 1) > width:
        slack = [w - m for w, m in zip(widths, least, strict=True)]
        if max(slack) <= 0:
            break
        widths[max(range(len(widths)), key=lambda k: (slack[k] > 0, text[k]))] -= 1
    right = [2 * sum(not any(c.isalpha() for c in r[j]) for r in rows) > len(rows)
             for j in range(len(head))]

    def block(cells: list[str], top: bool) -> list[str]:
        wrapped = [textwrap.wrap(c, w, break_long_words=False, break_on_hyphens=False) or [""]
                   for c, w in zip(cells, widths, strict=True)]
        height = max(len(w) for w in wrapped)
        wrapped = [([""] * (height - len(w)) + w) if top else (w + [""] * (height - len(w)))
                   for w in wrapped]
        return [(" " * GAP).join(
            (t.rjust(w) if r else t.ljust(w)) for t, w, r in zip(line, widths, right,
                                                                  strict=True)).rstrip()
            for line in zip(*wrapped, strict=True)]

    body = [block(r, top=False) for r in rows]
    sep = [""] if any(len(b) > 1 for b in body) else []
    out = [*block(head, top=True), (" " * GAP).join("-" * w for w in widths)]
    for k, b in enumerate(body):
        out += (sep if k else []) + b
    return out
