"""The ``task`` scene: the press scene's button and lamp with the grasp block, for tasks that
chain skills (press the light off, then grasp the block: :mod:`a2l.planning.execute`).

The box of the press scene stands out of the way (far right corner); the block is the grasp
scene's, between it and the button.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from a2l import _core
from a2l.sim.bullet import PressScene
from a2l.sim.object_configs import GraspConfig, PressConfig

__all__ = ["TaskConfig", "TaskScene"]


@dataclass
class TaskConfig(PressConfig, GraspConfig):
    """The ``task`` scene: :class:`a2l.sim.PressConfig` (button, lamp, box) plus the block
    of :class:`a2l.sim.GraspConfig` (same fields); the box stands out of the way."""

    lift_threshold: float = _core.LIFT_THRESHOLD  # the grasp scene's (PressConfig's: 0.03)
    block_position: tuple[float, float] = None  # type: ignore[assignment]
    box_position: tuple[float, float] = None  # type: ignore[assignment]

    _SCALED: ClassVar[dict[str, Any]] = {**PressConfig._SCALED, **GraspConfig._SCALED}
    _PLACES: ClassVar[dict[str, tuple[float, float]]] = {
        **PressConfig._PLACES, "block_position": (0.0, -0.05), "box_position": (0.33, -0.35)}

    def _validate_objects(self) -> None:
        PressConfig._validate_objects(self)
        GraspConfig._validate_objects(self)


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
