"""Validate a ``CITATION.cff`` against the Citation File Format 1.2.0 schema, with no package
beyond PyYAML (which a2l already needs): ``python tests/check_cff.py [CITATION.cff]``.

The schema (``tests/data/cff-1.2.0.schema.json``, vendored: see ``tests/data/README.md``) is
JSON Schema draft 07. This module checks the part of draft 07 that schema uses, and refuses a
schema with any other keyword, so that no constraint is skipped in silence: ``$ref`` to the
schema's own ``definitions``, ``type``, ``enum``, ``pattern``, ``minLength``, ``maxLength``,
``minimum``, ``maximum``, ``items``, ``minItems``, ``uniqueItems``, ``properties``,
``required``, ``additionalProperties``, ``anyOf``, ``oneOf`` and ``format`` (``date`` checked,
``uri`` and ``email`` left to the schema's patterns, as ``cffconvert --validate`` leaves them).
As the schema asks of tools, YAML dates are read as ISO strings. Exit status 0 when valid, 1
with one line per error otherwise, 2 on a usage error.
"""

from __future__ import annotations

import datetime
import json
import re
import sys
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = ROOT / "tests" / "data" / "cff-1.2.0.schema.json"

#: Keywords that say nothing about validity.
_ANNOTATIONS = {"$id", "$schema", "$comment", "title", "description", "examples", "default",
                "definitions"}
_CHECKED = {"$ref", "type", "enum", "pattern", "minLength", "maxLength", "minimum", "maximum",
            "items", "minItems", "uniqueItems", "properties", "required",
            "additionalProperties", "anyOf", "oneOf", "format"}
_TYPES: dict[str, Any] = {
    "string": lambda v: isinstance(v, str),
    "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    "boolean": lambda v: isinstance(v, bool),
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
    "null": lambda v: v is None,
}


def _where(path: tuple[Any, ...]) -> str:
    return "/".join(str(p) for p in path) or "(document)"


def _date(text: str) -> bool:
    try:
        datetime.date.fromisoformat(text)
    except ValueError:
        return False
    return len(text) == 10


