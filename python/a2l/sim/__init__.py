"""The simulated tabletop world: scenes, discrete movements, perception, effects,
perturbations and the context reader.

Make a scene with :func:`make_scene`::

    from a2l.sim import make_scene
    with make_scene("push", seed=0) as scene:
        scene.reset(eef=(0.5, -0.25, -0.16))
        ok = scene.execute((1, 0, 0))          # +x by 5 cm through the C++ IK
        print(scene.observe_effect(), scene.context().objects["box"].distance)

Scenes: ``push`` (a box), ``grasp`` (a block the gripper can lift), ``grasp_light`` (the
block next to a lamp: a "hot stove"), ``press`` (a button toggling a light, and a box) in
PyBullet with Baxter; ``virtual`` (the C++ kinematic push model of docs/virtual_scene.md,
no physics).
"""

from __future__ import annotations

from typing import Any

from a2l.sim.config import (
    GraspConfig,
    GraspLightConfig,
    PressConfig,
    PushConfig,
    SceneConfig,
    VirtualConfig,
    config_class,
    make_config,
    settings_for,
)
from a2l.sim.context import Context, ObjectContext, low_level_state
from a2l.sim.movement import MoveResult
from a2l.sim.scene import Scene

__all__ = [
    "SCENES",
    "Context",
    "GraspConfig",
    "GraspLightConfig",
    "MoveResult",
    "ObjectContext",
    "PressConfig",
    "PushConfig",
    "Scene",
    "SceneConfig",
    "VirtualConfig",
    "config_class",
    "low_level_state",
    "make_config",
    "make_scene",
    "settings_for",
]

#: Names of the scenes :func:`make_scene` builds.
SCENES: tuple[str, ...] = ("push", "grasp", "grasp_light", "press", "task", "virtual")


def make_scene(name: str, seed: int = 0, **config: Any) -> Scene:
    """Build a scene from its name, a seed and config overrides.

    Parameters
    ----------
    name : {"push", "grasp", "grasp_light", "press", "task", "virtual"}
        The scene.
    seed : int
        Seeds every random draw of the scene (object jitter on reset).
    **config
        Fields of the scene's config dataclass (:class:`PushConfig`, :class:`GraspConfig`,
        :class:`GraspLightConfig`, :class:`PressConfig`, :class:`VirtualConfig`), e.g.
        ``gui=True``, ``step=0.03``.

    Returns
    -------
    Scene
        Reset and ready; close it (or use it as a context manager) when done.

    Raises
    ------
    ValueError
        (:class:`a2l.A2LValueError`) an unknown scene name or config key, or a bad config
        value; the message names it.
    """
    cfg = make_config(name, **config)
    if name == "virtual":
        from a2l.sim.virtual import VirtualScene

        return VirtualScene(cfg, seed)
    from a2l.sim.bullet import GraspScene, PressScene, PushScene
    from a2l.sim.grasp_light import GraspLightScene
    from a2l.sim.task import TaskScene

    cls = {"push": PushScene, "grasp": GraspScene, "grasp_light": GraspLightScene,
           "press": PressScene, "task": TaskScene}[name]
    return cls(cfg, seed)
