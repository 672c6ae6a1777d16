"""Building a PyBullet scene: the floor, the table, the robot (its entry,
:func:`a2l.robot.robot_entry`) and the boxes on the table."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

import a2l
from a2l.errors import A2LValueError
from a2l.robot import pybullet_urdf, robot_entry
from a2l.robot.layout import TABLE_HEIGHT
from a2l.sim._pybullet import p, quiet
from a2l.sim.assets import collision_render_urdf
from a2l.sim.bodies import BodyCache

__all__ = ["BOX_MARGIN", "PARK", "BuildMixin", "SceneObject"]

#: Room (m) kept between a box's top and the hand above a tool point at the box's mid-height
#: (:meth:`BuildMixin.tool_clearance`).
BOX_MARGIN = 0.01

#: PyBullet's collision filter group of static bodies (``btBroadphaseProxy::StaticFilter``):
#: a body without mass on a fixed base (the floor, the table) is in it, and its mask leaves it
#: out, so that two static bodies are never tested against each other.
STATIC_GROUP = 2
PARK = np.array([3.5, 2.0])  # where removed objects rest on the floor: behind the camera


@dataclass
class SceneObject:
    """An object of the scene as built: its PyBullet body (renewed at every reset), size,
    colour and configured place."""

    name: str
    body: int
    size: tuple[float, float, float]
    rgba: tuple[float, float, float, float]
    xy: tuple[float, float]  # configured position
    movable: bool = True
    link: int = -1  # link whose position is the object's (button: the cap)


class BuildMixin:
    """Builds the world of a :class:`~a2l.sim.bullet.BulletScene` (one of its bases)."""

    _client: int
    _bodies: BodyCache
    _objects: dict[str, SceneObject]
    config: Any
    #: The scene grasps a block: its gripper opens to the entry's ``grasp_open``.
    grasps: bool = False

    def _build_world(self) -> None:
        c, cfg = self._client, self.config
        #: Height of the floor: the table stands on it (a2l.robot.layout.TABLE_HEIGHT).
        self._floor_z = round(cfg.table_z - TABLE_HEIGHT, 6)
        floor = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=c)
        # the software renderer fills a large floor slowly (16 ms of a 30 ms frame): the
        # floor is drawn only in the GUI. A body without a visual shape is drawn with its
        # collision shape, so outside the GUI a small box hidden under the pedestal stands
        # in for the floor's visual and the camera sees the background around the table.
        floor_vis = p.createVisualShape(
            p.GEOM_BOX, halfExtents=(3, 3, 0.001) if cfg.gui else (0.01, 0.01, 0.001),
            rgbaColor=(0.45, 0.45, 0.47, 1), physicsClientId=c)
        self._bodies.add("floor", baseMass=0, baseCollisionShapeIndex=floor,
                         baseVisualShapeIndex=floor_vis, basePosition=(0, 0, self._floor_z))
        (cx, cy), (sx, sy) = cfg.table_center, cfg.table_size
        top_h = 0.04
        top = p.createCollisionShape(p.GEOM_BOX, halfExtents=(sx / 2, sy / 2, top_h / 2),
                                     physicsClientId=c)
        top_vis = p.createVisualShape(p.GEOM_BOX, halfExtents=(sx / 2, sy / 2, top_h / 2),
                                      rgbaColor=(0.78, 0.76, 0.72, 1), physicsClientId=c)
        leg_len = cfg.table_z - top_h - self._floor_z
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
        entry = robot_entry(cfg.robot)
        if entry.tool_down is None:
            raise A2LValueError(f"robot '{entry.name}' has no tool_down: the scenes move its "
                                "tool pointing down")
        #: The robot's entry (:class:`a2l.robot.RobotEntry`).
        self.robot_entry = entry
        urdf = pybullet_urdf(entry.urdf)
        if cfg.robot_visual == "collision":
            urdf = collision_render_urdf(urdf)
        with quiet():
            self._robot = p.loadURDF(str(urdf), (0, 0, 0), useFixedBase=True,
                                     flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=c)
        gripper = entry.gripper
        grip_names = set(gripper.joints) if gripper else set()
        self._joint_index: dict[str, int] = {}
        self._link_index: dict[str, int] = {}
        self._movable: list[int] = []
        self._effort: list[float] = []
        limits: dict[int, tuple[float, float]] = {}
        for j in range(p.getNumJoints(self._robot, physicsClientId=c)):
            info = p.getJointInfo(self._robot, j, physicsClientId=c)
            name = info[1].decode()
            self._joint_index[name] = j
            self._link_index[info[12].decode()] = j
            if info[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC):
                self._movable.append(j)
                limits[j] = (float(info[8]), float(info[9]))
                effort = float(info[10]) if info[10] > 0 else 50.0
                # the motors of revolute joints hold the arms against gravity
                # (motor_force_scale); the grippers' and the prismatic ones keep their limit
                held = info[2] == p.JOINT_PRISMATIC or name in grip_names
                self._effort.append(effort if held else effort * cfg.motor_force_scale)
        self.kinematics = a2l.Kinematics(entry.urdf, entry.base_link, entry.tool_link)
        self._arm = [self._joint_index[n] for n in self.kinematics.joint_names]
        vmax = np.asarray(self.kinematics.velocity_limits, dtype=float)
        self._vmax = np.where(vmax > 0, vmax, np.inf)
        self._neutral_q = np.asarray(entry.neutral, dtype=float)
        self._tool_down = np.asarray(entry.tool_down, dtype=float)
        self._build_gripper()
        # the joint targets every movable joint holds: 0 (or its nearest limit), the
        # entry's rest positions, the arm neutral, the gripper open
        self._targets = {j: _hold_zero(*limits[j]) for j in self._movable}
        for name, q in entry.rest:
            self._targets[self._named_joint(name, "rest")] = q
        for j, q in zip(self._arm, self._neutral_q, strict=True):
            self._targets[j] = float(q)
        for j, q in zip(self._fingers, self._finger_open, strict=True):
            self._targets[j] = q
        self._filter_still_links()

    def _named_joint(self, name: str, what: str) -> int:
        if name not in self._joint_index:
            raise A2LValueError(f"robot '{self.robot_entry.name}': {what} names the joint "
                                f"'{name}', which its URDF does not have")
        return self._joint_index[name]

    def _build_gripper(self) -> None:
        """The gripper's joints, their open (:meth:`a2l.robot.Gripper.opening`: wide in a
        scene that grasps) and closed positions, and the links they move (grip friction 1.5
        on every one of them)."""
        c, gripper = self._client, self.robot_entry.gripper
        self._fingers = [self._named_joint(n, "gripper") for n in
                         (gripper.joints if gripper else ())]
        self._finger_open = gripper.opening(self.grasps) if gripper else ()
        self._finger_closed = tuple(gripper.closed) if gripper else ()
        self._finger_links = self._moved_by(set(self._fingers))
        for link in sorted(self._finger_links):
            p.changeDynamics(self._robot, link, lateralFriction=1.5, physicsClientId=c)

    def _filter_still_links(self) -> None:
        """Leave the robot's still links out of the collision tests with the static bodies.

        Every link but the acting arm's (the pedestal, the torso, the head, the other arm
        held at its neutral pose) stays where it is, a third of a metre or more from the
        table top and the floor: it joins the static bodies' filter group
        (:data:`STATIC_GROUP`), so PyBullet no longer tests it against the floor and the
        table at every physics step (the floor plane overlaps every link's bounding box: 38
        pairs, 6-8 % of a step's CPU time). Those pairs never made a contact the solver could
        act on (a fixed link against a static body), so every movement is the same to the
        bit. The still links still collide with the objects that move.
        """
        c, r = self._client, self._robot
        acting = self._moved_by(set(self._arm))
        for link in range(-1, p.getNumJoints(r, physicsClientId=c)):
            if link not in acting:
                p.setCollisionFilterGroupMask(r, link, STATIC_GROUP, -1 ^ STATIC_GROUP,
                                              physicsClientId=c)

    def _moved_by(self, joints: set[int]) -> set[int]:
        """The robot's links that `joints` move (PyBullet indices: a link's index is its
        parent joint's): those with one of them on the way to the base."""
        c, r = self._client, self._robot
        parent = {j: p.getJointInfo(r, j, physicsClientId=c)[16]
                  for j in range(p.getNumJoints(r, physicsClientId=c))}
        out = set()
        for link in parent:
            up = link
            while up >= 0 and up not in joints:
                up = parent[up]
            if up >= 0:
                out.add(link)
        return out

    def _fit_tall_objects(self) -> None:
        """Lower a box whose size the layout gave (:meth:`a2l.sim.SceneConfig.layout_sized`)
        to fit under the hand: at most twice :meth:`tool_clearance` less
        :data:`BOX_MARGIN` (the Panda's push box: 5.9 cm, not 8). The configuration says the
        size built."""
        cfg = self.config
        names = cfg.layout_sized()
        if not names:
            return
        top = round(2 * self.tool_clearance() - BOX_MARGIN, 6)
        for name in names:
            x, y, h = getattr(cfg, name)
            if h > top:
                setattr(cfg, name, (x, y, top))

    def tool_clearance(self) -> float:
        """Height (m) above the tool point, at the neutral pose, of the lowest point of the
        links the chain's last joint moves, the gripper's fingers (they push) and the links
        holding the tool point (a pusher rod, a fixed jaw) left out; ``inf`` when no such link
        has a collision shape. Leaves the arm at the neutral pose.

        The pushes move the tool point at the height of the box's centre, and above the tool
        point sits the hand (the Panda's: 3.4 cm above its fingertips' centre, 21 cm wide): a
        box taller than twice the clearance reaches into it, and the hand clips its top going
        round it (on the Panda with the 8 cm box, 68 of 128 held-out pushes of a tuning run
        moved it the wrong way, the hand touching it 10 cm off the tool point).
        """
        c, robot = self._client, self._robot
        for j, q in zip(self._arm, self._neutral_q, strict=True):
            p.resetJointState(robot, j, float(q), physicsClientId=c)
        tool = self.kinematics.fk(self._neutral_q)[:3, 3]
        low = float("inf")
        for link in sorted(self._moved_by({self._arm[-1]}) - self._finger_links):
            if not p.getCollisionShapeData(robot, link, physicsClientId=c):
                continue
            lo, hi = p.getAABB(robot, link, physicsClientId=c)
            if all(lo[i] - 1e-3 <= tool[i] <= hi[i] + 1e-3 for i in range(3)):
                continue  # it holds the tool point
            low = min(low, lo[2] - float(tool[2]))
        return low

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
        self._objects[name] = SceneObject(name, body, tuple(size), tuple(rgba), tuple(xy))

    def _lamp_rgba(self) -> tuple[float, float, float, float] | None:
        return None



def _hold_zero(lower: float, upper: float) -> float:
    """0, or the nearest limit of a joint whose range leaves 0 out (none when ``upper <
    lower``: a continuous joint)."""
    if upper < lower:
        return 0.0
    return min(max(0.0, lower), upper)