class Validator:
    """Draft-07 validation of a document against `schema` (the keywords listed above)."""

    def __init__(self, schema: dict[str, Any]) -> None:
        self.schema = schema
        self._check_keywords(schema)

    def _check_keywords(self, node: Any) -> None:
        if isinstance(node, list):
            for item in node:
                self._check_keywords(item)
            return
        if not isinstance(node, dict):
            return
        unknown = set(node) - _ANNOTATIONS - _CHECKED
        if unknown:
            raise ValueError(f"schema keyword(s) this validator does not check: {sorted(unknown)}")
        for key, value in node.items():
            if key in ("properties", "definitions"):
                for sub in value.values():
                    self._check_keywords(sub)
            elif key in ("items", "additionalProperties", "anyOf", "oneOf"):
                self._check_keywords(value)

    def _resolve(self, ref: str) -> dict[str, Any]:
        if not ref.startswith("#/"):
            raise ValueError(f"only references inside the schema are supported, got {ref!r}")
        node: Any = self.schema
        for part in ref[2:].split("/"):
            node = node[part]
        return node

    def errors(self, doc: Any, schema: dict[str, Any] | None = None,
               path: tuple[Any, ...] = ()) -> list[str]:
        """Every error of `doc` against `schema` (default: the whole schema), as
        ``"path: message"`` lines; empty when valid."""
        s = self.schema if schema is None else schema
        if "$ref" in s:
            return self.errors(doc, self._resolve(s["$ref"]), path)
        out: list[str] = []
        where = _where(path)
        if "type" in s:
            types = s["type"] if isinstance(s["type"], list) else [s["type"]]
            if not any(_TYPES[t](doc) for t in types):
                return [f"{where}: {doc!r} is not of type {' or '.join(types)}"]
        if "enum" in s and doc not in s["enum"]:
            out.append(f"{where}: {doc!r} is not one of {s['enum']}")
        if isinstance(doc, str):
            if "minLength" in s and len(doc) < s["minLength"]:
                out.append(f"{where}: {doc!r} is shorter than {s['minLength']}")
            if "maxLength" in s and len(doc) > s["maxLength"]:
                out.append(f"{where}: {doc!r} is longer than {s['maxLength']}")
            if "pattern" in s and not re.search(s["pattern"], doc):
                out.append(f"{where}: {doc!r} does not match {s['pattern']!r}")
            if s.get("format") == "date" and not _date(doc):
                out.append(f"{where}: {doc!r} is not a date (YYYY-MM-DD)")
        if _TYPES["number"](doc):
            if "minimum" in s and doc < s["minimum"]:
                out.append(f"{where}: {doc!r} is less than {s['minimum']}")
            if "maximum" in s and doc > s["maximum"]:
                out.append(f"{where}: {doc!r} is greater than {s['maximum']}")
        if isinstance(doc, list):
            if "minItems" in s and len(doc) < s["minItems"]:
                out.append(f"{where}: {len(doc)} item(s), fewer than {s['minItems']}")
            if s.get("uniqueItems"):
                seen = [json.dumps(v, sort_keys=True, default=str) for v in doc]
                if len(set(seen)) != len(seen):
                    out.append(f"{where}: items are not unique")
            if "items" in s:
                for i, item in enumerate(doc):
                    out += self.errors(item, s["items"], (*path, i))
        if isinstance(doc, dict):
            for key in s.get("required", []):
                if key not in doc:
                    out.append(f"{where}: {key!r} is required")
            props = s.get("properties", {})
            extra = s.get("additionalProperties", True)
            for key, value in doc.items():
                if key in props:
                    out += self.errors(value, props[key], (*path, key))
                elif extra is False:
                    out.append(f"{where}: {key!r} is not a property the format knows")
                elif isinstance(extra, dict):
                    out += self.errors(value, extra, (*path, key))
        if "anyOf" in s and not any(not self.errors(doc, sub, path) for sub in s["anyOf"]):
            out.append(f"{where}: {_brief(doc)} matches none of the allowed forms")
        if "oneOf" in s:
            n = sum(not self.errors(doc, sub, path) for sub in s["oneOf"])
            if n != 1:
                out.append(f"{where}: {_brief(doc)} matches {n} of the forms, not exactly one")
        return out


def _brief(doc: Any) -> str:
    text = repr(doc)
    return text if len(text) <= 60 else text[:57] + "..."


def _dates_as_strings(node: Any) -> Any:
    if isinstance(node, dict):
        return {k: _dates_as_strings(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_dates_as_strings(v) for v in node]
    if isinstance(node, (datetime.date, datetime.datetime)):
        return node.isoformat()
    return node


def load_cff(text: str) -> Any:
    """A CITATION.cff's YAML as JSON data (YAML dates as ISO strings)."""
    return _dates_as_strings(yaml.safe_load(text))


def validate(text: str, schema_path: Path = SCHEMA) -> list[str]:
    """The errors of the CITATION.cff `text` against the schema (empty when valid)."""
    validator = Validator(json.loads(schema_path.read_text(encoding="utf-8")))
    try:
        doc = load_cff(text)
    except yaml.YAMLError as exc:
        return [f"(document): not YAML: {exc}"]
    return validator.errors(doc)


def main(argv: list[str]) -> int:
    if len(argv) > 1:
        print("usage: python tests/check_cff.py [CITATION.cff]", file=sys.stderr)
        return 2
    path = Path(argv[0]) if argv else ROOT / "CITATION.cff"
    if not path.is_file():
        print(f"check_cff: no file {path}", file=sys.stderr)
        return 2
    errors = validate(path.read_text(encoding="utf-8"))
    for line in errors:
        print(f"{path.name}: {line}")
    if not errors:
        print(f"{path.name}: valid (Citation File Format 1.2.0)")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
