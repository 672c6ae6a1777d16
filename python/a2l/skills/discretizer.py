"""Discretization of interactions: context bins, movements, effects, high-level states.

:class:`Discretizer` ties together the pieces, each in its own module, and turns a raw
interaction dataset into the discrete dataset the learning reads:

==========================  ================================================================
variable                    module
==========================  ================================================================
``distance``                :mod:`a2l.skills.bins` (:class:`DistanceBins`)
``orientation``             :mod:`a2l.skills.bins` (:class:`OrientationBins`)
``inclination``             :mod:`a2l.skills.bins` (:class:`InclinationBins`)
``offset_x``, ``offset_y``  :mod:`a2l.skills.bins` (:class:`OffsetBins`)
``move``                    :mod:`a2l.skills.repertoire` (:class:`MovementRepertoire`): signs
                            of the end-effector step per axis, with a dead-band
``effect``                  :mod:`a2l.skills.effects` (:class:`EffectDiscretizer`)
high-level state            :mod:`a2l.skills.states` (:class:`HighLevelState`)
==========================  ================================================================
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from a2l.data.schema import (
    EEF_COLUMNS,
    EFFECT_DISPLACEMENT_COLUMNS,
    MOVE_COLUMNS,
    OBJECT_COLUMNS,
    check_columns,
)
from a2l.skills.bins import (
    ContextBins,
    DistanceBins,
    InclinationBins,
    OffsetBins,
    OrientationBins,
    context_bins,
)
from a2l.skills.effects import EffectDiscretizer
from a2l.skills.repertoire import MovementRepertoire
from a2l.skills.spec import VariableSpec
from a2l.skills.states import HighLevelState

__all__ = ["Discretizer"]


@dataclass(frozen=True)
class Discretizer:
    """Everything that turns a raw interaction dataset into discrete variables.

    Parameters
    ----------
    distance, orientation, inclination : bins or None
        Context discretizations; None leaves the variable out.
    offsets : tuple of OffsetBins
        Planar offset discretizations (``offset_x``, ``offset_y``), after the others; empty
        by default.
    movements : MovementRepertoire
        The movement repertoire (variable ``move``).
    effects : EffectDiscretizer
        The effect discretization (variable ``effect``).
    high_level : tuple of HighLevelState
        High-level states, read from dataset columns of the same names.
    """

    distance: DistanceBins | None = field(default_factory=DistanceBins)
    orientation: OrientationBins | None = field(default_factory=OrientationBins)
    inclination: InclinationBins | None = field(default_factory=InclinationBins)
    offsets: tuple[OffsetBins, ...] = ()
    movements: MovementRepertoire = field(default_factory=MovementRepertoire)
    effects: EffectDiscretizer = field(default_factory=EffectDiscretizer)
    high_level: tuple[HighLevelState, ...] = ()

    def __post_init__(self) -> None:
        names = self.variable_names
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"variable names must be unique, repeated: {sorted(dup)}")

    @property
    def context(self) -> tuple[ContextBins, ...]:
        """The low-level context discretizations in use."""
        return (*(b for b in (self.distance, self.orientation, self.inclination) if b),
                *self.offsets)

    @property
    def variable_names(self) -> list[str]:
        """Names of the discrete variables: effect, context, high-level states, move."""
        return [
            self.effects.name,
            *(b.name for b in self.context),
            *(h.name for h in self.high_level),
            self.movements.name,
        ]

    @property
    def evidence(self) -> list[str]:
        """The evidence variables of the action generator (every variable but ``move``)."""
        return self.variable_names[:-1]

    def state_names(self) -> dict[str, list[int] | list[str]]:
        """Every variable's states, in index order (ints for bins, names otherwise)."""
        out: dict[str, list[int] | list[str]] = {self.effects.name: list(self.effects.values)}
        for b in self.context:
            out[b.name] = list(range(b.n_bins))
        for h in self.high_level:
            out[h.name] = list(h.values)
        out[self.movements.name] = list(self.movements.labels)
        return out

    def variable_specs(self) -> dict[str, VariableSpec]:
        """Bundle variable of each evidence variable, by name."""
        specs = [self.effects.spec(), *(b.spec() for b in self.context)]
        specs += [h.spec() for h in self.high_level]
        return {s.name: s for s in specs}

    def context_bins(self, eef: np.ndarray, obj: np.ndarray) -> dict[str, np.ndarray]:
        """Low-level context bins.

        Parameters
        ----------
        eef, obj : ndarray, shape (n, 3) or (3,)
            End-effector and object positions (m).

        Returns
        -------
        dict of str to ndarray of int64, shape (n,)
            Bin of each context variable, -1 where an input is not finite.
        """
        bins = context_bins(eef, obj, self.context)
        return {b.name: bins[:, i].copy() for i, b in enumerate(self.context)}

    def discretize(self, raw: pd.DataFrame) -> pd.DataFrame:
        """The discrete dataset of a raw interaction dataset (:mod:`a2l.data.schema`).

        Rows whose movement is in the dead-band, whose effect is ``none`` or whose context
        is not finite are dropped; their number is in ``result.attrs["dropped_rows"]``.

        Parameters
        ----------
        raw : pandas.DataFrame, shape (n_rows, n_columns)
            Raw dataset with the columns of :data:`a2l.data.schema.REQUIRED_COLUMNS`, either
            ``effect_dx, effect_dy, effect_dz`` or ``effect``, and a column per high-level
            state.

        Returns
        -------
        pandas.DataFrame, shape (n_kept, n_variables)
            One categorical column per variable of :attr:`variable_names`, with every state
            of :meth:`state_names` as categories (so unseen states stay known).

        Raises
        ------
        ValueError
            A column is missing (named), or an ``effect`` / high-level value is unknown.
        """
        check_columns(raw, ("episode", "step", *EEF_COLUMNS, *OBJECT_COLUMNS, *MOVE_COLUMNS))
        check_columns(raw, [h.name for h in self.high_level])
        eef = raw.loc[:, list(EEF_COLUMNS)].to_numpy(np.float64)
        obj = raw.loc[:, list(OBJECT_COLUMNS)].to_numpy(np.float64)
        cols: dict[str, np.ndarray] = {}
        if "effect" in raw.columns:
            lut = {v: i for i, v in enumerate(self.effects.values)}
            bad = sorted({str(v) for v in raw["effect"]} - set(lut) - {"none"})
            if bad:
                raise ValueError(
                    f"column 'effect' has unknown effect(s) {bad}; known: {self.effects.values}"
                )
            cols[self.effects.name] = np.array(
                [lut.get(str(v), -1) for v in raw["effect"]], dtype=np.int64
            )
        elif all(c in raw.columns for c in EFFECT_DISPLACEMENT_COLUMNS):
            disp = raw.loc[:, list(EFFECT_DISPLACEMENT_COLUMNS)].to_numpy(np.float64)
            cols[self.effects.name] = self.effects.discretize(disp)
        else:
            raise ValueError(
                "dataset is missing the effect: it needs column 'effect' or columns "
                f"{list(EFFECT_DISPLACEMENT_COLUMNS)}"
            )
        cols.update(self.context_bins(eef, obj))
        for h in self.high_level:
            idx = h.discretize(raw[h.name])
            if (idx < 0).any():
                bad = sorted({str(v) for v, i in zip(raw[h.name], idx, strict=True) if i < 0})
                raise ValueError(f"column {h.name!r} has unknown value(s) {bad}; known: {h.values}")
            cols[h.name] = idx
        move = raw.loc[:, list(MOVE_COLUMNS)].to_numpy(np.float64)
        cols[self.movements.name] = self._movement_indices(raw, move)
        keep = np.logical_and.reduce([c >= 0 for c in cols.values()])
        states = self.state_names()
        out = pd.DataFrame(
            {
                name: pd.Categorical.from_codes(cols[name][keep], categories=states[name])
                for name in self.variable_names
            },
            index=pd.RangeIndex(int(keep.sum())),
        )
        out.attrs["dropped_rows"] = int((~keep).sum())
        return out

    def _movement_indices(self, raw: pd.DataFrame, move: np.ndarray) -> np.ndarray:
        """Movement index per row: the row's ``action`` (optional column: an action name, or
        empty / None for a displacement) if it has one, else its displacement's direction."""
        idx = self.movements.discretize(move)
        if "action" not in raw.columns:
            return idx
        names = ["" if v is None or (isinstance(v, float) and np.isnan(v)) else str(v)
                 for v in raw["action"]]
        bad = sorted({n for n in names if n and n not in self.movements.actions})
        if bad:
            raise ValueError(
                f"column 'action' has action(s) {bad} outside the repertoire's "
                f"{list(self.movements.actions)}"
            )
        for i, n in enumerate(names):
            if n:
                idx[i] = self.movements.index_of(n)
        return idx

    def to_json(self) -> dict[str, object]:
        """A JSON-able description (kept in a bundle's ``extra`` and in run configs)."""
        d: dict[str, object] = {}
        for b in self.context:
            d[b.name] = {"kind": b.spec().kind, "n_bins": b.n_bins}
            if isinstance(b, DistanceBins | OffsetBins):
                d[b.name].update(low=b.low, high=b.high)  # type: ignore[union-attr]
            if isinstance(b, DistanceBins) and b.edges:
                d[b.name]["edges"] = list(b.edges)
        m = self.movements
        d["move"] = {
            "name": m.name,
            "planar": m.planar,
            "step": m.step,
            "dead_band": m.dead_band,
            "relative_dead_band": m.relative_dead_band,
            "actions": list(m.actions),
        }
        e = self.effects
        d["effect"] = {
            "name": e.name,
            "n_effects": e.n_effects,
            "threshold": e.threshold,
            "ratio": e.ratio,
        }
        d["high_level"] = {h.name: list(h.values) for h in self.high_level}
        return d
