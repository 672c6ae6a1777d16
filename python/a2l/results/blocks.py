"""Generated tables inside hand-written Markdown: marked blocks.

A page includes the table ``NAME`` of ``docs/results/`` as::

    <!-- results:NAME -->
    (anything: replaced by a2l results)
    <!-- /results:NAME -->

``docs/results/NAME.md`` holds the same block with the generated content (the source);
:func:`fill_blocks` copies each source into a page, :func:`stale_blocks` lists the blocks of a
page that differ from their source (a test runs it on the README and every page of
``docs/``: a number edited by hand fails it).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from pathlib import Path

__all__ = ["BLOCK", "block", "fill_blocks", "pages_with_blocks", "read_blocks", "stale_blocks"]

#: One marked block: its name and its content (without the marker lines). A marker is a
#: line of its own (a marker quoted inside a sentence is text).
BLOCK = re.compile(r"^<!-- results:(?P<name>[A-Za-z0-9_-]+) -->\n(?P<body>.*?)"
                   r"^<!-- /results:(?P=name) -->$", re.S | re.M)
_OPEN = re.compile(r"^<!-- results:([A-Za-z0-9_-]+) -->$", re.M)


def block(name: str, body: str) -> str:
    """The marked block `name` around `body` (a trailing newline added when missing)."""
    body = body if body.endswith("\n") else body + "\n"
    return f"<!-- results:{name} -->\n{body}<!-- /results:{name} -->"


def read_blocks(text: str) -> dict[str, str]:
    """The blocks of `text`: name -> content; a name used twice is an error."""
    out: dict[str, str] = {}
    for m in BLOCK.finditer(text):
        if m["name"] in out:
            raise ValueError(f"results block {m['name']!r} appears twice")
        out[m["name"]] = m["body"]
    opened = _OPEN.findall(text)
    unclosed = sorted(set(opened) - set(out))
    if unclosed:
        raise ValueError(f"results block(s) {unclosed} not closed by <!-- /results:NAME -->")
    return out


def fill_blocks(text: str, sources: dict[str, str]) -> str:
    """`text` with every block's content replaced by its source's.

    Raises
    ------
    KeyError
        A block of `text` has no source (no ``docs/results/NAME.md``).
    """
    missing = sorted(set(read_blocks(text)) - set(sources))
    if missing:
        raise KeyError(f"results block(s) {missing} have no generated table in docs/results/ "
                       f"(known: {', '.join(sorted(sources)) or 'none'})")
    return BLOCK.sub(lambda m: block(m["name"], sources[m["name"]]), text)


def stale_blocks(text: str, sources: dict[str, str]) -> list[str]:
    """The names of the blocks of `text` whose content differs from their source (or that
    have none)."""
    return [name for name, body in read_blocks(text).items() if sources.get(name) != body]


def pages_with_blocks(root: str | os.PathLike[str], results: str = "docs/results"
                      ) -> list[Path]:
    """The Markdown pages under `root` that may include blocks: ``README.md`` and every
    ``docs/**/*.md`` outside `results` (the sources)."""
    root = Path(root)
    pages: Iterable[Path] = [root / "README.md", *sorted((root / "docs").rglob("*.md"))]
    src = (root / results).resolve()
    return [p for p in pages if p.is_file() and src not in p.resolve().parents]
