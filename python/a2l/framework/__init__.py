"""The A2L iterative framework: acquire interactions, generate skills, validate, repeat.

The A2L loop (``docs/method.md``), for the push effects:

1. **Interaction acquisition** (:mod:`a2l.acquisition`) by random motor babbling: from start
   positions evenly on a circle around the object, up to ``max_babble_steps`` random
   movements; a trajectory is kept only if the object moved, and every step is labelled
   with the observed effect.
2. **Skill generation**: discretize, learn a Bayesian network (hill-climbing + K2, ``move``
   has no children), compile the posterior over ``move`` into a table, save a skill bundle.
3. **Interaction validation** (:mod:`a2l.framework.validation`): each effect from each
   start (and, to measure only, from ``heldout_starts`` held-out starts no phase of
   training uses), in closed loop through the C++ skill step (:mod:`a2l._core`): success, false
   positive (the object moved with another effect) or fail; the iteration's score
   (:mod:`a2l.framework.scoring`) is ``Σ(4·success + 1·false positive) /
   (4 · n_effects · n_starts) · 100``.
4. **Iteration** (:mod:`a2l.framework.loop`): extend the dataset (successful and
   false-positive trajectories cut back and extended at random; effect-directed babbling
   for (start, effect) pairs stuck for long), keep the new dataset only if the score did
   not drop, stop at score 100 or at the iteration cap.

Every random draw comes from a generator seeded by ``(seed, iteration, phase, index)``, so a
run is reproducible, independent of the number of workers, and resumable from the
checkpoint written after each iteration.

The modules: :mod:`~a2l.framework.config` (:class:`FrameworkConfig`, composed of the parts
of :mod:`~a2l.framework.parts`), :mod:`~a2l.framework.result` (:class:`FrameworkResult`),
:mod:`~a2l.framework.starts` (where training and held-out rollouts start),
:mod:`~a2l.framework.validation` (each effect from each start through the C++ step,
:class:`a2l.skills.CppSkillRunner`, in the scene of :mod:`a2l.rollout.env`),
:mod:`~a2l.framework.scoring` and :mod:`~a2l.framework.loop`, with the loop's own
acquisition strategies (:mod:`~a2l.framework.random_babbling`,
:mod:`~a2l.framework.waypoints`, :mod:`~a2l.framework.noveb_rollouts`). Their names are
re-exported here, loaded on first use, so that a worker process that runs one task does not
import the whole loop.
"""

from __future__ import annotations

from a2l.lazy import lazy_exports

__all__ = [
    "DIRECTED_TRY_CAP",
    "FAIL",
    "FALSE_POSITIVE",
    "SUCCESS",
    "BabbleTask",
    "BabblingConfig",
    "DirectedConfig",
    "DirectedTask",
    "ExtensionConfig",
    "FrameworkConfig",
    "FrameworkResult",
    "HeldoutConfig",
    "IterationResult",
    "LearningConfig",
    "SkillConfig",
    "StartsConfig",
    "ValidationTask",
    "acquire",
    "babble_task",
    "directed_task",
    "extend",
    "generate_skill",
    "heading_chooser",
    "heldout_metrics",
    "heldout_task",
    "iteration_metrics",
    "phase_seed",
    "random_waypoints",
    "run_framework",
    "score_of",
    "validate",
    "validate_heldout",
    "validate_task",
]

#: Where each re-exported name lives.
_HOME = {
    "DIRECTED_TRY_CAP": "a2l.framework.config",
    "FrameworkConfig": "a2l.framework.config",
    "BabblingConfig": "a2l.framework.parts",
    "DirectedConfig": "a2l.framework.parts",
    "ExtensionConfig": "a2l.framework.parts",
    "HeldoutConfig": "a2l.framework.parts",
    "LearningConfig": "a2l.framework.parts",
    "SkillConfig": "a2l.framework.parts",
    "StartsConfig": "a2l.framework.parts",
    "FrameworkResult": "a2l.framework.result",
    "BabbleTask": "a2l.framework.random_babbling",
    "DirectedTask": "a2l.framework.waypoints",
    "ValidationTask": "a2l.framework.validation",
    "phase_seed": "a2l.framework.loop",
    "FAIL": "a2l.framework.scoring",
    "FALSE_POSITIVE": "a2l.framework.scoring",
    "SUCCESS": "a2l.framework.scoring",
    "IterationResult": "a2l.framework.scoring",
    "iteration_metrics": "a2l.framework.scoring",
    "score_of": "a2l.framework.scoring",
    "heldout_metrics": "a2l.framework.scoring",
    "validate": "a2l.framework.validation",
    "validate_heldout": "a2l.framework.validation",
    "heldout_task": "a2l.framework.validation",
    "validate_task": "a2l.framework.validation",
    "acquire": "a2l.framework.loop",
    "extend": "a2l.framework.loop",
    "generate_skill": "a2l.framework.loop",
    "run_framework": "a2l.framework.loop",
    "babble_task": "a2l.framework.random_babbling",
    "directed_task": "a2l.framework.waypoints",
    "heading_chooser": "a2l.framework.waypoints",
    "random_waypoints": "a2l.framework.waypoints",
}


__getattr__, __dir__ = lazy_exports(__name__, _HOME)
