"""A skill bundle as the policy of a closed loop (:func:`a2l.rollout.loop.closed_loop`):
each step is the C++ step (:class:`a2l.skills.runner.CppSkillRunner`), nothing is
re-implemented here.

- :class:`TablePolicy` (``mode="table"``): bins -> compiled table -> a movement of the
  repertoire (carried out as its direction) or an action (open, close, stay: its name).
- :class:`PhasePolicy` (``mode="ds"``): the bundle's DS phases through the C++ ``step_ds``:
  a displacement of at most one movement's length along the DS velocity, or the phase's
  end action, the phase chosen by the high-level states.
"""

from __future__ import annotations

import os

import numpy as np
from numpy.typing import NDArray

from a2l.errors import A2LValueError
from a2l.rollout.loop import Decision
from a2l.skills.runner import MODES, CppSkillRunner

__all__ = ["PhasePolicy", "TablePolicy", "skill_policy"]


class TablePolicy:
    """The C++ step of a bundle's compiled table for one wanted effect.

    Parameters
    ----------
    bundle : str or PathLike
        The skill bundle.
    effect : str or int
        The wanted effect (a value of the bundle's effect variable, or its index).
    """

    def __init__(self, bundle: str | os.PathLike[str], effect: str | int) -> None:
        self.runner = CppSkillRunner(bundle, mode="table")
        self.effect = effect
        self.skill = self.runner.skill
        self.step_length = self.runner.step_length
        self.step_cap = self.runner.step_cap
        self.directions = np.asarray(self.skill.movements.directions, dtype=int)

    def __call__(self, k: int, eef: NDArray[np.float64], obj: NDArray[np.float64],
                 states: dict[str, str]) -> Decision:
        """Step k from the context ``(eef, obj, states)``."""
        try:
            out = self.runner.step(eef, obj, self.effect, states)
        except A2LValueError:  # a state value the table does not know
            return Decision("unknown_context")
        if out.status != "ok":
            return Decision(out.status)
        if out.action is not None:  # open / close / stay: no displacement
            return Decision("ok", out.action, np.zeros(3), out.action, out.movement)
        return Decision("ok", out.label, np.asarray(out.displacement, dtype=float),
                        tuple(int(v) for v in self.directions[out.movement]), out.movement)


class PhasePolicy:
    """The bundle's DS phases through the C++ ``step_ds``: a DS displacement (the command
    is the displacement) or the phase's end action (the command is its name).

    Parameters
    ----------
    bundle : str or PathLike
        A skill bundle with DS phases.
    effect : str
        The wanted effect (ignored by the DS: the phases are chosen by the states).
    """

    def __init__(self, bundle: str | os.PathLike[str], effect: str | int) -> None:
        self.runner = CppSkillRunner(bundle, mode="ds")
        self.effect = effect

    def __call__(self, k: int, eef: NDArray[np.float64], obj: NDArray[np.float64],
                 states: dict[str, str]) -> Decision:
        """Step k from the context ``(eef, obj, states)``."""
        if not np.all(np.isfinite(obj)):
            return Decision("unknown_context")
        out = self.runner.step(eef, obj, self.effect, states)
        if out.status != "ok":
            return Decision(out.status)
        if out.action is not None:
            return Decision("ok", out.action, np.zeros(3), out.action, out.movement)
        disp = np.asarray(out.displacement, dtype=float)
        return Decision("ok", f"ds:{out.phase}", disp, disp)


def skill_policy(bundle: str | os.PathLike[str], effect: str | int, mode: str = "table"
                 ) -> TablePolicy | PhasePolicy:
    """The policy of `bundle` for `effect` in `mode` (``"table"`` or ``"ds"``).

    Raises
    ------
    a2l.A2LValueError
        An unknown mode.
    """
    if mode not in MODES:
        raise A2LValueError(f"mode: {mode!r} is not one of {MODES}")
    return TablePolicy(bundle, effect) if mode == "table" else PhasePolicy(bundle, effect)
