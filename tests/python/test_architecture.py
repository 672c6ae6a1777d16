"""The layers of the Python package (docs/architecture.md) are enforced by import-linter.

The contracts live in pyproject.toml; ``make lint`` and ``make test`` run them. These tests run
the same ``lint-imports`` on the package as it is (every contract kept) and on a copy with one
deliberate upward import and one deliberate circle (each contract broken, the import named).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import tomllib

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "python" / "a2l"


def _lint(config: Path, cwd: Path, pythonpath: Path | None = None) -> subprocess.CompletedProcess:
    """``lint-imports --config CONFIG`` in `cwd` (the same entry point as the console script)."""
    code = "import sys; from importlinter.cli import lint_imports_command; " \
           "sys.exit(lint_imports_command())"
    env = None if pythonpath is None else {**os.environ, "PYTHONPATH": str(pythonpath)}
    return subprocess.run([sys.executable, "-c", code, "--config", str(config), "--no-cache"],
                          cwd=cwd, capture_output=True, text=True, timeout=300, env=env)


def test_contracts_kept_on_the_package() -> None:
    """Every contract in pyproject.toml is kept: no upward import, no circle."""
    out = _lint(ROOT / "pyproject.toml", ROOT)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "broken" not in out.stdout.lower().replace("0 broken", "")
    assert re.search(r"Contracts: \d+ kept, 0 broken", out.stdout), out.stdout


@pytest.fixture(scope="module")
def package_copy(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A copy of the package named ``a2lcopy`` and the contracts rewritten for that name.

    A new name keeps the copy apart from the installed ``a2l`` (an editable install finds
    ``a2l`` before ``PYTHONPATH``).
    """
    tmp = tmp_path_factory.mktemp("layers")
    dst = tmp / "a2lcopy"
    shutil.copytree(PACKAGE, dst, ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    for path in dst.rglob("*.py"):
        text = path.read_text()
        path.write_text(re.sub(r"\ba2l\b(?=[.\s]|$)", "a2lcopy", text))
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    assert cfg["root_package"] == "a2l"
    lines = ["[importlinter]", "root_package = a2lcopy", "include_external_packages = False"]
    for contract in cfg["contracts"]:
        lines += ["", f"[importlinter:contract:{contract['id']}]"]
        for key, value in contract.items():
            if key == "id":
                continue
            if isinstance(value, list):
                items = [v.replace("a2l", "a2lcopy") if key != "layers" else v for v in value]
                lines.append(f"{key} =")
                lines += [f"    {v}" for v in items]
            else:
                text = str(value) if key == "name" else str(value).replace("a2l", "a2lcopy")
                lines.append(f"{key} = {text}")
    config = tmp / ".importlinter"
    config.write_text("\n".join(lines) + "\n")
    return dst, config


def _with_line(path: Path, line: str) -> str:
    original = path.read_text()
    path.write_text(original + f"\n{line}\n")
    return original


def test_copy_is_kept_before_the_change(package_copy: tuple[Path, Path]) -> None:
    """The renamed copy passes, so the failures below come from the lines added."""
    dst, config = package_copy
    out = _lint(config, dst.parent, dst.parent)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.parametrize(("module", "line", "expected"), [
    # a foundation module importing the CLI: the layers contract names the import
    ("errors.py", "import a2lcopy.cli", ["a2lcopy.errors -> a2lcopy.cli",
                                         "no import upward BROKEN"]),
    # two sibling modules of one layer importing each other: the acyclic contract
    ("lfd/config.py", "import a2lcopy.lfd.library", ["No cycles are allowed in a2lcopy.lfd"]),
], ids=["upward-import", "circle"])
def test_a_violation_breaks_a_contract(package_copy: tuple[Path, Path], module: str, line: str,
                                       expected: list[str]) -> None:
    """One line added to the copy fails ``lint-imports`` with a message naming it."""
    dst, config = package_copy
    target = dst / module
    original = _with_line(target, f"{line}  # noqa: E402,F401")
    try:
        out = _lint(config, dst.parent, dst.parent)
    finally:
        target.write_text(original)
    assert out.returncode != 0
    for text in expected:
        assert text in out.stdout, out.stdout


def test_lazy_exports_stay_in_their_package() -> None:
    """A package's lazy names (:func:`a2l.lazy.lazy_exports`) come from its own modules.

    import-linter does not see an import made by name at run time, so a lazy re-export of
    another package could hide an upward import or a circle; re-exports stay inside.
    """
    import ast

    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text())
        if not any(isinstance(n, ast.Name) and n.id == "lazy_exports" for n in ast.walk(tree)):
            continue
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
        package = ".".join(parts)
        for node in ast.walk(tree):
            if isinstance(node, ast.Dict):
                for value in node.values:
                    home = value.elts[0] if isinstance(value, ast.Tuple) else value
                    if isinstance(home, ast.Constant) and isinstance(home.value, str) \
                            and not home.value.startswith(package + "."):
                        offenders.append(f"{path.relative_to(ROOT)}: {home.value}")
    assert not offenders, "lazy exports from outside their package:\n" + "\n".join(offenders)
