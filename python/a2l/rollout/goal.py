"""Bringing an object to a goal position by chaining learned push effects
(:func:`reach_goal`): at each moment the controller chooses which effect of the push skill to
run (:class:`GoalPolicy`: the effect whose direction points best at the goal, kept while it
still brings the object nearer along it), and the C++ step of the skill chooses every
movement for that effect, in closed loop (:func:`a2l.rollout.loop.closed_loop`), until the
object is within a tolerance of the goal, the caller says the episode is over, the step
budget is spent or the skill stops.

It makes a push skill a skill for goal-conditioned tasks: ``reach_goal(scene, bundle,
goal)`` where a task names a position.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.errors import A2LValueError
from a2l.rollout.approach import DESCENT, TRANSIT, Transit, descent
from a2l.rollout.loop import Decision, closed_loop
from a2l.rollout.protocol import SceneProtocol
from a2l.rollout.world import SceneWorld
from a2l.skills.effects import EFFECT_DIRECTIONS
from a2l.skills.runner import CppSkillRunner

__all__ = ["GoalPolicy", "GoalRun", "reach_goal"]




class GoalPolicy:
    """The policy of a goal-reaching run: which push effect to run now, and the C++ step of
    the skill for it.

    The effect is the one whose planar direction has the largest cosine with the way from
    the object to the goal; the current effect is kept while the object still has more than
    `keep` to go along its direction (a switch makes the arm go round the object to another
    face). When the effect changes, or the step reaches its step cap, the skill's run starts
    anew (the cap bounds one push, not the whole chain).

    A push skill learns and acts at the object's height. An end-effector higher than `air`
    above the object's centre first descends (:func:`descent`, recorded as
    :data:`DESCENT`): straight down where it is at least `clear_radius` from the object in
    the plane; nearer, straight away from it in the plane first.

    Parameters
    ----------
    bundle : str or PathLike
        A push skill bundle whose effects include axis or diagonal push effects.
    goal : array_like, shape (2,) or (3,)
        The goal position (m); only x and y count.
    keep : float
        Distance left along the current effect's direction (m) above which it is kept.
    effects : sequence of str, optional
        The effects to chain (default: every push effect of the bundle).

    Attributes
    ----------
    chosen : list of str
        The effect of each step the policy answered, in order.
    """

    def __init__(self, bundle: str | os.PathLike[str], goal: ArrayLike, keep: float = 0.02,
                 effects: Sequence[str] | None = None, air: float = 0.02,
                 clear_radius: float = 0.06, transit: Transit | None = None) -> None:
        self.runner = CppSkillRunner(bundle)
        known = [e for e in self.runner.skill.effect_values if e in EFFECT_DIRECTIONS]
        names = list(effects) if effects is not None else known
        bad = [e for e in names if e not in known]
        if bad or not names:
            raise A2LValueError(f"effects {bad or names}: the skill's push effects are "
                                f"{known}")
        self.effects = names
        units = np.array([EFFECT_DIRECTIONS[e] for e in names], dtype=float)
        self.units = units / np.linalg.norm(units, axis=1, keepdims=True)
        self.goal = np.asarray(goal, dtype=float).reshape(-1)[:2].copy()
        self.keep = float(keep)
        self.air, self.clear_radius = float(air), float(clear_radius)
        self.transit = transit
        self.step = self.runner.step_length
        self.current: int | None = None
        self.travelling = 0
        self.chosen: list[str] = []

    def effect_for(self, obj: NDArray[np.float64]) -> int:
        """Index (into :attr:`effects`) of the effect to run with the object at `obj` (3,)."""
        d = self.goal - np.asarray(obj, dtype=float)[:2]
        along = self.units @ d
        if self.current is not None and along[self.current] > self.keep:
            return self.current
        return int(np.argmax(along / max(float(np.linalg.norm(d)), 1e-12)))

    def _descent(self, eef: NDArray[np.float64], obj: NDArray[np.float64]
                 ) -> Decision | None:
        """The descent's next movement (:func:`descent`), recorded, or None."""
        down = descent(eef, obj, self.step, self.air, self.clear_radius)
        if down is None:
            return None
        self.chosen.append(DESCENT)
        return Decision("ok", DESCENT, down, down.copy())

    def __call__(self, k: int, eef: NDArray[np.float64], obj: NDArray[np.float64],
                 states: dict[str, str]) -> Decision:
        """Step k: the movement the C++ step chooses for the effect of the moment."""
        if not np.all(np.isfinite(obj)):
            return Decision("unknown_context")
        if self.transit is None:
            down = self._descent(eef, obj)
            if down is not None:
                return down
        e = self.effect_for(obj)
        if e != self.current:
            self.runner.reset()
            self.current = e
            travel = self.transit is not None and not self.transit.in_place(
                eef, obj, self.units[e], self.air)
            self.travelling = self.transit.max_steps if travel and self.transit else 0
        if self.travelling > 0:
            assert self.transit is not None
            move = self.transit.next(eef, obj, self.units[e], self.step)
            self.travelling = self.travelling - 1 if move is not None else 0
            if move is not None:
                self.chosen.append(TRANSIT)
                return Decision("ok", TRANSIT, move, move.copy())
        if self.transit is not None:  # a transit cut short in the air
            down = self._descent(eef, obj)
            if down is not None:
                return down
        out = self.runner.step(eef, obj, self.effects[e], states)
        if out.status == "step_cap":  # one push is capped, the chain goes on
            self.runner.reset()
            out = self.runner.step(eef, obj, self.effects[e], states)
        if not out.ok:
            return Decision(out.status)
        self.chosen.append(self.effects[e])
        if out.action is not None:
            return Decision("ok", out.action, np.zeros(3), out.action, out.movement)
        disp = np.asarray(out.displacement, dtype=float)
        return Decision("ok", out.label, disp, disp.copy(), out.movement)



