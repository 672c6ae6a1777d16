"""The repository's documents stand on their own: no file cites a document the repository
does not contain, every relative link of the README and of ``docs/`` points to a file that
exists (and, for a link to a heading, to a heading that exists), and every commit a document
cites is in the history."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Documents that live outside the repository; citing them leaves a reader without the text.
OUTSIDE = re.compile(r"METHOD\.md|DESIGN\.md|\.\./shared")

#: A markdown link or image: ``[text](target)``.
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


#: A commit as the documents cite one: a short or full hash standing alone (7 to 40 lower-case
#: hex digits, with at least one digit and one letter, so that neither a number nor a word is
#: taken for one), not inside a path, a URL, a version or an identifier (``tel-01809989``).
COMMIT = re.compile(r"(?<![\w./#:-])(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])([0-9a-f]{7,40})(?![\w/-])")

#: What precedes a hash that is not a commit: a file's digest, e.g. the benchmarks' stamp
#: "uncommitted changes on top of COMMIT (diff sha256 0123456789ab)".
NOT_A_COMMIT = re.compile(r"(sha-?256|sha-?1|md5|crc32|digest|checksum)\W{0,3}$", re.I)

#: The documents whose cited commits are checked: the README, the benchmarks, the project files
#: and every page under docs/.
CITING = ["README.md", "BENCHMARKS.md", "CHANGELOG.md", "CONTRIBUTING.md"]


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


def _cited_commits() -> dict[str, list[str]]:
    """Every hash the documents cite as a commit -> where (``file:line``)."""
    cited: dict[str, list[str]] = {}
    docs = [ROOT / name for name in CITING if (ROOT / name).exists()]
    for doc in [*docs, *sorted((ROOT / "docs").rglob("*.md"))]:
        for i, line in enumerate(doc.read_text(encoding="utf-8").splitlines(), 1):
            for m in COMMIT.finditer(line):
                if not NOT_A_COMMIT.search(line[:m.start()]):
                    cited.setdefault(m.group(1), []).append(f"{doc.relative_to(ROOT)}:{i}")
    return cited


def test_the_commit_pattern_takes_hashes_and_leaves_numbers() -> None:
    def found(text: str) -> list[str]:
        return [m.group(1) for m in COMMIT.finditer(text)
                if not NOT_A_COMMIT.search(text[:m.start()])]

    assert found("measured at 98b7595 (the code of 3c9e826), | 0c0cd98 | 2026-12-03") == [
        "98b7595", "3c9e826", "0c0cd98"]
    assert found("commit 072b740._ and 705e57402216f9d1f47deafa29a70c0c33167e41") == [
        "072b740", "705e57402216f9d1f47deafa29a70c0c33167e41"]
    assert found("on top of 98b7595 (diff sha256 0a1b2c3d4e5f)") == ["98b7595"]
    assert found("1000000 starts, 1.16582199, deadbeef, facade, tel-01809989v2, "
                 "docs/a1b2c3d.png, https://x.org/commit/a1b2c3d4, v1.2.3abcdef0") == []


def test_every_cited_commit_is_in_the_history() -> None:
    """Every commit hash cited by README.md, BENCHMARKS.md, the project files and docs/ names
    a commit of the repository (``git cat-file -e HASH^{commit}``): a figure's commit that a
    rebase rewrote is found nowhere else, and the figure stands on nothing."""
    shallow = subprocess.run(["git", "rev-parse", "--is-shallow-repository"], cwd=ROOT,
                             check=True, capture_output=True, text=True).stdout.strip()
    assert shallow == "false", "a shallow clone lacks the cited commits: git fetch --unshallow"
    cited = _cited_commits()
    assert cited, "no commit cited: the pattern no longer matches how the documents cite one"
    query = "".join(f"{h}^{{commit}}\n" for h in cited)
    out = subprocess.run(["git", "cat-file", "--batch-check=%(objecttype)"], cwd=ROOT,
                         input=query, check=True, capture_output=True, text=True).stdout
    answers = out.splitlines()
    assert len(answers) == len(cited)
    bad = [f"{h} ({answer}): {', '.join(where)}"
           for (h, where), answer in zip(cited.items(), answers, strict=True)
           if answer != "commit"]
    assert not bad, "cited commits not in the history:\n" + "\n".join(bad)


#: An abbreviation of the README: a word of capitals and digits with at least two capitals
#: (an "s" of the plural allowed), outside code, and not a file's name (``BENCHMARKS.md``).
ABBREVIATION = re.compile(r"\b((?=[A-Z0-9]*[A-Z][A-Z0-9]*[A-Z])[A-Z][A-Z0-9]*)s?\b(?!\.[a-z])")

#: Capitalised words of the README that are not abbreviations, with the reason.
NOT_ABBREVIATIONS = {
    "README": "a file's name, also written without its extension",
    "LICENSE": "a file's name, also written without its extension",
}


def _prose(text: str) -> str:
    """`text` without fenced code, inline code and link targets."""
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    text = re.sub(r"`[^`\n]*`", "", text)
    return re.sub(r"\]\([^)]*\)", "]", text)


def _glossary_terms() -> set[str]:
    """The words of the first column of docs/glossary.md's table (``RGB-D`` gives ``RGB``
    and ``D``; ``ASan, UBSan`` gives both)."""
    terms: set[str] = set()
    for line in (ROOT / "docs" / "glossary.md").read_text(encoding="utf-8").splitlines():
        if line.startswith("| ") and not line.startswith("| abbreviation"):
            terms.update(re.split(r"[\s,/-]+", line.split("|")[1].strip()))
    return terms


def test_every_abbreviation_of_the_readme_is_in_the_glossary() -> None:
    """Every abbreviation the README uses (all capitals, digits allowed, outside code) is
    spelt out in docs/glossary.md, and the README links the glossary."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "(docs/glossary.md)" in text, "the README does not link docs/glossary.md"
    terms = _glossary_terms()
    used = {m.group(1) for m in ABBREVIATION.finditer(_prose(text))}
    missing = sorted(used - terms - set(NOT_ABBREVIATIONS))
    assert not missing, f"abbreviations of the README missing from docs/glossary.md: {missing}"
    for word in ("NovEB", "LfD", "BDeu", "A2L", "K2"):
        assert word in terms, word


