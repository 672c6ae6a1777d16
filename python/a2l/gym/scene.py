"""a2l's scene protocol over a Gymnasium environment (:class:`GymScene`): babbling, the
framework's loop, validation and the skills run inside the environment's own simulation
(its robot, physics and object), one discrete movement being one ``env.step``, and every
``env.step`` counted (:attr:`GymScene.env_steps`).

A movement of the repertoire is the action along its direction, of the movement's length
(``step / action_scale``: 1 for a 5 cm movement in panda-gym, whose action is at most 5 cm
an axis). A planar movement keeps the end-effector at the work height (the object's centre
height): the action's z component brings it there, except over the object, where it holds
its height until it is clear of the object (an episode of the environment starts with the
gripper 18 cm above the table).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l import _core
from a2l.checks import check_choice, check_length
from a2l.errors import A2LValueError, UnreachableError
from a2l.gym.access import EnvAccess, env_access
from a2l.sim import MoveResult, Scene
from a2l.sim.observation import Observation

__all__ = ["PLACEMENTS", "GymScene", "GymSceneConfig", "gym_scene"]

#: How a rollout's start is reached: the arm put there as the environment's reset puts it
#: (``teleport``, no ``env.step``), or driven there by ``env.step`` (``drive``, counted).
PLACEMENTS = ("teleport", "drive")
#: Most ``env.step`` a driven placement may take.
DRIVE_CAP = 40
#: Height above the object's top at which a driven placement travels, and to which a
#: planar movement in the air over the object rises (m).
SAFE_HEIGHT = 0.04
#: Above the work height by more than this, the end-effector is in the air (m).
AIR = 0.02


@dataclass
class GymSceneConfig:
    """A :class:`GymScene`'s settings.

    Attributes
    ----------
    env_id : str
        The Gymnasium environment (``gymnasium.make``): panda-gym's ``PandaPush-v3`` by
        default.
    env_kwargs : dict
        Keyword arguments of ``gymnasium.make``.
    step : float
        A movement's length (m).
    action_scale : float
        The end-effector displacement of one unit of the environment's action (m; panda-gym:
        0.05).
    home : tuple of float
        ``(x, y)`` where a rollout puts the object (m): the middle of panda-gym's object
        square, moved 5 cm towards the robot so that a start 0.2 m beyond it is in reach.
    work_height : float or None
        The end-effector height of planar movements (m); None: the object's centre height.
    clear_radius : float
        In the air (above the work height), a planar movement lowers the end-effector
        towards the work height only where it and its target are at least this far from
        the object's centre in the plane (m); nearer, it rises to :data:`SAFE_HEIGHT` above
        the object's top, and stays there until it is clear.
    slow_radius, slow_scale : float
        A movement that starts or ends within `slow_radius` of the object's centre in the
        plane (m) is carried out `slow_scale` times as fast (1: no change): panda-gym's
        cube slides up to 16 cm after a full-speed push.
    placement : {"teleport", "drive"}
        How a rollout's start position is reached (:data:`PLACEMENTS`).
    place_tolerance : float
        A start position not reached within this (m) is unreachable.
    context_source : {"ground_truth", "perceived"}
        The scene has no camera: both read the simulator's positions.
    object_jitter : float
        Accepted for the framework's scene settings; must be 0 (rollouts place the object).
    n_push_effects, effect_threshold, effect_ratio
        What :meth:`observe_effect` names (as :class:`a2l.sim.SceneConfig`).
    """

    env_id: str = "PandaPush-v3"
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    step: float = 0.05
    action_scale: float = 0.05
    home: tuple[float, float] = (-0.05, 0.0)
    work_height: float | None = None
    clear_radius: float = 0.06
    slow_radius: float = 0.0
    slow_scale: float = 1.0
    placement: str = "teleport"
    place_tolerance: float = 0.005
    context_source: str = "ground_truth"
    object_jitter: float = 0.0
    n_push_effects: int = 8
    effect_threshold: float = _core.EFFECT_THRESHOLD
    effect_ratio: float = _core.EFFECT_RATIO

    def __post_init__(self) -> None:
        for name in ("step", "action_scale", "clear_radius", "place_tolerance"):
            check_length("gym", name, getattr(self, name))
        check_length("gym", "slow_radius", self.slow_radius, allow_zero=True)
        if not 0 < self.slow_scale <= 1:
            raise A2LValueError(f"gym.slow_scale: must be in (0, 1], got {self.slow_scale!r}")
        check_choice("gym", "placement", self.placement, PLACEMENTS)
        check_choice("gym", "context_source", self.context_source,
                     ("ground_truth", "perceived"))
        if self.object_jitter:
            raise A2LValueError("gym: object_jitter must be 0 (rollouts place the object)")
        self.home = (float(self.home[0]), float(self.home[1]))


class GymScene(Scene):
    """A Gymnasium environment that exposes an end-effector and an object, as an a2l scene.

    Parameters
    ----------
    env : gymnasium.Env
        The environment (made by ``gymnasium.make``, wrappers included: every ``env.step``
        goes through them).
    config : GymSceneConfig, optional
    seed : int
        Seeds the environment's reset draws (its goal, before a rollout places the object).
    access : EnvAccess, optional
        How to read and place the end-effector and the object (default: found by
        :func:`a2l.gym.access.env_access`, which refuses an environment without them).

    Attributes
    ----------
    env_steps : int
        Every ``env.step`` the scene made (movements, actions, driven placements).
    resets : int
        Every ``env.reset``.
    placements : int
        Start positions reached by putting the arm there (``placement="teleport"``).
    terminated, truncated : bool
        The last ``env.step``'s flags (False after a reset).
    info : dict
        The last ``env.step``'s or ``env.reset``'s info (panda-gym: ``is_success``).
    """

    name = "gym"
    primary_object = "object"

    def __init__(self, env: Any, config: GymSceneConfig | None = None, seed: int = 0,
                 access: EnvAccess | None = None) -> None:
        super().__init__(config or GymSceneConfig(), seed)
        self.env = env
        self.env_steps = self.resets = self.placements = 0
        self._exact = False
        self.terminated = self.truncated = False
        self.info: dict[str, Any] = {}
        self.access = access or env_access(env)
        self.new_episode()
        self.object_z = float(self.access.object_position(self.primary_object)[2])
        self.reset()

    # --- the environment's episodes ---------------------------------------------------
    def new_episode(self, seed: int | None = None) -> dict[str, Any]:
        """``env.reset`` (seeded with `seed`, else with the scene's next draw), nothing
        placed: the environment's own initial state; returns its observation."""
        if seed is None:
            seed = int(self._rng.integers(2**31 - 1))
        obs, self.info = self.env.reset(seed=int(seed))
        self.resets += 1
        self.terminated = self.truncated = False
        self._episode_start = self._step_start = self._snapshot()
        return obs

    @property
    def goal(self) -> NDArray[np.float64] | None:
        """The episode's goal position (3,), or None."""
        return self.access.goal()

    @property
    def episode_over(self) -> bool:
        """The environment ended the episode (terminated or truncated)."""
        return self.terminated or self.truncated

    # --- Scene ------------------------------------------------------------------------
    def reset(self, eef: ArrayLike | None = None,
              objects: dict[str, ArrayLike] | None = None) -> None:
        """A new episode of the environment with the objects placed (default: the
        primary object at ``config.home``) and, when given, the end-effector at `eef`.

        Raises
        ------
        a2l.errors.UnreachableError
            The end-effector cannot be put (or driven) within ``place_tolerance`` of `eef`.
        """
        cfg = self.config
        self.new_episode()
        if objects is None:
            objects = {self.primary_object: cfg.home}
        for name, pos in objects.items():
            if name not in self.access.object_names:
                raise A2LValueError(f"unknown object {name!r}; this scene has "
                                    f"{list(self.access.object_names)}")
            p = np.asarray(pos, dtype=float).reshape(-1)
            z = p[2] if p.shape[0] == 3 else self.object_z
            self.access.place_object(name, np.array([p[0], p[1], z]))
        if eef is not None:
            target = np.asarray(eef, dtype=float).reshape(3)
            if cfg.placement == "teleport":
                err = self.access.place_ee(target)
                self.placements += 1
            else:
                err = self._drive_to(target)
            if err > cfg.place_tolerance:
                raise UnreachableError(f"gym scene: eef {tuple(np.round(target, 4))} is "
                                       f"unreachable ({err * 1000:.1f} mm off)")
        self._episode_start = self._step_start = self._snapshot()

    def eef_position(self) -> NDArray[np.float64]:
        return self.access.ee_position()

    @property
    def work_height(self) -> float:
        """The end-effector height of planar movements (m)."""
        wh = self.config.work_height
        return self.object_z if wh is None else float(wh)

    def _ground_truth(self) -> Observation:
        objects: dict[str, tuple[float, float, float]] = {}
        for n in self.access.object_names:
            if n not in self._removed:
                x, y, z = (float(v) for v in self.access.object_position(n))
                objects[n] = (x, y, z)
        return Observation(objects=objects, eef=self.eef_position())

    def _perceive(self) -> Observation:
        return self._ground_truth()  # no camera

    def _object_names(self) -> list[str]:
        return list(self.access.object_names)

    def move_by(self, displacement: ArrayLike) -> MoveResult:
        """Move the end-effector by `displacement` (3,) (m) in one ``env.step``, its z
        component as given (a planar movement of the repertoire, :meth:`execute`, has its
        height set by the scene); at most ``action_scale`` along each axis is carried out."""
        self._exact = True
        try:
            return super().move_by(displacement)
        finally:
            self._exact = False

    def _move(self, displacement: NDArray[np.float64]) -> MoveResult:
        cfg = self.config
        here = self.eef_position()
        obj = self.access.object_position(self.primary_object)
        target = here + displacement
        near = min(np.hypot(*(here - obj)[:2]), np.hypot(*(target - obj)[:2]))
        action = np.asarray(displacement, dtype=float) / cfg.action_scale
        if near < cfg.slow_radius and here[2] <= self.work_height + AIR:
            action *= cfg.slow_scale
        if displacement[2] == 0.0 and not self._exact:
            action[2] = self._height_action(here[2], obj, near)
        self._env_step(action)
        return MoveResult(True, "ok", "", target, self.eef_position())

    def _height_action(self, z: float, obj: NDArray[np.float64], near: float) -> float:
        """The z action of a planar movement from height `z` whose start or end is `near`
        the object at `obj` (3,) in the plane (m): towards the work height, unless in the
        air near the object (then up to the safe height above it)."""
        wh = self.work_height
        goal = wh
        if z > wh + AIR and near < self.config.clear_radius:
            goal = max(z, 2 * obj[2] + SAFE_HEIGHT)
        return float(np.clip((goal - z) / self.config.action_scale, -1.0, 1.0))

    def _env_step(self, action: NDArray[np.float64]) -> None:
        low, high = self.env.action_space.low, self.env.action_space.high
        act = np.zeros(self.env.action_space.shape, dtype=np.float32)
        act[:3] = action
        _obs, _r, term, trunc, self.info = self.env.step(np.clip(act, low, high))
        self.env_steps += 1
        self.terminated, self.truncated = bool(term), bool(trunc)

    def _drive_to(self, target: NDArray[np.float64]) -> float:
        """Drive the end-effector to `target` (3,) by ``env.step``: up to the travel height
        (:data:`SAFE_HEIGHT` above the object), across, down; the distance left (m)."""
        top = self.object_z * 2 + SAFE_HEIGHT
        for _ in range(DRIVE_CAP):
            p = self.eef_position()
            if np.linalg.norm(target - p) <= self.config.place_tolerance:
                break
            if np.hypot(*(target - p)[:2]) > 0.01:
                want = np.array([p[0], p[1], max(p[2], top)]) if p[2] < top - 0.01 else \
                    np.array([target[0], target[1], max(p[2], top)])
            else:
                want = target
            self._env_step(np.clip((want - p) / self.config.action_scale, -1.0, 1.0))
        return float(np.linalg.norm(target - self.eef_position()))

    def _idle(self) -> None:
        self._env_step(np.zeros(3))

    def _place(self, name: str, xyz: NDArray[np.float64]) -> None:
        self.access.place_object(name, np.asarray(xyz, dtype=float))

    def _toggle(self, state: str) -> None:
        raise A2LValueError("the gym scene has no high-level state to toggle")

    def _park(self, name: str) -> None:
        raise A2LValueError("the gym scene cannot take an object out of the environment")

    def close(self) -> None:
        env = self.__dict__.pop("env", None)
        if env is not None:
            env.close()


def gym_scene(env_id: str = "PandaPush-v3", seed: int = 0, **config: Any) -> GymScene:
    """The :class:`GymScene` of the environment `env_id` (``gymnasium.make``; panda-gym's
    environments are registered on import), with :class:`GymSceneConfig` fields `config`.

    Raises
    ------
    a2l.A2LValueError
        An unknown config field, or an environment without end-effector or object access.
    """
    import gymnasium

    import_env_package(env_id)
    known = set(GymSceneConfig.__dataclass_fields__)
    unknown = sorted(set(config) - known)
    if unknown:
        raise A2LValueError(f"gym scene: unknown setting(s) {unknown}; known: {sorted(known)}")
    cfg = GymSceneConfig(env_id=env_id, **config)
    env = gymnasium.make(env_id, **cfg.env_kwargs)
    try:
        return GymScene(env, cfg, seed)
    except Exception:
        env.close()
        raise


def import_env_package(env_id: str) -> None:
    """Import the package that registers `env_id` so that ``gymnasium.make`` knows it:
    panda-gym for its ``Panda*`` (a2l's ``a2l/*`` are registered by ``import a2l.gym``)."""
    if env_id.startswith("Panda"):
        try:
            import panda_gym  # noqa: F401 - registers the Panda environments
        except ImportError as exc:
            raise A2LValueError(f"environment {env_id!r} is panda-gym's: install the "
                                "extra a2l[gym] (pip install 'a2l[gym]')") from exc
