"""Rollouts: one end-effector trajectory played in a scene (:func:`play`), its record
(:class:`Rollout`), loop erasure, the conversion of rollouts that moved the object into
the interaction dataset's rows (:func:`interaction_rows`, :mod:`a2l.data.schema`), and a
table of whole rollouts, one per row, to store and read back (:func:`rollouts_table`,
:func:`rollouts_from_table`: a checkpoint's validation and held-out rollouts).

Every acquisition strategy's trajectories end up here; the framework's validation plays the
skills' trajectories the same way.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from a2l.data.schema import EEF_COLUMNS, EFFECT_DISPLACEMENT_COLUMNS, MOVE_COLUMNS, OBJECT_COLUMNS
from a2l.rollout.env import SceneEnv
from a2l.rollout.loop import Decision, closed_loop

__all__ = ["Interactions", "Rollout", "effect_of", "erase_loops", "interaction_rows", "play",
           "rollouts_from_table", "rollouts_table"]


@dataclass
class Rollout:
    """One trajectory of the end-effector from a start position.

    Attributes
    ----------
    start : int
        Index of the start position.
    moves : list of int
        Movement indices executed, in order.
    eef : ndarray, shape (len(moves) + 1, 3)
        End-effector positions before each movement and after the last.
    obj : ndarray, shape (len(moves) + 1, 3)
        Object positions at the same instants.
    effect : int
        Observed effect index (-1: the object did not move).
    wanted : int
        Wanted effect in validation (-1 in babbling).
    outcome : str
        ``success``, ``false_positive`` or ``fail`` (validation), ``""`` (babbling).
    stop : str
        Why the rollout ended (``moved``, ``step_cap``, ``unknown_context``,
        ``unreachable``, ``exhausted``).
    executed : int
        Discrete movements the scene was asked to execute to play it (:func:`play`): the
        moves, plus the one that could not be carried out (``stop == "unreachable"``),
        plus those :func:`erase_loops` cut out; 0 when not recorded (a rollout read back
        from a checkpoint).
    fallbacks : int
        Validation only: the movements the skill took in a context cell without data, from
        the nearest cell with data (the C++ step's fallback, the trace's ``fallback``).
    true_effect : int
        The effect of the object's true displacement from the start to the end of the
        rollout (the simulator's ground truth; -1: no effect). It equals `effect` when the
        context comes from the ground truth; with the camera, `effect` is what the robot saw
        and `true_effect` what happened. Validation judges by `true_effect`.
    """

    start: int
    moves: list[int]
    eef: np.ndarray
    obj: np.ndarray
    effect: int = -1
    wanted: int = -1
    outcome: str = ""
    stop: str = ""
    executed: int = 0
    fallbacks: int = 0
    true_effect: int = -1

    @property
    def moved(self) -> bool:
        """True if the object moved (an effect was observed)."""
        return self.effect >= 0


@dataclass
class Interactions:
    """What an acquisition phase gathered: its rollouts, and the robot movements it took.

    Attributes
    ----------
    rollouts : list of Rollout
        The interactions kept (those that moved the object, or, in the framework's
        extension, the validation trajectories reused).
    movements : int
        Discrete movements the robot executed for them, those of the tries that were
        thrown away included: the sum, over every trajectory the phase's strategy was told
        (:mod:`a2l.acquisition.protocol`), of the movements played for it. A round run
        ahead on workers and dropped (:func:`~a2l.acquisition.protocol.drive_ahead`) is not
        told, so the count is what a run with one worker executes.
    """

    rollouts: list[Rollout]
    movements: int


def effect_of(disc: Any, displacement: np.ndarray) -> int:
    """Effect index of one object displacement (-1: none, or not seen):
    :meth:`a2l.skills.effects.EffectDiscretizer.classify` of ``disc.effects`` (the C++
    classifier the scenes and the runtime use)."""
    return disc.effects.classify(displacement)


class _EnvWorld:
    """A framework scene env (:class:`a2l.rollout.env.SceneEnv`) as the world of a closed
    loop: movements by index into the repertoire, ``"unreachable"`` when the env cannot
    carry one out."""

    def __init__(self, env: SceneEnv, directions: np.ndarray) -> None:
        self.env = env
        self.directions = directions

    def observe(self) -> tuple[np.ndarray, np.ndarray, dict[str, str]]:
        return self.env.eef().copy(), self.env.object().copy(), {}

    def act(self, decision: Decision) -> str:
        ok = self.env.execute(tuple(int(s) for s in self.directions[decision.movement]))
        return "ok" if ok else "unreachable"


def play(env: SceneEnv, disc: Any, start: int, offset: np.ndarray, prefix: Sequence[int],
         choose: Callable[[np.ndarray, np.ndarray], int | None], max_steps: int) -> Rollout:
    """Start at `offset`, replay `prefix`, then ``choose(eef, obj)`` until the object moves
    (the closed loop of :func:`a2l.rollout.loop.closed_loop`).

    `choose` returns a movement index, or None to stop (``stop == "stopped"``). The run
    ends ``moved`` when the object moved with an effect (:func:`effect_of`),
    ``unreachable`` when a movement could not be carried out (it is not recorded), or
    ``exhausted`` after `max_steps` movements.
    """
    env.begin(offset)
    effect = -1
    obj0 = np.zeros(3)
    true0 = env.true_object()

    def moved(k: int, _eef: np.ndarray, obj: np.ndarray, _states: dict[str, str]
              ) -> str | None:
        nonlocal effect, obj0
        if k == 0:
            obj0 = obj
            return None
        effect = effect_of(disc, obj - obj0)
        return "moved" if effect >= 0 else None

    def policy(k: int, eef: np.ndarray, obj: np.ndarray, _states: dict[str, str]
               ) -> Decision:
        move = prefix[k] if k < len(prefix) else choose(eef, obj)
        if move is None:
            return Decision("stopped")
        return Decision("ok", movement=int(move))

    run = closed_loop(_EnvWorld(env, disc.movements.directions), policy, moved, max_steps,
                      cap_status="exhausted", fatal=("unreachable",))
    moves = run.carried_out()
    n = len(moves) + 1
    return Rollout(start, moves, run.eef[:n].copy(), run.obj[:n].copy(),
                   effect=effect if run.stop == "moved" else -1, stop=run.stop,
                   executed=run.executed,
                   true_effect=effect_of(disc, env.true_object() - true0))


def erase_loops(r: Rollout, tol: float = 0.01) -> Rollout:
    """The rollout with its loops cut out: where the end-effector comes back (within `tol`)
    to a place it was at while the object had not moved yet, the steps in between go.

    A random walk that produced an effect wanders; the loop-free walk reaches the same
    contact with the same object state, so it is an equally real interaction with less
    noise in its labels.
    """
    keep_e, keep_o, keep_m = [r.eef[0]], [r.obj[0]], []
    moving_from = next((k for k in range(1, len(r.obj))
                        if np.linalg.norm(r.obj[k] - r.obj[0]) > 1e-9), len(r.obj))
    for k in range(len(r.moves)):
        p = r.eef[k + 1]
        if k + 1 < moving_from:
            hits = [i for i, q in enumerate(keep_e) if np.linalg.norm(p - q) < tol]
            if hits:
                i = hits[0]
                keep_e, keep_o, keep_m = keep_e[: i + 1], keep_o[: i + 1], keep_m[:i]
                continue
        keep_e.append(p)
        keep_o.append(r.obj[k + 1])
        keep_m.append(r.moves[k])
    return dataclasses.replace(r, moves=keep_m, eef=np.array(keep_e), obj=np.array(keep_o))


def interaction_rows(rollouts: Sequence[Rollout], disc: Any, first_episode: int = 0
                     ) -> pd.DataFrame:
    """Raw dataset rows (:mod:`a2l.data.schema`) of rollouts that moved the object.

    Every step of a trajectory is labelled with the trajectory's observed effect (the
    object's displacement from the start to the end).

    Returns
    -------
    pandas.DataFrame, shape (total steps, 16)
    """
    cols = ["episode", "step", "start", *EEF_COLUMNS, *OBJECT_COLUMNS, *MOVE_COLUMNS,
            *EFFECT_DISPLACEMENT_COLUMNS]
    moved = [r for r in rollouts if r.moved]
    if not moved:
        return pd.DataFrame([], columns=cols)
    # column by column (a dict per row cost ~25 us a row in the main process, serial)
    lens = np.array([len(r.moves) for r in moved])
    moves = np.concatenate([np.asarray(r.moves, dtype=np.int64) for r in moved])
    blocks = [
        np.repeat(np.arange(first_episode, first_episode + len(moved)), lens)[:, None],
        np.concatenate([np.arange(n) for n in lens])[:, None],
        np.repeat([r.start for r in moved], lens)[:, None],
    ]
    ints = np.hstack(blocks).astype(np.int64)
    floats = np.hstack([
        np.concatenate([r.eef[:n] for r, n in zip(moved, lens, strict=True)]),
        np.concatenate([r.obj[:n] for r, n in zip(moved, lens, strict=True)]),
        disc.movements.displacement(moves).reshape(-1, 3),
        np.repeat(np.array([r.obj[-1] - r.obj[0] for r in moved]), lens, axis=0),
    ]).astype(np.float64)
    data = {c: ints[:, i] for i, c in enumerate(cols[:3])}
    data.update({c: floats[:, i] for i, c in enumerate(cols[3:])})
    return pd.DataFrame(data, columns=cols)


def rollouts_table(rollouts: Sequence[Rollout]) -> pd.DataFrame:
    """Validation rollouts as a table (one row per rollout; positions as lists): the
    columns of a checkpoint's ``validation.parquet`` and ``heldout.parquet``."""
    return pd.DataFrame({
        "start": [r.start for r in rollouts], "wanted": [r.wanted for r in rollouts],
        "effect": [r.effect for r in rollouts], "outcome": [r.outcome for r in rollouts],
        "stop": [r.stop for r in rollouts], "moves": [list(r.moves) for r in rollouts],
        "fallbacks": [r.fallbacks for r in rollouts],
        "true_effect": [r.true_effect for r in rollouts],
        "eef": [r.eef.ravel().tolist() for r in rollouts],
        "obj": [r.obj.ravel().tolist() for r in rollouts],
    })


def rollouts_from_table(df: pd.DataFrame) -> list[Rollout]:
    """The rollouts of a table :func:`rollouts_table` wrote (a checkpoint's
    ``validation.parquet``, ``heldout.parquet``), in its row order."""
    out = []
    for row in df.itertuples(index=False):
        out.append(Rollout(int(row.start), [int(m) for m in row.moves],
                           np.asarray(row.eef, dtype=float).reshape(-1, 3),
                           np.asarray(row.obj, dtype=float).reshape(-1, 3),
                           effect=int(row.effect), wanted=int(row.wanted),
                           outcome=str(row.outcome), stop=str(row.stop),
                           fallbacks=int(getattr(row, "fallbacks", 0)),
                           true_effect=int(getattr(row, "true_effect", row.effect))))
    return out
