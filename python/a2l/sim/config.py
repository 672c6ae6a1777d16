"""Scene configurations: one dataclass per scene, looked up by scene name.

The dataclasses live in :mod:`a2l.sim.scene_config` (the base, :class:`SceneConfig`),
:mod:`a2l.sim.object_configs` (``push``, ``grasp``, ``grasp_light``, ``press``) and
:mod:`a2l.sim.virtual_config`; the field checks in :mod:`a2l.sim.config_fields`. This module
maps scene names to them and builds validated configs.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Any

from a2l.errors import A2LValueError
from a2l.sim.object_configs import GraspConfig, GraspLightConfig, PressConfig, PushConfig
from a2l.sim.scene_config import SceneConfig
from a2l.sim.virtual_config import VirtualConfig

__all__ = [
    "GraspConfig",
    "GraspLightConfig",
    "PressConfig",
    "PushConfig",
    "SceneConfig",
    "VirtualConfig",
    "config_class",
    "make_config",
    "settings_for",
]


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


def settings_for(scene: str, settings: dict[str, Any]) -> dict[str, Any]:
    """The items of `settings` that `scene`'s config has (e.g. a skill's ``gripper_yaw``
    applies to the Baxter scenes, and the virtual scene has no gripper to turn)."""
    known = {f.name for f in fields(config_class(scene))}
    return {k: v for k, v in settings.items() if k in known}


def make_config(scene: str, **values: Any) -> Any:
    """Build and validate the config of `scene`; an unknown key raises naming it."""
    cls = config_class(scene)
    known = {f.name for f in fields(cls)}
    for key in values:
        if key not in known:
            raise A2LValueError(f"unknown config key '{key}' for scene '{scene}'; "
                                f"known: {sorted(known)}")
    return cls(**values)
