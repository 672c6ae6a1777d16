"""The closed loop every rollout runs: observe the context, check whether to stop, ask the
policy (the C++ step of a skill, a random walk, a replayed prefix...) for the next
movement, carry it out, and again (:func:`closed_loop`).

The three rooms that run rollouts use it: babbling and validation trajectories
(:func:`a2l.acquisition.interactions.play`, a framework scene env), and the demonstrated skills
(:func:`a2l.rollout.run.run_skill`, an :mod:`a2l.sim` scene, table or DS mode). What
differs between them is what a :class:`World` observes and does, the policy and the stop
test; the order of the loop, its record (:class:`LoopRun` of :class:`LoopStep`) and its stop
statuses are here only. (The *trace* is the skill's own record of each step, the C++
``TraceRecord`` that :meth:`a2l.skills.runner.CppSkillRunner.trace` returns.)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

__all__ = ["FATAL_MOVES", "Decision", "LoopRun", "LoopStep", "Policy", "StopTest", "World",
           "closed_loop"]

#: Movement statuses after which a run cannot go on (the same movement would be chosen).
FATAL_MOVES = ("unreachable", "workspace_limit", "joint_limit")

#: An observation: end-effector (3,), object (3,) (NaN: not seen), high-level states.
Observed = tuple[NDArray[np.float64], NDArray[np.float64], dict[str, str]]


def _zero() -> NDArray[np.float64]:
    return np.zeros(3)


@dataclass(frozen=True)
class Decision:
    """What a policy chose for one step.

    Attributes
    ----------
    status : str
        ``"ok"`` to carry out `command`, else why the run stops (``step_cap``,
        ``unknown_context``, ``converged``, ``stopped``...).
    label : str
        The movement's label (``""`` when none).
    displacement : ndarray, shape (3,)
        The commanded end-effector displacement (zero for an action or a stop).
    command : object
        What the :class:`World` carries out (a direction, an action's name, a DS
        displacement); None on a stop.
    movement : int
        Index of the movement in the repertoire; -1 for a DS displacement or a stop.
    """

    status: str
    label: str = ""
    displacement: NDArray[np.float64] = field(default_factory=_zero)
    command: Any = None
    movement: int = -1


@dataclass
class LoopStep:
    """One step of a closed-loop run.

    Attributes
    ----------
    index : int
        Step number (0 first).
    status : str
        ``"ok"`` when a movement was chosen, else why the run stopped.
    label : str
        The movement's label (table mode), ``"ds"`` (DS mode) or ``""`` (none).
    displacement : ndarray, shape (3,)
        The commanded end-effector displacement (zero when none).
    move_status : str
        What the world did with it (:class:`a2l.sim.MoveResult` status; ``""`` if none).
    eef, obj : ndarray, shape (3,)
        End-effector and object before the movement.
    states : dict of str to str
        High-level states the step saw.
    movement : int
        Index of the movement in the repertoire (-1: a DS displacement, or none).
    """

    index: int
    status: str
    label: str
    displacement: np.ndarray
    move_status: str
    eef: np.ndarray
    obj: np.ndarray
    states: dict[str, str]
    movement: int = -1


@dataclass
class LoopRun:
    """What :func:`closed_loop` recorded.

    Attributes
    ----------
    steps : list of LoopStep
        Every step, the last one holding the stop status (after a fatal movement, the
        step that tried it and then the stop).
    eef, obj : ndarray, shape (T, 3)
        End-effector and object at each step (T = len(steps)).
    stop : str
        Why the run ended: the stop test's status, the cap status, the policy's stop
        status or a fatal movement status.
    """

    steps: list[LoopStep]
    eef: NDArray[np.float64]
    obj: NDArray[np.float64]
    stop: str

    @property
    def executed(self) -> int:
        """Movements the world was asked to carry out."""
        return sum(1 for s in self.steps if s.status == "ok")

    def carried_out(self, ok: Sequence[str] = ("ok",)) -> list[int]:
        """Movement indices of the steps the world carried out (move status in `ok`)."""
        return [s.movement for s in self.steps if s.status == "ok" and s.move_status in ok]


class World(Protocol):
    """Where a closed loop runs: what it observes and how it acts."""

    def observe(self) -> Observed:
        """``(eef, obj, states)`` now (copies the loop may keep)."""
        ...

    def act(self, decision: Decision) -> str:
        """Carry out ``decision.command``; the move status (``"ok"``, or why not)."""
        ...


#: A policy: ``(k, eef, obj, states) -> Decision`` for step k.
Policy = Callable[[int, NDArray[np.float64], NDArray[np.float64], dict[str, str]], Decision]

#: A stop test: ``(k, eef, obj, states) -> status or None`` before step k (None: go on).
StopTest = Callable[[int, NDArray[np.float64], NDArray[np.float64], dict[str, str]],
                    str | None]


def closed_loop(world: World, policy: Policy, stop_test: StopTest, cap: int,
                cap_status: str = "step_cap", fatal: Sequence[str] = FATAL_MOVES,
                on_step: Callable[[int, LoopStep], None] | None = None) -> LoopRun:
    """Run `policy` in closed loop in `world` from where it is now.

    Before step k the loop observes the world and asks, in this order: `stop_test` (a
    status ends the run), whether ``k >= cap`` (ends with `cap_status`), the policy (a
    status other than ``"ok"`` ends the run). Otherwise the world carries out the
    decision; a move status in `fatal` ends the run after one more observation (the step
    is recorded, then the stop); else ``on_step(k, step)`` is called (a perturbation may
    be applied there) and the loop observes again.

    Parameters
    ----------
    world : World
    policy : callable ``(k, eef, obj, states) -> Decision``
    stop_test : callable ``(k, eef, obj, states) -> str or None``
    cap : int
        Most movements.
    cap_status : str
        The stop status at the cap.
    fatal : sequence of str
        Move statuses after which the run cannot go on.
    on_step : callable ``(k, LoopStep) -> None``, optional

    Returns
    -------
    LoopRun
    """
    steps: list[LoopStep] = []
    eefs: list[NDArray[np.float64]] = []
    objs: list[NDArray[np.float64]] = []
    eef, obj, states = world.observe()
    k = 0
    while True:
        eefs.append(eef)
        objs.append(obj)
        stop = stop_test(k, eef, obj, states)
        if stop is None and k >= cap:
            stop = cap_status
        if stop is None:
            decision = policy(k, eef, obj, states)
            if decision.status != "ok":
                stop = decision.status
        if stop is not None:
            steps.append(LoopStep(k, stop, "", np.zeros(3), "", eef, obj, states))
            break
        move_status = world.act(decision)
        step = LoopStep(k, "ok", decision.label, np.asarray(decision.displacement, float),
                         move_status, eef, obj, states, decision.movement)
        steps.append(step)
        if move_status in fatal:
            stop = move_status
            eef, obj, states = world.observe()
            eefs.append(eef)
            objs.append(obj)
            steps.append(LoopStep(k + 1, stop, "", np.zeros(3), "", eef, obj, states))
            break
        if on_step is not None:
            on_step(k, step)
        k += 1
        eef, obj, states = world.observe()
    return LoopRun(steps, np.asarray(eefs), np.asarray(objs), stop)
