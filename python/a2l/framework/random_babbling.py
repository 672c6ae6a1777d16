"""Random motor babbling (``docs/method.md``, acquisition): from start positions around the object,
uniformly random movements until the object moves; only the trajectories that moved it are
kept.

:func:`babble_task` plays one trajectory (it runs in worker processes too);
:class:`RandomBabbling` is the strategy that asks for them until enough moved the object.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from a2l.acquisition.interactions import Rollout, erase_loops, play
from a2l.framework.config import FrameworkConfig
from a2l.framework.validation import reachable_start
from a2l.rollout.env import scene_env

__all__ = ["BabbleTask", "RandomBabbling", "babble_task", "random_walk"]


@dataclass(frozen=True)
class BabbleTask:
    """One babbling trajectory, as a worker plays it (:func:`babble_task`).

    Attributes
    ----------
    config : FrameworkConfig
        The run's configuration (scene, starts, discretization).
    start : int
        Training start index (:meth:`FrameworkConfig.start_offsets`).
    prefix : tuple of int
        Movements played first (an extension's cut trajectory; empty for babbling).
    seed : int
        Seed of the random movements.
    steps : int
        Most random movements after the prefix.
    """

    config: FrameworkConfig
    start: int
    prefix: tuple[int, ...]
    seed: int
    steps: int


def babble_task(task: BabbleTask) -> Rollout:
    """Play one babbling trajectory: uniformly random movements after ``task.prefix``, at
    most ``task.steps`` of them, until the object moves."""
    return random_walk(task.config, task.start, task.prefix, task.seed, task.steps)


def random_walk(cfg: FrameworkConfig, start: int, prefix: Sequence[int], seed: int,
                steps: int) -> Rollout:
    """`prefix`, then at most `steps` uniformly random movements from start `start`."""
    disc = cfg.discretization.discretizer()
    rng = np.random.default_rng(seed)
    n = disc.movements.n_moves

    def choose(_eef: np.ndarray, _obj: np.ndarray) -> int:
        return int(rng.integers(n))

    offset = reachable_start(cfg, start)
    r = play(scene_env(cfg), disc, start, offset, prefix, choose, len(prefix) + steps)
    return erase_loops(r) if cfg.babbling.erase_loops else r


class RandomBabbling:
    """Random babbling until `target` trajectories moved the object or `try_cap` were tried.

    Candidates are :class:`BabbleTask` records (evaluate them with :func:`babble_task`);
    the i-th one starts at start ``i mod n_starts`` with seed ``seed_of(i)``. Outcomes are
    told in ask order and cut where the target is reached, so the kept trajectories do not
    depend on the batch size or on where the tasks ran.

    Parameters
    ----------
    cfg : FrameworkConfig
        Starts, babbling length and the scene.
    seed_of : callable
        ``seed_of(i)``: the seed of the i-th trajectory.
    target : int
        Trajectories that moved the object wanted.
    try_cap : int
        Most trajectories tried.
    """

    #: Candidates depend on their position only: may be asked before the previous are told.
    asks_ahead = True

    def __init__(self, cfg: FrameworkConfig, seed_of: Callable[[int], int], target: int,
                 try_cap: int) -> None:
        self.cfg = cfg
        self.seed_of = seed_of
        self.target = int(target)
        self.try_cap = int(try_cap)
        self.tried = 0
        #: Candidates asked so far (ahead of `tried` while outcomes are on their way).
        self.asked = 0
        self.kept: list[Rollout] = []
        #: Discrete movements of every trajectory told (:attr:`Rollout.executed`).
        self.movements = 0

    @property
    def done(self) -> bool:
        """Enough trajectories moved the object, or the try cap is reached."""
        return len(self.kept) >= self.target or self.tried >= self.try_cap

    def ask(self, n: int) -> list[BabbleTask]:
        """The next (at most) `n` trajectories to try: those after every one asked so far
        (told or not)."""
        if self.done:
            return []
        first = self.asked
        n = max(0, min(n, self.try_cap - first))
        self.asked += n
        return [BabbleTask(self.cfg, (first + i) % self.cfg.starts.n_starts, (),
                           self.seed_of(first + i), self.cfg.babbling.max_steps)
                for i in range(n)]

    def tell(self, asked: Sequence[BabbleTask], outcomes: Sequence[Rollout]) -> None:
        """Keep, in order, the trajectories that moved the object (up to the target); count
        the movements of all."""
        for r in outcomes:
            self.tried += 1
            self.movements += r.executed
            if r.moved and len(self.kept) < self.target:
                self.kept.append(r)
