"""Collision-free transit of an arm between skills: the C++ planner (OMPL + Bullet) from Python.

:class:`ArmTransit` builds :class:`a2l._core.TransitPlanner` for the arm of a robot entry
(:func:`a2l.robot.robot_entry`: a built-in robot or a robot file) from its URDF (collision
meshes read by :func:`a2l.sim.assets.mesh_vertices` and turned into convex hulls in C++),
ignores the link pairs that touch at the neutral pose, and plans with the obstacles of a
PyBullet scene; :meth:`ArmTransit.for_scene` takes the scene's robot. :func:`execute_transit`
runs a planned trajectory in that scene as joint position targets. See ``docs/planning.md``.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l import Kinematics, _core
from a2l.errors import A2LError, A2LValueError, URDFError
from a2l.robot import DEFAULT_ROBOT, RobotEntry, arm_entry, pybullet_urdf
from a2l.rollout.protocol import ArmSceneProtocol
from a2l.sim.assets import mesh_vertices

__all__ = ["ArmTransit", "TransitPlan", "execute_transit", "transit_robot",
           "urdf_collision_meshes"]


def urdf_collision_meshes(urdf: str | Path) -> dict[str, NDArray[np.float64]]:
    """Vertices (k, 3) of every collision mesh of a URDF, keyed by its filename attribute.

    Raises
    ------
    a2l.URDFError
        A mesh cannot be read.
    """
    out: dict[str, NDArray[np.float64]] = {}
    root = ET.parse(str(urdf)).getroot()
    for col in root.iter("collision"):
        for mesh in col.iter("mesh"):
            name = mesh.get("filename", "")
            path = Path(name)
            if not path.is_absolute():
                path = Path(urdf).parent / path
            verts = mesh_vertices(path)
            if verts is None or len(verts) < 4:
                raise URDFError(f"URDF '{urdf}': cannot read collision mesh '{name}'")
            out[name] = verts
    return out


@dataclass(frozen=True)
class TransitPlan:
    """A planned transit (or why there is none).

    Attributes
    ----------
    status : str
        ``ok`` or a :class:`a2l._core.TransitStatus` name (``no_path``, ``goal_in_collision``...).
    message : str
        Why, when not ok.
    planning_time : float
        s.
    waypoints : ndarray, shape (m, n)
        The collision-free joint-space polyline.
    times : ndarray, shape (k,)
    positions, velocities, accelerations : ndarray, shape (k, n)
        The time-parameterised trajectory.
    duration : float
        s, of the trajectory.
    path_length : float
        rad, summed joint-space length of `waypoints`.
    """

    status: str
    message: str
    planning_time: float
    waypoints: NDArray[np.float64]
    times: NDArray[np.float64]
    positions: NDArray[np.float64]
    velocities: NDArray[np.float64]
    accelerations: NDArray[np.float64]
    duration: float
    path_length: float

    @property
    def ok(self) -> bool:
        """True if a path was found."""
        return self.status == "ok"


def transit_robot(robot: str | os.PathLike[str] | RobotEntry, arm: str = "right") -> RobotEntry:
    """The robot entry whose arm :class:`ArmTransit` plans for.

    Parameters
    ----------
    robot : str, PathLike or RobotEntry
        A built-in robot's name (:data:`a2l.robot.BUILTIN_ROBOTS`), a robot file, or an
        entry (a scene's ``robot_entry``).
    arm : str
        Baxter's arm, ``"right"`` or ``"left"`` (``baxter`` with ``"left"`` is
        ``"baxter-left"``); ignored for an entry and for the other robots.

    Raises
    ------
    a2l.A2LValueError
        An unknown robot or Baxter arm (:func:`a2l.robot.arm_entry`).
    """
    if isinstance(robot, RobotEntry):
        return robot
    return arm_entry(robot, arm)


class ArmTransit:
    """Transit planning for the arm of a robot.

    Parameters
    ----------
    robot : str, PathLike or RobotEntry
        The robot (:func:`transit_robot`): ``baxter``, ``panda``..., a robot file, or a
        scene's ``robot_entry`` (:meth:`for_scene`).
    arm : str
        Baxter's arm, ``"right"`` or ``"left"``; ignored for the other robots.
    padding : float
        m added around every obstacle box.
    velocity_scale : float
        Fraction of the URDF velocity limits the trajectory may use.
    acceleration : float
        rad/s^2, every joint.
    time_limit : float
        s per planning call.
    """

    def __init__(self, robot: str | os.PathLike[str] | RobotEntry = DEFAULT_ROBOT,
                 arm: str = "right", padding: float = 0.02, velocity_scale: float = 0.5,
                 acceleration: float = 1.5, time_limit: float = 2.0,
                 resolution: float = 0.01) -> None:
        if not _core.transit_available():
            raise A2LError("this build of a2l has no transit planner (needs Bullet and OMPL)")
        self.robot = transit_robot(robot, arm)
        spec = self.robot.arm_spec()
        urdf = pybullet_urdf(spec.urdf)
        self.spec = spec
        self.padding = float(padding)
        self.planner = _core.TransitPlanner(str(urdf), spec.base_link, spec.tip_link,
                                            urdf_collision_meshes(urdf))
        self.neutral = np.asarray(spec.neutral, dtype=float)
        self.options = _core.TransitOptions()
        self.options.velocity_scale = velocity_scale
        self.options.acceleration = acceleration
        self.options.time_limit = time_limit
        self.options.resolution = resolution
        self._neutral_allowed = False

    @classmethod
    def for_scene(cls, scene: ArmSceneProtocol, **options: Any) -> ArmTransit:
        """Transit planning for the arm of a PyBullet scene's robot (its ``robot_entry``:
        Baxter's right arm, the Panda, a robot file's arm...); `options` as the class's."""
        return cls(scene.robot_entry, **options)

    @property
    def joint_names(self) -> list[str]:
        """The arm's joints, base to tip."""
        return list(self.planner.joint_names)

    def set_robot_joints(self, positions: dict[str, float]) -> None:
        """Positions of the joints outside the arm (the other arm, head, fingers); the pairs
        in collision at the neutral pose are then ignored (once)."""
        self.planner.set_joint_positions(positions)
        if not self._neutral_allowed:
            self.planner.allow_collisions_at(self.neutral)
            self._neutral_allowed = True

    def set_obstacles(self, boxes: list[tuple[str, ArrayLike, ArrayLike]]) -> None:
        """Replace the obstacles: (name, centre (3,), half-extents (3,)) axis-aligned boxes."""
        self.planner.set_obstacles(
            [_core.CollisionBox(n, np.asarray(c, float), np.asarray(h, float))
             for n, c, h in boxes], self.padding)

    def sync(self, scene: ArmSceneProtocol, ignore: tuple[str, ...] = ()) -> None:
        """Take the other joints and the obstacles from a PyBullet scene
        (:class:`a2l.sim.bullet.BulletScene`), leaving out the objects named in `ignore`
        (an object in the gripper moves with it: it is no obstacle)."""
        self.set_robot_joints(scene.other_joint_positions())
        self.set_obstacles([b for b in scene.obstacle_boxes()
                            if b[0] not in ignore and b[0].split("_")[0] not in ignore])

    def in_collision(self, q: ArrayLike) -> bool:
        """True if the arm at `q` (n,) collides with an obstacle or the robot."""
        return bool(self.planner.in_collision(np.asarray(q, dtype=float)))

    def plan(self, q_start: ArrayLike, q_goal: ArrayLike, seed: int = 0,
             time_limit: float | None = None) -> TransitPlan:
        """Plan from `q_start` to `q_goal` (n,) each; never raises for a failed search."""
        if not self._neutral_allowed:
            self.set_robot_joints({})
        opts = _core.TransitOptions()
        for k in ("velocity_scale", "acceleration", "resolution", "coarse_resolution",
                  "sample_period", "shorten", "shortcut_rounds", "shortcut_patience",
                  "default_velocity"):
            setattr(opts, k, getattr(self.options, k))
        opts.time_limit = self.options.time_limit if time_limit is None else float(time_limit)
        opts.seed = int(seed)
        r = self.planner.plan(np.asarray(q_start, float), np.asarray(q_goal, float), opts)
        return TransitPlan(_core.transit_status_name(r.status), r.message, r.planning_time,
                           np.asarray(r.waypoints), np.asarray(r.times), np.asarray(r.positions),
                           np.asarray(r.velocities), np.asarray(r.accelerations), r.duration,
                           r.path_length)

    def velocity_limits(self) -> NDArray[np.float64]:
        """Joint velocity limits (n,) the trajectories respect (URDF x velocity_scale)."""
        k = Kinematics(self.spec.urdf, self.spec.base_link, self.spec.tip_link)
        v = np.asarray(k.velocity_limits, dtype=float)
        v = np.where(v > 0, v, self.options.default_velocity)
        return v * self.options.velocity_scale


def execute_transit(scene: ArmSceneProtocol, plan: TransitPlan) -> float:
    """Run a planned transit in a PyBullet scene as joint position targets.

    Returns
    -------
    float
        Largest joint error (rad) to the goal at the end.

    Raises
    ------
    a2l.A2LValueError
        The plan has no trajectory.
    """
    if not plan.ok:
        raise A2LValueError(f"execute_transit: the plan has no trajectory ({plan.status}: "
                            f"{plan.message})")
    return scene.follow_joint_trajectory(plan.times, plan.positions)
