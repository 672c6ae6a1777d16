"""The push scene a framework rollout plays in: :class:`SceneEnv` wraps an :mod:`a2l.sim`
scene (``virtual``: the C++ kinematic push model; ``bullet``: the PyBullet push scene with
the robot's C++ IK): start the end-effector at an offset from the object's home, execute discrete
movements, read positions. :func:`scene_env` keeps one per thread for rollouts
(:func:`a2l.rollout.cache.thread_scene`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from a2l.errors import ConfigError
from a2l.rollout.cache import thread_scene
from a2l.rollout.protocol import SceneProtocol
from a2l.sim import make_scene

if TYPE_CHECKING:
    from a2l.skills.discretization import DiscretizationConfig

__all__ = ["ENV_SCENES", "LEGACY_SCENES", "ROBOT_SCENES", "EnvSpec", "SceneEnv", "make_env",
           "normalise_scene", "scene_env"]

#: Framework scene name -> the a2l.sim scene it plays in (:data:`a2l.sim.SCENES` names those):
#: ``bullet`` is the PyBullet push scene with the configuration's robot; ``gym`` is a
#: Gymnasium environment's own simulation (:class:`a2l.gym.GymScene`, the extra
#: ``a2l[gym]``; its ``env_id`` a setting of ``scene_config``, panda-gym's ``PandaPush-v3``
#: by default). An earlier name of a scene is in :data:`LEGACY_SCENES`.
ENV_SCENES = {"virtual": "virtual", "bullet": "push", "gym": "gym"}
#: The framework scenes that have a robot and a camera (PyBullet).
ROBOT_SCENES = ("bullet",)
#: The scene names of earlier runs -> the (scene, robot) each names now, for the framework
#: and for the experiments on demonstrated skills (their PyBullet scene is also ``bullet``):
#: before robots were data, the PyBullet scenes with Baxter were scene ``baxter``. Commands
#: and ``config.json`` files of those runs still name it; :func:`normalise_scene` reads it
#: where a scene name comes in (:class:`a2l.framework.FrameworkConfig`,
#: :func:`a2l.experiments.lfd_skills.resolve_scene`), and this is the only place it is
#: written.
LEGACY_SCENES: dict[str, tuple[str, str]] = {"baxter": ("bullet", "baxter")}


def normalise_scene(scene: str, robot: str, field: str = "robot") -> tuple[str, str]:
    """The scene and robot of a run given `scene` and `robot`: an earlier scene name
    (:data:`LEGACY_SCENES`) as the scene and robot it names now, any other as given.

    Parameters
    ----------
    scene : str
        A scene name, current or earlier (checked by the caller, not here).
    robot : str
        The robot given with it (its default when none was).
    field : str
        The field or option named by the error (``robot``, ``--robot``).

    Returns
    -------
    tuple of str
        ``(scene, robot)``.

    Raises
    ------
    a2l.errors.ConfigError
        An earlier scene name given with another robot than its own.
    """
    if scene not in LEGACY_SCENES:
        return scene, robot
    now, own = LEGACY_SCENES[scene]
    if robot != own:
        raise ConfigError(field, f"scene {scene!r} is {own.capitalize()}'s; for robot "
                          f"{robot!r} use scene {now!r}")
    return now, own


class SceneEnv:
    """A scene seen as the framework's rollout environment.

    Parameters
    ----------
    scene : a2l.sim.Scene
        A push-like scene with one movable object.
    source : {"ground_truth", "perceived"}
        Where object positions come from (the camera, or the simulator's truth).
    """

    def __init__(self, scene: SceneProtocol, source: str | None = None) -> None:
        self.scene = scene
        self.source = source
        self.obj_name = scene.primary_object
        truth = scene.ground_truth()["objects"]
        if self.obj_name not in truth:
            raise ValueError(f"scene {scene.name!r} has no object {self.obj_name!r}")
        self.home = np.asarray(truth[self.obj_name], dtype=float)

    def begin(self, offset: np.ndarray) -> None:
        """Object at its home, end-effector at ``home + offset`` (same height as the object)."""
        self.scene.reset(eef=self.home + np.asarray(offset, dtype=float),
                         objects={self.obj_name: self.home[:2].copy()})

    def execute(self, direction: tuple[int, int, int]) -> bool:
        """One discrete movement; False if it could not be carried out."""
        return bool(self.scene.execute(direction))

    def eef(self) -> np.ndarray:
        """End-effector position, shape (3,)."""
        return np.asarray(self.scene.eef_position(), dtype=float)

    def object(self) -> np.ndarray:
        """Object position, shape (3,) (NaN if not seen)."""
        obs = (self.scene.perceive() if self.source == "perceived"
               else self.scene.ground_truth())
        pos = obs["objects"].get(self.obj_name)
        return np.full(3, np.nan) if pos is None else np.asarray(pos, dtype=float)

    def true_object(self) -> np.ndarray:
        """The object's true position (the simulator's ground truth, whatever `source`
        says), shape (3,): what an outcome is judged by."""
        return np.asarray(self.scene.ground_truth()["objects"][self.obj_name], dtype=float)

    def close(self) -> None:
        """Release the scene."""
        self.scene.close()


def make_env(scene: str, seed: int = 0, step: float = 0.05, source: str | None = None,
             **config: Any) -> SceneEnv:
    """The rollout environment of a framework scene name (:data:`ENV_SCENES`).

    The scene's ``context_source`` is the env's `source` (default the camera,
    ``"perceived"``): one camera frame per movement, read by :meth:`SceneEnv.object` and
    cached for the next movement's start (:meth:`a2l.sim.Scene.execute` records the
    observation the step's effect is measured from). With ``"ground_truth"`` the scene
    renders nothing.
    """
    if scene not in ENV_SCENES:
        raise ValueError(f"unknown scene {scene!r}; choose one of {sorted(ENV_SCENES)}")
    source = source or config.get("context_source") or "perceived"
    if source not in ("ground_truth", "perceived"):
        raise ValueError(f"source: must be 'ground_truth' or 'perceived', got {source!r}")
    if config.setdefault("context_source", source) != source:
        raise ValueError(f"context_source {config['context_source']!r} contradicts the env's "
                         f"source {source!r}: the env reads object positions from its source")
    # Rollouts place the object themselves: a random jitter on reset would make a rollout
    # depend on how many resets its process made before (and so on the worker count).
    config.setdefault("object_jitter", 0.0)
    if scene == "gym":
        from a2l.gym.scene import gym_scene  # the extra a2l[gym]

        return SceneEnv(gym_scene(seed=seed, step=step, **config), source)
    return SceneEnv(make_scene(ENV_SCENES[scene], seed=seed, step=step, **config), source)


class EnvSpec(Protocol):
    """What :func:`scene_env` reads of a configuration (e.g.
    :class:`a2l.framework.FrameworkConfig`)."""

    @property
    def scene(self) -> str: ...
    @property
    def scene_config(self) -> Mapping[str, Any]: ...
    @property
    def discretization(self) -> DiscretizationConfig: ...
    @property
    def seed(self) -> int: ...
    @property
    def robot(self) -> str: ...


def scene_env(cfg: EnvSpec) -> SceneEnv:
    """The scene of this thread for `cfg` (built once per thread and reused), reading the
    context from ``cfg.context_source`` unless ``cfg.scene_config`` names a source."""
    config = dict(cfg.scene_config)
    if cfg.scene in ROBOT_SCENES:
        config.setdefault("robot", cfg.robot)
    source = config.pop("source", None) or config.get("context_source") or getattr(
        cfg, "context_source", None)
    step = cfg.discretization.step
    key = repr((cfg.scene, sorted(config.items()), source, step, cfg.seed))
    return thread_scene("envs", key, lambda: make_env(cfg.scene, seed=cfg.seed, step=step,
                                                      source=source, **config))
