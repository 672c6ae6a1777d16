"""The world of the babbling experiment: a robot's PyBullet push scene (Baxter's by default)
with one box (``push``) or two boxes far apart (``two_objects``), a trajectory played from a
genotype, and what comes out of it.

The start, the waypoints' box and the two boxes' homes are the thesis' (on Baxter) as offsets
from the robot's work point, turned and scaled with its table (:func:`a2l.robot.table_layout`):
on Baxter they are the thesis' values to the micrometre.

An evaluation has two parts that never mix:

- :func:`act_and_look`, what a strategy may know: the end-effector follows the genotype's
  waypoints with the scene's discrete movements, the arm is put back at the start
  (kinematically) and the world left to rest, and the camera image then, against the image
  before, gives the behaviour descriptor. It calls only ``reset``, ``execute``,
  ``eef_position`` (proprioception), ``place_arm``, ``settle`` and ``render``.
- :func:`evaluate_task` adds the experimenter's measurement (the true object positions
  before and after) for the metrics; strategies are never told it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from a2l.acquisition.trajectory import WaypointEncoding, play_and_look
from a2l.robot import DEFAULT_ROBOT
from a2l.rollout.cache import thread_scene
from a2l.rollout.protocol import ArmSceneProtocol

__all__ = ["BABBLING_SCENES", "Evaluation", "EvaluationTask", "WorldConfig", "act_and_look",
           "evaluate_task", "make_world", "object_homes"]

#: Scenes of the babbling experiment.
BABBLING_SCENES = ("push", "two_objects")

#: Where the boxes of the ``two_objects`` scene stand, from the work point (table frame, m
#: at scale 1): 0.46 m apart (on Baxter (0.55, -0.45) and (0.72, -0.02)).
TWO_OBJECTS = {"box": (-0.07, -0.20), "box2": (0.10, 0.23)}

#: The start and the waypoints' box from the work point (table frame, m at scale 1; heights
#: above the table top): on Baxter (0.42, -0.25, 0.25), (0.40, -0.72, 0.03), (0.78, 0.12, 0.30).
START = (-0.20, 0.0, 0.25)
LOW = (-0.22, -0.47, 0.03)
HIGH = (0.16, 0.37, 0.30)


@dataclass(frozen=True)
class WorldConfig:
    """The babbling world.

    Attributes
    ----------
    scene : {"push", "two_objects"}
        One box (the push scene's), or two boxes far apart.
    robot : str
        The robot: a built-in name (``baxter``, ``pr2``...) or a robot file's path.
    start : tuple of 3 float, optional
        Where every trajectory starts and ends (x, y, height above the table top) (m);
        default :data:`START` placed at the robot's work point.
    low, high : tuple of 3 float, optional
        The box the waypoints lie in (x, y, height above the table top) (m): the
        workspace over the table that the arm reaches with the gripper pointing down
        (waypoints in its unreachable corners are given up on the way); default
        :data:`LOW`, :data:`HIGH` placed at the robot's work point (the bounding box of the
        turned rectangle on a turned table).
    n_waypoints : int
        Waypoints per trajectory (genotype length ``3 * n_waypoints``).
    max_moves : int
        Most movements per trajectory.
    image_size : int
        Side of the downsampled image of the descriptor (pixels).
    camera_width, camera_height : int
        Camera image size (pixels).
    speed : float
        Cartesian speed of the end-effector during a movement (m/s; the scene's ``speed``;
        twice its default: half the physics steps per movement).
    time_step : float
        Physics step (s; the scene's ``time_step``): 120 Hz, half the scenes' default
        rate, half the physics steps again. Measured against 240 Hz on 40 trajectories
        aimed low at the box (BENCHMARKS.md, babbling): 29 moved it at both rates, one at
        240 Hz only; the median push is as long (13.0 against 13.1 cm); where a pushed box
        ended differs by a median 3.9 cm (pushes that turn the box diverge).
    seed : int
        The scene's seed.
    """

    scene: str = "push"
    robot: str = DEFAULT_ROBOT
    start: tuple[float, float, float] | None = None
    low: tuple[float, float, float] | None = None
    high: tuple[float, float, float] | None = None
    n_waypoints: int = 3
    max_moves: int = 16
    image_size: int = 32
    camera_width: int = 160
    camera_height: int = 120
    speed: float = 0.5
    time_step: float = 1.0 / 120.0
    seed: int = 0

    def __post_init__(self) -> None:
        if self.scene not in BABBLING_SCENES:
            raise ValueError(f"scene: unknown {self.scene!r}; choose one of "
                             f"{list(BABBLING_SCENES)}")
        if None in (self.start, self.low, self.high):
            start, low, high = _placed(self.layout())
            for name, v in (("start", start), ("low", low), ("high", high)):
                if getattr(self, name) is None:
                    object.__setattr__(self, name, v)
        for name in ("n_waypoints", "max_moves", "image_size", "camera_width",
                     "camera_height"):
            v = getattr(self, name)
            if not isinstance(v, int) or v < 1:
                raise ValueError(f"{name}: must be a positive integer, got {v!r}")
        for name in ("start", "low", "high"):
            v = getattr(self, name)
            if len(v) != 3 or not all(np.isfinite(v)):
                raise ValueError(f"{name}: must be 3 finite numbers, got {v!r}")
            object.__setattr__(self, name, tuple(float(x) for x in v))
        if not self.speed > 0:
            raise ValueError(f"speed: must be > 0, got {self.speed!r}")
        if not 0 < self.time_step <= 0.05:
            raise ValueError(f"time_step: must be in (0, 0.05] s, got {self.time_step!r}")
        if self.low[2] <= 0:
            raise ValueError(f"low: the height must be above the table top, got {self.low}")

    def layout(self) -> Any:
        """The robot's table layout (:func:`a2l.robot.table_layout`)."""
        from a2l.robot import robot_entry, table_layout

        return table_layout(robot_entry(self.robot))

    def encoding(self, table_z: float) -> WaypointEncoding:
        """The genotype encoding over a table top at height `table_z`."""
        up = np.array([0.0, 0.0, table_z])
        return WaypointEncoding(tuple(np.asarray(self.low) + up),
                                tuple(np.asarray(self.high) + up), self.n_waypoints)


def _placed(layout: Any) -> tuple[tuple[float, float, float], ...]:
    """:data:`START`, :data:`LOW` and :data:`HIGH` placed at the work point of `layout` (a
    :class:`a2l.robot.TableLayout`)."""
    k = layout.scale

    def z(v: float) -> float:
        return round(k * v, 6)

    corners = np.array([layout.place(c) for c in
                        (LOW[:2], HIGH[:2], (LOW[0], HIGH[1]), (HIGH[0], LOW[1]))])
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    return ((*layout.place(START[:2]), z(START[2])),
            (float(lo[0]), float(lo[1]), z(LOW[2])), (float(hi[0]), float(hi[1]), z(HIGH[2])))


def make_world(cfg: WorldConfig) -> Any:
    """The PyBullet scene of `cfg` (close it when done)."""
    from a2l.sim import make_config
    from a2l.sim.bullet import PushScene

    sim = make_config("push", robot=cfg.robot, object_jitter=0.0,
                      context_source="ground_truth",
                      camera_width=cfg.camera_width, camera_height=cfg.camera_height,
                      extra_camera_eyes=(), speed=cfg.speed,
                      time_step=cfg.time_step)
    if cfg.scene == "push":
        return PushScene(sim, cfg.seed)

    class TwoObjectsScene(PushScene):
        name = "two_objects"

        def _build_objects(self) -> None:
            c = self.config
            homes = object_homes(cfg, c)
            self._add_box("box", c.box_size, c.box_mass, c.box_friction, homes["box"],
                          c.box_color)
            self._add_box("box2", c.box_size, c.box_mass, c.box_friction, homes["box2"],
                          (0.1, 0.65, 0.2, 1.0))

    return TwoObjectsScene(sim, cfg.seed)


def _world(cfg: WorldConfig) -> Any:
    """The scene of this thread for `cfg` (built once, reused)."""
    return thread_scene("worlds", cfg, lambda: make_world(cfg))


def act_and_look(scene: ArmSceneProtocol, cfg: WorldConfig, genotype: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], int]:
    """Play `genotype` and look: what a babbling strategy may know of the movement
    (:func:`a2l.acquisition.trajectory.play_and_look`).

    Returns
    -------
    descriptor : ndarray, shape (image_size ** 2,)
        The grey image after the movement minus the one before, downsampled.
    path : ndarray, shape (m + 1, 3)
        End-effector positions (proprioception) at the start and after each movement.
    moves : int
        Movements tried (the way back is a placement, not a movement).
    """
    up = np.array([0.0, 0.0, scene.config.table_z])
    points = cfg.encoding(scene.config.table_z).decode(genotype)
    descriptor, path, _ = play_and_look(scene, np.asarray(cfg.start) + up, points,
                                        cfg.max_moves, cfg.image_size)
    return descriptor, path, len(path) - 1


