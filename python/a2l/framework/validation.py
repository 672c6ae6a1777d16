"""Interaction validation: each effect from each start, in closed loop through the C++
skill step (:mod:`a2l._core`), with the outcome success, false positive (the object moved
with another effect) or fail."""

from __future__ import annotations

from collections.abc import Callable, Sequence
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

__all__ = ["ValidationTask", "heldout_task", "reachable_heldout", "reachable_start",
           "validate", "validate_fresh", "validate_heldout", "validate_task"]

#: Reachable drawn offsets already probed in this process (:func:`reachable_heldout`,
#: :func:`reachable_start`), by scene, seed, the parts that draw them and the start.
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
    return _closed_loop(cfg, task.bundle, task.start, reachable_start(cfg, task.start),
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
    offsets = cfg.heldout_offsets()
    return _first_reachable(cfg, ("heldout", cfg.heldout, start), f"held-out start {start}",
                            lambda attempt: (cfg.heldout_redraw(start, attempt) if attempt
                                             else offsets[start]))


def reachable_start(cfg: FrameworkConfig, start: int) -> np.ndarray:
    """Training start `start`'s offset from the object, shape (3,)
    (:meth:`~a2l.framework.config.FrameworkConfig.start_offset`): a training start as laid
    out; a fresh validation start, when the arm cannot reach it, replaced by the first
    reachable of its redraws (as :func:`reachable_heldout`), the same on every worker, so
    the extension and effect-directed babbling from it start where its validation did.

    Raises
    ------
    UnreachableError
        A fresh start none of whose :data:`HELDOUT_REDRAWS` redraws is reachable.
    """
    if start < cfg.starts.n_starts:
        return cfg.start_offset(start)
    return _first_reachable(cfg, ("fresh", cfg.starts, cfg.validation, start),
                            f"fresh validation start {start}",
                            lambda attempt: cfg.start_offset(start, attempt))


def _first_reachable(cfg: FrameworkConfig, key: tuple[Any, ...], what: str,
                     draw: Callable[[int], np.ndarray]) -> np.ndarray:
    """The first of ``draw(0)``, ``draw(1)``, ... (at most :data:`HELDOUT_REDRAWS` redraws)
    the scene's arm can start from; probed once per process and start (`key`)."""
    key = (cfg.scene, cfg.seed, *key)
    if key in _REACHABLE:  # probed once per process: every effect starts from it
        return _REACHABLE[key].copy()
    env = scene_env(cfg)
    for attempt in range(HELDOUT_REDRAWS + 1):
        offset = draw(attempt)
        try:
            env.begin(offset)
        except UnreachableError:
            continue
        _REACHABLE[key] = offset
        return offset.copy()
    raise UnreachableError(f"{what}: neither it nor its {HELDOUT_REDRAWS} redraws is "
                           f"reachable in scene {cfg.scene!r}")


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

    r = play(scene_env(cfg), disc, start, offset, [], choose, runner.step_cap + 1)
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
    """Run the skill for every (training start, effect) pair; results in (start, effect)
    order."""
    tasks = [ValidationTask(cfg, str(bundle_path), s, e)
             for s in range(cfg.starts.n_starts) for e in range(cfg.discretization.n_effects)]
    total = len(tasks)
    return executor.map(validate_task, tasks,
                        on_done=(lambda k: progress("validate", k, total)) if progress else None)


def validate_fresh(cfg: FrameworkConfig, executor: Executor, iteration: int,
                   bundles: Sequence[Path],
                   progress: Callable[[str, int, int], None] | None = None
                   ) -> list[list[Rollout]]:
    """Run each skill of `bundles` for every (fresh start of iteration `iteration`, effect)
    pair (:meth:`FrameworkConfig.fresh_starts`): the same starts for all, so their success
    rates compare pair by pair. Returns one list per bundle, in (start, effect) order."""
    starts = cfg.fresh_starts(iteration)
    per = len(starts) * cfg.discretization.n_effects
    tasks = [ValidationTask(cfg, str(b), s, e) for b in bundles for s in starts
             for e in range(cfg.discretization.n_effects)]
    total = len(tasks)
    out = executor.map(validate_task, tasks,
                       on_done=(lambda k: progress("validate fresh", k, total)) if progress
                       else None)
    return [out[i * per:(i + 1) * per] for i in range(len(bundles))]



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
