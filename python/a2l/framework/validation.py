"""Interaction validation: each effect from each start, in closed loop through the C++
skill step (:mod:`a2l._core`), with the outcome success, false positive (the object moved
with another effect) or fail."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from a2l.acquisition.interactions import Rollout, play
from a2l.errors import UnreachableError
from a2l.framework.config import FrameworkConfig
from a2l.framework.scoring import SUCCESS, outcome_of
from a2l.framework.starts import HELDOUT_REDRAWS
from a2l.parallel import Executor
from a2l.rollout.env import scene_env
from a2l.skills.runner import CppSkillRunner

__all__ = ["ValidationTask", "heldout_task", "reachable_heldout", "validate",
           "validate_heldout", "validate_task"]

#: Reachable held-out offsets already probed in this process (:func:`reachable_heldout`),
#: by (scene, seed, held-out starts, ring radii, start).
_REACHABLE: dict[tuple[Any, ...], np.ndarray] = {}

@dataclass(frozen=True)
class ValidationTask:
    """One validation rollout, as a worker runs it (:func:`validate_task`,
    :func:`heldout_task`).

    Attributes
    ----------
    config : FrameworkConfig
        The run's configuration.
    bundle : str
        Path of the skill bundle to run.
    start : int
        Start index: a training start (:meth:`FrameworkConfig.start_offsets`) or a held-out
        one (:meth:`FrameworkConfig.heldout_offsets`).
    wanted : int
        The effect index asked of the skill.
    """

    config: FrameworkConfig
    bundle: str
    start: int
    wanted: int


def validate_task(task: ValidationTask) -> Rollout:
    """One validation rollout from the training start ``task.start``
    (:meth:`FrameworkConfig.start_offsets`).

    The skill runs in closed loop through the C++ step until the object moves (success if
    with the wanted effect, else false positive), or the step returns a stop status (step
    cap, unknown context: fail).
    """
    cfg = task.config
    return _closed_loop(cfg, task.bundle, task.start, cfg.start_offsets()[task.start],
                        task.wanted)


def heldout_task(task: ValidationTask) -> Rollout:
    """As :func:`validate_task`, from the held-out start ``task.start``
    (:meth:`FrameworkConfig.heldout_offsets`; ``Rollout.start`` is its index there)."""
    cfg, bundle, start, wanted = task.config, task.bundle, task.start, task.wanted
    offsets = cfg.heldout_offsets()
    if not 0 <= start < len(offsets):
        raise ValueError(f"held-out start {start} out of range: the config has "
                         f"{len(offsets)} held-out starts")
    return _closed_loop(cfg, bundle, start, reachable_heldout(cfg, start), wanted)


def reachable_heldout(cfg: FrameworkConfig, start: int) -> np.ndarray:
    """Held-out start `start`'s offset from the object, shape (3,), or, when the arm cannot
    put its end-effector there (:class:`~a2l.errors.UnreachableError` at the scene's reset,
    e.g. Baxter's gripper pointing down 0.25 m beyond a box near the rim of its reach), the
    first reachable of its redraws
    (:meth:`~a2l.framework.config.FrameworkConfig.heldout_redraw`): a deterministic
    replacement from the same distribution, the same on every worker.

    Raises
    ------
    UnreachableError
        None of the start and its :data:`HELDOUT_REDRAWS` redraws is reachable.
    """
    key = (cfg.scene, cfg.seed, cfg.heldout, start)
    if key in _REACHABLE:  # probed once per process: every effect starts from it
        return _REACHABLE[key].copy()
    offset = cfg.heldout_offsets()[start]
    env = scene_env(cfg)
    for attempt in range(HELDOUT_REDRAWS + 1):
        if attempt:
            offset = cfg.heldout_redraw(start, attempt)
        try:
            env.begin(offset)
        except UnreachableError:
            continue
        _REACHABLE[key] = offset
        return offset.copy()
    raise UnreachableError(f"held-out start {start}: neither it nor its {HELDOUT_REDRAWS} "
                           f"redraws is reachable in scene {cfg.scene!r}")


def _closed_loop(cfg: FrameworkConfig, bundle: str, start: int, offset: np.ndarray,
                 wanted: int) -> Rollout:
    """The skill of `bundle` for effect `wanted` from `offset` (shape (3,)) off the object,
    recorded as start `start`."""
    disc = cfg.discretization.discretizer()
    runner = CppSkillRunner.cached(bundle)
    if tuple(runner.labels) != tuple(disc.movements.labels):
        raise ValueError(f"skill bundle '{bundle}' has movements {runner.labels}, the "
                         f"framework's repertoire is {disc.movements.labels}")
    runner.reset()
    status: list[str] = []
    fallbacks = [0]

    def choose(eef: np.ndarray, obj: np.ndarray) -> int | None:
        out = runner.step(eef, obj, wanted)
        if not out.ok:
            status.append(out.status)
            return None
        fallbacks[0] += out.fallback
        return out.movement

    r = play(scene_env(cfg), disc, start, offset, [], choose, cfg.skill.step_cap + 1)
    r.wanted = wanted
    r.fallbacks = fallbacks[0]
    # Judged by what happened (the object's true displacement), not by what the robot saw:
    # with the camera as the context source the two can differ; with the ground truth they
    # are the same (the loop stops at the first true effect).
    r.outcome = outcome_of(r.true_effect, wanted)
    if r.outcome != SUCCESS and status:
        r.stop = status[0]
    return r


def validate(cfg: FrameworkConfig, executor: Executor, bundle_path: Path,
             progress: Callable[[str, int, int], None] | None = None) -> list[Rollout]:
    """Run the skill for every (start, effect) pair; results in (start, effect) order."""
    tasks = [ValidationTask(cfg, str(bundle_path), s, e)
             for s in range(cfg.starts.n_starts) for e in range(cfg.discretization.n_effects)]
    total = len(tasks)
    return executor.map(validate_task, tasks,
                        on_done=(lambda k: progress("validate", k, total)) if progress else None)



def validate_heldout(cfg: FrameworkConfig, executor: Executor, bundle_path: Path,
                     progress: Callable[[str, int, int], None] | None = None
                     ) -> list[Rollout]:
    """Run the skill for every (held-out start, effect) pair (``cfg.heldout.n_starts``
    starts, :meth:`FrameworkConfig.heldout_offsets`); results in (start, effect) order, empty
    without held-out starts."""
    tasks = [ValidationTask(cfg, str(bundle_path), s, e)
             for s in range(cfg.heldout.n_starts) for e in range(cfg.discretization.n_effects)]
    if not tasks:
        return []
    total = len(tasks)
    return executor.map(heldout_task, tasks,
                        on_done=(lambda k: progress("held-out", k, total)) if progress else None)
