"""The PyBullet scenes with their objects: ``push`` (a box), ``grasp`` (a block) and
``press`` (a button toggling a lamp, and a box)."""

from __future__ import annotations

from a2l.errors import A2LValueError
from a2l.sim._pybullet import p
from a2l.sim.bullet.base import BulletScene
from a2l.sim.bullet.build import SceneObject
from a2l.sim.lamp import LampMixin
from a2l.sim.object_configs import GraspConfig, PressConfig, PushConfig

__all__ = ["GraspScene", "PressScene", "PushScene"]


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
    grasps = True
    config: GraspConfig

    def _build_objects(self) -> None:
        cfg = self.config
        if not self._fingers:
            raise A2LValueError(f"robot '{self.robot_entry.name}' has no gripper: the "
                                f"{self.name} scene grasps its block (give the robot file a "
                                "gripper, or use the push or press scene)")
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
        self._objects["button"] = SceneObject("button", body, (sx, sy, sz), tuple(cfg.button_color),
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
