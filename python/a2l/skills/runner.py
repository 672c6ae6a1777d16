"""Running a skill bundle step by step from Python through the C++ runtime.

:class:`CppSkillRunner` holds a loaded :class:`a2l._core.Skill` and its run state, and calls
the one C++ implementation of a step: ``a2l._core.step`` (the compiled table, ``mode="table"``)
or ``a2l._core.step_ds`` (the DS phases, ``mode="ds"``). It only converts names to indices
and the C++ output to a :class:`StepResult`. :meth:`CppSkillRunner.cached` keeps one runner
per bundle per thread (the validation rollouts of a Dask worker).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np

from a2l import _core
from a2l.errors import A2LValueError, BundleError

__all__ = ["MODES", "CppSkillRunner", "StepResult"]

#: What a runner runs: the compiled table or the DS phases.
MODES = ("table", "ds")


@dataclass(frozen=True)
class StepResult:
    """What one step decided.

    Attributes
    ----------
    status : str
        ``"ok"``, or why the run stops: ``effect_produced``, ``step_cap``,
        ``unknown_context``, ``converged`` (a DS phase at its target), ``not_initialized``.
    movement : int
        Index of the movement in the repertoire (a direction or an action); -1 for a DS
        displacement or a stop.
    label : str
        The movement's label (an action's name), ``"ds"`` for a DS displacement, ``""`` on a
        stop.
    displacement : ndarray, shape (3,)
        End-effector displacement (m); zero for an action or a stop.
    action : str or None
        ``"open"``, ``"close"`` or ``"stay"`` for an action, else None.
    probability : float
        The movement's (smoothed) probability for a table step; 1 for a DS step; 0 on a stop.
    phase : str or None
        The DS phase that decided (``mode="ds"``), else None.
    fallback : bool
        The context cell had no data and the movement is its fallback's (the skill's
        ``nearest`` or ``approach`` fallback, ``docs/runtime.md``).
    """

    status: str
    movement: int
    label: str
    displacement: np.ndarray
    action: str | None
    probability: float = 0.0
    phase: str | None = None
    fallback: bool = False

    @property
    def ok(self) -> bool:
        """True if the step moved or acted."""
        return self.status == "ok"


class CppSkillRunner:
    """A skill bundle run step by step by the C++ runtime.

    Parameters
    ----------
    bundle_path : str or PathLike
        A skill bundle (``docs/bundle_format.md``); ``mode="ds"`` needs its ``ds_phases``.
    mode : {"table", "ds"}
        The context skill (compiled table, ``a2l._core.step``) or its DS phases
        (``a2l._core.step_ds``).
    trace_capacity : int
        Records the C++ trace ring buffer holds.

    Raises
    ------
    a2l.BundleError
        The bundle does not load, or ``mode="ds"`` and it has no DS phases.
    a2l.A2LValueError
        An unknown mode.
    """

    #: Runners per thread (a runner's SkillState is mutable: a Dask worker runs tasks in
    #: several threads), keyed by the bundle's path, mode, size and modification time.
    _local: ClassVar[threading.local] = threading.local()

    def __init__(self, bundle_path: str | os.PathLike[str], mode: str = "table",
                 trace_capacity: int = 1024) -> None:
        if mode not in MODES:
            raise A2LValueError(f"mode: {mode!r} is not one of {MODES}")
        self.path = Path(bundle_path)
        self.mode = mode
        self.skill = _core.load_bundle(self.path)
        self.phases = [p["name"] for p in self.skill.ds_phases]
        if mode == "ds" and not self.phases:
            raise BundleError(
                f"skill bundle '{self.path}': mode 'ds' needs DS phases and the bundle has "
                "none; write them with a2l.skills.save_bundle(spec, path, ds_phases=[...])"
            )
        self.state = _core.SkillState(self.skill, trace_capacity)
        self.labels: list[str] = list(self.skill.movements.labels)

    @classmethod
    def cached(cls, bundle_path: str | os.PathLike[str], mode: str = "table"
               ) -> CppSkillRunner:
        """One runner per bundle and mode per thread (loading validates the whole file).

        A file rewritten at the same path (a new run in the same directory, on a long-lived
        Dask worker) is loaded again. The caller resets the runner (:meth:`reset`).
        """
        cache: dict[tuple[str, str, int, int], CppSkillRunner] = \
            cls._local.__dict__.setdefault("runners", {})
        path = os.fspath(bundle_path)
        st = os.stat(path)
        key = (path, mode, st.st_size, st.st_mtime_ns)
        runner = cache.get(key)
        if runner is None:
            if len(cache) > 8:
                cache.clear()
            runner = cache[key] = cls(path, mode)
        return runner

    @property
    def step_length(self) -> float:
        """Movement length (m)."""
        return float(self.skill.movements.step)

    @property
    def step_cap(self) -> int:
        """Most movements a run may take."""
        return int(self.skill.step_cap)

    def reset(self) -> None:
        """Start a new run (step counter, DS end actions; the trace is kept)."""
        self.state.reset()

    def trace(self) -> list[_core.TraceRecord]:
        """The skill's trace, oldest first: the C++ ``TraceRecord`` of each step (its
        ``step``, ``bins``, ``movement``, ``probability``, ``status``, ``phase`` and
        ``fallback``; ``to_dict()`` gives them as a dict)."""
        return list(self.state.trace())

    def step(self, eef: np.ndarray, obj: np.ndarray, effect: str | int,
             states: Mapping[str, str] | None = None) -> StepResult:
        """One step from the current context.

        Parameters
        ----------
        eef, obj : array_like, shape (3,)
            End-effector and object positions (m).
        effect : str or int
            The wanted effect, a value of the bundle's effect variable or its index
            (ignored by the DS).
        states : mapping of str to str, optional
            High-level states (light, gripper, ...); states the table or the phases do not
            name are ignored.

        Returns
        -------
        StepResult

        Raises
        ------
        a2l.A2LValueError
            An effect or a state value the bundle does not know.
        """
        eef = np.asarray(eef, dtype=np.float64).reshape(3)
        obj = np.asarray(obj, dtype=np.float64).reshape(3)
        states = dict(states or {})
        if self.mode == "table":
            ctx = self.skill.context(eef, obj, effect, states)
            out = _core.step(self.skill, self.state, ctx)
        else:
            out = _core.step_ds(self.skill, self.state, eef, obj, states)
        status = _core.status_name(out.status)
        action = None
        if out.action != _core.MovementAction.none:
            action = _core.movement_action_name(out.action)
        phase = self.phases[out.record.phase] if out.record.phase >= 0 else None
        m = int(out.movement)
        if status != "ok":
            label = ""
        elif action is not None:
            label = action
        else:
            label = self.labels[m] if m >= 0 else "ds"
        return StepResult(status, m, label, np.array(out.displacement, dtype=np.float64),
                          action, float(out.probability), phase, bool(out.record.fallback))
