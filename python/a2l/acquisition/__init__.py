"""How interactions are acquired: one module per strategy, all behind one small ask/tell
protocol (:mod:`a2l.acquisition.protocol`): a strategy proposes trajectories
(:meth:`~Strategy.ask`) and is told their outcomes (:meth:`~Strategy.tell`).

- :mod:`~a2l.acquisition.random_babbling`: random motor babbling around the object
  (METHOD.md's acquisition; :class:`RandomBabbling`).
- :mod:`~a2l.acquisition.waypoints`: effect-directed waypoint trajectories for the pairs a
  skill keeps failing (:class:`EffectDirected`).
- :mod:`~a2l.acquisition.rollout`: playing a trajectory in a scene, and rollouts as
  interaction-dataset rows.
"""

from a2l.acquisition.protocol import Strategy, drive
from a2l.acquisition.random_babbling import RandomBabbling, babble_task, random_walk
from a2l.acquisition.rollout import Rollout, effect_of, erase_loops, play, rollouts_to_frame
from a2l.acquisition.waypoints import (
    EffectDirected,
    directed_task,
    heading_chooser,
    random_waypoints,
)

__all__ = [
    "EffectDirected",
    "RandomBabbling",
    "Rollout",
    "Strategy",
    "babble_task",
    "directed_task",
    "drive",
    "effect_of",
    "erase_loops",
    "heading_chooser",
    "play",
    "random_walk",
    "random_waypoints",
    "rollouts_to_frame",
]
