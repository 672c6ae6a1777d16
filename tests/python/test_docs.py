"""The repository's documents stand on their own: no file cites a document the repository
does not contain, and every relative link of the README and of ``docs/`` points to a file that
exists (and, for a link to a heading, to a heading that exists)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Documents that live outside the repository; citing them leaves a reader without the text.
OUTSIDE = re.compile(r"METHOD\.md|DESIGN\.md|\.\./shared")

#: A markdown link or image: ``[text](target)``.
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def _tracked_files() -> list[str]:
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True,
                         capture_output=True).stdout
    return [p for p in out.decode().split("\0") if p]


def _documents() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def _anchor(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S)
    return {_anchor(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", text, flags=re.M)}


def test_no_file_cites_a_document_outside_the_repository() -> None:
    """``git grep -n -E 'METHOD\\.md|DESIGN\\.md|\\.\\./shared'`` finds nothing."""
    found = []
    for rel in _tracked_files():
        path = ROOT / rel
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue  # binary files and files missing from the working tree
        for i, line in enumerate(text.splitlines(), 1):
            if OUTSIDE.search(line):
                found.append(f"{rel}:{i}: {line.strip()}")
    assert not found, "files cite documents outside the repository:\n" + "\n".join(found)


def test_relative_links_of_the_docs_resolve() -> None:
    """Every relative link in README.md and docs/*.md names an existing file, and a link
    to a heading (``file.md#heading``, ``#heading``) names an existing heading."""
    broken = []
    for doc in _documents():
        text = re.sub(r"```.*?```", "", doc.read_text(encoding="utf-8"), flags=re.S)
        for target in LINK.findall(text):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                continue
            file_part, _, anchor = target.partition("#")
            dest = (doc.parent / file_part).resolve() if file_part else doc
            where = f"{doc.relative_to(ROOT)}: ({target})"
            if not dest.exists():
                broken.append(f"{where}: no such file")
            elif anchor and dest.suffix == ".md" and anchor not in _anchors(dest):
                broken.append(f"{where}: no heading '#{anchor}' in {dest.name}")
    assert not broken, "broken links:\n" + "\n".join(broken)


def test_readme_is_a_guide_that_shows_the_two_commands() -> None:
    """The README shows ``make demo`` and ``make test`` and stays a guide (≤ 300 lines)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "make demo" in text and "make test" in text
    assert len(text.splitlines()) <= 300
