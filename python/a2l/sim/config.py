"""Scene configurations: one dataclass per scene, validated field by field.

Every length is in metres, every position in the world frame, which is Baxter's ``base``
link frame (x forward, y to the robot's left, z up); the table top is the plane
``z = table_z``. An object position on the table is given as its centre ``(x, y)``; its
height follows from its size.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any

from a2l.errors import A2LValueError

__all__ = [
    "GraspConfig",
    "GraspLightConfig",
    "PressConfig",
    "PushConfig",
    "SceneConfig",
    "VirtualConfig",
    "config_class",
    "make_config",
]

_RGBA = tuple[float, float, float, float]


def _err(field_name: str, message: str) -> A2LValueError:
    return A2LValueError(f"scene config field '{field_name}': {message}")


def _vector(cfg: Any, name: str, n: int, positive: bool = False) -> None:
    value = getattr(cfg, name)
    try:
        vals = tuple(float(v) for v in value)
    except TypeError as exc:
        raise _err(name, f"expected {n} numbers, got {value!r}") from exc
    if len(vals) != n:
        raise _err(name, f"expected {n} numbers, got {len(vals)}: {value!r}")
    if not all(math.isfinite(v) for v in vals):
        raise _err(name, f"must be finite, got {value!r}")
    if positive and any(v <= 0 for v in vals):
        raise _err(name, f"every entry must be > 0, got {value!r}")
    setattr(cfg, name, vals)


def _positive(cfg: Any, name: str, allow_zero: bool = False) -> None:
    value = getattr(cfg, name)
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise _err(name, f"expected a number, got {value!r}") from exc
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise _err(name, f"must be {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    setattr(cfg, name, v)


def _choice(cfg: Any, name: str, choices: tuple[Any, ...]) -> None:
    value = getattr(cfg, name)
    if value not in choices:
        raise _err(name, f"must be one of {list(choices)}, got {value!r}")


@dataclass
class SceneConfig:
    """What every PyBullet scene shares: the world, the robot, the camera, the rules.

    Attributes
    ----------
    gui : bool
        Open the PyBullet GUI (default: DIRECT, no window) and run in real time.
    time_step : float
        Physics time step (s).
    arm : str
        Baxter arm that acts: ``"right"`` (the other one holds its neutral pose).
    step : float
        Length of one discrete movement (m).
    speed : float
        Cartesian speed of the end-effector during a movement (m/s); slower where a joint
        would exceed its URDF velocity limit.
    waypoint_spacing : float
        A movement is a straight line cut into waypoints this far apart (m), each solved by
        the C++ IK seeded with the previous solution.
    max_joint_jump : float
        Largest joint change (rad) allowed between two consecutive waypoints; a larger IK
        solution means the arm would swing around, and the movement is reported as
        unreachable instead.
    reach_tolerance : float
        A movement is carried out when the end-effector ends this close to its target (m);
        otherwise it is reported as ``blocked``.
    motor_force_scale : float
        The position motors of the arm and head joints may apply this multiple of the
        URDF's effort limits (50 Nm at the shoulder). The real Baxter holds its arms
        against gravity with springs and a gravity-compensating controller; with the bare
        limits the stretched arm sags under its own weight.
    position_gain : float
        Position gain of PyBullet's joint position motors (its default, 0.1, leaves the
        end-effector about 2 mm short under gravity; 0.3 brings it within 0.1 mm).
    workspace_min, workspace_max : tuple of 3 float
        Bounds of the end-effector point; a movement whose target leaves them is reported
        as ``workspace_limit``. ``workspace_min[2]`` is relative to the table top.
    table_z : float
        Height of the table top (m).
    table_center, table_size : tuple of 2 float
        Centre ``(x, y)`` and size ``(depth, width)`` of the table top (m).
    robot_visual : str
        ``"collision"`` draws the robot with its collision shapes (fast camera frames),
        ``"mesh"`` with its visual meshes (slow, pretty; the GUI's default).
    camera_width, camera_height : int
        Camera image size (pixels).
    camera_eye, camera_target : tuple of 3 float
        Camera position and the point it looks at (m): by default a camera facing the robot
        from beyond the table, high enough to see the whole table top.
    camera_fov : float
        Vertical field of view (degrees).
    extra_camera_eyes : tuple of (x, y, z)
        More cameras looking at ``camera_target`` (by default from the robot's left and
        right). Perception renders the main camera and, only when it sees less than
        ``min_visible`` of an object's top face (the arm is in front of it), these in turn,
        keeping for each object the view that sees most of it.
    min_visible : float
        Share of an object's top face in view above which no other camera is rendered.
    context_source : str
        ``"perceived"`` (camera + OpenCV, the default in experiments) or ``"ground_truth"``.
    n_push_effects : int
        4 (axes only) or 8 (axes and diagonals) push effects.
    effect_threshold : float
        Object displacement (m) below which the effect is ``none``.
    effect_ratio : float
        An axis effect when the dominant axis moved more than this times the other.
    lift_threshold : float
        Rise (m) above which an object held in the closed gripper is ``grasped``.
    object_jitter : float
        Each reset draws every movable object's ``(x, y)`` uniformly within ± this (m),
        from the scene's seed.
    states : dict
        Initial high-level states, e.g. ``{"gripper": "closed"}``; names the scene does not
        have are an error.
    """

    gui: bool = False
    time_step: float = 1.0 / 240.0
    arm: str = "right"
    step: float = 0.05
    speed: float = 0.25
    waypoint_spacing: float = 0.01
    max_joint_jump: float = 0.5
    reach_tolerance: float = 0.01
    motor_force_scale: float = 4.0
    position_gain: float = 0.3
    workspace_min: tuple[float, float, float] = (0.35, -0.75, 0.01)
    workspace_max: tuple[float, float, float] = (0.95, 0.45, 0.45)
    table_z: float = -0.20
    table_center: tuple[float, float] = (0.75, -0.15)
    table_size: tuple[float, float] = (0.7, 1.2)
    robot_visual: str = "collision"
    camera_width: int = 320
    camera_height: int = 240
    camera_eye: tuple[float, float, float] = (1.55, -0.15, 0.85)
    camera_target: tuple[float, float, float] = (0.75, -0.15, -0.2)
    camera_fov: float = 55.0
    extra_camera_eyes: tuple[tuple[float, float, float], ...] = (
        (0.75, 0.95, 0.85), (0.75, -1.25, 0.85))
    min_visible: float = 0.9
    context_source: str = "perceived"
    n_push_effects: int = 8
    effect_threshold: float = 0.01
    effect_ratio: float = 3.0
    lift_threshold: float = 0.03
    object_jitter: float = 0.0
    states: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.validate()

    # --- validation -------------------------------------------------------------
    def state_values(self) -> dict[str, tuple[str, ...]]:
        """The scene's high-level states and their possible values (first = default)."""
        return {"gripper": ("open", "closed")}

    def validate(self) -> None:
        """Check every field; raise :class:`a2l.A2LValueError` naming the first bad one."""
        for name in ("gui",):
            if not isinstance(getattr(self, name), bool):
                raise _err(name, f"must be True or False, got {getattr(self, name)!r}")
        for name in ("time_step", "step", "speed", "waypoint_spacing", "max_joint_jump",
                     "reach_tolerance", "motor_force_scale", "position_gain", "camera_fov",
                     "effect_threshold", "effect_ratio", "lift_threshold"):
            _positive(self, name)
        _positive(self, "object_jitter", allow_zero=True)
        if self.time_step > 0.05:
            raise _err("time_step", f"must be <= 0.05 s, got {self.time_step}")
        if self.camera_fov >= 170:
            raise _err("camera_fov", f"must be < 170 degrees, got {self.camera_fov}")
        _choice(self, "arm", ("right",))
        _choice(self, "robot_visual", ("collision", "mesh"))
        _choice(self, "context_source", ("perceived", "ground_truth"))
        _choice(self, "n_push_effects", (4, 8))
        for name in ("camera_width", "camera_height"):
            v = getattr(self, name)
            if not isinstance(v, int) or isinstance(v, bool) or not 16 <= v <= 4096:
                raise _err(name, f"must be an integer in [16, 4096], got {v!r}")
        if not isinstance(self.table_z, (int, float)) or not math.isfinite(self.table_z):
            raise _err("table_z", f"must be a finite number, got {self.table_z!r}")
        self.table_z = float(self.table_z)
        _vector(self, "table_center", 2)
        _vector(self, "table_size", 2, positive=True)
        _vector(self, "workspace_min", 3)
        _vector(self, "workspace_max", 3)
        for i, axis in enumerate("xyz"):
            if self.workspace_min[i] >= self.workspace_max[i]:
                raise _err("workspace_max", f"{axis} bound must exceed workspace_min's")
        _vector(self, "camera_eye", 3)
        _vector(self, "camera_target", 3)
        if self.camera_eye == self.camera_target:
            raise _err("camera_eye", "must differ from camera_target")
        try:
            eyes = [tuple(float(v) for v in e) for e in self.extra_camera_eyes]
        except (TypeError, ValueError) as exc:
            raise _err("extra_camera_eyes", "expected a sequence of (x, y, z)") from exc
        if any(len(e) != 3 or not all(math.isfinite(v) for v in e) or e == self.camera_target
               for e in eyes):
            raise _err("extra_camera_eyes", f"every eye must be 3 finite numbers away from "
                       f"camera_target, got {self.extra_camera_eyes!r}")
        self.extra_camera_eyes = tuple(eyes)  # type: ignore[assignment]
        _positive(self, "min_visible", allow_zero=True)
        if self.min_visible > 1:
            raise _err("min_visible", f"must be in [0, 1], got {self.min_visible}")
        if not isinstance(self.states, dict):
            raise _err("states", f"expected a dict name -> value, got {self.states!r}")
        known = self.state_values()
        for name, value in self.states.items():
            if name not in known:
                raise _err("states", f"unknown high-level state '{name}' for this scene; "
                           f"known: {sorted(known)}")
            if value not in known[name]:
                raise _err("states", f"state '{name}' must be one of {list(known[name])}, "
                           f"got {value!r}")
        self._validate_objects()

    def _validate_objects(self) -> None:
        """Validate the scene's objects (sizes, masses, positions on the table)."""

    def _check_object(self, prefix: str, footprint_xy: tuple[float, float] | None = None) -> None:
        """Validate ``<prefix>_size``, ``_mass``, ``_friction``, ``_position`` if present."""
        size_name = f"{prefix}_size"
        _vector(self, size_name, 3, positive=True)
        for suffix in ("mass", "friction"):
            if hasattr(self, f"{prefix}_{suffix}"):
                _positive(self, f"{prefix}_{suffix}")
        pos_name = f"{prefix}_position"
        _vector(self, pos_name, 2)
        size = getattr(self, size_name)
        half = footprint_xy if footprint_xy is not None else (size[0] / 2, size[1] / 2)
        if hasattr(self, f"{prefix}_mass"):  # a movable object: jittered on every reset
            half = (half[0] + self.object_jitter, half[1] + self.object_jitter)
        self.check_on_table(pos_name, getattr(self, pos_name), half)

    def check_on_table(self, name: str, xy: tuple[float, float],
                       half: tuple[float, float]) -> None:
        """Raise naming `name` if a footprint of half-extents `half` centred at `xy` leaves
        the table top."""
        cx, cy = self.table_center
        dx, dy = self.table_size[0] / 2, self.table_size[1] / 2
        if not (cx - dx <= xy[0] - half[0] and xy[0] + half[0] <= cx + dx
                and cy - dy <= xy[1] - half[1] and xy[1] + half[1] <= cy + dy):
            raise _err(name, f"({xy[0]:.3f}, {xy[1]:.3f}) is off the table "
                       f"(x in [{cx - dx:.3f}, {cx + dx:.3f}], y in [{cy - dy:.3f}, "
                       f"{cy + dy:.3f}] for the object's footprint)")

    def initial_states(self) -> dict[str, str]:
        """Initial high-level states: the defaults overridden by :attr:`states`."""
        out = {k: v[0] for k, v in self.state_values().items()}
        out.update(self.states)
        return out


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

    box_size: tuple[float, float, float] = (0.07, 0.085, 0.08)
    box_mass: float = 0.3
    box_friction: float = 0.4
    box_position: tuple[float, float] = (0.62, -0.25)
    box_color: _RGBA = (0.6, 0.15, 0.85, 1.0)

    def _validate_objects(self) -> None:
        self._check_object("box")


@dataclass
class GraspConfig(SceneConfig):
    """The ``grasp`` scene: a narrow block that Baxter's electric gripper can hold.

    The fingers close along the world y axis; ``block_size[1]`` must fit between the open
    finger tips (4.8 cm) and exceed the closed gap (0.65 cm). ``grasped`` needs the block
    5 cm up (``lift_threshold``), in the closed gripper.
    """

    lift_threshold: float = 0.05
    block_size: tuple[float, float, float] = (0.03, 0.03, 0.06)
    block_mass: float = 0.05
    block_friction: float = 1.0
    block_position: tuple[float, float] = (0.62, -0.25)
    block_color: _RGBA = (0.1, 0.7, 0.15, 1.0)

    def _validate_objects(self) -> None:
        self._check_object("block")
        if not 0.008 <= self.block_size[1] <= 0.045:
            raise _err("block_size", f"y extent must be in [0.008, 0.045] m to fit the "
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

    lamp_position: tuple[float, float] = (0.85, -0.05)
    lamp_radius: float = 0.03

    def state_values(self) -> dict[str, tuple[str, ...]]:
        return {"gripper": ("open", "closed"), "light": ("off", "on")}

    def _validate_objects(self) -> None:
        super()._validate_objects()
        _positive(self, "lamp_radius")
        _vector(self, "lamp_position", 2)
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

    button_size: tuple[float, float, float] = (0.06, 0.06, 0.02)
    button_base_height: float = 0.025
    button_travel: float = 0.02
    button_trigger: float = 0.008
    button_position: tuple[float, float] = (0.62, -0.1)
    button_color: _RGBA = (0.1, 0.25, 0.9, 1.0)
    lamp_position: tuple[float, float] = (0.95, 0.2)
    lamp_radius: float = 0.03
    box_size: tuple[float, float, float] = (0.07, 0.085, 0.08)
    box_mass: float = 0.3
    box_friction: float = 0.4
    box_position: tuple[float, float] = (0.62, -0.35)
    box_color: _RGBA = (0.6, 0.15, 0.85, 1.0)

    def state_values(self) -> dict[str, tuple[str, ...]]:
        return {"gripper": ("open", "closed"), "light": ("off", "on")}

    def _validate_objects(self) -> None:
        self._check_object("box")
        self._check_object("button")
        for name in ("button_base_height", "button_travel", "button_trigger", "lamp_radius"):
            _positive(self, name)
        if self.button_trigger >= self.button_travel:
            raise _err("button_trigger", f"must be < button_travel ({self.button_travel})")
        _vector(self, "lamp_position", 2)
        self.check_on_table("lamp_position", self.lamp_position,
                            (self.lamp_radius, self.lamp_radius))


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
        _choice(self, "context_source", ("perceived", "ground_truth"))
        for name in ("step", "eef_radius", "effect_threshold", "effect_ratio"):
            _positive(self, name)
        _positive(self, "object_jitter", allow_zero=True)
        if not isinstance(self.table_z, (int, float)) or not math.isfinite(self.table_z):
            raise _err("table_z", f"must be a finite number, got {self.table_z!r}")
        _vector(self, "box_half_size", 3, positive=True)
        _vector(self, "box_position", 2)
        _vector(self, "eef_position", 3)
        _choice(self, "n_push_effects", (4, 8))
        if not isinstance(self.states, dict):
            raise _err("states", f"expected a dict, got {self.states!r}")
        for name in self.states:
            raise _err("states", f"unknown high-level state '{name}': the virtual scene has "
                       "none")


_CONFIGS: dict[str, type] = {
    "push": PushConfig,
    "grasp": GraspConfig,
    "grasp_light": GraspLightConfig,
    "press": PressConfig,
    "virtual": VirtualConfig,
}


def _task_config() -> type:
    from a2l.sim.task import TaskConfig

    return TaskConfig


def config_class(scene: str) -> type:
    """The config dataclass of a scene name; ``ValueError`` naming an unknown scene."""
    if scene == "task":
        return _task_config()
    if scene not in _CONFIGS:
        raise A2LValueError(f"unknown scene '{scene}'; choose one of "
                            f"{sorted([*_CONFIGS, 'task'])}")
    return _CONFIGS[scene]


def make_config(scene: str, **values: Any) -> Any:
    """Build and validate the config of `scene`; an unknown key raises naming it."""
    cls = config_class(scene)
    known = {f.name for f in fields(cls)}
    for key in values:
        if key not in known:
            raise A2LValueError(f"unknown config key '{key}' for scene '{scene}'; "
                                f"known: {sorted(known)}")
    return cls(**values)
