"""The ``grasp_light`` scene: the grasp block next to a lamp, a "hot stove".

A skill whose behaviour depends on a high-level state (a demonstrated skill): with the light off it
grasps the block; with the light on it must move away from the block and wait. The light
does not change by itself; it is set at reset (config ``states={"light": "on"}``) or
switched mid-action by ``scene.perturb("toggle", state="light")``; being no effect of the
robot, a light change is not the ``pressed`` effect here.
"""

from __future__ import annotations

from dataclasses import replace

from a2l.sim.bullet import GraspScene
from a2l.sim.lamp import LampMixin
from a2l.sim.object_configs import GraspLightConfig
from a2l.sim.observation import Observation

__all__ = ["GraspLightScene"]


class GraspLightScene(LampMixin, GraspScene):
    """The grasp block and a lamp (config: :class:`a2l.sim.GraspLightConfig`)."""

    name = "grasp_light"
    primary_object = "block"
    config: GraspLightConfig

    def _build_objects(self) -> None:
        super()._build_objects()
        self._build_lamp()

    def _reset_extra(self) -> None:
        self._show_light()

    def _effect(self, before: Observation, after: Observation) -> str:
        # the light is not the robot's doing here (no button): its change is no effect
        states = {**before.states, "light": after.states.get("light", "off")}
        return super()._effect(replace(before, states=states), after)
