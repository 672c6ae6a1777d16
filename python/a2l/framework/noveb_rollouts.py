"""NovEB as the framework's first acquisition (``a2l experiment push --acquisition noveb``).

NovEB explores the framework's scene from a fixed start in front of the robot, with
waypoints at the push height anywhere over the reachable table (it is not told where the
object is), and is told only image descriptors. The experimenter records, beside, the
object's positions during every trajectory; the trajectories that moved the object become
interactions in the common dataset format (cut where the object moved, as babbling's are,
and labelled with the observed effect), which feed the framework's iteration 0.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from a2l.acquisition.interactions import Rollout, effect_of
from a2l.acquisition.noveb import NovEB, NovEBConfig
from a2l.acquisition.protocol import drive
from a2l.acquisition.trajectory import WaypointEncoding, play_and_look
from a2l.framework.config import FrameworkConfig
from a2l.parallel import Executor
from a2l.rollout.env import ROBOT_SCENES, scene_env
from a2l.skills.repertoire import default_directions

__all__ = ["NOVEB_START", "NOVEB_WORKSPACE", "NovebTask", "noveb_acquire", "noveb_task"]

#: Where NovEB's trajectories start (x, y; at the push height) (m).
NOVEB_START = (0.42, -0.25)
#: The rectangle of the table its waypoints lie in (x, y low; x, y high) (m): what Baxter's
#: right arm reaches over the table with the gripper pointing down.
NOVEB_WORKSPACE = ((0.40, -0.72), (0.78, 0.12))

#: What :func:`noveb_task` returns: (descriptor (1024,), rollout or None, movements).
NovebResult = tuple[NDArray[np.float64], Rollout | None, int]


@dataclass(frozen=True)
class NovebTask:
    """One NovEB genotype, as a worker plays it (:func:`noveb_task`).

    Attributes
    ----------
    config : FrameworkConfig
        The run's configuration (its scene).
    genotype : ndarray, shape (3 k,)
        The waypoints' encoding (:class:`a2l.acquisition.trajectory.WaypointEncoding`).
    max_moves : int
        Most movements of the trajectory.
    """

    config: FrameworkConfig
    genotype: NDArray[np.float64]
    max_moves: int


def noveb_task(task: NovebTask) -> NovebResult:
    """Play one genotype in the framework's scene.

    Returns
    -------
    descriptor : ndarray, shape (1024,)
        What NovEB is told.
    rollout : Rollout or None
        The interaction up to the movement that moved the object (None: nothing moved, or
        a movement outside the framework's repertoire came first).
    movements : int
        Robot movements tried (the arm is put back at the start without moving).
    """
    cfg, genotype, max_moves = task.config, task.genotype, task.max_moves
    env = scene_env(cfg)
    disc = cfg.discretization.discretizer()
    z = float(env.home[2])
    (x0, y0), (x1, y1) = NOVEB_WORKSPACE
    points = WaypointEncoding((x0, y0, z), (x1, y1, z), len(genotype) // 3).decode(genotype)
    eefs: list[NDArray[np.float64]] = []
    objs: list[NDArray[np.float64]] = []

    def observe() -> None:  # the experimenter's record, never shown to NovEB
        eefs.append(env.eef().copy())
        objs.append(env.object().copy())

    descriptor, path, out = play_and_look(env.scene, (*NOVEB_START, z), points, max_moves,
                                          observe=observe, on_reset=observe)
    made = len(path) - 1
    directions = default_directions()  # play_and_look's movements, in the core's order
    repertoire = {tuple(int(s) for s in d): i
                  for i, d in enumerate(disc.movements.directions)}
    moves: list[int] = []
    for k, m in enumerate(out):
        idx = repertoire.get(tuple(int(s) for s in directions[m]))
        if idx is None:
            return descriptor, None, made
        moves.append(idx)
        effect = effect_of(disc, objs[k + 1] - objs[0])
        if effect >= 0:
            return descriptor, Rollout(-1, moves, np.array(eefs[: k + 2]),
                                       np.array(objs[: k + 2]), effect=effect,
                                       stop="moved"), made
    return descriptor, None, made


def noveb_acquire(cfg: FrameworkConfig, executor: Executor, evaluations: int,
                  generation_size: int = 20,
                  progress: Callable[[str, int, int], None] | None = None,
                  max_moves: int = 16) -> tuple[list[Rollout], NovEB, int]:
    """Run NovEB for `evaluations` trajectories; the interactions that moved the object.

    Returns
    -------
    rollouts : list of Rollout
        In evaluation order.
    noveb : NovEB
        The strategy at the end (archive, history).
    movements : int
        Robot movements made in all.
    """
    if cfg.scene not in ROBOT_SCENES:
        raise ValueError(f"NovEB sees the world through a camera: the {cfg.scene!r} scene has "
                         "none; use scene 'bullet'")
    noveb = NovEB(9, cfg.seed, evaluations,
                  NovEBConfig(mu=generation_size, lambda_=generation_size))
    kept: list[Rollout] = []
    count = {"done": 0, "movements": 0}

    def record(asked: Sequence[Any], results: Sequence[NovebResult]) -> None:
        kept.extend(r for _, r, _ in results if r is not None)
        count["movements"] += sum(m for _, _, m in results)
        count["done"] += len(asked)
        if progress:
            progress("noveb", count["done"], evaluations)

    drive(noveb, lambda asked: executor.map(noveb_task, [NovebTask(cfg, g, max_moves)
                                                          for g in asked]),
          generation_size, told=lambda results: np.array([d for d, _, _ in results]),
          on_batch=record)
    return kept, noveb, count["movements"]
