"""The two test lanes: ``make test`` runs every test, ``make test-fast`` those not marked
``slow``; the marker is registered (a misspelt one fails the run) and every family of slow
tests keeps a case in the fast lane."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

#: Modules whose every test is slow (no short case of them exists).
WHOLLY_SLOW = {"test_framework_baxter_workers.py"}


def _collect(*args: str) -> tuple[list[str], str]:
    out = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q",
                          "-p", "no:cacheprovider", *args, "tests/python"], cwd=ROOT,
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stdout + out.stderr
    return [line for line in out.stdout.splitlines() if "::" in line], out.stdout


@pytest.mark.slow
def test_the_fast_lane_is_a_strict_part_of_all_and_keeps_every_module() -> None:
    fast, text = _collect("-m", "not slow")
    counts = re.search(r"(\d+)/(\d+) tests collected \((\d+) deselected\)", text)
    assert counts, text
    assert int(counts[1]) == len(fast) and int(counts[3]) > 0  # some tests are slow
    modules = {p.name for p in (ROOT / "tests" / "python").glob("test_*.py")}
    fast_modules = {t.split("::")[0].rsplit("/", 1)[-1] for t in fast}
    assert modules - fast_modules == WHOLLY_SLOW
    # one regression seed stays fast, the others are slow
    golden = [t for t in fast if "metrics_are_those_of_the_old_framework" in t]
    assert len(golden) == 1


def test_a_misspelt_marker_fails_the_run(tmp_path: Path) -> None:
    probe = tmp_path / "test_probe.py"
    probe.write_text("import pytest\n\n\n@pytest.mark.slwo\ndef test_x():\n    pass\n")
    out = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          "-c", str(ROOT / "pyproject.toml"), "--rootdir", str(ROOT),
                          str(probe)], capture_output=True, text=True, timeout=120)
    assert out.returncode != 0
    assert re.search(r"'slwo' not found in `markers`", out.stdout + out.stderr)
