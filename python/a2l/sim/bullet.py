"""The PyBullet scenes: Baxter on its pedestal, a table, and the scene's objects."""

from __future__ import annotations

import math
import os
import sys
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

import a2l
from a2l.errors import A2LError, A2LValueError
from a2l.robot import BAXTER_ARMS, arm_spec, pybullet_urdf
from a2l.sim._pybullet import p, quiet
from a2l.sim.assets import collision_render_urdf
from a2l.sim.bodies import BodyCache
from a2l.sim.config import GraspConfig, PressConfig, PushConfig, SceneConfig
from a2l.sim.lamp import LampMixin
from a2l.sim.perception import Camera, ColorTarget, Perception
from a2l.sim.scene import MoveResult, Observation, Scene

__all__ = ["BulletScene", "GraspScene", "PressScene", "PushScene", "GRIPPER_DOWN"]



#: Orientation of the gripper frame when it points down: z to the floor, fingers closing
#: along the world y axis.
GRIPPER_DOWN: NDArray[np.float64] = np.diag([-1.0, 1.0, -1.0])

_FLOOR_Z = -0.92418  # bottom of Baxter's pedestal in the base frame (pedestal mesh)
_FINGER_OPEN = 0.020833
_PARK = np.array([3.5, 2.0])  # where removed objects rest on the floor: behind the camera


@dataclass
class _Object:
    name: str
    body: int
    size: tuple[float, float, float]
    rgba: tuple[float, float, float, float]
    xy: tuple[float, float]  # configured position
    movable: bool = True
    link: int = -1  # link whose position is the object's (button: the cap)


