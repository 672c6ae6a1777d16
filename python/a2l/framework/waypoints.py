"""Effect-directed trajectories: random waypoint trajectories around the object
(:func:`random_waypoints` followed by :func:`heading_chooser`), or random walks, kept only
when they produce one wanted effect. The framework asks for them for (start, effect) pairs
its skill keeps failing (:class:`EffectDirected`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from a2l.acquisition.interactions import Rollout, erase_loops, play
from a2l.framework.config import FrameworkConfig
from a2l.framework.random_babbling import random_walk
from a2l.framework.validation import reachable_start
from a2l.rollout.env import scene_env

__all__ = ["DirectedTask", "EffectDirected", "Missed", "directed_outcome_task", "directed_task",
           "heading_chooser", "random_waypoints"]


@dataclass(frozen=True)
class DirectedTask:
    """One effect-directed trajectory, as a worker plays it (:func:`directed_task`).

    Attributes
    ----------
    config : FrameworkConfig
        The run's configuration (``directed.mode``, the scene, the starts).
    start : int
        Training start index.
    seed : int
        Seed of its random draws.
    steps : int
        Most movements.
    wanted : int
        The effect index it is tried for (-1: none; :func:`directed_outcome_task` needs
        one).
    """

    config: FrameworkConfig
    start: int
    seed: int
    steps: int
    wanted: int = -1


def random_waypoints(rng: np.random.Generator, home: np.ndarray, n_max: int, r_low: float,
                     r_high: float, aim: float) -> np.ndarray:
    """The points of a random waypoint trajectory around an object at `home`.

    0 to `n_max` via-points (uniformly many), each at a uniform angle and a uniform distance
    in ``[r_low, r_high]`` from `home` in the table plane, then a last point drawn uniformly
    within ± `aim` of `home` on each table axis. Like NovEB's genotypes (waypoints in the
    workspace), the trajectory is random, but it keeps a heading for several movements, so
    it goes around the object far more often than a random walk of the same length.

    Returns
    -------
    ndarray, shape (k, 3), 1 <= k <= n_max + 1
        The points, at `home`'s height; the last one is the aim on the object.
    """
    home = np.asarray(home, dtype=float)
    points = []
    for _ in range(int(rng.integers(0, n_max + 1))):
        a, r = rng.uniform(0, 2 * np.pi), rng.uniform(r_low, r_high)
        points.append(home + np.array([r * np.cos(a), r * np.sin(a), 0.0]))
    points.append(home + np.array([*rng.uniform(-aim, aim, 2), 0.0]))
    return np.array(points)


def heading_chooser(points: np.ndarray, disc: Any, start: np.ndarray
                    ) -> Callable[[np.ndarray, np.ndarray], int]:
    """A ``choose(eef, obj)`` that follows `points` (shape (k, 3)) from `start` (3,) with the
    repertoire's movements: each movement is the direction closest to the way to the
    current point; a point is passed when the end-effector comes within 0.7 steps of it
    (table plane), and the last one is headed for until the rollout ends (the object moves
    on the way).

    The chooser plans on the nominal positions (`start` plus the movements chosen so far),
    not on the measured `eef`: the trajectory is a function of its points alone. A physics
    scene ends a movement a few 1e-8 m off its target, differently in a process that ran
    other rollouts before (PyBullet keeps solver state across restores), and near a tie
    between two directions that noise would change the movement, and so the results with
    the number of workers.
    """
    dirs = disc.movements.directions.astype(float)
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    reach = 0.7 * disc.movements.step
    # every movement's displacement, once (the same numbers as displacement(move))
    steps = disc.movements.displacement(np.arange(disc.movements.n_moves)).reshape(-1, 3)
    k = 0
    at = np.array(start, dtype=float)

    def choose(_eef: np.ndarray, _obj: np.ndarray) -> int:
        nonlocal k, at
        while k < len(points) - 1 and np.linalg.norm((points[k] - at)[:2]) < reach:
            k += 1
        d = points[k] - at
        if disc.movements.planar:
            d[2] = 0.0
        move = int(np.argmax(dirs @ d))
        at = at + steps[move]
        return move

    return choose


def directed_task(task: DirectedTask) -> Rollout:
    """Play one effect-directed babbling trajectory.

    ``directed.mode == "random"``: uniformly random movements (as
    :func:`~a2l.framework.random_babbling.babble_task`); ``"waypoints"``: a random waypoint
    trajectory (:func:`random_waypoints`, :func:`heading_chooser`) with via-points between
    ``discretization.dist_low`` and the outer start radius + ``discretization.step`` from
    the object. At most ``task.steps`` movements, until the object moves.
    """
    cfg, start, seed, steps = task.config, task.start, task.seed, task.steps
    if cfg.directed.mode == "random":
        return random_walk(cfg, start, [], seed, steps)
    d = cfg.discretization
    disc = d.discretizer()
    env = scene_env(cfg)
    offset = reachable_start(cfg, start)
    points = random_waypoints(np.random.default_rng(seed), env.home, cfg.directed.waypoints_max,
                              d.dist_low, cfg.outer_start_radius + d.step,
                              cfg.directed.waypoint_aim)
    choose = heading_chooser(points, disc, env.home + offset)
    r = play(env, disc, start, offset, [], choose, steps)
    return erase_loops(r) if cfg.babbling.erase_loops else r


class Missed(NamedTuple):
    """What comes back of an effect-directed trajectory that did not produce the wanted
    effect (:func:`directed_outcome_task`)."""

    #: Its effect index (-1: nothing moved).
    effect: int
    #: The discrete movements played for it (:attr:`Rollout.executed`).
    movements: int


def directed_outcome_task(task: DirectedTask) -> Rollout | Missed:
    """:func:`directed_task` for its wanted effect (``task.wanted``).

    Returns the rollout only when it produced the wanted effect, else just its effect index
    and movement count (:class:`Missed`): all :meth:`EffectDirected.tell` needs, so a worker
    does not send back the many trajectories that are thrown away.
    """
    if task.wanted < 0:
        raise ValueError("directed_outcome_task: the task names no wanted effect")
    r = directed_task(task)
    return r if r.effect == task.wanted else Missed(r.effect, r.executed)


class EffectDirected:
    """Effect-directed trajectories from one start until `want` produced `effect` or `cap`
    were tried.

    Candidates are :class:`DirectedTask` records for `effect` (evaluate them with
    :func:`directed_outcome_task`), the i-th with seed ``seed_of(i)``; outcomes are told in
    ask order and cut at `want`.

    Parameters
    ----------
    cfg : FrameworkConfig
        Scene, trajectory mode and length (``directed.steps``).
    start : int
        Start index.
    effect : int
        The effect wanted.
    seed_of : callable
        ``seed_of(i)``: the seed of the i-th trajectory.
    want, cap : int
        Trajectories wanted, most tried.
    """

    #: Candidates depend on their position only: may be asked before the previous are told.
    asks_ahead = True

    def __init__(self, cfg: FrameworkConfig, start: int, effect: int,
                 seed_of: Callable[[int], int], want: int, cap: int) -> None:
        self.cfg = cfg
        self.start, self.effect = int(start), int(effect)
        self.seed_of = seed_of
        self.want, self.cap = int(want), int(cap)
        self.tried = 0
        #: Candidates asked so far (ahead of `tried` while outcomes are on their way).
        self.asked = 0
        self.found: list[Rollout] = []
        #: Discrete movements of every trajectory told.
        self.movements = 0

    @property
    def done(self) -> bool:
        """Enough trajectories produced the effect, or the try cap is reached."""
        return len(self.found) >= self.want or self.tried >= self.cap

    def ask(self, n: int) -> list[DirectedTask]:
        """The next (at most) `n` trajectories to try: those after every one asked so far
        (told or not)."""
        if self.done:
            return []
        first = self.asked
        n = max(0, min(n, self.cap - first))
        self.asked += n
        return [DirectedTask(self.cfg, self.start, self.seed_of(first + i),
                             self.cfg.directed.steps, self.effect) for i in range(n)]

    def tell(self, asked: Sequence[DirectedTask], outcomes: Sequence[Rollout | Missed]
             ) -> None:
        """Keep, in order, the trajectories that produced the effect (up to `want`); count
        the movements of all.

        An outcome is a :class:`Rollout` (:func:`directed_task`), or the :class:`Missed`
        record of a trajectory that did not produce the wanted effect
        (:func:`directed_outcome_task`).
        """
        for r in outcomes:
            self.tried += 1
            light = isinstance(r, Missed)
            self.movements += r.movements if light else r.executed
            if r.effect == self.effect and len(self.found) < self.want:
                if light:
                    raise ValueError(f"the outcome of a trajectory with effect {r.effect} "
                                     "must be its Rollout")
                self.found.append(r)
