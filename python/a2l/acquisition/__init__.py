"""How interactions are acquired: one module per strategy, all behind one small ask/tell
protocol (:mod:`a2l.acquisition.protocol`): a strategy proposes trajectories
(:meth:`~Strategy.ask`) and is told their outcomes (:meth:`~Strategy.tell`).

- :mod:`~a2l.acquisition.random_babbling`: random motor babbling around the object
  (METHOD.md's acquisition; :class:`RandomBabbling`).
- :mod:`~a2l.acquisition.waypoints`: effect-directed waypoint trajectories for the pairs a
  skill keeps failing (:class:`EffectDirected`).
- :mod:`~a2l.acquisition.noveb`: novelty-driven evolutionary babbling on camera images
  (:class:`NovEB`, with DEAP).
- :mod:`~a2l.acquisition.goal_babbling`: random goal babbling (:class:`GoalBabbling`) and
  random motor babbling (:class:`RandomTrajectories`) over NovEB's trajectory encoding
  (:mod:`~a2l.acquisition.trajectory`), told the same image descriptors
  (:mod:`~a2l.acquisition.images`).
- :mod:`~a2l.acquisition.rollout`: playing a trajectory in a scene, and rollouts as
  interaction-dataset rows.
"""

from a2l.acquisition.goal_babbling import GoalBabbling, RandomTrajectories
from a2l.acquisition.images import image_descriptor
from a2l.acquisition.noveb import ArchiveThreshold, NovEB, NovEBConfig, novelty
from a2l.acquisition.protocol import Strategy, drive
from a2l.acquisition.random_babbling import RandomBabbling, babble_task, random_walk
from a2l.acquisition.rollout import Rollout, effect_of, erase_loops, play, rollouts_to_frame
from a2l.acquisition.trajectory import WaypointEncoding, follow_waypoints
from a2l.acquisition.waypoints import (
    EffectDirected,
    directed_outcome_task,
    directed_task,
    heading_chooser,
    random_waypoints,
)

__all__ = [
    "ArchiveThreshold",
    "EffectDirected",
    "GoalBabbling",
    "NovEB",
    "NovEBConfig",
    "RandomBabbling",
    "RandomTrajectories",
    "Rollout",
    "Strategy",
    "WaypointEncoding",
    "babble_task",
    "directed_outcome_task",
    "directed_task",
    "drive",
    "effect_of",
    "erase_loops",
    "follow_waypoints",
    "heading_chooser",
    "image_descriptor",
    "novelty",
    "play",
    "random_walk",
    "random_waypoints",
    "rollouts_to_frame",
]