class BulletScene(Scene):
    """A PyBullet scene; subclasses add the objects. Use :func:`a2l.sim.make_scene`."""

    config: SceneConfig

    def __init__(self, config: SceneConfig, seed: int = 0) -> None:
        super().__init__(config, seed)
        self._client = -1
        cfg = config
        if cfg.gui and sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
            # PyBullet would print "cannot connect to X server" and end the process
            raise A2LError("gui=True needs a display (DISPLAY is not set); run without the "
                           "GUI or under xvfb-run")
        self._client = p.connect(p.GUI if cfg.gui else p.DIRECT)
        if self._client < 0:
            raise A2LError("cannot connect to PyBullet" + (" in GUI mode: is there a display?"
                                                           if cfg.gui else ""))
        c = self._client
        if cfg.gui:
            p.configureDebugVisualizer(p.COV_ENABLE_GUI, 0, physicsClientId=c)
            p.resetDebugVisualizerCamera(1.6, 120, -25, (0.65, -0.15, -0.15), physicsClientId=c)
        p.setGravity(0, 0, -9.81, physicsClientId=c)
        p.setTimeStep(cfg.time_step, physicsClientId=c)
        # Contacts solved in an order that does not depend on the world's history (with the
        # objects rebuilt at every reset, see a2l.sim.bodies): same start, same rollout.
        p.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=c)
        self._tick = 0
        self._perceived_cache: tuple[int, Observation] | None = None
        self._objects: dict[str, _Object] = {}
        self._states: dict[str, str] = cfg.initial_states()
        #: Every body but the robot, rebuilt at each reset (a2l.sim.bodies).
        self._bodies = BodyCache(c)
        self._build_world()
        self._build_robot()
        self._build_objects()
        targets = [ColorTarget(o.name, o.rgba, o.size[2] / 2, o.size[0] * o.size[1])
                   for o in self._objects.values()]
        #: The cameras: the main one first, then the ones looked at when an object is
        #: hidden from it (see :meth:`perceive`).
        self.cameras = [Camera(c, cfg.camera_width, cfg.camera_height, eye,
                               cfg.camera_target, cfg.camera_fov)
                        for eye in (cfg.camera_eye, *cfg.extra_camera_eyes)]
        self.perceptions = [Perception(cam, targets, lamp_rgba=self._lamp_rgba())
                            for cam in self.cameras]
        self.camera = self.cameras[0]
        self.perception = self.perceptions[0]
        self.reset()

    # --- construction -------------------------------------------------------------
    def _build_world(self) -> None:
        c, cfg = self._client, self.config
        floor = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=c)
        # the software renderer fills a large floor slowly (16 ms of a 30 ms frame): the
        # floor is drawn only in the GUI. A body without a visual shape is drawn with its
        # collision shape, so outside the GUI a small box hidden under the pedestal stands
        # in for the floor's visual and the camera sees the background around the table.
        floor_vis = p.createVisualShape(
            p.GEOM_BOX, halfExtents=(3, 3, 0.001) if cfg.gui else (0.01, 0.01, 0.001),
            rgbaColor=(0.45, 0.45, 0.47, 1), physicsClientId=c)
        self._bodies.add("floor", baseMass=0, baseCollisionShapeIndex=floor,
                         baseVisualShapeIndex=floor_vis, basePosition=(0, 0, _FLOOR_Z))
        (cx, cy), (sx, sy) = cfg.table_center, cfg.table_size
        top_h = 0.04
        top = p.createCollisionShape(p.GEOM_BOX, halfExtents=(sx / 2, sy / 2, top_h / 2),
                                     physicsClientId=c)
        top_vis = p.createVisualShape(p.GEOM_BOX, halfExtents=(sx / 2, sy / 2, top_h / 2),
                                      rgbaColor=(0.78, 0.76, 0.72, 1), physicsClientId=c)
        leg_len = cfg.table_z - top_h - _FLOOR_Z
        legs = []
        if leg_len > 0:
            leg_vis = p.createVisualShape(p.GEOM_BOX, halfExtents=(0.025, 0.025, leg_len / 2),
                                          rgbaColor=(0.35, 0.33, 0.3, 1), physicsClientId=c)
            for ix in (-1, 1):
                for iy in (-1, 1):
                    legs.append((leg_vis, (ix * (sx / 2 - 0.05), iy * (sy / 2 - 0.05),
                                           -top_h / 2 - leg_len / 2)))
        self._bodies.add(
            "table", [(-1, {"lateralFriction": 0.5})], baseMass=0,
            baseCollisionShapeIndex=top, baseVisualShapeIndex=top_vis,
            basePosition=(cx, cy, cfg.table_z - top_h / 2), linkMasses=[0] * len(legs),
            linkCollisionShapeIndices=[-1] * len(legs),
            linkVisualShapeIndices=[v for v, _ in legs], linkPositions=[q for _, q in legs],
            linkOrientations=[(0, 0, 0, 1)] * len(legs),
            linkInertialFramePositions=[(0, 0, 0)] * len(legs),
            linkInertialFrameOrientations=[(0, 0, 0, 1)] * len(legs),
            linkParentIndices=[0] * len(legs), linkJointTypes=[p.JOINT_FIXED] * len(legs),
            linkJointAxis=[(0, 0, 1)] * len(legs))

    def _build_robot(self) -> None:
        c, cfg = self._client, self.config
        urdf = pybullet_urdf()
        if cfg.robot_visual == "collision":
            urdf = collision_render_urdf(urdf)
        with quiet():
            self._robot = p.loadURDF(str(urdf), (0, 0, 0), useFixedBase=True,
                                     flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=c)
        self._joint_index: dict[str, int] = {}
        self._link_index: dict[str, int] = {}
        self._movable: list[int] = []
        self._effort: list[float] = []
        for j in range(p.getNumJoints(self._robot, physicsClientId=c)):
            info = p.getJointInfo(self._robot, j, physicsClientId=c)
            self._joint_index[info[1].decode()] = j
            self._link_index[info[12].decode()] = j
            if info[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC):
                self._movable.append(j)
                effort = float(info[10]) if info[10] > 0 else 50.0
                finger = "finger" in info[1].decode()
                self._effort.append(effort if finger else effort * cfg.motor_force_scale)
        spec = arm_spec("baxter", cfg.arm)
        self.kinematics = a2l.Kinematics(spec.urdf, spec.base_link, spec.tip_link)
        self._arm = [self._joint_index[n] for n in self.kinematics.joint_names]
        vmax = np.asarray(self.kinematics.velocity_limits, dtype=float)
        self._vmax = np.where(vmax > 0, vmax, np.inf)
        self._neutral_q = np.asarray(spec.neutral, dtype=float)
        prefix = cfg.arm[0]
        self._fingers = [self._joint_index[f"{prefix}_gripper_l_finger_joint"],
                         self._joint_index[f"{prefix}_gripper_r_finger_joint"]]
        self._finger_links = set(self._fingers)
        for name in (f"{prefix}_gripper_l_finger_tip", f"{prefix}_gripper_r_finger_tip"):
            self._finger_links.add(self._link_index[name])
            p.changeDynamics(self._robot, self._link_index[name], lateralFriction=1.5,
                             physicsClientId=c)
        for j in self._fingers:
            p.changeDynamics(self._robot, j, lateralFriction=1.5, physicsClientId=c)
        # the joint targets every movable joint holds: both arms neutral, head straight
        self._targets = {j: 0.0 for j in self._movable}
        for arm, (_, _, neutral) in BAXTER_ARMS.items():
            for name, q in zip(
                    [f"{arm}_{s}" for s in ("s0", "s1", "e0", "e1", "w0", "w1", "w2")],
                    neutral, strict=True):
                self._targets[self._joint_index[name]] = q
        for arm in ("l", "r"):
            self._targets[self._joint_index[f"{arm}_gripper_l_finger_joint"]] = _FINGER_OPEN
            self._targets[self._joint_index[f"{arm}_gripper_r_finger_joint"]] = -_FINGER_OPEN

    def _build_objects(self) -> None:
        """Create the scene's objects (subclasses)."""

    def _add_box(self, name: str, size: tuple[float, float, float], mass: float,
                 friction: float, xy: tuple[float, float], rgba: tuple[float, ...]) -> None:
        c = self._client
        half = [s / 2 for s in size]
        col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=c)
        vis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=rgba,
                                  physicsClientId=c)
        body = self._bodies.add(name, [(-1, {"lateralFriction": friction})], baseMass=mass,
                                baseCollisionShapeIndex=col, baseVisualShapeIndex=vis,
                                basePosition=(xy[0], xy[1], self.config.table_z + half[2]))
        self._objects[name] = _Object(name, body, tuple(size), tuple(rgba), tuple(xy))

    def _lamp_rgba(self) -> tuple[float, float, float, float] | None:
        return None

    # --- low level ----------------------------------------------------------------
    def _arm_q(self) -> NDArray[np.float64]:
        states = p.getJointStates(self._robot, self._arm, physicsClientId=self._client)
        return np.array([s[0] for s in states])

    def eef_position(self) -> NDArray[np.float64]:
        return self.kinematics.fk(self._arm_q())[:3, 3].copy()

    def joint_positions(self) -> NDArray[np.float64]:
        """Joint positions (7,) of the acting arm, base to tip."""
        return self._arm_q()

    def _command(self) -> None:
        idx = list(self._targets)
        p.setJointMotorControlArray(
            self._robot, idx, p.POSITION_CONTROL,
            targetPositions=[self._targets[j] for j in idx],
            forces=self._effort, positionGains=[self.config.position_gain] * len(idx),
            physicsClientId=self._client)

    def _sim_step(self) -> None:
        p.stepSimulation(physicsClientId=self._client)
        self._tick += 1
        self._after_sim_step()
        if self.config.gui:
            time.sleep(self.config.time_step)

    def _after_sim_step(self) -> None:
        """Hook run after every physics step (the press scene watches its button)."""

    def _set_arm_targets(self, q: NDArray[np.float64]) -> None:
        for j, v in zip(self._arm, q, strict=True):
            self._targets[j] = float(v)

    def _set_fingers(self, closed: bool) -> None:
        l_, r_ = self._fingers
        self._targets[l_] = 0.0 if closed else _FINGER_OPEN
        self._targets[r_] = 0.0 if closed else -_FINGER_OPEN

    def _pose(self, xyz: ArrayLike) -> NDArray[np.float64]:
        t = np.eye(4)
        t[:3, :3] = GRIPPER_DOWN
        t[:3, 3] = np.asarray(xyz, dtype=float)
        return t

    # --- Scene interface ------------------------------------------------------------
    def reset(self, eef: ArrayLike | None = None,
              objects: dict[str, ArrayLike] | None = None) -> None:
        c, cfg = self._client, self.config
        # check the arguments before touching the world: a bad reset leaves it as it was
        q_arm = self._neutral_q.copy()
        if eef is not None:
            target = np.asarray(eef, dtype=float).reshape(3)
            if not np.all(np.isfinite(target)):
                raise A2LValueError(f"reset: eef must be 3 finite numbers, got {eef!r}")
            q_arm, rep = self.kinematics.ik_report(self._pose(target), self._neutral_q)
            if rep.status != a2l.Status.ok:
                raise A2LValueError(f"reset: eef {tuple(np.round(target, 4))} is unreachable "
                                    f"with the gripper pointing down "
                                    f"({a2l._core.status_name(rep.status)})")
        placed = dict(objects or {})
        for name in placed:
            if name not in self._objects:
                raise A2LValueError(f"reset: unknown object '{name}'; this scene has "
                                    f"{sorted(self._objects)}")
        moves = []
        for o in self._objects.values():
            xy = np.asarray(placed.get(o.name, o.xy), dtype=float).reshape(2)
            if o.movable and cfg.object_jitter > 0:
                xy = xy + self._rng.uniform(-cfg.object_jitter, cfg.object_jitter, 2)
            if o.name in placed or (o.movable and cfg.object_jitter > 0):
                cfg.check_on_table(f"{o.name} position", (float(xy[0]), float(xy[1])),
                                   (o.size[0] / 2, o.size[1] / 2))
                moves.append((o, xy))
        # New bodies but the robot: no contact or pair cache survives from earlier episodes
        # (restoreState would not clear them, a2l.sim.bodies); the robot's joints are all
        # reset below, its base is fixed.
        ids = self._bodies.rebuild()
        for o in self._objects.values():
            o.body = ids[o.name]
        self._removed = set()
        self._hold = 0
        self._states = cfg.initial_states()
        self._set_arm_targets(q_arm)
        self._set_fingers(self._states["gripper"] == "closed")
        for j, v in self._targets.items():
            p.resetJointState(self._robot, j, v, 0.0, physicsClientId=c)
        self._command()
        for o, xy in moves:
            self._place_base(o, xy)
        self._reset_extra()
        self._tick += 1
        self._perceived_cache = None
        self._episode_start = self._snapshot()
        self._step_start = self._episode_start

    def _place_base(self, o: _Object, xy: NDArray[np.float64]) -> None:
        pos, orn = p.getBasePositionAndOrientation(o.body, physicsClientId=self._client)
        if o.link == -1:
            z = self.config.table_z + o.size[2] / 2
        else:
            z = pos[2]
        self._teleport(o.body, (float(xy[0]), float(xy[1]), z),
                       orn if o.link != -1 else (0, 0, 0, 1))

    def _teleport(self, body: int, pos: Any, orn: Any) -> None:
        c = self._client
        p.resetBasePositionAndOrientation(body, pos, orn, physicsClientId=c)
        p.resetBaseVelocity(body, (0, 0, 0), (0, 0, 0), physicsClientId=c)

    def _reset_extra(self) -> None:
        """Scene-specific reset (light, button)."""

    def _object_names(self) -> list[str]:
        return list(self._objects)

    def _object_position(self, o: _Object) -> tuple[float, float, float]:
        c = self._client
        if o.link == -1:
            pos = p.getBasePositionAndOrientation(o.body, physicsClientId=c)[0]
        else:
            pos = p.getLinkState(o.body, o.link, computeForwardKinematics=True,
                                 physicsClientId=c)[4]
        return (float(pos[0]), float(pos[1]), float(pos[2]))

    def _ground_truth(self) -> Observation:
        objs = {n: self._object_position(o) for n, o in self._objects.items()
                if n not in self._removed}
        return Observation(objs, dict(self._states), self.eef_position(),
                           self._states["gripper"] == "closed")

    def _perceive(self) -> Observation:
        if self._perceived_cache is not None and self._perceived_cache[0] == self._tick:
            return self._perceived_cache[1]
        best: dict[str, tuple[float, tuple[float, float, float]]] = {}
        lit: bool | None = None
        for perception in self.perceptions:
            objs, lamp, visible = perception.locate(*perception.camera.render())
            for name, pos in objs.items():
                if name not in best or visible[name] > best[name][0]:
                    best[name] = (visible[name], pos)
            if "light_on" in lamp:
                lit = bool(lit) or lamp["light_on"]
            if len(best) == len(perception.targets) and all(
                    v >= self.config.min_visible for v, _ in best.values()):
                break  # every object well seen: no need for another view
        objs = {name: pos for name, (_, pos) in best.items()}
        states = dict(self._states)
        if lit is not None:
            states["light"] = "on" if lit else "off"
        obs = Observation(objs, states, self.eef_position(), self._states["gripper"] == "closed")
        self._perceived_cache = (self._tick, obs)
        return obs

    def render(self, camera: int = 0) -> tuple[NDArray[np.uint8], NDArray[np.float32]]:
        """One frame of camera `camera` (0: the main one): RGB (H, W, 3) uint8 and the
        depth buffer (H, W) float32."""
        return self.cameras[camera].render()

    def _move(self, disp: NDArray[np.float64]) -> MoveResult:
        cfg = self.config
        start = self.eef_position()
        target = start + disp
        lo = np.array(cfg.workspace_min) + np.array([0, 0, cfg.table_z])
        hi = np.array(cfg.workspace_max) + np.array([0, 0, cfg.table_z])
        if np.any(target < lo) or np.any(target > hi):
            axis = "xyz"[int(np.argmax((target < lo) | (target > hi)))]
            return MoveResult(False, "workspace_limit",
                              f"target {tuple(np.round(target, 3))} leaves the workspace along "
                              f"{axis} ([{tuple(np.round(lo, 3))}, {tuple(np.round(hi, 3))}])",
                              target, start)
        plan = self._plan_path(start, disp)
        if isinstance(plan, MoveResult):
            return plan
        self._follow_path(plan, float(np.linalg.norm(disp)))
        self._settle_at(target)
        reached = self.eef_position()
        err = float(np.linalg.norm(reached - target))
        if err > cfg.reach_tolerance:
            return MoveResult(False, "blocked", f"the end-effector stopped {err:.3f} m short "
                              f"of its target {tuple(np.round(target, 3))}", target, reached)
        return MoveResult(True, "ok", "", target, reached)

    # The three phases of a movement, timed apart by benchmarks/bench_sim.py.
    def _plan_path(self, start: NDArray[np.float64], disp: NDArray[np.float64]
                   ) -> list[NDArray[np.float64]] | MoveResult:
        """Joint positions (7,) of the straight line's waypoints, by the C++ IK, or why the
        line cannot be followed (a MoveResult)."""
        cfg = self.config
        target = start + disp
        n = max(1, math.ceil(np.linalg.norm(disp) / cfg.waypoint_spacing - 1e-9))
        q = self._arm_q()
        plan = []
        for i in range(1, n + 1):
            wp = start + disp * (i / n)
            qi, rep = self.kinematics.ik_report(self._pose(wp), q)
            if rep.status != a2l.Status.ok:
                status = a2l._core.status_name(rep.status)
                return MoveResult(False, "unreachable" if status != "joint_limit" else status,
                                  f"IK found no solution within the joint limits for waypoint "
                                  f"{i}/{n} at {tuple(np.round(wp, 3))} ({status}; error "
                                  f"{rep.position_error:.4f} m, {rep.orientation_error:.4f} rad)",
                                  target, start)
            jump = float(np.max(np.abs(qi - q)))
            if jump > cfg.max_joint_jump:
                return MoveResult(False, "unreachable",
                                  f"the IK solution for waypoint {i}/{n} at "
                                  f"{tuple(np.round(wp, 3))} is {jump:.2f} rad away in joint "
                                  f"space (> max_joint_jump {cfg.max_joint_jump}): the arm "
                                  "would swing around", target, start)
            plan.append(qi)
            q = qi
        return plan

    def _follow_path(self, plan: list[NDArray[np.float64]], length: float) -> None:
        """Send the waypoints one after the other, each held for the time the nominal speed
        gives it (longer where a joint would exceed its URDF velocity limit)."""
        cfg = self.config
        steps_per_wp = max(1, round(length / len(plan) / cfg.speed / cfg.time_step))
        q = self._arm_q()
        for qi in plan:
            need = float(np.max(np.abs(qi - q) / self._vmax)) / cfg.time_step
            self._set_arm_targets(qi)
            self._command()
            for _ in range(max(steps_per_wp, math.ceil(need))):
                self._sim_step()
            q = qi

    def _settle_at(self, target: NDArray[np.float64]) -> None:
        """Step until the end-effector is within 2 mm of `target` (at least 5 steps, at most
        0.3 s)."""
        settle_max = max(1, round(0.3 / self.config.time_step))
        for i in range(settle_max):
            self._sim_step()
            if i >= 4 and np.linalg.norm(self.eef_position() - target) < 0.002:
                break

    def _idle(self) -> None:
        cfg = self.config
        n = max(1, round(cfg.step / cfg.speed / cfg.time_step))
        for _ in range(n):
            self._sim_step()

    def settle(self, seconds: float = 0.2) -> None:
        """Let the physics run for `seconds` with the current joint targets."""
        for _ in range(max(1, round(seconds / self.config.time_step))):
            self._sim_step()

    def open_gripper(self) -> None:
        """Open the gripper and let the fingers move (0.4 s)."""
        self._states["gripper"] = "open"
        self._set_fingers(False)
        self._command()
        self.settle(0.4)

    def _gripper(self, closed: bool) -> None:
        if closed:
            self.close_gripper()
        else:
            self.open_gripper()

    def close_gripper(self) -> None:
        """Close the gripper and let the fingers move (0.4 s); an object between the finger
        tips is squeezed with the fingers' effort limit."""
        self._states["gripper"] = "closed"
        self._set_fingers(True)
        self._command()
        self.settle(0.4)

    def _place(self, name: str, xyz: NDArray[np.float64]) -> None:
        o = self._objects[name]
        self.config.check_on_table("delta", (float(xyz[0]), float(xyz[1])),
                                   (o.size[0] / 2, o.size[1] / 2))
        c = self._client
        pos, orn = p.getBasePositionAndOrientation(o.body, physicsClientId=c)
        shift = np.asarray(xyz, dtype=float) - np.asarray(self._object_position(o))
        self._teleport(o.body, tuple(np.asarray(pos) + shift), orn)
        self._tick += 1

    def _park(self, name: str) -> None:
        o = self._objects[name]
        c = self._client
        orn = p.getBasePositionAndOrientation(o.body, physicsClientId=c)[1]
        k = list(self._objects).index(name)
        self._teleport(o.body, (_PARK[0], _PARK[1] + 0.5 * k, _FLOOR_Z + o.size[2] / 2 + 0.05),
                       orn)
        self._tick += 1

    def _toggle(self, state: str) -> None:
        if state == "gripper":
            closed = self._states["gripper"] != "closed"
            self._states["gripper"] = "closed" if closed else "open"
            self._set_fingers(closed)
            self._command()
        self._tick += 1

    def contacts(self, name: str) -> bool:
        """Whether object `name` touches one of the gripper's fingers (ground truth)."""
        o = self._objects[name]
        pts = p.getContactPoints(self._robot, o.body, physicsClientId=self._client)
        return any(pt[3] in self._finger_links for pt in pts)

    # --- transit (a2l.planning.transit) -------------------------------------------
    @property
    def robot(self) -> int:
        """PyBullet body id of the robot."""
        return self._robot

    @property
    def arm_joints(self) -> list[int]:
        """PyBullet joint indices of the acting arm, base to tip (kinematics' order)."""
        return list(self._arm)

    def other_joint_positions(self) -> dict[str, float]:
        """Positions of the robot's movable joints outside the acting arm, by URDF name."""
        names = {j: n for n, j in self._joint_index.items()}
        return {names[j]: float(p.getJointState(self._robot, j, physicsClientId=self._client)[0])
                for j in self._movable if j not in self._arm}

    def obstacle_boxes(self) -> list[tuple[str, NDArray[np.float64], NDArray[np.float64]]]:
        """Everything but the robot as axis-aligned boxes, from PyBullet's current state.

        Returns
        -------
        list of (str, ndarray (3,), ndarray (3,))
            Name, centre and half-extents (m) of the table top, of every object (the
            button's housing and cap, the lamp...) and of the floor.
        """
        c = self._client
        out = [("floor", np.array([0.0, 0.0, _FLOOR_Z - 0.05]), np.array([3.0, 3.0, 0.05]))]
        ids = self._bodies.ids  # rebuilt at every reset: read the current ids
        bodies = [("table", ids["table"], [-1])]
        bodies += [(o.name, o.body, list(range(-1, p.getNumJoints(o.body, physicsClientId=c))))
                   for o in self._objects.values() if o.name not in self._removed]
        if "lamp" in ids:
            bodies.append(("lamp", ids["lamp"], [-1]))
        for name, body, links in bodies:
            for link in links:
                if link >= 0 and p.getCollisionShapeData(body, link, physicsClientId=c) == ():
                    continue
                lo, hi = (np.asarray(v, dtype=float)
                          for v in p.getAABB(body, link, physicsClientId=c))
                label = name if link < 0 else f"{name}_{link}"
                out.append((label, (lo + hi) / 2, np.maximum((hi - lo) / 2, 1e-4)))
        return out

    def follow_joint_trajectory(self, times: ArrayLike, positions: ArrayLike) -> float:
        """Track a joint trajectory of the acting arm with position targets, one per physics
        step (linear interpolation between samples), then let the arm settle (<= 0.3 s).

        Parameters
        ----------
        times : array_like, shape (k,)
            Increasing sample times (s), from 0.
        positions : array_like, shape (k, 7)
            Joint positions of the arm at `times`.

        Returns
        -------
        float
            Largest joint error (rad) to the last sample at the end.
        """
        t = np.asarray(times, dtype=float).reshape(-1)
        q = np.asarray(positions, dtype=float)
        if q.ndim != 2 or q.shape != (t.size, len(self._arm)) or t.size == 0 or \
                np.any(np.diff(t) < 0) or not np.all(np.isfinite(q)):
            raise A2LValueError(f"follow_joint_trajectory: need increasing times (k,) and "
                                f"finite positions (k, {len(self._arm)}), got {t.shape} and "
                                f"{q.shape}")
        dt = self.config.time_step
        for k in range(1, max(1, math.ceil(t[-1] / dt)) + 1):
            tk = min(k * dt, t[-1])
            self._set_arm_targets(np.array([np.interp(tk, t, q[:, i])
                                            for i in range(q.shape[1])]))
            self._command()
            self._sim_step()
        for _ in range(round(0.3 / dt)):
            if np.max(np.abs(self._arm_q() - q[-1])) < 2e-3:
                break
            self._sim_step()
        self._perceived_cache = None
        return float(np.max(np.abs(self._arm_q() - q[-1])))

    def close(self) -> None:
        if getattr(self, "_client", -1) >= 0:
            try:
                p.disconnect(physicsClientId=self._client)
            except p.error:
                pass
            self._client = -1

    @property
    def client(self) -> int:
        """The PyBullet physics client id of this scene."""
        return self._client


