"""Discrete states: high-level state variables and the state codes of dataset columns."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from a2l.skills.spec import VariableSpec

__all__ = ["HighLevelState", "as_state_names", "state_codes"]


@dataclass(frozen=True)
class HighLevelState:
    """A discrete high-level state (light, gripper, colour) and its value names.

    Parameters
    ----------
    name : str
        Variable (and dataset column) name.
    values : tuple of str
        Value names in index order.
    """

    name: str
    values: tuple[str, ...]

    def __post_init__(self) -> None:
        vals = tuple(str(v) for v in self.values)
        if not vals or len(set(vals)) != len(vals):
            raise ValueError(f"{self.name}: values must be non-empty and unique, got {vals}")
        object.__setattr__(self, "values", vals)

    def discretize(self, column: Sequence[str] | np.ndarray) -> np.ndarray:
        """Value index of each entry, -1 where the value is not one of :attr:`values`.

        Returns
        -------
        ndarray of int64, shape (n,)
        """
        lut = {v: i for i, v in enumerate(self.values)}
        return np.array([lut.get(str(v), -1) for v in column], dtype=np.int64)

    def spec(self) -> VariableSpec:
        """The bundle variable of this state."""
        return VariableSpec(self.name, "high_level", len(self.values), values=self.values)


def state_codes(column: pd.Series, states: Sequence, name: str) -> np.ndarray:
    """Index of each entry of `column` in `states`.

    Returns
    -------
    ndarray of int64, shape (n,)

    Raises
    ------
    ValueError
        An entry is missing or not one of `states` (the message names `name` and the values).
    """
    values = (
        column.astype(object).to_numpy()
        if isinstance(column.dtype, pd.CategoricalDtype)
        else (column.to_numpy())
    )
    codes = pd.Index(list(states), dtype=object).get_indexer(pd.Index(values, dtype=object))
    if (codes < 0).any():
        bad = sorted({str(v) for v in values[codes < 0]})
        raise ValueError(
            f"column {name!r} has missing value(s) or value(s) not in its states: {bad}"
        )
    return codes.astype(np.int64)


def as_state_names(df: pd.DataFrame, state_names: Mapping[str, Sequence] | None = None) -> dict:
    """State names of every column of `df`: `state_names` first, then categories, then the
    sorted observed values."""
    out: dict[str, list] = {}
    for c in df.columns:
        if state_names is not None and c in state_names:
            out[c] = list(state_names[c])
        elif isinstance(df[c].dtype, pd.CategoricalDtype):
            out[c] = list(df[c].cat.categories)
        else:
            out[c] = sorted(pd.unique(df[c].dropna()))
    return out
