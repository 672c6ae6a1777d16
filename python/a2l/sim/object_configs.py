"""The configs of the PyBullet object scenes (``push``, ``grasp``, ``grasp_light``,
``press``): the base :class:`a2l.sim.SceneConfig` plus each scene's objects."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from a2l import _core
from a2l.sim.config_fields import RGBA, field_error, positive_field, vector_field
from a2l.sim.scene_config import SceneConfig

__all__ = ["BOX_SIZE", "GraspConfig", "GraspLightConfig", "PressConfig", "PushConfig"]

#: The thesis' box (m, at scale 1): the push scene's and the press scene's.
BOX_SIZE = (0.07, 0.085, 0.08)


@dataclass
class PushConfig(SceneConfig):
    """The ``push`` scene: one box on the table (the authors' box by default).

    Attributes
    ----------
    box_size : tuple of 3 float
        Full extents (x, y, z) of the box (m).
    box_mass : float
        kg.
    box_friction : float
        Lateral friction coefficient of the box (the table has 0.5).
    box_position : tuple of 2 float
        Centre (x, y) of the box on the table.
    box_color : tuple of 4 float
        RGBA colour; perception segments it by hue (purple: Baxter's own meshes are red).
    """

    box_size: tuple[float, float, float] = None  # type: ignore[assignment]
    box_mass: float = 0.3
    box_friction: float = 0.4
    box_position: tuple[float, float] = None  # type: ignore[assignment]
    box_color: RGBA = (0.6, 0.15, 0.85, 1.0)

    _SCALED: ClassVar[dict[str, Any]] = {**SceneConfig._SCALED, "box_size": BOX_SIZE}
    _PLACES: ClassVar[dict[str, tuple[float, float]]] = {"box_position": (0.0, 0.0)}
    _TALL: ClassVar[tuple[str, ...]] = ("box_size",)

    def _validate_objects(self) -> None:
        self._check_object("box")


@dataclass
class GraspConfig(SceneConfig):
    """The ``grasp`` scene: a narrow block that Baxter's electric gripper can hold.

    The fingers close along the world y axis; ``block_size[1]`` must fit between the open
    finger tips (4.8 cm) and exceed the closed gap (0.65 cm). ``grasped`` needs the block
    5 cm up (``lift_threshold``, the C++ core's ``a2l::kLiftThreshold``, which ``a2l-run``
    uses), in the closed gripper.
    """

    lift_threshold: float = _core.LIFT_THRESHOLD
    block_size: tuple[float, float, float] = None  # type: ignore[assignment]
    block_mass: float = 0.05
    block_friction: float = 1.0
    block_position: tuple[float, float] = None  # type: ignore[assignment]
    block_color: RGBA = (0.1, 0.7, 0.15, 1.0)

    _SCALED: ClassVar[dict[str, Any]] = {**SceneConfig._SCALED,
                                         "block_size": (0.03, 0.03, 0.06)}
    _PLACES: ClassVar[dict[str, tuple[float, float]]] = {"block_position": (0.0, 0.0)}

    def _validate_objects(self) -> None:
        self._check_object("block")
        if not 0.008 <= self.block_size[1] <= 0.045:
            raise field_error("block_size", f"y extent must be in [0.008, 0.045] m to fit the "
                       f"gripper, got {self.block_size[1]}")


@dataclass
class GraspLightConfig(GraspConfig):
    """The ``grasp_light`` scene: the grasp block and a lamp, a "hot stove" next to it.

    With the light on the block must not be taken: the skill moves away and waits. The
    light is a high-level state (``"off"``/``"on"``) switched by ``states`` at reset or by
    the ``toggle`` perturbation; the camera sees the lamp.

    Attributes
    ----------
    lamp_position : tuple of 2 float
        Where the lamp stands on the table (m).
    lamp_radius : float
        Radius of the lamp's sphere (m).
    """

    lamp_position: tuple[float, float] = None  # type: ignore[assignment]
    lamp_radius: float = None  # type: ignore[assignment]

    _SCALED: ClassVar[dict[str, Any]] = {**GraspConfig._SCALED, "lamp_radius": 0.03}
    _PLACES: ClassVar[dict[str, tuple[float, float]]] = {**GraspConfig._PLACES,
                                                         "lamp_position": (0.23, 0.20)}

    def state_values(self) -> dict[str, tuple[str, ...]]:
        return {"gripper": ("open", "closed"), "light": ("off", "on")}

    def _validate_objects(self) -> None:
        super()._validate_objects()
        positive_field(self, "lamp_radius")
        vector_field(self, "lamp_position", 2)
        self.check_on_table("lamp_position", self.lamp_position,
                            (self.lamp_radius, self.lamp_radius))


@dataclass
class PressConfig(SceneConfig):
    """The ``press`` scene: a button that toggles a light, and a box.

    Attributes
    ----------
    button_size : tuple of 3 float
        Extents of the button's cap (m); it sits on a housing ``button_base_height`` high.
    button_travel : float
        How far the cap can be pushed down (m); a press is counted when it goes down more
        than ``button_trigger`` and the light toggles.
    lamp_position : tuple of 2 float
        Where the lamp (a sphere whose colour the camera sees) stands on the table.
    """

    button_size: tuple[float, float, float] = None  # type: ignore[assignment]
    button_base_height: float = None  # type: ignore[assignment]
    button_travel: float = None  # type: ignore[assignment]
    button_trigger: float = None  # type: ignore[assignment]
    button_position: tuple[float, float] = None  # type: ignore[assignment]
    button_color: RGBA = (0.1, 0.25, 0.9, 1.0)
    lamp_position: tuple[float, float] = None  # type: ignore[assignment]
    lamp_radius: float = None  # type: ignore[assignment]
    box_size: tuple[float, float, float] = None  # type: ignore[assignment]
    box_mass: float = 0.3
    box_friction: float = 0.4
    box_position: tuple[float, float] = None  # type: ignore[assignment]
    box_color: RGBA = (0.6, 0.15, 0.85, 1.0)

    _SCALED: ClassVar[dict[str, Any]] = {
        **SceneConfig._SCALED, "button_size": (0.06, 0.06, 0.02), "button_base_height": 0.025,
        "button_travel": 0.02, "button_trigger": 0.008, "lamp_radius": 0.03,
        "box_size": BOX_SIZE}
    _PLACES: ClassVar[dict[str, tuple[float, float]]] = {
        "button_position": (0.0, 0.15), "lamp_position": (0.33, 0.45),
        "box_position": (0.0, -0.10)}
    _TALL: ClassVar[tuple[str, ...]] = ("box_size",)

    def state_values(self) -> dict[str, tuple[str, ...]]:
        return {"gripper": ("open", "closed"), "light": ("off", "on")}

    def _validate_objects(self) -> None:
        self._check_object("box")
        self._check_object("button")
        for name in ("button_base_height", "button_travel", "button_trigger", "lamp_radius"):
            positive_field(self, name)
        if self.button_trigger >= self.button_travel:
            raise field_error("button_trigger", f"must be < button_travel ({self.button_travel})")
        vector_field(self, "lamp_position", 2)
        self.check_on_table("lamp_position", self.lamp_position,
                            (self.lamp_radius, self.lamp_radius))