@dataclass
class Evaluation:
    """One evaluated genotype.

    Attributes
    ----------
    descriptor : ndarray, shape (d,)
        What the strategy is told.
    path : ndarray, shape (m + 1, 3)
        End-effector positions.
    moves : int
        Movements carried out.
    displacement : dict of str to (dx, dy)
        Each object's displacement on the table (experimenter's measurement).
    final : dict of str to (x, y)
        Each object's final position (experimenter's measurement).
    """

    descriptor: NDArray[np.float64]
    path: NDArray[np.float64]
    moves: int
    displacement: dict[str, tuple[float, float]]
    final: dict[str, tuple[float, float]]


def object_homes(cfg: WorldConfig, sim_config: Any) -> dict[str, tuple[float, float]]:
    """Where the scene of `cfg` puts each object on reset (x, y) (m)."""
    if cfg.scene == "two_objects":
        layout = cfg.layout()
        return {n: layout.place(o) for n, o in TWO_OBJECTS.items()}
    return {"box": tuple(sim_config.box_position)}


@dataclass(frozen=True)
class EvaluationTask:
    """One genotype to evaluate, as a worker evaluates it (:func:`evaluate_task`).

    Attributes
    ----------
    world : WorldConfig
        The babbling world (scene, encoding, camera, seed).
    genotype : ndarray, shape (3 * world.n_waypoints,)
        The trajectory's waypoints, encoded (:meth:`WorldConfig.encoding`).
    """

    world: WorldConfig
    genotype: NDArray[np.float64]


def evaluate_task(task: EvaluationTask) -> Evaluation:
    """Evaluate one genotype in the world of ``task.world`` (runs in workers too)."""
    cfg = task.world
    scene = _world(cfg)
    descriptor, path, moves = act_and_look(scene, cfg, np.asarray(task.genotype, dtype=float))
    after = scene.ground_truth()["objects"]
    home = object_homes(cfg, scene.config)
    disp = {n: (float(after[n][0] - home[n][0]), float(after[n][1] - home[n][1]))
            for n in home}
    final = {n: (float(after[n][0]), float(after[n][1])) for n in home}
    return Evaluation(descriptor, path, moves, disp, final)
