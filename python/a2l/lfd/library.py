"""The demonstrated skills: how each is demonstrated, learned and tried.

:data:`SKILLS` maps a skill name to its :class:`SkillRecipe`: the scene it acts in, the
effect, the scripted demonstrations, the trial start distribution and the high-level states
of its table (:mod:`a2l.lfd.recipes`). The push skills are defined here; the grasp and press
skills in :mod:`a2l.lfd.manipulation_skills`; both are registered when this module loads.

A trial (:func:`reset_for_trial`) draws, from its seed only, the object's position (its
configured home ± ``object_jitter``) and the end-effector's start relative to the object
from the recipe's start distribution: the same distribution the demonstrations start from,
so that held-out trials (seeds no demonstration and no tuning used) measure generalisation
to new starts, not to another task.

**Robots.** The demonstrations, the starts and the effects are in the object's frame, and a
scene places its objects at the robot's work point (:func:`a2l.robot.table_layout`): a skill
is demonstrated, learned and tried on any robot the PyBullet scenes take
(``learn_recipe(name, out, robot="panda")``, ``make_skill_scene(name, robot="panda")``;
Baxter by default). Its bundle records the robot it was learned for (:func:`robot_record`),
and a scene of another robot refuses it (:meth:`a2l.robot.RobotEntry.check_learned_for`).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from a2l.errors import A2LValueError
from a2l.lfd import manipulation_skills
from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.lfd.demonstrators import PushDemonstrator
from a2l.lfd.recipes import SKILLS, SkillRecipe, get_recipe, register_skill
from a2l.lfd.skill import Behaviour, LearnedSkill, learn_skill
from a2l.robot import DEFAULT_ROBOT
from a2l.rollout.protocol import SceneProtocol
from a2l.sim import make_scene, settings_for

__all__ = ["SIDEWAYS_SCENE", "SKILLS", "SkillRecipe", "check_robot_for", "learn_recipe",
           "make_skill_scene", "register_skill", "reset_for_trial", "robot_record",
           "skill_config"]

_TRIAL_STREAM = 0x7472696C  # seeds trial draws apart from every other stream


#: The sideways pushes' scene: the gripper turned by 90 degrees about the
#: vertical, its fingers closing along x. With the fingers along y (every other skill's
#: gripper), a push across y meets the box with the outer finger, which reaches 4.9 cm
#: beyond the gripper's centre: an approach from far off the push axis slid along x within
#: that reach and met the box's corner (`effect_failed`, 10 % of unperturbed trials, 20 %
#: with the box moved, even with demonstrations and bins made for it). Turned, the fingers
#: lie side by side on the face the push meets, as they do for the pushes along x. Chosen
#: on tuning trial seeds 500-579 (docs/experiments/lfd.md); the demonstrations and the
#: configuration are the other pushes'.
SIDEWAYS_SCENE: dict[str, Any] = {"gripper_yaw": 90.0}


def _push_recipe(effect: str) -> SkillRecipe:
    sideways = effect in ("right", "left")
    demonstrator = PushDemonstrator(effect)

    def behaviours(cfg: LfDConfig, seed: int) -> list[Behaviour]:
        return [Behaviour(demonstrator.demonstrations(cfg.n_demos, seed), effect,
                          phase=f"push_{effect}")]

    return SkillRecipe(
        name=f"push_{effect}", scene="push", effect=effect, object_name="box",
        behaviours=behaviours, start=demonstrator.start,
        scene_config=dict(SIDEWAYS_SCENE) if sideways else {},
        description=f"push the box {effect} (>= 5 cm), from a start within "
                    f"{demonstrator.spread_deg:.0f} deg of the side opposite the push, "
                    f"{demonstrator.r_low:.2f}-{demonstrator.r_high:.2f} m away")


for _effect in ("right", "left", "close", "far"):
    register_skill(_push_recipe(_effect))
manipulation_skills.register()  # grasp, press, grasp_light (after the pushes: SKILLS' order)


def skill_config(name: str, cfg: LfDConfig | None = None) -> LfDConfig:
    """The configuration skill `name` is learned and run with: `cfg` if given, else the
    recipe's own (:attr:`SkillRecipe.config`), else :data:`a2l.lfd.config.DEFAULT`."""
    if cfg is not None:
        return cfg
    return get_recipe(name).config or DEFAULT


def make_skill_scene(name: str, seed: int = 0, cfg: LfDConfig | None = None,
                     scene: str | None = None, robot: str | None = None,
                     **config: Any) -> Any:
    """The scene a skill is tried in, with the movement length of `cfg`.

    Parameters
    ----------
    name : str
        A skill of :data:`SKILLS`.
    seed : int
        The scene's seed.
    cfg : LfDConfig, optional
        Its ``step`` is the scene's movement length (default: :func:`skill_config`).
    scene : str, optional
        Another :func:`a2l.sim.make_scene` scene than the recipe's (``"virtual"``, or
        ``"press"`` for a push with a light).
    robot : str, optional
        The robot of a PyBullet scene: a built-in name or a robot file's path (default: the
        scene's, Baxter). The virtual scene has none.
    **config
        Scene config overrides (``gui=True``, ``context_source="ground_truth"``...).
        Default: the context from the camera (``context_source="perceived"``), no reset
        jitter (trials place the object themselves) and the recipe's
        :attr:`~a2l.lfd.recipes.SkillRecipe.scene_config` (its fields the scene's config
        has: the virtual scene has no gripper).

    Returns
    -------
    a2l.sim.Scene

    Raises
    ------
    a2l.A2LValueError
        A robot for a scene that has none (the virtual scene), an unknown robot, a skill
        that closes the gripper on a robot without one.
    """
    recipe = get_recipe(name)
    cfg = skill_config(name, cfg)
    config.setdefault("context_source", "perceived")
    config.setdefault("object_jitter", 0.0)
    config.setdefault("step", cfg.step)
    scene_name = scene or recipe.scene
    if robot is not None:
        if not settings_for(scene_name, {"robot": robot}):
            raise A2LValueError(f"the {scene_name} scene has no robot (asked for robot "
                                f"{robot!r}): try skill {name!r} in a PyBullet scene")
        check_robot_for(name, robot)
        config["robot"] = robot
    for key, value in settings_for(scene_name, recipe.scene_config).items():
        config.setdefault(key, value)
    return make_scene(scene_name, seed=seed, **config)


