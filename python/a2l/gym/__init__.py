"""Gymnasium both ways (the optional extra ``a2l[gym]``, ``docs/gym.md``):

- :mod:`~a2l.gym.envs`: a2l's push scenes as registered, goal-conditioned Gymnasium
  environments (``gymnasium.make("a2l/Push-v0")``; registered by ``import a2l.gym``), for
  any reinforcement-learning library;
- :mod:`~a2l.gym.scene`: a Gymnasium environment that exposes an end-effector and an object
  (panda-gym's tasks) as an a2l scene (:class:`GymScene`, the framework's scene ``gym``), so
  that babbling, the iterative loop, validation and the learned skills run inside its own
  simulation, every ``env.step`` counted;
- :mod:`~a2l.gym.access`: what a2l reads and places in such an environment, and the refusal
  of one that does not expose it.
"""

from __future__ import annotations

try:
    import gymnasium  # noqa: F401
except ImportError as exc:  # pragma: no cover - the extra is installed by make test
    raise ImportError("a2l.gym needs Gymnasium: install the extra a2l[gym] "
                      "(pip install 'a2l[gym]')") from exc

from a2l.gym.access import EnvAccess, PandaGymAccess, env_access
from a2l.gym.envs import ENV_IDS, PushEnv, register_envs
from a2l.gym.scene import PLACEMENTS, GymScene, GymSceneConfig, gym_scene

__all__ = ["ENV_IDS", "PLACEMENTS", "EnvAccess", "GymScene", "GymSceneConfig",
           "PandaGymAccess", "PushEnv", "env_access", "gym_scene", "register_envs"]

register_envs()