class _GoalWorld(SceneWorld):
    """The scene of a goal-reaching run: a transit's displacement (longer than a
    movement along the diagonal) is carried out by ``scene.move_by``."""

    def act(self, decision: Decision) -> str:
        if decision.label != TRANSIT:
            return super().act(decision)
        before = self.truth()
        res = self.scene.move_by(decision.command)
        self.produced += self.truth() - before
        return str(res.status)


@dataclass
class GoalRun:
    """What :func:`reach_goal` did.

    Attributes
    ----------
    reached : bool
        The object ended within the tolerance of the goal.
    stop : str
        ``"reached"``, ``"done"`` (the caller's test), ``"budget"``, or why the skill or
        the scene stopped (``unknown_context``, ``unreachable``...).
    eef, obj : ndarray, shape (T, 3)
        End-effector and object before each movement and after the last.
    effects : list of str
        The effect each movement was chosen for (:data:`DESCENT` for the descent's).
    movements : list of int
        The movements carried out (indices into the skill's repertoire; -1 for the
        descent's).
    goal : ndarray, shape (2,)
    """

    reached: bool
    stop: str
    eef: NDArray[np.float64]
    obj: NDArray[np.float64]
    effects: list[str] = field(default_factory=list)
    movements: list[int] = field(default_factory=list)
    goal: NDArray[np.float64] = field(default_factory=lambda: np.zeros(2))

    @property
    def steps(self) -> int:
        """Movements carried out."""
        return len(self.movements)

    @property
    def error(self) -> float:
        """The object's final planar distance to the goal (m)."""
        return float(np.linalg.norm(self.obj[-1, :2] - self.goal))


def reach_goal(scene: SceneProtocol, bundle: str | os.PathLike[str], goal: ArrayLike,
               tolerance: float | None = 0.05, budget: int = 50,
               done: Callable[[], bool] | None = None, keep: float = 0.02,
               effects: Sequence[str] | None = None, air: float = 0.02,
               clear_radius: float = 0.06, transit: Transit | None = None) -> GoalRun:
    """Bring the scene's primary object to `goal` by chaining the push effects of `bundle`.

    Parameters
    ----------
    scene : SceneProtocol
        Where it runs, from its state now (ground truth positions).
    bundle : str or PathLike
        The push skill.
    goal : array_like, shape (2,) or (3,)
        Goal position (m); only x and y count.
    tolerance : float or None
        Stop, reached, when the object is within this of the goal in the plane (m); None:
        only `done` ends the run before the budget.
    budget : int
        Most movements.
    done : callable, optional
        ``done() -> bool`` before each movement: the episode is over (e.g. a Gymnasium
        environment terminated or truncated it).
    keep, effects, air, clear_radius, transit
        As :class:`GoalPolicy`.

    Returns
    -------
    GoalRun
    """
    policy = GoalPolicy(bundle, goal, keep=keep, effects=effects, air=air,
                        clear_radius=clear_radius, transit=transit)
    world = _GoalWorld(scene, scene.primary_object, source="ground_truth",
                       displacements=True)

    def stop(_k: int, _eef: NDArray[np.float64], obj: NDArray[np.float64],
             _states: dict[str, str]) -> str | None:
        if tolerance is not None and np.linalg.norm(obj[:2] - policy.goal) < tolerance:
            return "reached"
        return "done" if done is not None and done() else None

    run = closed_loop(world, policy, stop, budget, cap_status="budget")
    final = np.linalg.norm(run.obj[-1, :2] - policy.goal)
    reached = run.stop == "reached" or (tolerance is not None and final < tolerance)
    moves = run.carried_out(ok=("ok", "blocked"))
    return GoalRun(reached, run.stop, run.eef, run.obj, policy.chosen, moves,
                   policy.goal.copy())