def test_the_abbreviation_pattern() -> None:
    found = [m.group(1) for m in ABBREVIATION.finditer(
        "A2L, URDFs and UR5, PR2, SO-101, RGB-D; not Baxter, K, A, PyBullet, BENCHMARKS.md")]
    assert found == ["A2L", "URDF", "UR5", "PR2", "SO", "RGB"]


def test_the_thesis_page_quotes_its_figures_from_the_generated_pages() -> None:
    """docs/thesis.md: every figure quoted in a row ("...") is on the results page that row
    links, so a regenerated page that changes it fails here; and the thesis is cited by its
    HAL identifier, in the README too."""
    text = (ROOT / "docs" / "thesis.md").read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith("| ") and "results/" in line]
    assert len(rows) >= 6, "a row per experiment chapter"
    for row in rows:
        pages = re.findall(r"\]\((results/[\w-]+\.md)\)", row)
        quoted = re.findall(r'"([^"]+)"', row)
        assert pages and quoted, row
        sources = "".join((ROOT / "docs" / p).read_text(encoding="utf-8") for p in pages)
        absent = [q for q in quoted if q not in sources]
        assert not absent, f"quoted in docs/thesis.md but not on {pages}: {absent}"
    hal = "https://hal.archives-ouvertes.fr/tel-01809989v2"
    assert hal in text
    assert hal in (ROOT / "README.md").read_text(encoding="utf-8"), "the README cites the thesis"
