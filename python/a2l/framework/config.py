"""The configuration of an A2L run (:class:`FrameworkConfig`): the scene, the seed, the
iteration cap and the context source, composed with frozen parts (:mod:`a2l.framework.parts`
and the package's :class:`~a2l.skills.discretization.DiscretizationConfig`), each validating
itself.

``FrameworkConfig(scene="bullet", discretization=DiscretizationConfig(n_effects=8),
starts={"n_starts": 12})``: a part is given as its dataclass or as a mapping of its fields.
:meth:`FrameworkConfig.with_` changes fields by their dotted names
(``"discretization.n_orient"``); :meth:`FrameworkConfig.from_dict` reads a run's
``config.json``, and converts the flat form of earlier versions (``n_orient``,
``heldout_starts``...: :data:`FLAT_NAMES`), naming each renamed field. An earlier scene
name (:data:`a2l.rollout.env.LEGACY_SCENES`) becomes the scene and robot it names now when
the configuration is made, whether given or read from an earlier run's ``config.json``.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from a2l.checks import check_choice, check_count
from a2l.errors import ConfigError
from a2l.framework.parts import (
    FALLBACK_RULES,
    BabblingConfig,
    DirectedConfig,
    ExtensionConfig,
    HeldoutConfig,
    LearningConfig,
    SkillConfig,
    StartsConfig,
    ValidationConfig,
)
from a2l.framework.presets import PRESETS
from a2l.framework.robots import check_robot, scaled_parts
from a2l.framework.starts import (
    fresh_offsets,
    fresh_redraw,
    heldout_offsets,
    heldout_redraw,
    spread_ranks,
)
from a2l.robot import DEFAULT_ROBOT
from a2l.rollout.env import ENV_SCENES, normalise_scene
from a2l.skills.discretization import DiscretizationConfig

__all__ = ["DIRECTED_TRY_CAP", "FALLBACK", "FALLBACK_RULES", "FLAT_NAMES", "PARTS", "PRESETS",
           "SCENES", "TRAIN_FALLBACK", "FrameworkConfig", "flat_renames"]

#: The framework's scenes: the C++ kinematic push model, the PyBullet push scene and a
#: Gymnasium environment (the names of :data:`a2l.rollout.env.ENV_SCENES`; an earlier name,
#: :data:`a2l.rollout.env.LEGACY_SCENES`, is read as the scene it names).
SCENES = tuple(ENV_SCENES)

#: Default ``directed.try_cap`` of each scene.
DIRECTED_TRY_CAP = {"virtual": 2000, "bullet": 100, "gym": 100}

#: Default ``skill.fallback`` of each scene (``docs/experiments/push.md``): on Baxter the
#: held-out starts reach context cells the training never did (``unknown_context`` was half
#: of the held-out misses), and heading for the nearest cell with data, never undoing the
#: previous movement (``approach``), ends the two-cell loops that taking its movement
#: (``nearest``) ran into (tuning seeds 3 and 4); on the virtual scene such cells are rare
#: and the fallback measured no gain.
FALLBACK = {"virtual": "none", "bullet": "approach", "gym": "approach"}

#: Default ``skill.train_fallback`` of each scene: the rule of the skill the training
#: validation runs. A fallback that carries a rollout through a cell without data also hides
#: that cell from the extension, which babbles where validation failed: trained with
#: ``approach``, Baxter tuning seeds 3 and 4 reached 75.8 / 79.7 % held-out success at
#: iteration 1; trained with ``nearest`` and run with ``approach``, 94.5 / 92.2 %
#: (``docs/experiments/push.md``).
TRAIN_FALLBACK = {"virtual": "none", "bullet": "nearest", "gym": "nearest"}

#: The parts of a :class:`FrameworkConfig`, by field name.
PARTS: dict[str, type] = {
    "discretization": DiscretizationConfig, "starts": StartsConfig,
    "babbling": BabblingConfig, "learning": LearningConfig, "skill": SkillConfig,
    "validation": ValidationConfig, "extension": ExtensionConfig,
    "directed": DirectedConfig, "heldout": HeldoutConfig,
}

#: The fields of the flat configuration of earlier versions (a ``config.json`` written
#: before the parts) and their names now.
FLAT_NAMES: dict[str, str] = {
    **{n: f"discretization.{n}" for n in (
        "n_effects", "effect_threshold", "planar", "step", "n_orient", "n_dist", "n_incl",
        "dist_low", "dist_high", "n_offset", "offset_half_x", "offset_half_y")},
    "n_starts": "starts.n_starts", "start_layout": "starts.layout",
    "start_radius": "starts.radius", "start_r_low": "starts.r_low",
    "start_r_high": "starts.r_high",
    "max_babble_steps": "babbling.max_steps", "try_cap": "babbling.try_cap",
    "erase_loops": "babbling.erase_loops",
    **{n: f"learning.{n}" for n in ("structure", "effect_parent", "fixed_parents")},
    **{n: f"skill.{n}" for n in ("step_cap", "smoothing", "fallback", "train_fallback")},
    "extension_cut": "extension.cut", "keep_validation": "extension.keep_validation",
    "max_extensions": "extension.max_extensions",
    "stuck_after": "directed.stuck_after", "directed_per_pair": "directed.per_pair",
    "directed_try_cap": "directed.try_cap", "directed_steps": "directed.steps",
    "directed_growth": "directed.growth", "directed_mode": "directed.mode",
    "waypoints_max": "directed.waypoints_max", "waypoint_aim": "directed.waypoint_aim",
    "heldout_starts": "heldout.n_starts", "heldout_r_low": "heldout.r_low",
    "heldout_r_high": "heldout.r_high",
}


def _part(name: str, value: Any) -> Any:
    """`value` as the dataclass of part `name` (a mapping of its fields is built into it)."""
    cls = PARTS[name]
    if isinstance(value, cls):
        return value
    if not isinstance(value, Mapping):
        raise ConfigError(name, f"expected a {cls.__name__} or a mapping of its fields, got "
                          f"{value!r}")
    known = [f.name for f in fields(cls)]
    unknown = sorted(set(value) - set(known))
    if unknown:
        raise ConfigError(name, f"unknown field(s) {unknown}; the fields of {name}: "
                          f"{', '.join(known)}")
    return cls(**value)


@dataclass(frozen=True)
class FrameworkConfig:
    """Every parameter of an A2L run (defaults explained in ``docs/method.md``), composed of
    frozen parts that validate themselves.

    Attributes
    ----------
    scene : {"virtual", "bullet", "gym"}
        ``"virtual"`` (C++ kinematic push model), ``"bullet"`` (the PyBullet push scene
        with `robot`) or ``"gym"`` (a Gymnasium environment's own simulation,
        :class:`a2l.gym.GymScene`: ``scene_config`` holds its settings, ``env_id``
        panda-gym's ``PandaPush-v3`` by default). ``baxter``, the earlier name of the
        PyBullet scene with Baxter (:data:`a2l.rollout.env.LEGACY_SCENES`), is read as
        ``"bullet"`` with robot Baxter.
    discretization : DiscretizationConfig
        Bins of the context variables, the movement repertoire and the effects
        (``n_effects`` 4 or 8 push effects, ``step`` the movement length...).
    starts : StartsConfig
        Where the training rollouts start.
    babbling : BabblingConfig
        Random motor babbling, the first acquisition.
    learning : LearningConfig
        The Bayesian network's structure.
    skill : SkillConfig
        How the skill runs: step cap, smoothing, fallbacks.
    validation : ValidationConfig
        Where each iteration validates (fresh starts over the ring, or the training
        starts), what accepts a skill and stops the run.
    extension : ExtensionConfig
        The dataset's extension from the validation trajectories.
    directed : DirectedConfig
        Effect-directed babbling for pairs that stay failed.
    heldout : HeldoutConfig
        The held-out starts, which only measure.
    max_iterations : int
        Iteration cap (iteration 0 included).
    seed : int
        Seed of every random draw.
    context_source : {"perceived", "ground_truth"}
        Where every rollout (babbling, extension, validation, held-out) reads the object's
        position: the scene's camera (``"perceived"``, the default: OpenCV segmentation of
        the rendered frames, one frame per movement) or the simulator's truth. The virtual
        scene has no camera: both read its true state. A ``source`` (or ``context_source``)
        key of ``scene_config`` overrides it.
    robot : str
        The robot of a PyBullet scene: a built-in name (:data:`a2l.robot.BUILTIN_ROBOTS`)
        or a robot file's path; its scene geometry follows from it
        (:func:`a2l.robot.table_layout`). The earlier scene name ``baxter`` takes only
        Baxter. On a robot whose scene is scaled (scale < 1: a small arm), the lengths left
        at their defaults are scaled with it (:mod:`a2l.framework.robots`).
    scene_config : dict
        Extra keyword arguments for :func:`a2l.sim.make_scene`.
    """

    scene: str = "virtual"
    discretization: DiscretizationConfig = field(default_factory=DiscretizationConfig)
    starts: StartsConfig = field(default_factory=StartsConfig)
    babbling: BabblingConfig = field(default_factory=BabblingConfig)
    learning: LearningConfig = field(default_factory=LearningConfig)
    skill: SkillConfig = field(default_factory=SkillConfig)
    validation: ValidationConfig = field(default_factory=ValidationConfig)
    extension: ExtensionConfig = field(default_factory=ExtensionConfig)
    directed: DirectedConfig = field(default_factory=DirectedConfig)
    heldout: HeldoutConfig = field(default_factory=HeldoutConfig)
    max_iterations: int = 10
    seed: int = 0
    context_source: str = "perceived"
    scene_config: dict[str, Any] = field(default_factory=dict)
    robot: str = DEFAULT_ROBOT

    def __post_init__(self) -> None:
        for name in PARTS:
            object.__setattr__(self, name, _part(name, getattr(self, name)))
        scene, robot = normalise_scene(self.scene, self.robot)
        object.__setattr__(self, "scene", scene)
        object.__setattr__(self, "robot", robot)
        check_choice("", "scene", self.scene, SCENES)
        # the scene's defaults of the fields left None
        if self.directed.try_cap is None:
            object.__setattr__(self, "directed", replace(
                self.directed, try_cap=DIRECTED_TRY_CAP[self.scene]))
        if self.skill.fallback is None or self.skill.train_fallback is None:
            object.__setattr__(self, "skill", replace(
                self.skill, fallback=self.skill.fallback or FALLBACK[self.scene],
                train_fallback=self.skill.train_fallback or TRAIN_FALLBACK[self.scene]))
        if not isinstance(self.scene_config, Mapping):
            raise ConfigError("scene_config", f"must be a mapping of scene options, got "
                              f"{self.scene_config!r}")
        self.validate()
        self._scale_lengths()

    def _scale_lengths(self) -> None:
        """Scale the lengths left at their defaults to the robot's scene."""
        for name, part in scaled_parts(self.scene, self.robot, self.__dict__).items():
            object.__setattr__(self, name, part)

    def validate(self) -> None:
        """Check what no part can check alone; raise :class:`a2l.errors.ConfigError` (a
        ValueError) naming the field, variable names in ``learning.fixed_parents``
        included. (Every part checked its own fields when it was made.)"""
        check_count("", "max_iterations", self.max_iterations)
        check_count("", "seed", self.seed, minimum=0)
        check_robot(self.robot, self.scene_config)
        check_choice("", "context_source", self.context_source, ("perceived", "ground_truth"))
        names = self.discretization.context_names()
        unknown = [v for v in self.learning.fixed_parents if v not in names]
        if unknown:
            raise ConfigError("learning.fixed_parents", f"{unknown} not context variables; "
                              f"they are {names}")

    def to_dict(self) -> dict[str, Any]:
        """The composed form as a JSON-able dict (what ``config.json`` holds under
        ``framework``): the parts as nested dicts, tuples as lists."""
        return json_ready(dataclasses.asdict(self))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> FrameworkConfig:
        """Build from a dict (e.g. a run's ``config.json``). The flat form of earlier versions
        is converted, with a :class:`FutureWarning` naming each renamed field
        (:func:`flat_renames`); a key that is neither is an error naming the valid ones."""
        d = dict(d)
        renames = flat_renames(d)
        if renames:
            warnings.warn("a flat framework configuration (an earlier version's): "
                          + ", ".join(f"{old} is now {new}" for old, new in renames.items()),
                          FutureWarning, stacklevel=2)
            d = _unflatten(d)
        known = [f.name for f in fields(cls)]
        unknown = sorted(set(d) - set(known))
        if unknown:
            raise ConfigError(unknown[0], f"unknown config key(s) {unknown}; known: "
                              f"{', '.join(known)}")
        return cls(**d)

    @classmethod
    def preset(cls, name: str, **kwargs: Any) -> FrameworkConfig:
        """The named configuration `name` (:data:`PRESETS`), with the top-level fields
        `kwargs` (``FrameworkConfig.preset("thesis", scene="bullet", seed=3)``).

        Raises
        ------
        ConfigError
            An unknown preset (the message lists them).
        """
        if name not in PRESETS:
            raise ConfigError("preset", f"unknown {name!r}; choose "
                              + ", ".join(repr(p) for p in PRESETS))
        return cls(**kwargs).with_(PRESETS[name])

    def with_(self, changes: Mapping[str, Any] | None = None, **kwargs: Any) -> FrameworkConfig:
        """A copy with fields changed, each named by its dotted path
        (``{"discretization.n_orient": 24}``) or, as keywords, by a top-level field (a part
        given as a mapping changes only the fields it names:
        ``with_(heldout={"n_starts": 0})``).

        Raises
        ------
        ConfigError
            An unknown part or field (the message lists the valid names), or a value out of
            its domain.
        """
        parts: dict[str, dict[str, Any]] = {}
        top: dict[str, Any] = {}
        for path, value in {**(changes or {}), **kwargs}.items():
            head, _, rest = path.partition(".")
            if head in PARTS and (rest or isinstance(value, Mapping)):
                sub = {rest: value} if rest else dict(value)
                bad = sorted(set(sub) - {f.name for f in fields(PARTS[head])})
                if bad:
                    raise ConfigError(path, f"{head} has no field {bad[0]!r}; its fields: "
                                      + ", ".join(f.name for f in fields(PARTS[head])))
                parts.setdefault(head, {}).update(sub)
            elif rest or head not in {f.name for f in fields(self)}:
                hint = f" (now {FLAT_NAMES[path]})" if path in FLAT_NAMES else ""
                raise ConfigError(path, f"no such field{hint}; the fields: "
                                  + ", ".join(field_paths(type(self))))
            else:
                top[head] = value
        for head, sub in parts.items():
            top[head] = replace(getattr(self, head), **sub)
        return replace(self, **top)

    def start_offsets(self) -> np.ndarray:
        """End-effector training start positions relative to the object, shape (n_starts, 3).

        Start ``i`` is at angle ``2πi / n_starts``; its distance is ``starts.radius``
        (``layout="circle"``) or, on the ring, ``r_low + (r_high - r_low) · k /
        (n_starts - 1)`` with ``k`` the bit-reversed rank of ``i`` (0, 4, 2, 6, 1, 5, 3, 7
        for 8 starts): every radius from the inner to the outer edge once, neighbouring
        angles far apart in radius. A fixed layout, independent of the held-out starts'
        random draw (:meth:`heldout_offsets`).
        """
        s = self.starts
        n = s.n_starts
        a = 2 * np.pi * np.arange(n) / n
        if s.layout == "circle" or n == 1:
            r = np.full(n, s.radius)
        else:
            r = s.r_low + (s.r_high - s.r_low) * spread_ranks(n) / (n - 1)
        return np.stack([r * np.cos(a), r * np.sin(a), np.zeros_like(a)], axis=1)

    def fresh_starts(self, iteration: int) -> range:
        """The start indices of iteration `iteration`'s fresh validation starts
        (``validation.n_fresh`` of them, after the training starts and every earlier
        iteration's: :meth:`start_offset` resolves each)."""
        n = self.validation.n_fresh
        first = self.starts.n_starts + iteration * n
        return range(first, first + n)

    def start_offset(self, start: int, attempt: int = 0) -> np.ndarray:
        """Where training start `start` is, relative to the object, shape (3,): a training
        start (``start < starts.n_starts``, :meth:`start_offsets`) or a fresh validation
        start (:meth:`fresh_starts`: iteration ``i``'s ``k``-th,
        :func:`a2l.framework.starts.fresh_offsets`). `attempt` > 0: the fresh start's
        `attempt`-th redraw, for when the arm cannot reach it (a training start has none).

        Raises
        ------
        ValueError
            A negative `start`, or a redraw of a training start.
        """
        n = self.starts.n_starts
        if start < 0:
            raise ValueError(f"start: must be >= 0, got {start}")
        if start < n:
            if attempt:
                raise ValueError(f"training start {start} has a fixed position, no redraw")
            return self.start_offsets()[start]
        v = self.validation
        it, k = divmod(start - n, v.n_fresh)
        if attempt:
            return fresh_redraw(self.seed, it, k, attempt, v.r_low, v.r_high)
        return fresh_offsets(self.seed, it, v.n_fresh, v.r_low, v.r_high)[k]

    @property
    def outer_start_radius(self) -> float:
        """The largest distance from the object a training rollout may start at (m): the
        training starts' outer radius, or the fresh starts' with ``validation.starts =
        "fresh"``."""
        r = self.starts.outer_radius
        return max(r, self.validation.r_high) if self.validation.fresh else r

    def heldout_offsets(self) -> np.ndarray:
        """Held-out end-effector start positions relative to the object, shape
        (heldout.n_starts, 3): uniform angle, distance uniform in ``[heldout.r_low,
        heldout.r_high]``, drawn from their own stream
        (:func:`a2l.framework.starts.heldout_offsets`)."""
        h = self.heldout
        return heldout_offsets(self.seed, h.n_starts, h.r_low, h.r_high)

    def heldout_redraw(self, start: int, attempt: int) -> np.ndarray:
        """Replacement `attempt` (1, 2, ...) for held-out start `start` when the arm cannot
        reach it, shape (3,) (:func:`a2l.framework.starts.heldout_redraw`)."""
        h = self.heldout
        return heldout_redraw(self.seed, start, attempt, h.r_low, h.r_high)


def json_ready(value: Any) -> Any:
    """`value` with tuples as lists, recursively (dicts and lists kept): what JSON keeps."""
    if isinstance(value, dict):
        return {k: json_ready(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_ready(v) for v in value]
    return value


def field_paths(cls: type) -> list[str]:
    """Every field of the configuration class `cls` by its dotted path, parts expanded
    (``scene``, ``discretization.n_effects``, ...), in order."""
    out: list[str] = []
    for f in fields(cls):
        if f.name in PARTS and cls is FrameworkConfig:
            out += [f"{f.name}.{g.name}" for g in fields(PARTS[f.name])]
        else:
            out.append(f.name)
    return out


def flat_renames(d: Mapping[str, Any]) -> dict[str, str]:
    """The keys of `d` that are fields of the flat configuration of earlier versions, with
    their dotted names now (empty for the composed form)."""
    return {k: FLAT_NAMES[k] for k in d if k in FLAT_NAMES}


def _unflatten(d: Mapping[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in d.items():
        head, _, rest = FLAT_NAMES.get(key, key).partition(".")
        if rest:
            out.setdefault(head, {})[rest] = value
        else:
            out[head] = value
    return out
