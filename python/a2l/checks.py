"""Field checks of the configuration parts: each raises :class:`a2l.errors.ConfigError`
naming the field (``discretization.n_orient``: the command line reports it as that option).

Every part of a composed configuration (:class:`a2l.framework.FrameworkConfig`,
:class:`a2l.skills.discretization.DiscretizationConfig`, ...) validates itself with these,
in its ``__post_init__``, so a part that exists is valid.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

from a2l.errors import ConfigError

__all__ = ["check_choice", "check_count", "check_edges", "check_fraction", "check_length",
           "check_names", "check_odd_or_zero", "check_range"]


def _name(owner: str, name: str) -> str:
    return f"{owner}.{name}" if owner else name


def check_count(owner: str, name: str, value: Any, minimum: int = 1) -> None:
    """`value` is an integer (not a bool) ``>= minimum``."""
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum:
        what = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
        raise ConfigError(_name(owner, name), f"must be {what}, got {value!r}")


def check_length(owner: str, name: str, value: Any, allow_zero: bool = False) -> None:
    """`value` is a finite number > 0 (>= 0 with `allow_zero`): a length in metres."""
    ok = (isinstance(value, int | float) and not isinstance(value, bool)
          and math.isfinite(value) and (value >= 0 if allow_zero else value > 0))
    if not ok:
        what = "a length >= 0" if allow_zero else "a positive length"
        raise ConfigError(_name(owner, name), f"must be {what}, got {value!r}")


def check_fraction(owner: str, name: str, value: Any) -> None:
    """`value` is a finite number in (0, 1]: a rate to reach."""
    ok = (isinstance(value, int | float) and not isinstance(value, bool)
          and math.isfinite(value) and 0 < value <= 1)
    if not ok:
        raise ConfigError(_name(owner, name), f"must be a rate in (0, 1], got {value!r}")


def check_range(owner: str, low_name: str, high_name: str, low: float, high: float,
                strict: bool = False) -> None:
    """``low <= high`` (``low < high`` when `strict`), reported as ``owner.low, high``."""
    if low > high or (strict and low == high):
        op = "<" if strict else "<="
        raise ConfigError(f"{_name(owner, low_name)}, {high_name}",
                          f"need low {op} high, got {low}, {high}")


def check_choice(owner: str, name: str, value: Any, choices: Iterable[Any]) -> None:
    """`value` is one of `choices`."""
    choices = tuple(choices)
    if value not in choices:
        raise ConfigError(_name(owner, name), f"unknown {value!r}; choose "
                          + ", ".join(repr(c) for c in choices))


def check_odd_or_zero(owner: str, name: str, value: Any) -> None:
    """`value` is 0 or an odd positive integer."""
    if (not isinstance(value, int) or isinstance(value, bool) or value < 0
            or (value and value % 2 == 0)):
        raise ConfigError(_name(owner, name),
                          f"must be 0 or an odd positive integer, got {value!r}")


def check_names(owner: str, name: str, value: Any) -> None:
    """`value` is a tuple of strings."""
    if not isinstance(value, tuple) or not all(isinstance(v, str) for v in value):
        raise ConfigError(_name(owner, name), f"must be a list of names, got {value!r}")


def check_edges(owner: str, name: str, value: Any, most: int = 1023) -> None:
    """`value` is a tuple of at most `most` bin edges: lengths (finite numbers > 0, not bools)
    in strictly increasing order; empty is fine."""
    ok = (isinstance(value, tuple) and len(value) <= most
          and all(isinstance(x, int | float) and not isinstance(x, bool) and math.isfinite(x)
                  and x > 0 for x in value)
          and all(a < b for a, b in zip(value, value[1:], strict=False)))
    if not ok:
        raise ConfigError(_name(owner, name), f"must be a list of at most {most} bin edges "
                          f"(lengths > 0, strictly increasing), got {value!r}")
