"""A correct K2 structure score for pgmpy's ``HillClimbSearch``.

The K2 score (Cooper & Herskovits 1992) of a variable X with r states and parents Π is

.. math::
    \\sum_{j=1}^{q} \\Big[\\log\\Gamma(r) - \\log\\Gamma(N_{j} + r)
        + \\sum_{k=1}^{r} \\log\\Gamma(N_{jk} + 1)\\Big],

summed over all q parent configurations. A configuration absent from the data has
N_j = N_jk = 0 and contributes exactly 0, so the sum runs over the **observed** parent
configurations only. pgmpy 1.1.2's ``K2`` sums the counts over the observed configurations
but adds log Γ(r) for all q of them, so every unseen configuration adds log Γ(r) > 0 (r ≥ 3):
the score then rewards parents with many empty configurations. This implementation counts
with numpy on integer codes and never enumerates the q configurations.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd
from pgmpy.structure_score import BaseStructureScore
from scipy.special import gammaln

from a2l.skills.states import as_state_names, state_codes

__all__ = ["K2Score", "k2_local_score"]


def k2_local_score(child: np.ndarray, parents: np.ndarray, r: int, cards: Sequence[int]) -> float:
    """K2 local score of integer-coded data.

    Parameters
    ----------
    child : ndarray of int, shape (n,)
        The variable's state codes in [0, r).
    parents : ndarray of int, shape (n, n_parents)
        The parents' state codes, column p in [0, cards[p]).
    r : int
        Number of states of the variable.
    cards : sequence of int, length n_parents
        Number of states of each parent.

    Returns
    -------
    float
        The K2 local score (log marginal likelihood under uniform Dirichlet(1) priors).
    """
    n = child.shape[0]
    if parents.shape[1] == 0:
        config = np.zeros(n, dtype=np.int64)
    else:
        q = 1
        for c in cards:
            q *= int(c)
        if q < 2**62 // max(r, 1):
            config = np.ravel_multi_index(tuple(parents.T), tuple(int(c) for c in cards))
        else:  # too many configurations for one int64: relabel the observed ones
            config = np.unique(parents, axis=0, return_inverse=True)[1].reshape(-1)
    config = config.astype(np.int64)
    _, n_j = np.unique(config, return_counts=True)
    _, n_jk = np.unique(config * r + child, return_counts=True)
    return float(n_j.size * gammaln(r) - gammaln(n_j + r).sum() + gammaln(n_jk + 1.0).sum())


class K2Score(BaseStructureScore):
    """K2 score correct when parent configurations are missing from the data.

    Usable wherever pgmpy takes a score, e.g.
    ``HillClimbSearch(scoring_method=K2Score(df), return_type="dag").fit(df)``.

    Parameters
    ----------
    data : pandas.DataFrame, shape (n_rows, n_variables)
        Discrete data (categorical, string or integer columns), no missing values.
    state_names : mapping of str to sequence, optional
        States of each variable (their number r matters); default: the categories of a
        categorical column, else the sorted observed values.

    Raises
    ------
    ValueError
        The data has missing values, or a value not among its variable's state names.
    """

    _tags = {
        "name": "k2-a2l",
        "supported_datatype": "discrete",
        "default_for": None,
        "is_parameteric": False,
    }

    def __init__(
        self, data: pd.DataFrame, state_names: Mapping[str, Sequence] | None = None
    ) -> None:
        names = as_state_names(data, state_names)
        self._codes: dict[str, np.ndarray] = {}
        for var in data.columns:
            self._codes[var] = state_codes(data[var], names[var], str(var))
        super().__init__(data, state_names=names)
        self.state_names = names

    def local_score(self, variable: str, parents: tuple[str, ...]) -> float:
        """Cached K2 local score of `variable` given `parents` (any order)."""
        return self._cached_local_score(variable, tuple(sorted(parents)))

    def _local_score(self, variable: str, parents: tuple[str, ...]) -> float:
        pa = (
            np.stack([self._codes[p] for p in parents], axis=1)
            if parents
            else np.zeros((len(self._codes[variable]), 0), dtype=np.int64)
        )
        return k2_local_score(
            self._codes[variable],
            pa,
            len(self.state_names[variable]),
            [len(self.state_names[p]) for p in parents],
        )
