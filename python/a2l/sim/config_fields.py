"""Field checks of the scene configs: each names the bad field in an
:class:`a2l.A2LValueError` and stores the value normalised (floats, tuples of floats)."""

from __future__ import annotations

import math
from typing import Any

from a2l.errors import A2LValueError

__all__ = ["RGBA", "choice_field", "field_error", "positive_field", "vector_field"]

#: An RGBA colour, each channel in [0, 1].
RGBA = tuple[float, float, float, float]


def field_error(field_name: str, message: str) -> A2LValueError:
    """The error for a bad config field: ``scene config field '<name>': <message>``."""
    return A2LValueError(f"scene config field '{field_name}': {message}")


def vector_field(cfg: Any, name: str, n: int, positive: bool = False) -> None:
    """Check that ``cfg.<name>`` holds `n` finite numbers (all > 0 if `positive`) and
    store them as a tuple of floats."""
    value = getattr(cfg, name)
    try:
        vals = tuple(float(v) for v in value)
    except TypeError as exc:
        raise field_error(name, f"expected {n} numbers, got {value!r}") from exc
    if len(vals) != n:
        raise field_error(name, f"expected {n} numbers, got {len(vals)}: {value!r}")
    if not all(math.isfinite(v) for v in vals):
        raise field_error(name, f"must be finite, got {value!r}")
    if positive and any(v <= 0 for v in vals):
        raise field_error(name, f"every entry must be > 0, got {value!r}")
    setattr(cfg, name, vals)


def positive_field(cfg: Any, name: str, allow_zero: bool = False) -> None:
    """Check that ``cfg.<name>`` is a finite number > 0 (>= 0 if `allow_zero`) and store
    it as a float."""
    value = getattr(cfg, name)
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise field_error(name, f"expected a number, got {value!r}") from exc
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise field_error(name, f"must be {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    setattr(cfg, name, v)


def choice_field(cfg: Any, name: str, choices: tuple[Any, ...]) -> None:
    """Check that ``cfg.<name>`` is one of `choices`."""
    value = getattr(cfg, name)
    if value not in choices:
        raise field_error(name, f"must be one of {list(choices)}, got {value!r}")
