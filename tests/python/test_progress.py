"""The one progress helper (:mod:`a2l.progress`): silent when quiet, one bar per
label otherwise, and no other module builds ``rich`` progress bars."""

from __future__ import annotations

import re
from pathlib import Path

import a2l
from a2l.progress import ProgressBars, progress_bar


def test_quiet_shows_nothing_and_yields_no_callback(capsys) -> None:
    with progress_bar("trials", 10, quiet=True) as on_done:
        assert on_done is None
    with ProgressBars(quiet=True) as bars:
        bars.update("acquire", 3, 10)
        bars.print("hidden")
        bars.clear()
        assert bars.counter("x", 4) is None
    assert capsys.readouterr().out == ""


def test_bars_follow_their_labels() -> None:
    with ProgressBars() as bars:
        on_done = bars.counter("trials", 8)
        assert on_done is not None
        on_done(5)
        bars.update("acquire", 2, 10, info="moved 20%")
        bars.update("acquire", 4)  # the total is kept
        tasks = {t.description: t for t in bars._rich.tasks}
        assert (tasks["trials"].completed, tasks["trials"].total) == (5, 8)
        assert (tasks["acquire"].completed, tasks["acquire"].total) == (4, 10)
        bars.clear()
        assert bars._rich.tasks == []
        bars.update("validate", 1, 2)
        assert [t.description for t in bars._rich.tasks] == ["validate"]


def test_one_progress_helper() -> None:
    root = Path(a2l.__file__).parent
    users = [p.relative_to(root).as_posix() for p in sorted(root.rglob("*.py"))
             if p.name != "progress.py"
             and re.search(r"rich\.progress", p.read_text(encoding="utf-8"))]
    assert users == []
