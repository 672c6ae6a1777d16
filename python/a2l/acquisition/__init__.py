"""How interactions are acquired: one module per strategy, all behind one small ask/tell
protocol (:mod:`a2l.acquisition.protocol`): a strategy proposes trajectories
(:meth:`~Strategy.ask`) and is told their outcomes (:meth:`~Strategy.tell`).

- :mod:`~a2l.acquisition.noveb`: novelty-driven evolutionary babbling on camera images
  (:class:`NovEB`, with DEAP).
- :mod:`~a2l.acquisition.goal_babbling`: random goal babbling (:class:`GoalBabbling`) and
  random motor babbling (:class:`RandomTrajectories`) over NovEB's trajectory encoding
  (:mod:`~a2l.acquisition.trajectory`), told the same image descriptors
  (:mod:`~a2l.acquisition.images`).
- :mod:`~a2l.acquisition.interactions`: playing a trajectory in a scene (through the closed
  loop of :mod:`a2l.rollout.loop`), and rollouts as interaction-dataset rows.

The A2L loop's own strategies (random babbling around the object from the start positions,
effect-directed waypoints, NovEB's first iteration) are built on these in
:mod:`a2l.framework` (:mod:`~a2l.framework.random_babbling`, :mod:`~a2l.framework.waypoints`,
:mod:`~a2l.framework.noveb_rollouts`).
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
    "Interactions": "a2l.acquisition.interactions",
    "Rollout": "a2l.acquisition.interactions",
    "effect_of": "a2l.acquisition.interactions",
    "erase_loops": "a2l.acquisition.interactions",
    "play": "a2l.acquisition.interactions",
    "interaction_rows": "a2l.acquisition.interactions",
    "WaypointEncoding": "a2l.acquisition.trajectory",
    "follow_waypoints": "a2l.acquisition.trajectory",
}

__all__ = [
    "ArchiveThreshold",
    "GoalBabbling",
    "Interactions",
    "NovEB",
    "NovEBConfig",
    "RandomTrajectories",
    "Rollout",
    "Strategy",
    "WaypointEncoding",
    "drive",
    "drive_ahead",
    "effect_of",
    "erase_loops",
    "follow_waypoints",
    "image_descriptor",
    "novelty",
    "play",
    "interaction_rows",
]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
