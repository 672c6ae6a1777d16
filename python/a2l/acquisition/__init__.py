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

from a2l.lazy import lazy_exports

# Names are imported from their module on first use (PEP 562): a worker process that
# needs one module does not import the others (pgmpy, OpenCV: seconds per process).
_EXPORTS: dict[str, str] = {
    "GoalBabbling": "a2l.acquisition.goal_babbling",
    "RandomTrajectories": "a2l.acquisition.goal_babbling",
    "image_descriptor": "a2l.acquisition.images",
    "ArchiveThreshold": "a2l.acquisition.noveb",
    "NovEB": "a2l.acquisition.noveb",
    "NovEBConfig": "a2l.acquisition.noveb",
    "novelty": "a2l.acquisition.noveb",
    "Strategy": "a2l.acquisition.protocol",
    "drive": "a2l.acquisition.protocol",
    "drive_ahead": "a2l.acquisition.protocol",
    "RandomBabbling": "a2l.acquisition.random_babbling",
    "babble_task": "a2l.acquisition.random_babbling",
    "random_walk": "a2l.acquisition.random_babbling",
    "Interactions": "a2l.acquisition.rollout",
    "Rollout": "a2l.acquisition.rollout",
    "effect_of": "a2l.acquisition.rollout",
    "erase_loops": "a2l.acquisition.rollout",
    "play": "a2l.acquisition.rollout",
    "rollouts_to_frame": "a2l.acquisition.rollout",
    "WaypointEncoding": "a2l.acquisition.trajectory",
    "follow_waypoints": "a2l.acquisition.trajectory",
    "EffectDirected": "a2l.acquisition.waypoints",
    "Missed": "a2l.acquisition.waypoints",
    "directed_outcome_task": "a2l.acquisition.waypoints",
    "directed_task": "a2l.acquisition.waypoints",
    "heading_chooser": "a2l.acquisition.waypoints",
    "random_waypoints": "a2l.acquisition.waypoints",
}

__all__ = [
    "ArchiveThreshold",
    "EffectDirected",
    "GoalBabbling",
    "Interactions",
    "Missed",
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
    "drive_ahead",
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


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
