"""The config of the ``virtual`` scene (the C++ kinematic push model, no physics)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from a2l.sim.config_fields import choice_field, field_error, positive_field, vector_field

__all__ = ["VirtualConfig"]


@dataclass
class VirtualConfig:
    """The ``virtual`` scene (no physics; see docs/virtual_scene.md).

    Attributes
    ----------
    step : float
        Length of one discrete movement (m).
    table_z : float
        Height of the table plane (m).
    box_half_size : tuple of 3 float
        Half extents of the box (m).
    eef_radius : float
        Radius of the end-effector point (m).
    box_position : tuple of 2 float
        Initial centre (x, y) of the box.
    eef_position : tuple of 3 float
        Initial end-effector position.
    n_push_effects, effect_threshold, effect_ratio, object_jitter :
        As in :class:`SceneConfig`.
    context_source : str
        Accepted for uniformity; both sources give the true state (no camera).
    """

    step: float = 0.05
    table_z: float = 0.0
    box_half_size: tuple[float, float, float] = (0.035, 0.0425, 0.04)
    eef_radius: float = 0.01
    box_position: tuple[float, float] = (0.0, 0.0)
    eef_position: tuple[float, float, float] = (-0.2, 0.0, 0.04)
    n_push_effects: int = 8
    effect_threshold: float = 0.01
    effect_ratio: float = 3.0
    object_jitter: float = 0.0
    context_source: str = "ground_truth"
    states: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        choice_field(self, "context_source", ("perceived", "ground_truth"))
        for name in ("step", "eef_radius", "effect_threshold", "effect_ratio"):
            positive_field(self, name)
        positive_field(self, "object_jitter", allow_zero=True)
        if not isinstance(self.table_z, (int, float)) or not math.isfinite(self.table_z):
            raise field_error("table_z", f"must be a finite number, got {self.table_z!r}")
        vector_field(self, "box_half_size", 3, positive=True)
        vector_field(self, "box_position", 2)
        vector_field(self, "eef_position", 3)
        choice_field(self, "n_push_effects", (4, 8))
        if not isinstance(self.states, dict):
            raise field_error("states", f"expected a dict, got {self.states!r}")
        for name in self.states:
            raise field_error("states", f"unknown high-level state '{name}': the virtual scene has "
                       "none")