def _object_home(scene: SceneProtocol, name: str) -> tuple[np.ndarray, float]:
    """Configured (x, y) of object `name` and the height of its centre."""
    cfg = scene.config
    if hasattr(cfg, "box_half_size") and name == "box":  # the virtual scene
        return np.asarray(cfg.box_position, float), cfg.table_z + cfg.box_half_size[2]
    pos, size = getattr(cfg, f"{name}_position", None), getattr(cfg, f"{name}_size", None)
    if pos is None or size is None:
        raise ValueError(f"scene {scene.name!r} has no configured object {name!r}")
    return np.asarray(pos, float), cfg.table_z + size[2] / 2


def reset_for_trial(scene: SceneProtocol, name: str, seed: int) -> dict[str, np.ndarray]:
    """Reset `scene` for a trial of skill `name`, every draw from `seed`.

    Returns
    -------
    dict
        ``{"object": (3,), "eef": (3,), "start": (3,)}``: the object's and the
        end-effector's positions and the start relative to the object.
    """
    recipe = get_recipe(name)
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), _TRIAL_STREAM]))
    xy, z = _object_home(scene, recipe.object_name)
    j = recipe.object_jitter
    xy = xy + rng.uniform(-j, j, 2)
    start = np.asarray(recipe.start(rng), dtype=float).reshape(3)
    obj = np.array([xy[0], xy[1], z])
    scene.reset(eef=obj + start, objects={recipe.object_name: xy})
    if recipe.setup is not None:
        recipe.setup(scene, rng)
    return {"object": obj, "eef": obj + start, "start": start}


def robot_record(robot: str | None) -> dict[str, str] | None:
    """What a skill bundle records of the robot it was learned for
    (:meth:`a2l.robot.RobotEntry.record`); None for no robot (a skill of the virtual scene).

    Raises
    ------
    a2l.A2LValueError
        An unknown robot (the built-in ones named), an unreadable robot file.
    """
    if robot is None:
        return None
    from a2l.robot import robot_entry

    return robot_entry(robot).record()


def check_robot_for(name: str, robot: str) -> None:
    """Refuse to demonstrate or run skill `name` on `robot` when it cannot: a skill that opens
    and closes the gripper (a high-level state ``gripper`` it acts on) on an arm without one.

    Raises
    ------
    a2l.A2LValueError
        Naming the skill and the robot; an unknown robot (:func:`a2l.robot.robot_entry`).
    """
    from a2l.robot import robot_entry

    recipe = get_recipe(name)
    entry = robot_entry(robot)
    if entry.gripper is None and any(h.name == "gripper" for h in recipe.high_level):
        raise A2LValueError(f"skill {name!r} closes the gripper, and robot '{entry.name}' "
                            "has none: give its robot file a gripper, or learn a push or press")


def learn_recipe(name: str, out_dir: str | os.PathLike[str], cfg: LfDConfig | None = None,
                 seed: int = 0, robot: str | None = DEFAULT_ROBOT) -> LearnedSkill:
    """Demonstrate (seeds ``seed ...``), learn and save skill `name` as
    ``out_dir/<name>.a2lb`` (with :func:`skill_config`).

    Parameters
    ----------
    name : str
        A skill of :data:`SKILLS`.
    out_dir : path
        Where the bundle goes.
    cfg : LfDConfig, optional
        Default: :func:`skill_config`.
    seed : int
        First demonstration seed.
    robot : str or None
        The robot the skill is learned for (a built-in name or a robot file's path), which
        the bundle records (:func:`robot_record`): the demonstrations are in the object's
        frame, the scene puts the object at the robot's work point. None: no robot (a skill
        of the virtual scene, run on any arm).

    Raises
    ------
    a2l.A2LValueError
        An unknown robot, or a skill that closes the gripper on an arm without one
        (:func:`check_robot_for`).
    """
    recipe = get_recipe(name)
    if robot is not None:
        check_robot_for(name, robot)
    cfg = skill_config(name, cfg)
    disc = recipe.discretizer(cfg) if recipe.discretizer else None
    return learn_skill(name, recipe.behaviours(cfg, seed), Path(out_dir) / f"{name}.a2lb",
                       cfg, high_level=recipe.high_level, planar=recipe.planar,
                       discretizer=disc, context_edges=recipe.context_edges,
                       scene=recipe.scene_config, robot=robot_record(robot))
