"""Rollouts: a policy run in closed loop in a scene, between :mod:`a2l.sim` (the scenes)
and the rooms that run rollouts (:mod:`a2l.acquisition`, :mod:`a2l.lfd`,
:mod:`a2l.framework`).

- :mod:`~a2l.rollout.protocol`: what those rooms may ask of a scene
  (:class:`SceneProtocol`, :class:`ArmSceneProtocol`);
- :mod:`~a2l.rollout.loop`: the one closed loop (:func:`closed_loop`) and its record
  (:class:`LoopRun`, :class:`LoopStep`; the skill's own trace is the C++ ``TraceRecord``);
- :mod:`~a2l.rollout.policy`: a skill bundle as its policy, through the C++ step (table or
  DS mode);
- :mod:`~a2l.rollout.world`: an :mod:`a2l.sim` scene as its world;
- :mod:`~a2l.rollout.run`: a skill bundle run in closed loop in a scene until its effect
  test says done (:func:`run_skill`);
- :mod:`~a2l.rollout.env`: the framework's push scene (:class:`SceneEnv`);
- :mod:`~a2l.rollout.cache`: the one per-thread scene cache (:func:`thread_scene`);
- :mod:`~a2l.rollout.effect_tests`: did a run produce its effect?
"""

from __future__ import annotations

from a2l.rollout.cache import thread_scene
from a2l.rollout.env import (
    ENV_SCENES,
    LEGACY_SCENES,
    EnvSpec,
    SceneEnv,
    make_env,
    normalise_scene,
    scene_env,
)
from a2l.rollout.loop import (
    FATAL_MOVES,
    Decision,
    LoopRun,
    LoopStep,
    Policy,
    StopTest,
    World,
    closed_loop,
)
from a2l.rollout.policy import PhasePolicy, TablePolicy, skill_policy
from a2l.rollout.protocol import ArmSceneProtocol, SceneProtocol
from a2l.rollout.run import SkillRun, run_skill
from a2l.rollout.world import SceneWorld, observe

__all__ = [
    "ENV_SCENES",
    "LEGACY_SCENES",
    "FATAL_MOVES",
    "ArmSceneProtocol",
    "Decision",
    "EnvSpec",
    "LoopRun",
    "LoopStep",
    "PhasePolicy",
    "Policy",
    "SceneEnv",
    "SceneProtocol",
    "SceneWorld",
    "SkillRun",
    "StopTest",
    "TablePolicy",
    "World",
    "closed_loop",
    "make_env",
    "normalise_scene",
    "observe",
    "run_skill",
    "scene_env",
    "skill_policy",
    "thread_scene",
]
