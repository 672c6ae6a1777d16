"""The ``task`` scene: the press scene's button and lamp with the grasp block, for tasks that
chain skills (press the light off, then grasp the block: issue 13's executor).

The box of the press scene stands out of the way (far right corner); the block is the grasp
scene's, between it and the button.
"""

from __future__ import annotations

from dataclasses import dataclass

from a2l.sim.bullet import PressScene
from a2l.sim.config import _RGBA, PressConfig, _err

__all__ = ["TaskConfig", "TaskScene"]


@dataclass
class TaskConfig(PressConfig):
    """The ``task`` scene: :class:`a2l.sim.PressConfig` plus the grasp block
    (:class:`a2l.sim.GraspConfig`'s fields, same meaning)."""

    lift_threshold: float = 0.05
    block_size: tuple[float, float, float] = (0.03, 0.03, 0.06)
    block_mass: float = 0.05
    block_friction: float = 1.0
    block_position: tuple[float, float] = (0.62, -0.3)
    block_color: _RGBA = (0.1, 0.7, 0.15, 1.0)
    box_position: tuple[float, float] = (0.95, -0.6)

    def _validate_objects(self) -> None:
        super()._validate_objects()
        self._check_object("block")
        if not 0.008 <= self.block_size[1] <= 0.045:
            raise _err("block_size", f"y extent must be in [0.008, 0.045] m to fit the "
                       f"gripper, got {self.block_size[1]}")


class TaskScene(PressScene):
    """Button, lamp, box and the grasp block (config: :class:`TaskConfig`)."""

    name = "task"
    primary_object = "block"
    config: TaskConfig

    def _build_objects(self) -> None:
        super()._build_objects()
        cfg = self.config
        self._add_box("block", cfg.block_size, cfg.block_mass, cfg.block_friction,
                      cfg.block_position, cfg.block_color)
