"""The base scene configuration: what every PyBullet scene shares (world, robot, camera,
rules), validated field by field.

Every length is in metres, every position in the world frame, which is the robot's base
link frame (x forward, y to the robot's left, z up); the table top is the plane
``z = table_z``. An object position on the table is given as its centre ``(x, y)``; its
height follows from its size. The geometry a field left at None takes (the table, the
cameras, the workspace, the objects' places and sizes, the movement length) follows from
the robot (:func:`a2l.robot.table_layout`): on Baxter, the thesis' scene.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

from a2l.robot import DEFAULT_ROBOT
from a2l.sim.config_fields import choice_field, field_error, positive_field, vector_field

__all__ = ["PLACE_MARGIN", "SceneConfig"]

#: An object placed from the layout (an offset from the work point) that would stand closer
#: than this (m, at scale 1) to the table's edge is moved in to it: the press scene's lamp,
#: 0.45 m left of the work point, left the table of an arm whose work point is off its
#: centre line (the Panda's).
PLACE_MARGIN = 0.05


@dataclass
class SceneConfig:
    """What every PyBullet scene shares: the world, the robot, the camera, the rules.

    Attributes
    ----------
    robot : str
        The robot: a built-in name (:data:`a2l.robot.BUILTIN_ROBOTS`) or the path of a
        robot file (``docs/robots.md``).
    gui : bool
        Open the PyBullet GUI (default: DIRECT, no window) and run in real time.
    time_step : float
        Physics time step (s).
    arm : str
        Kept for earlier configurations: ``"right"`` (Baxter's left arm is the robot
        ``"baxter-left"``).
    step : float
        Length of one discrete movement (m); None: 0.05 times the robot's scale.
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
    gripper_yaw : float
        Turn of the downward-pointing gripper about the vertical (degrees, in
        [-180, 180]): 0 closes the fingers along the world y axis, 90 along x. Every
        movement, reset and transit asks the IK for this orientation. The sideways pushes
        turn it by 90 degrees (:data:`a2l.lfd.library.SIDEWAYS_SCENE`): pushing across y
        with the fingers along y, the outer finger reaches 4.9 cm beyond the gripper's
        centre and met the box's corner on approaches from off the push axis.
    position_gain : float
        Position gain of PyBullet's joint position motors (its default, 0.1, leaves the
        end-effector about 2 mm short under gravity; 0.3 brings it within 0.1 mm).
    workspace_min, workspace_max : tuple of 3 float
        Bounds of the end-effector point; a movement whose target leaves them is reported
        as ``workspace_limit``. ``workspace_min[2]`` is relative to the table top.
    table_z : float
        Height of the table top (m). This field and the other geometry left at None (the
        table, the workspace, the cameras) come from the robot's layout.
    table_center, table_size : tuple of 2 float
        Centre ``(x, y)`` and size ``(depth, width)`` of the table top (m).
    robot_visual : str
        ``"collision"`` draws the robot with its collision shapes (fast camera frames),
        ``"mesh"`` with its visual meshes (slow, pretty; the GUI's default).
    camera_width, camera_height : int
        Camera image size (pixels). The default, 256 x 192, keeps the planar error within
        the error budget on the push and grasp scenes (95 % of reads within half the
        effect threshold, 5 mm; ``BENCHMARKS.md``, simulation, perception error vs
        resolution); a 320 x 240 frame costs 1.4 times its CPU.
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
    track_hidden : bool
        While the hand hides more than ``1 - min_visible`` of an object's top face, or all
        of it, locate the object from where it was last seen well, moved as little as what
        the cameras still see of it requires (:mod:`a2l.sim.tracking`); off: from the
        visible part of the top face alone, and an object no camera sees is not located.
    context_source : str
        ``"perceived"`` (camera + OpenCV, the default in experiments) or ``"ground_truth"``.
    n_push_effects : int
        4 (axes only) or 8 (axes and diagonals) push effects.
    effect_threshold : float
        Object displacement (m) below which the effect is ``none``; None: 0.01 times the
        robot's scale.
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

    robot: str = DEFAULT_ROBOT
    gui: bool = False
    time_step: float = 1.0 / 240.0
    arm: str = "right"
    step: float = None  # type: ignore[assignment]
    speed: float = 0.25
    waypoint_spacing: float = 0.01
    max_joint_jump: float = 0.5
    reach_tolerance: float = 0.01
    motor_force_scale: float = 4.0
    position_gain: float = 0.3
    gripper_yaw: float = 0.0
    workspace_min: tuple[float, float, float] = None  # type: ignore[assignment]
    workspace_max: tuple[float, float, float] = None  # type: ignore[assignment]
    table_z: float = None  # type: ignore[assignment]
    table_center: tuple[float, float] = None  # type: ignore[assignment]
    table_size: tuple[float, float] = None  # type: ignore[assignment]
    robot_visual: str = "collision"
    camera_width: int = 256
    camera_height: int = 192
    camera_eye: tuple[float, float, float] = None  # type: ignore[assignment]
    camera_target: tuple[float, float, float] = None  # type: ignore[assignment]
    camera_fov: float = 55.0
    extra_camera_eyes: tuple[tuple[float, float, float], ...] = None  # type: ignore[assignment]
    min_visible: float = 0.9
    track_hidden: bool = True
    context_source: str = "perceived"
    n_push_effects: int = 8
    effect_threshold: float = None  # type: ignore[assignment]
    effect_ratio: float = 3.0
    lift_threshold: float = 0.03
    object_jitter: float = 0.0
    states: dict[str, str] = field(default_factory=dict)

    #: Geometry fields the robot's layout fills when left at None.
    _LAYOUT_FIELDS: ClassVar[tuple[str, ...]] = (
        "table_z", "table_center", "table_size", "workspace_min", "workspace_max",
        "camera_eye", "camera_target", "extra_camera_eyes")
    #: Lengths at scale 1 of fields left at None: multiplied by the robot's scale.
    _SCALED: ClassVar[dict[str, Any]] = {"step": 0.05, "effect_threshold": 0.01}
    #: Object positions left at None: their offset (table frame, m at scale 1) from the
    #: robot's work point (:meth:`a2l.robot.TableLayout.place`).
    _PLACES: ClassVar[dict[str, tuple[float, float]]] = {}
    #: Object sizes whose height the scene lowers below the robot's hand when the layout
    #: gave them (:meth:`a2l.sim.bullet.build.BuildMixin.tool_clearance`).
    _TALL: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self) -> None:
        self._apply_layout()
        self.validate()

    def _apply_layout(self) -> None:
        """Fill the fields left at None from the robot's layout (module docstring)."""
        if not isinstance(self.robot, str) or not self.robot:
            raise field_error("robot", f"must be a robot's name or a robot file's path, got "
                              f"{self.robot!r}")
        empty = [f for f in (*self._LAYOUT_FIELDS, *self._SCALED, *self._PLACES)
                 if getattr(self, f) is None]
        #: The fields the layout filled (not given).
        self._from_layout = frozenset(empty)
        if not empty:
            return
        lay = self.layout()
        for name in self._LAYOUT_FIELDS:
            if getattr(self, name) is None:
                setattr(self, name, getattr(lay, name))
        for name, value in self._SCALED.items():
            if getattr(self, name) is None:
                setattr(self, name, _scaled(value, lay.scale))
        for name, offset in self._PLACES.items():
            if getattr(self, name) is None:
                setattr(self, name, _inside(lay.place(offset), self.table_center,
                                            self.table_size, PLACE_MARGIN * lay.scale))

    def layout_sized(self) -> tuple[str, ...]:
        """The object sizes the layout gave (not given) whose height a scene fits under the
        robot's hand (:meth:`a2l.sim.bullet.build.BuildMixin.tool_clearance`)."""
        return tuple(n for n in self._TALL if n in self._from_layout)

    def layout(self) -> Any:
        """The robot's :class:`a2l.robot.TableLayout` (computed once per robot and process).

        Raises
        ------
        a2l.A2LValueError
            `robot` names no built-in robot and no readable robot file, or the robot
            reaches no point of the table.
        """
        from a2l.robot import robot_entry
        from a2l.robot.layout import table_layout

        return table_layout(robot_entry(self.robot))

    # --- validation -------------------------------------------------------------
    def state_values(self) -> dict[str, tuple[str, ...]]:
        """The scene's high-level states and their possible values (first = default)."""
        return {"gripper": ("open", "closed")}

    def validate(self) -> None:
        """Check every field; raise :class:`a2l.A2LValueError` naming the first bad one."""
        for name in ("gui",):
            if not isinstance(getattr(self, name), bool):
                raise field_error(name, f"must be True or False, got {getattr(self, name)!r}")
        for name in ("time_step", "step", "speed", "waypoint_spacing", "max_joint_jump",
                     "reach_tolerance", "motor_force_scale", "position_gain", "camera_fov",
                     "effect_threshold", "effect_ratio", "lift_threshold"):
            positive_field(self, name)
        positive_field(self, "object_jitter", allow_zero=True)
        if (isinstance(self.gripper_yaw, bool) or not isinstance(self.gripper_yaw, (int, float))
                or not -180 <= self.gripper_yaw <= 180):
            raise field_error("gripper_yaw", f"must be a number of degrees in [-180, 180], got "
                              f"{self.gripper_yaw!r}")
        self.gripper_yaw = float(self.gripper_yaw)
        if self.time_step > 0.05:
            raise field_error("time_step", f"must be <= 0.05 s, got {self.time_step}")
        if self.camera_fov >= 170:
            raise field_error("camera_fov", f"must be < 170 degrees, got {self.camera_fov}")
        choice_field(self, "arm", ("right",))
        choice_field(self, "robot_visual", ("collision", "mesh"))
        choice_field(self, "context_source", ("perceived", "ground_truth"))
        choice_field(self, "n_push_effects", (4, 8))
        for name in ("camera_width", "camera_height"):
            v = getattr(self, name)
            if not isinstance(v, int) or isinstance(v, bool) or not 16 <= v <= 4096:
                raise field_error(name, f"must be an integer in [16, 4096], got {v!r}")
        if not isinstance(self.table_z, (int, float)) or not math.isfinite(self.table_z):
            raise field_error("table_z", f"must be a finite number, got {self.table_z!r}")
        self.table_z = float(self.table_z)
        vector_field(self, "table_center", 2)
        vector_field(self, "table_size", 2, positive=True)
        vector_field(self, "workspace_min", 3)
        vector_field(self, "workspace_max", 3)
        for i, axis in enumerate("xyz"):
            if self.workspace_min[i] >= self.workspace_max[i]:
                raise field_error("workspace_max", f"{axis} bound must exceed workspace_min's")
        vector_field(self, "camera_eye", 3)
        vector_field(self, "camera_target", 3)
        if self.camera_eye == self.camera_target:
            raise field_error("camera_eye", "must differ from camera_target")
        try:
            eyes = [tuple(float(v) for v in e) for e in self.extra_camera_eyes]
        except (TypeError, ValueError) as exc:
            raise field_error("extra_camera_eyes", "expected a sequence of (x, y, z)") from exc
        if any(len(e) != 3 or not all(math.isfinite(v) for v in e) or e == self.camera_target
               for e in eyes):
            raise field_error("extra_camera_eyes", f"every eye must be 3 finite numbers away from "
                       f"camera_target, got {self.extra_camera_eyes!r}")
        self.extra_camera_eyes = tuple(eyes)  # type: ignore[assignment]
        positive_field(self, "min_visible", allow_zero=True)
        if self.min_visible > 1:
            raise field_error("min_visible", f"must be in [0, 1], got {self.min_visible}")
        if not isinstance(self.states, dict):
            raise field_error("states", f"expected a dict name -> value, got {self.states!r}")
        known = self.state_values()
        for name, value in self.states.items():
            if name not in known:
                raise field_error("states", f"unknown high-level state '{name}' for this scene; "
                           f"known: {sorted(known)}")
            if value not in known[name]:
                raise field_error("states", f"state '{name}' must be one of {list(known[name])}, "
                           f"got {value!r}")
        self._validate_objects()

    def _validate_objects(self) -> None:
        """Validate the scene's objects (sizes, masses, positions on the table)."""

    def _check_object(self, prefix: str, footprint_xy: tuple[float, float] | None = None) -> None:
        """Validate ``<prefix>_size``, ``_mass``, ``_friction``, ``_position`` if present."""
        size_name = f"{prefix}_size"
        vector_field(self, size_name, 3, positive=True)
        for suffix in ("mass", "friction"):
            if hasattr(self, f"{prefix}_{suffix}"):
                positive_field(self, f"{prefix}_{suffix}")
        pos_name = f"{prefix}_position"
        vector_field(self, pos_name, 2)
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
            raise field_error(name, f"({xy[0]:.3f}, {xy[1]:.3f}) is off the table "
                       f"(x in [{cx - dx:.3f}, {cx + dx:.3f}], y in [{cy - dy:.3f}, "
                       f"{cy + dy:.3f}] for the object's footprint)")

    def initial_states(self) -> dict[str, str]:
        """Initial high-level states: the defaults overridden by :attr:`states`."""
        out = {k: v[0] for k, v in self.state_values().items()}
        out.update(self.states)
        return out


def _inside(xy: tuple[float, float], center: tuple[float, float],
            size: tuple[float, float], margin: float) -> tuple[float, float]:
    """`xy` moved onto the table top (`center`, `size`), at least `margin` from its edges;
    unchanged (the same floats) when it is already there."""
    out = []
    for v, c, half in zip(xy, center, (size[0] / 2, size[1] / 2), strict=True):
        lo, hi = c - half + margin, c + half - margin
        out.append(v if lo <= v <= hi else round(min(max(v, lo), hi), 6))
    return out[0], out[1]


def _scaled(value: Any, scale: float) -> Any:
    """`value` (a length or a tuple of lengths, m) times `scale`, to the micrometre."""
    if isinstance(value, tuple):
        return tuple(round(v * scale, 6) for v in value)
    return round(value * scale, 6)
