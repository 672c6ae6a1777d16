"""A push skill judged on a Gymnasium task's own episodes (:func:`evaluate`): each episode
from the environment's reset (its object and goal, the arm at its neutral pose), the skill's
effects chained towards the goal (:func:`a2l.rollout.goal.reach_goal`) until the
environment ends the episode (its success, or its step limit: the approach included), the
environment's ``is_success`` the verdict; and the cause of each miss read from its episode
(:func:`miss_cause`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from a2l.rollout.goal import GoalRun, reach_goal
from a2l.skills.effects import EFFECT_DIRECTIONS

if TYPE_CHECKING:
    from a2l.gym.scene import GymScene

__all__ = ["EVAL_STREAM", "MISS_CAUSES", "Episode", "episode_seeds", "evaluate", "miss_cause"]

#: Tag of the evaluation episodes' seed stream: episode ``i`` of evaluation seed ``e``
#: resets the environment with a seed drawn from ``(e, EVAL_STREAM, i)``, a sequence no
#: learning draw uses.
EVAL_STREAM = 0x6576616C

#: Why an episode missed, in the order :func:`miss_cause` tests them.
MISS_CAUSES = ("approach", "off the table", "skill stopped", "push off the axis",
               "overshoot", "step budget")
#: The object moved less than this (m): the arm never pushed it.
MOVED = 0.01
#: A push whose object displacement is further than this from its effect's direction
#: (rad) went off the axis.
OFF_AXIS = np.deg2rad(45.0)


@dataclass
class Episode:
    """One evaluation episode.

    Attributes
    ----------
    index : int
        Its index in the evaluation.
    reset_seed : int
        The seed of its ``env.reset``.
    success : bool
        The environment's ``is_success`` at its end.
    steps : int
        Its ``env.step`` calls (the approach included).
    stop : str
        How the controller ended (``done``: the environment ended the episode).
    start_distance, final_distance : float
        The object's planar distance to the goal at the start and the end (m).
    cause : str
        Why it missed (:data:`MISS_CAUSES`); empty for a success.
    effects : str
        The effects run, in order, each once per push (``far,left``).
    cube_x, cube_y, goal_x, goal_y : float
        The cube and the goal at the start (m).
    """

    index: int
    reset_seed: int
    success: bool
    steps: int
    stop: str
    start_distance: float
    final_distance: float
    cause: str
    effects: str
    cube_x: float = 0.0
    cube_y: float = 0.0
    goal_x: float = 0.0
    goal_y: float = 0.0


def episode_seeds(eval_seed: int, n: int) -> list[int]:
    """The ``env.reset`` seeds of the `n` evaluation episodes of `eval_seed`."""
    return [int(np.random.SeedSequence([eval_seed, EVAL_STREAM, i]).generate_state(1)[0]
                >> 1) for i in range(n)]


def _segments(run: GoalRun) -> list[tuple[str, int, int]]:
    """The pushes of `run`: ``(effect, first step, last step + 1)`` of each run of steps
    chosen for the same effect."""
    out: list[tuple[str, int, int]] = []
    for k, e in enumerate(run.effects):
        if e not in EFFECT_DIRECTIONS:  # the descent's or the transit's
            continue
        if out and out[-1][0] == e and out[-1][2] == k:
            out[-1] = (e, out[-1][1], k + 1)
        else:
            out.append((e, k, k + 1))
    return out


def miss_cause(run: GoalRun, table_z: float = 0.0) -> str:
    """Why a goal-reaching episode missed, read from its trajectory.

    In this order: ``approach`` (the object never moved by :data:`MOVED`: the arm did not
    get to push it), ``off the table`` (it fell below `table_z`), ``skill stopped`` (the C++
    step stopped: unknown context), ``push off the axis`` (a push moved it more than
    :data:`OFF_AXIS` away from its effect's direction), ``overshoot`` (the last push took it
    past the goal along its direction), else ``step budget`` (the episode ended while it was
    still on its way).
    """
    obj = run.obj
    if np.max(np.linalg.norm(obj[:, :2] - obj[0, :2], axis=1)) < MOVED:
        return "approach"
    if obj[-1, 2] < table_z:
        return "off the table"
    if run.stop not in ("done", "budget", "reached"):
        return "skill stopped"
    segments = _segments(run)
    for effect, a, b in segments:
        moved = obj[min(b, len(obj) - 1), :2] - obj[a, :2]
        if np.linalg.norm(moved) >= MOVED:
            u = np.asarray(EFFECT_DIRECTIONS[effect], dtype=float)
            cos = float(moved @ u) / (np.linalg.norm(moved) * np.linalg.norm(u))
            if np.arccos(np.clip(cos, -1.0, 1.0)) > OFF_AXIS:
                return "push off the axis"
    if segments:
        effect, a, _ = segments[-1]
        u = np.asarray(EFFECT_DIRECTIONS[effect], dtype=float)
        u /= np.linalg.norm(u)
        if float((run.goal - obj[-1, :2]) @ u) < -MOVED < float((run.goal - obj[a, :2]) @ u):
            return "overshoot"
    return "step budget"


def evaluate(scene: GymScene, bundle: str | os.PathLike[str], seeds: Sequence[int],
             budget: int = 50, keep: float = 0.02,
             on_episode: Callable[[Episode, GoalRun], None] | None = None,
             **controller: Any) -> list[Episode]:
    """Run the push skill `bundle` on the episodes of a goal-conditioned
    :class:`a2l.gym.GymScene` reset with `seeds`.

    Parameters
    ----------
    scene : a2l.gym.GymScene
        The evaluation environment (not the one learning ran in).
    bundle : path
        The push skill.
    seeds : sequence of int
        One ``env.reset`` seed per episode (:func:`episode_seeds`).
    budget : int
        Most movements of an episode (the environment's own step limit ends it first).
    keep : float
        :class:`a2l.rollout.goal.GoalPolicy`'s `keep`.
    on_episode : callable, optional
        Called with each episode and its run.
    **controller
        Other arguments of :func:`a2l.rollout.goal.reach_goal` (``side``, ``loop``...).

    Returns
    -------
    list of Episode
    """
    out = []
    for i, seed in enumerate(seeds):
        scene.new_episode(seed=seed)
        before = scene.env_steps
        run = reach_goal(scene, bundle, scene.goal, tolerance=None, budget=budget,
                         done=lambda: scene.episode_over, keep=keep, **controller)
        success = bool(scene.info.get("is_success", False))
        ep = Episode(i, int(seed), success, scene.env_steps - before,
                     run.stop, float(np.linalg.norm(run.obj[0, :2] - run.goal)), run.error,
                     "" if success else miss_cause(run), ",".join(s[0] for s in _segments(run)),
                     *(float(v) for v in (*run.obj[0, :2], *run.goal)))
        out.append(ep)
        if on_episode is not None:
            on_episode(ep, run)
    return out


def episodes_table(episodes: Sequence[Episode]) -> pd.DataFrame:
    """The episodes as a table, one row each (``episodes.csv``)."""
    return pd.DataFrame([asdict(e) for e in episodes])