class PushScene(BulletScene):
    """A box on the table to push (config: :class:`a2l.sim.PushConfig`)."""

    name = "push"
    primary_object = "box"
    config: PushConfig

    def _build_objects(self) -> None:
        cfg = self.config
        self._add_box("box", cfg.box_size, cfg.box_mass, cfg.box_friction, cfg.box_position,
                      cfg.box_color)


class GraspScene(BulletScene):
    """A narrow block the gripper can grasp and lift (config: :class:`a2l.sim.GraspConfig`)."""

    name = "grasp"
    primary_object = "block"
    config: GraspConfig

    def _build_objects(self) -> None:
        cfg = self.config
        self._add_box("block", cfg.block_size, cfg.block_mass, cfg.block_friction,
                      cfg.block_position, cfg.block_color)


class PressScene(LampMixin, BulletScene):
    """A button that toggles a light, and a box (config: :class:`a2l.sim.PressConfig`).

    The button's cap slides down on a prismatic joint held up by a spring (a position
    motor of limited force); each time it goes down more than ``button_trigger`` the light
    toggles. The lamp is a sphere on the table, yellow when lit, dark grey when not.
    """

    name = "press"
    primary_object = "button"
    config: PressConfig

    def _build_objects(self) -> None:
        cfg, c = self.config, self._client
        self._add_box("box", cfg.box_size, cfg.box_mass, cfg.box_friction, cfg.box_position,
                      cfg.box_color)
        bx, by = cfg.button_position
        sx, sy, sz = cfg.button_size
        hb = cfg.button_base_height
        base_half = (sx / 2 + 0.01, sy / 2 + 0.01, hb / 2)
        cap_half = (sx / 2, sy / 2, sz / 2)
        base_col = p.createCollisionShape(p.GEOM_BOX, halfExtents=base_half, physicsClientId=c)
        base_vis = p.createVisualShape(p.GEOM_BOX, halfExtents=base_half,
                                       rgbaColor=(0.3, 0.3, 0.3, 1), physicsClientId=c)
        cap_col = p.createCollisionShape(p.GEOM_BOX, halfExtents=cap_half, physicsClientId=c)
        cap_vis = p.createVisualShape(p.GEOM_BOX, halfExtents=cap_half,
                                      rgbaColor=cfg.button_color, physicsClientId=c)
        # the cap rests with its top button_travel above the housing: it can go down by
        # button_travel before touching it
        cap_z = hb / 2 + cfg.button_travel + sz / 2 - 0.004
        body = self._bodies.add(
            "button", [(0, {"jointLowerLimit": -cfg.button_travel, "jointUpperLimit": 0.0})],
            baseMass=0, baseCollisionShapeIndex=base_col, baseVisualShapeIndex=base_vis,
            basePosition=(bx, by, cfg.table_z + hb / 2),
            linkMasses=[0.05], linkCollisionShapeIndices=[cap_col],
            linkVisualShapeIndices=[cap_vis], linkPositions=[(0, 0, cap_z)],
            linkOrientations=[(0, 0, 0, 1)], linkInertialFramePositions=[(0, 0, 0)],
            linkInertialFrameOrientations=[(0, 0, 0, 1)], linkParentIndices=[0],
            linkJointTypes=[p.JOINT_PRISMATIC], linkJointAxis=[(0, 0, 1)])
        self._objects["button"] = _Object("button", body, (sx, sy, sz), tuple(cfg.button_color),
                                          (bx, by), movable=False, link=0)
        self._build_lamp()
        self._presses = 0
        self._button_down = False

    @property
    def _button(self) -> int:
        return self._bodies.ids["button"]

    def _spring(self) -> None:
        p.setJointMotorControl2(self._button, 0, p.POSITION_CONTROL, targetPosition=0.0,
                                force=6.0, physicsClientId=self._client)

    def _reset_extra(self) -> None:
        p.resetJointState(self._button, 0, 0.0, 0.0, physicsClientId=self._client)
        self._spring()
        self._presses = 0
        self._button_down = False
        self._show_light()

    def button_depth(self) -> float:
        """How far the button's cap is pushed down (m, >= 0)."""
        return -float(p.getJointState(self._button, 0, physicsClientId=self._client)[0])

    @property
    def presses(self) -> int:
        """Number of presses since the last reset."""
        return self._presses

    def _after_sim_step(self) -> None:
        depth = self.button_depth()
        cfg = self.config
        if not self._button_down and depth > cfg.button_trigger:
            self._button_down = True
            self._presses += 1
            self._flip_light()
        elif self._button_down and depth < cfg.button_trigger / 2:
            self._button_down = False
