"""The project files agree with the code and with each other: ``CITATION.cff`` is valid
Citation File Format 1.2.0 (``tests/check_cff.py``, also run by ``make lint``) and a broken
one is refused; the licence is the same in ``LICENSE``, ``pyproject.toml`` and
``CITATION.cff``; ``CHANGELOG.md``'s newest version is the package's, dated from the
history."""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
HAL = "https://hal.archives-ouvertes.fr/tel-01809989v2"


@pytest.fixture(scope="module")
def cff() -> ModuleType:
    spec = importlib.util.spec_from_file_location("a2l_check_cff", ROOT / "tests" / "check_cff.py")
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _citation() -> str:
    return (ROOT / "CITATION.cff").read_text(encoding="utf-8")


def _pyproject_field(name: str) -> str:
    m = re.search(rf'^{name} = (.+)$', (ROOT / "pyproject.toml").read_text(), flags=re.M)
    assert m, name
    return m.group(1)


def test_the_vendored_schema_is_cff_1_2_0(cff: ModuleType) -> None:
    import json

    schema = json.loads(cff.SCHEMA.read_text(encoding="utf-8"))
    assert schema["$id"] == "https://citation-file-format.github.io/1.2.0/schema.json"
    assert schema["properties"]["cff-version"]["pattern"] == r"^1\.2\.0$"
    cff.Validator(schema)  # every keyword it uses is one the validator checks


def test_citation_cff_is_valid(cff: ModuleType) -> None:
    assert cff.validate(_citation()) == []
    assert cff.main([str(ROOT / "CITATION.cff")]) == 0


@pytest.mark.parametrize(("edit", "error"), [
    (lambda d: d.pop("title"), "'title' is required"),
    (lambda d: d.update({"cff-version": "1.1.0"}), "does not match"),
    (lambda d: d.update({"license": "BSD-3"}), "matches 0 of the forms"),
    (lambda d: d.update({"date-released": "2026-13-01"}), "date-released"),
    (lambda d: d.update({"authors": []}), "fewer than 1"),
    (lambda d: d.update({"homepage": "https://example.org"}), "'homepage' is not a property"),
    (lambda d: d["references"][0].pop("type"), "references/0: 'type' is required"),
    (lambda d: d["references"][0].update({"year": None}), "references/0/year"),
    (lambda d: d["references"][0]["authors"][0].update({"given-names": ""}),
     "references/0/authors/0: "),
    (lambda d: d["references"][0].update({"url": "hal.archives-ouvertes.fr"}), "does not match"),
])
def test_a_broken_citation_is_refused(cff: ModuleType, edit, error: str) -> None:
    doc = cff.load_cff(_citation())
    edit(doc)
    errors = cff.validate(yaml.safe_dump(doc, allow_unicode=True))
    assert errors and any(error in e for e in errors), errors


def test_the_check_script_exits_1_on_a_broken_file(cff: ModuleType, tmp_path: Path) -> None:
    bad = tmp_path / "CITATION.cff"
    bad.write_text(_citation().replace("cff-version: 1.2.0", "cff-version: 1.2"))
    run = subprocess.run([sys.executable, str(ROOT / "tests" / "check_cff.py"), str(bad)],
                         capture_output=True, text=True)
    assert run.returncode == 1 and "cff-version" in run.stdout
    assert cff.validate("title: [unclosed")[0].startswith("(document): not YAML")


def test_the_validator_refuses_a_keyword_it_does_not_check(cff: ModuleType) -> None:
    with pytest.raises(ValueError, match="const"):
        cff.Validator({"properties": {"a": {"const": 1}}})
    v = cff.Validator({"type": "object", "properties": {
        "n": {"type": "integer", "minimum": 1, "maximum": 12},
        "one": {"oneOf": [{"type": "string"}, {"type": "string", "minLength": 2}]},
        "set": {"type": "array", "uniqueItems": True, "items": {"enum": ["a", "b"]}}}})
    assert v.errors({"n": 5, "one": 3, "set": ["a"]}) == ["one: 3 matches 0 of the forms, "
                                                           "not exactly one"]
    assert v.errors({"n": True})[0].startswith("n: True is not of type integer")
    assert len(v.errors({"n": 13, "one": "xy", "set": ["a", "a", "c"]})) == 4


def test_the_licence_is_the_same_everywhere() -> None:
    licence = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert licence.startswith("BSD 3-Clause License\n\nCopyright (c) 2026, the a2l developers\n")
    assert "Neither the name of the copyright holder nor the names of its" in licence
    assert _pyproject_field("license") == '{ text = "BSD-3-Clause" }'
    doc = yaml.safe_load(_citation())
    assert doc["license"] == "BSD-3-Clause"
    assert doc["authors"] == [{"name": "the a2l developers"}]
    assert 'author = "the a2l developers"' in (ROOT / "docs" / "api" / "conf.py").read_text()
    assert "BSD-3-Clause ([LICENSE](LICENSE))" in (ROOT / "README.md").read_text(encoding="utf-8")


def test_citation_names_the_package_version_and_the_thesis() -> None:
    doc = yaml.safe_load(_citation())
    assert doc["version"] == _pyproject_field("version").strip('"')
    (thesis,) = [r for r in doc["references"] if r["type"] == "thesis"]
    assert thesis["url"] == HAL and thesis["year"] == 2018
    assert thesis["authors"] == [{"family-names": "Maestre", "given-names": "Carlos"}]
    assert thesis["institution"]["name"] == "Sorbonne Université"


def test_the_changelog_ends_at_the_package_version_with_dates_from_the_history() -> None:
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    versions = re.findall(r"^## \[(\d+\.\d+\.\d+)\] - (\d{4}-\d{2}-\d{2})$", text, flags=re.M)
    assert versions, "no dated version"
    package = _pyproject_field("version").strip('"')
    cmake = re.search(r"project\(a2l VERSION (\S+)", (ROOT / "CMakeLists.txt").read_text())
    assert cmake and cmake.group(1) == package
    assert versions[0][0] == package, "the newest version is not the package's"
    numbers = [tuple(int(x) for x in v.split(".")) for v, _ in versions]
    assert numbers == sorted(numbers, reverse=True) and len(set(numbers)) == len(numbers)
    dates = [d for _, d in versions]
    assert dates == sorted(dates, reverse=True)
    days = set(subprocess.run(["git", "log", "--format=%ad", "--date=short"], cwd=ROOT,
                              check=True, capture_output=True, text=True).stdout.split())
    assert set(dates) <= days, "a version dated on a day without a commit"
