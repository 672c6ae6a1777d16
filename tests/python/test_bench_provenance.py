"""benchmarks/run.py stamps a section with the commit only when the tree is clean: otherwise
it says "uncommitted changes" with a hash of the changes; versions come from the installed
packages."""

from __future__ import annotations

import importlib.metadata
import importlib.util
import re
import subprocess
from pathlib import Path
from types import ModuleType

import pytest

RUN_PY = Path(__file__).resolve().parents[2] / "benchmarks" / "run.py"


@pytest.fixture(scope="module")
def run_py() -> ModuleType:
    spec = importlib.util.spec_from_file_location("a2l_bench_run", RUN_PY)
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _git(repo: Path, *args: str) -> str:
    return subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args],
                          cwd=repo, check=True, capture_output=True, text=True).stdout.strip()


def test_stamp_names_the_commit_only_when_the_tree_is_clean(run_py: ModuleType,
                                                             tmp_path: Path) -> None:
    repo = tmp_path / "repo"
    (repo / "benchmarks" / "sections").mkdir(parents=True)
    (repo / "code.py").write_text("x = 1\n")
    _git(repo, "init", "-q")
    _git(repo, "add", "code.py")
    _git(repo, "commit", "-q", "-m", "one")
    head = _git(repo, "rev-parse", "--short", "HEAD")
    bench_dir = repo / "benchmarks"
    assert run_py.git_commit(bench_dir) == f"commit {head}"
    # run.py's own outputs do not make the tree dirty
    (repo / "BENCHMARKS.md").write_text("# figures\n")
    (repo / "benchmarks" / "sections" / "a.md").write_text("figures\n")
    assert run_py.git_commit(bench_dir) == f"commit {head}"
    # a changed tracked file does, with a hash of the change
    (repo / "code.py").write_text("x = 2\n")
    stamp = run_py.git_commit(bench_dir)
    m = re.fullmatch(rf"uncommitted changes on top of {head} \(diff sha256 ([0-9a-f]{{12}})\)",
                     stamp)
    assert m, stamp
    (repo / "code.py").write_text("x = 3\n")
    other = run_py.git_commit(bench_dir)
    assert other.startswith("uncommitted changes") and other != stamp
    # an untracked file does too
    (repo / "code.py").write_text("x = 1\n")
    assert run_py.git_commit(bench_dir) == f"commit {head}"
    (repo / "new.py").write_text("y = 1\n")
    assert run_py.git_commit(bench_dir).startswith(f"uncommitted changes on top of {head}")
    # outside a checkout
    plain = tmp_path / "plain"
    plain.mkdir()
    assert run_py.git_commit(plain) == "commit unknown"


def test_versions_come_from_the_installed_packages(run_py: ModuleType) -> None:
    text = run_py.package_versions(("pgmpy", "numpy", "no-such-package-a2l"))
    assert text == (f"pgmpy {importlib.metadata.version('pgmpy')}, numpy "
                    f"{importlib.metadata.version('numpy')}, no-such-package-a2l not installed")


def test_no_section_types_a_version_or_an_unsourced_published_figure() -> None:
    for path in sorted(RUN_PY.parent.glob("bench_*.py")):
        text = path.read_text()
        assert not re.search(r"pgmpy \d", text), f"{path.name}: a typed pgmpy version"
        if "published" in text.lower():
            assert "source" in text.lower(), f"{path.name}: published figure without source"


def test_benchmarks_md_is_its_section_files(run_py: ModuleType) -> None:
    """BENCHMARKS.md is what run.py assembles from benchmarks/sections/: a figure edited in
    BENCHMARKS.md alone would be lost at the next ``make bench`` (it happened once)."""
    root = RUN_PY.parents[1]
    assembled = run_py.assemble(run_py.discover(), root / "benchmarks" / "sections")
    kept = (root / "BENCHMARKS.md").read_text()
    assert kept == assembled, (
        "BENCHMARKS.md differs from benchmarks/sections/*.md assembled by benchmarks/run.py: "
        "edit the section file (and BENCHMARKS.md alike)")


def test_an_edit_to_benchmarks_md_alone_is_found(run_py: ModuleType, tmp_path: Path) -> None:
    root = RUN_PY.parents[1]
    sections = run_py.discover()
    directory = tmp_path / "sections"
    directory.mkdir()
    for name in sections:
        f = root / "benchmarks" / "sections" / f"{name}.md"
        if f.is_file():
            (directory / f.name).write_text(f.read_text())
    kept = (root / "BENCHMARKS.md").read_text()
    assert run_py.assemble(sections, directory) == kept
    name = next(n for n in sections if (directory / f"{n}.md").is_file())
    text = (directory / f"{name}.md").read_text()
    (directory / f"{name}.md").write_text(text.replace("\n\n", "\n\nedited\n\n", 1))
    assert run_py.assemble(sections, directory) != kept
