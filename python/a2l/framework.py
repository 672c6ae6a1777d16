"""The A2L iterative framework: acquire interactions, generate skills, validate, repeat.

METHOD.md's loop, for the push effects:

1. **Interaction acquisition** by random motor babbling: from start positions evenly on a
   circle around the object, up to ``max_babble_steps`` random movements; a trajectory is
   kept only if the object moved, and every step is labelled with the observed effect.
2. **Skill generation**: discretize, learn a Bayesian network (hill-climbing + K2, ``move``
   has no children), compile the posterior over ``move`` into a table, save a skill bundle.
3. **Interaction validation**: each effect from each start, in closed loop through the C++
   skill step (:mod:`a2l._core`): success, false positive (the object moved with another
   effect) or fail; the iteration's score is ``Σ(4·success + 1·false positive) /
   (4 · n_effects · n_starts) · 100``.
4. **Iteration**: extend the dataset (successful and false-positive trajectories cut back
   and extended at random; effect-directed babbling for (start, effect) pairs stuck for
   long), keep the new dataset only if the score did not drop, stop at score 100 or at the
   iteration cap.

Every random draw comes from a generator seeded by ``(seed, iteration, phase, index)``, so a
run is reproducible, independent of the number of workers, and resumable from the
checkpoint written after each iteration.
"""

from __future__ import annotations

import functools
import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l import _core
from a2l.data.schema import EEF_COLUMNS, EFFECT_DISPLACEMENT_COLUMNS, MOVE_COLUMNS, OBJECT_COLUMNS
from a2l.experiments.rundir import latest_checkpoint, save_checkpoint
from a2l.parallel import Executor

__all__ = [
    "FrameworkConfig",
    "IterationResult",
    "Rollout",
    "run_framework",
    "score_of",
]

#: Default ``directed_try_cap`` of each scene.
DIRECTED_TRY_CAP = {"virtual": 2000, "baxter": 100}

#: Outcomes of one validation rollout.
SUCCESS, FALSE_POSITIVE, FAIL = "success", "false_positive", "fail"


@dataclass
class FrameworkConfig:
    """Every parameter of an A2L run (METHOD.md defaults).

    Attributes
    ----------
    scene : str
        ``"virtual"`` (C++ kinematic push model) or ``"baxter"`` (PyBullet push scene).
    n_effects : {4, 8}
        Push effects to learn.
    n_starts : int
        Start positions, evenly on a circle around the object.
    start_radius : float
        Radius of that circle (m).
    max_babble_steps : int
        Most random movements of a babbling trajectory.
    try_cap : int
        Most babbling trajectories tried in one acquisition.
    max_iterations : int
        Iteration cap (iteration 0 included).
    step_cap : int
        Most movements a skill may take in validation.
    planar : bool
        8 planar movements instead of 26 in 3-D.
    step : float
        Movement length (m).
    n_orient, n_dist, n_incl : int
        Bins of the context variables (``n_incl = 0`` leaves inclination out).
    dist_low, dist_high : float
        Range of the distance bins (m).
    effect_threshold : float
        Smallest object displacement that counts as an effect (m).
    structure : str
        ``"hc-k2"`` or ``"hand-coded"``.
    effect_parent : bool
        With ``hc-k2``, fix the edge ``effect -> move`` (the action generator is queried with
        the wanted effect; without the edge, small datasets give a skill that ignores it).
        Hill-climbing still chooses every other parent.
    extension_cut : int
        Most steps cut from the end of a trajectory before extending it (each extension
        cuts 1 to ``extension_cut`` steps, drawn at random).
    erase_loops : bool
        Cut the loops out of babbling trajectories (:func:`erase_loops`).
    smoothing : bool
        METHOD.md's chapter-6 neighbour smoothing in the C++ step.
    keep_validation : bool
        Add the validation trajectories that moved the object to the next dataset (they
        are interactions too, labelled with the effect they produced).
    max_extensions : int
        Most extension trajectories added per iteration.
    stuck_after : int
        Iterations a (start, effect) pair must fail before effect-directed babbling.
    directed_per_pair : int
        Effect-directed trajectories added for a stuck pair.
    directed_try_cap : int or None
        Most tries to find them; None: the scene's default (:data:`DIRECTED_TRY_CAP`: a
        Baxter movement costs ~20-30 ms of physics, a virtual one ~20 µs).
    directed_steps : int
        Most movements of an effect-directed trajectory (going around the object takes
        more than ``max_babble_steps``).
    directed_growth : int
        Most times the effect-directed budget of a pair grows while it stays stuck
        (1: a fixed budget).
    directed_mode : str
        How effect-directed trajectories move: ``"waypoints"`` (random via-points around
        the object, then a random point on it, :func:`directed_task`) or ``"random"``
        (uniformly random movements, like acquisition).
    waypoints_max : int
        Most via-points of a waypoint trajectory (0 to this many, uniformly).
    waypoint_aim : float
        The last point of a waypoint trajectory is drawn within ± this of the object's
        start position on each table axis (m).
    seed : int
        Seed of every random draw.
    scene_config : dict
        Extra keyword arguments for :func:`a2l.sim.make_scene`.
    """

    scene: str = "virtual"
    n_effects: int = 4
    n_starts: int = 8
    start_radius: float = 0.2
    max_babble_steps: int = 7
    try_cap: int = 5000
    max_iterations: int = 10
    step_cap: int = 12
    planar: bool = True
    step: float = 0.05
    n_orient: int = 16
    n_dist: int = 3
    n_incl: int = 0
    dist_low: float = 0.05
    dist_high: float = 0.20
    effect_threshold: float = 0.01
    structure: str = "hc-k2"
    effect_parent: bool = True
    extension_cut: int = 3
    keep_validation: bool = True
    smoothing: bool = False
    erase_loops: bool = False
    max_extensions: int = 50
    stuck_after: int = 1
    directed_per_pair: int = 40
    directed_try_cap: int | None = None
    directed_steps: int = 20
    directed_growth: int = 5
    directed_mode: str = "waypoints"
    waypoints_max: int = 2
    waypoint_aim: float = 0.04
    seed: int = 0
    scene_config: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.directed_try_cap is None:
            self.directed_try_cap = DIRECTED_TRY_CAP.get(self.scene, 2000)

    def validate(self) -> None:
        """Raise ``ValueError`` naming the first field out of its domain."""
        if self.scene not in ("virtual", "baxter"):
            raise ValueError(f"scene: unknown scene {self.scene!r}; choose 'virtual' or 'baxter'")
        if self.n_effects not in (4, 8):
            raise ValueError(f"n_effects: must be 4 or 8, got {self.n_effects}")
        positive_ints = ("n_starts", "max_babble_steps", "try_cap", "max_iterations",
                         "step_cap", "n_orient", "n_dist", "max_extensions",
                         "directed_per_pair", "directed_try_cap", "directed_steps", "stuck_after",
                         "directed_growth")
        for name in positive_ints:
            v = getattr(self, name)
            if not isinstance(v, int) or v < 1:
                raise ValueError(f"{name}: must be a positive integer, got {v!r}")
        for name in ("start_radius", "step", "effect_threshold", "waypoint_aim"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name}: must be a positive length, got {v!r}")
        if not 0 < self.dist_low < self.dist_high:
            raise ValueError(f"dist_low, dist_high: need 0 < low < high, got "
                             f"{self.dist_low}, {self.dist_high}")
        if self.n_incl < 0:
            raise ValueError(f"n_incl: must be >= 0, got {self.n_incl}")
        if self.extension_cut < 1:
            raise ValueError(f"extension_cut: must be >= 1, got {self.extension_cut}")
        if self.structure not in ("hc-k2", "hand-coded"):
            raise ValueError(f"structure: unknown {self.structure!r}")
        if self.directed_mode not in ("waypoints", "random"):
            raise ValueError(f"directed_mode: unknown {self.directed_mode!r}; choose "
                             "'waypoints' or 'random'")
        if not isinstance(self.waypoints_max, int) or self.waypoints_max < 0:
            raise ValueError(f"waypoints_max: must be an integer >= 0, got "
                             f"{self.waypoints_max!r}")

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> FrameworkConfig:
        """Build from a dict (e.g. a run's ``config.json``); unknown keys are errors."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(d) - known)
        if unknown:
            raise ValueError(f"unknown config key(s) {unknown}; known: {sorted(known)}")
        cfg = cls(**d)
        cfg.validate()
        return cfg

    def start_offsets(self) -> np.ndarray:
        """End-effector start positions relative to the object, shape (n_starts, 3)."""
        a = 2 * np.pi * np.arange(self.n_starts) / self.n_starts
        r = self.start_radius
        return np.stack([r * np.cos(a), r * np.sin(a), np.zeros_like(a)], axis=1)


# ---------------------------------------------------------------------------------------
# Rollouts (module-level functions: they run in worker processes too)
# ---------------------------------------------------------------------------------------

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
    """

    start: int
    moves: list[int]
    eef: np.ndarray
    obj: np.ndarray
    effect: int = -1
    wanted: int = -1
    outcome: str = ""
    stop: str = ""

    @property
    def moved(self) -> bool:
        """True if the object moved (an effect was observed)."""
        return self.effect >= 0


#: Scenes per thread: a Dask worker runs tasks in several threads, and two rollouts must
#: never share a scene.
_LOCAL = threading.local()


def _env(cfg: FrameworkConfig) -> Any:
    """The scene of this thread for `cfg` (built once per thread and reused)."""
    from a2l.framework_env import make_env

    cache: dict[str, Any] = _LOCAL.__dict__.setdefault("envs", {})
    key = repr((cfg.scene, sorted(cfg.scene_config.items()), cfg.step, cfg.seed))
    env = cache.get(key)
    if env is None:
        for old in cache.values():
            old.close()
        cache.clear()
        env = make_env(cfg.scene, seed=cfg.seed, step=cfg.step, **cfg.scene_config)
        cache[key] = env
    return env


def _discretizers(cfg: FrameworkConfig) -> Any:
    """The discretization of `cfg` (built once per set of its parameters: rollouts call this
    for every task)."""
    return _discretizer_for(cfg.n_dist, cfg.dist_low, cfg.dist_high, cfg.n_orient, cfg.n_incl,
                            cfg.planar, cfg.step, cfg.n_effects, cfg.effect_threshold)


@functools.lru_cache(maxsize=16)
def _discretizer_for(n_dist: int, dist_low: float, dist_high: float, n_orient: int,
                     n_incl: int, planar: bool, step: float, n_effects: int,
                     effect_threshold: float) -> Any:
    from a2l.skills.discretize import (
        Discretizer,
        DistanceBins,
        EffectDiscretizer,
        InclinationBins,
        MovementRepertoire,
        OrientationBins,
    )

    return Discretizer(
        distance=DistanceBins(n_bins=n_dist, low=dist_low, high=dist_high),
        orientation=OrientationBins(n_bins=n_orient),
        inclination=InclinationBins(n_bins=n_incl) if n_incl > 0 else None,
        movements=MovementRepertoire(planar=planar, step=step),
        effects=EffectDiscretizer(n_effects=n_effects, threshold=effect_threshold),
    )


def _effect_of(disc: Any, displacement: np.ndarray) -> int:
    """Effect index of one object displacement (-1: none, or not seen), by the C++
    classifier the scenes and the runtime use (same indices as ``disc.effects``; tested
    equal)."""
    e = disc.effects
    return int(_core.classify_effect(np.asarray(displacement, dtype=float), e.n_effects,
                                     e.threshold, e.ratio))


def _play(env: Any, disc: Any, start: int, offset: np.ndarray, prefix: Sequence[int],
          choose: Callable[[np.ndarray, np.ndarray], int | None], max_steps: int) -> Rollout:
    """Start at `offset`, replay `prefix`, then ``choose(eef, obj)`` until the object moves.

    `choose` returns a movement index, or None to stop.
    """
    env.begin(offset)
    obj0 = env.object().copy()
    eefs, objs, moves = [env.eef().copy()], [obj0.copy()], []
    stop = "exhausted"
    effect = -1
    for i in range(max_steps):
        move = prefix[i] if i < len(prefix) else choose(eefs[-1], objs[-1])
        if move is None:
            stop = "stopped"
            break
        if not env.execute(tuple(int(s) for s in disc.movements.directions[move])):
            stop = "unreachable"
            break
        moves.append(int(move))
        eefs.append(env.eef().copy())
        objs.append(env.object().copy())
        effect = _effect_of(disc, objs[-1] - obj0)
        if effect >= 0:
            stop = "moved"
            break
    return Rollout(start, moves, np.array(eefs), np.array(objs), effect=effect, stop=stop)


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
    return Rollout(r.start, keep_m, np.array(keep_e), np.array(keep_o), effect=r.effect,
                   wanted=r.wanted, outcome=r.outcome, stop=r.stop)


def babble_task(task: tuple[dict[str, Any], int, list[int], int, int]) -> Rollout:
    """One babbling trajectory: ``(config, start, prefix, seed, steps)``.

    Uniformly random movements after `prefix` (METHOD.md), at most `steps` of them, until
    the object moves.
    """
    cfg_d, start, prefix, seed, steps = task
    return _random_walk(FrameworkConfig(**cfg_d), start, prefix, seed, steps)


def _random_walk(cfg: FrameworkConfig, start: int, prefix: Sequence[int], seed: int,
                 steps: int) -> Rollout:
    """`prefix`, then at most `steps` uniformly random movements from start `start`."""
    disc = _discretizers(cfg)
    rng = np.random.default_rng(seed)
    n = disc.movements.n_moves

    def choose(_eef: np.ndarray, _obj: np.ndarray) -> int:
        return int(rng.integers(n))

    offset = cfg.start_offsets()[start]
    r = _play(_env(cfg), disc, start, offset, prefix, choose, len(prefix) + steps)
    return erase_loops(r) if cfg.erase_loops else r


def random_waypoints(rng: np.random.Generator, home: np.ndarray, n_max: int, r_low: float,
                     r_high: float, aim: float) -> np.ndarray:
    """The points of a random waypoint trajectory around an object at `home`.

    0 to `n_max` via-points (uniformly many), each at a uniform angle and a uniform distance
    in ``[r_low, r_high]`` from `home` in the table plane, then a last point drawn uniformly
    within ± `aim` of `home` on each table axis. Like NovEB's genotypes (waypoints in the
    workspace), the trajectory is random, but it keeps a heading for several movements, so
    it goes around the object far more often than a random walk of the same length.

    Returns
    -------
    ndarray, shape (k, 3), 1 <= k <= n_max + 1
        The points, at `home`'s height; the last one is the aim on the object.
    """
    home = np.asarray(home, dtype=float)
    points = []
    for _ in range(int(rng.integers(0, n_max + 1))):
        a, r = rng.uniform(0, 2 * np.pi), rng.uniform(r_low, r_high)
        points.append(home + np.array([r * np.cos(a), r * np.sin(a), 0.0]))
    points.append(home + np.array([*rng.uniform(-aim, aim, 2), 0.0]))
    return np.array(points)


def heading_chooser(points: np.ndarray, disc: Any, start: np.ndarray
                    ) -> Callable[[np.ndarray, np.ndarray], int]:
    """A ``choose(eef, obj)`` that follows `points` (shape (k, 3)) from `start` (3,) with the
    repertoire's movements: each movement is the direction closest to the way to the
    current point; a point is passed when the end-effector comes within 0.7 steps of it
    (table plane), and the last one is headed for until the rollout ends (the object moves
    on the way).

    The chooser plans on the nominal positions (`start` plus the movements chosen so far),
    not on the measured `eef`: the trajectory is a function of its points alone. A physics
    scene ends a movement a few 1e-8 m off its target, differently in a process that ran
    other rollouts before (PyBullet keeps solver state across restores), and near a tie
    between two directions that noise would change the movement, and so the results with
    the number of workers.
    """
    dirs = disc.movements.directions.astype(float)
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    reach = 0.7 * disc.movements.step
    k = 0
    at = np.array(start, dtype=float)

    def choose(_eef: np.ndarray, _obj: np.ndarray) -> int:
        nonlocal k, at
        while k < len(points) - 1 and np.linalg.norm((points[k] - at)[:2]) < reach:
            k += 1
        d = points[k] - at
        if disc.movements.planar:
            d[2] = 0.0
        move = int(np.argmax(dirs @ d))
        at = at + disc.movements.displacement(move)
        return move

    return choose


def directed_task(task: tuple[dict[str, Any], int, int, int]) -> Rollout:
    """One effect-directed babbling trajectory: ``(config, start, seed, steps)``.

    ``directed_mode == "random"``: uniformly random movements (as :func:`babble_task`);
    ``"waypoints"``: a random waypoint trajectory (:func:`random_waypoints`,
    :func:`heading_chooser`) with via-points between ``dist_low`` and
    ``start_radius + step`` from the object. At most `steps` movements, until the object
    moves.
    """
    cfg_d, start, seed, steps = task
    cfg = FrameworkConfig(**cfg_d)
    if cfg.directed_mode == "random":
        return _random_walk(cfg, start, [], seed, steps)
    disc = _discretizers(cfg)
    env = _env(cfg)
    offset = cfg.start_offsets()[start]
    points = random_waypoints(np.random.default_rng(seed), env.home, cfg.waypoints_max,
                              cfg.dist_low, cfg.start_radius + cfg.step, cfg.waypoint_aim)
    choose = heading_chooser(points, disc, env.home + offset)
    r = _play(env, disc, start, offset, [], choose, steps)
    return erase_loops(r) if cfg.erase_loops else r


def validate_task(task: tuple[dict[str, Any], str, int, int]) -> Rollout:
    """One validation rollout: ``(config, bundle_path, start, wanted_effect)``.

    The skill runs in closed loop through the C++ step until the object moves (success if
    with the wanted effect, else false positive), or the step returns a stop status (step
    cap, unknown context: fail).
    """
    from a2l.framework_env import CppSkillRunner

    cfg_d, bundle, start, wanted = task
    cfg = FrameworkConfig(**cfg_d)
    disc = _discretizers(cfg)
    runner = CppSkillRunner.cached(bundle)
    if tuple(runner.labels) != tuple(disc.movements.labels):
        raise ValueError(f"skill bundle '{bundle}' has movements {runner.labels}, the "
                         f"framework's repertoire is {disc.movements.labels}")
    runner.reset()
    status: list[str] = []

    def choose(eef: np.ndarray, obj: np.ndarray) -> int | None:
        move, st = runner.step(eef, obj, wanted)
        if move is None:
            status.append(st)
        return move

    r = _play(_env(cfg), disc, start, cfg.start_offsets()[start], [], choose, cfg.step_cap + 1)
    r.wanted = wanted
    if r.moved:
        r.outcome = SUCCESS if r.effect == wanted else FALSE_POSITIVE
    else:
        r.outcome = FAIL
        if status:
            r.stop = status[0]
    return r


# ---------------------------------------------------------------------------------------
# Datasets
# ---------------------------------------------------------------------------------------

def rollouts_to_frame(rollouts: Sequence[Rollout], disc: Any, first_episode: int = 0
                      ) -> pd.DataFrame:
    """Raw dataset rows (:mod:`a2l.data.schema`) of rollouts that moved the object.

    Every step of a trajectory is labelled with the trajectory's observed effect (the
    object's displacement from the start to the end).

    Returns
    -------
    pandas.DataFrame, shape (total steps, 16)
    """
    rows: list[dict[str, Any]] = []
    ep = first_episode
    for r in rollouts:
        if not r.moved:
            continue
        disp = r.obj[-1] - r.obj[0]
        for k, move in enumerate(r.moves):
            d = disc.movements.displacement(move)
            row = {"episode": ep, "step": k, "start": r.start}
            row.update(zip(EEF_COLUMNS, r.eef[k], strict=True))
            row.update(zip(OBJECT_COLUMNS, r.obj[k], strict=True))
            row.update(zip(MOVE_COLUMNS, d, strict=True))
            row.update(zip(EFFECT_DISPLACEMENT_COLUMNS, disp, strict=True))
            rows.append(row)
        ep += 1
    cols = ["episode", "step", "start", *EEF_COLUMNS, *OBJECT_COLUMNS, *MOVE_COLUMNS,
            *EFFECT_DISPLACEMENT_COLUMNS]
    return pd.DataFrame(rows, columns=cols)


def _seed(cfg: FrameworkConfig, iteration: int, phase: int, index: int) -> int:
    ss = np.random.SeedSequence([cfg.seed, iteration, phase, index])
    return int(ss.generate_state(1, dtype=np.uint64)[0] >> 1)


def acquire(cfg: FrameworkConfig, executor: Executor, iteration: int,
            progress: Callable[[str, int, int], None] | None = None) -> list[Rollout]:
    """Random babbling until ``n_starts · n_effects`` trajectories moved the object.

    Tries are made in batches (in parallel) and cut, in try order, at the point where the
    target count is reached: the result is the same for any number of workers.
    """
    target = cfg.n_starts * cfg.n_effects
    cfg_d = asdict(cfg)
    kept: list[Rollout] = []
    tried = 0
    batch = max(16, 8 * executor.workers)
    while len(kept) < target and tried < cfg.try_cap:
        n = min(batch, cfg.try_cap - tried)
        tasks = [(cfg_d, (tried + i) % cfg.n_starts, [], _seed(cfg, iteration, 0, tried + i),
                  cfg.max_babble_steps) for i in range(n)]
        for r in executor.map(babble_task, tasks):
            tried += 1
            if r.moved and len(kept) < target:
                kept.append(r)
        if progress:
            progress("acquire", len(kept), target)
    return kept


def extend(cfg: FrameworkConfig, executor: Executor, iteration: int,
           validation: Sequence[Rollout], stuck: dict[tuple[int, int], int]) -> list[Rollout]:
    """New trajectories for iteration `iteration` (METHOD.md's dataset extension).

    - successful and false-positive validation trajectories (themselves, with
      ``keep_validation``), and cut back 1 to ``extension_cut`` steps and extended with
      random movements (at most ``max_extensions``);
    - for each (start, effect) pair failed ``stuck_after`` iterations in a row, up to
      ``directed_per_pair`` effect-directed trajectories: random trajectories from that
      start (:func:`directed_task`; at most ``directed_steps`` movements), kept only when
      they produce that effect. The budget of a pair stuck for ``stuck_after + k``
      iterations is ``k + 1`` times that (trajectories and tries), at most
      ``directed_growth`` times: a pair whose failing context cells are outvoted by the
      rest of the dataset gets more votes each iteration.
    """
    cfg_d = asdict(cfg)
    tasks = []
    moved = [v for v in validation if v.outcome in (SUCCESS, FALSE_POSITIVE)]
    cut_rng = np.random.default_rng(_seed(cfg, iteration, 1, -1 % 2**31))
    for i in range(min(cfg.max_extensions, len(moved) * cfg.extension_cut)):
        r = moved[i % len(moved)]
        cut = int(cut_rng.integers(1, cfg.extension_cut + 1))
        prefix = r.moves[: max(0, len(r.moves) - cut)]
        tasks.append((cfg_d, r.start, prefix, _seed(cfg, iteration, 1, i),
                      cfg.max_babble_steps))
    out = list(moved) if cfg.keep_validation else []
    out += [r for r in executor.map(babble_task, tasks) if r.moved]
    pairs = sorted(p for p, n in stuck.items() if n >= cfg.stuck_after)
    for j, (start, effect) in enumerate(pairs):
        found: list[Rollout] = []
        tried = 0
        grow = min(stuck[(start, effect)] - cfg.stuck_after + 1, cfg.directed_growth)
        want, cap = cfg.directed_per_pair * grow, cfg.directed_try_cap * grow
        while len(found) < want and tried < cap:
            n = min(32, cap - tried)
            tasks = [(cfg_d, start, _seed(cfg, iteration, 2 + j, tried + i),
                      cfg.directed_steps) for i in range(n)]
            for r in executor.map(directed_task, tasks):
                tried += 1
                if r.effect == effect and len(found) < want:
                    found.append(r)
        out.extend(found)
    return out


# ---------------------------------------------------------------------------------------
# Skills and validation
# ---------------------------------------------------------------------------------------

def generate_skill(cfg: FrameworkConfig, dataset: pd.DataFrame, bundle_path: Path,
                   robot: dict[str, str] | None = None) -> Any:
    """Learn the network from `dataset`, compile it, and save the skill bundle.

    Returns
    -------
    a2l.skills.PolicyTable
        The compiled table (the bundle holds the same numbers).
    """
    from a2l.skills import compile_policy, learn_network, make_skill_spec, save_bundle

    disc = _discretizers(cfg)
    discrete = disc.discretize(dataset)
    if len(discrete) == 0:
        raise ValueError("the dataset has no usable row: nothing moved the object")
    constraints: dict[str, Any] = {}
    if cfg.structure == "hc-k2" and cfg.effect_parent:
        constraints["fixed_edges"] = [(disc.effects.name, disc.movements.name)]
    network = learn_network(discrete, structure=cfg.structure, state_names=disc.state_names(),
                            **constraints)
    table = compile_policy(network, target="move", evidence=disc.evidence)
    spec = make_skill_spec(table, disc, name="push", robot=robot, step_cap=cfg.step_cap,
                           smoothing=cfg.smoothing, extra={"framework": asdict(cfg)})
    save_bundle(spec, bundle_path)
    return table


def validate(cfg: FrameworkConfig, executor: Executor, bundle_path: Path,
             progress: Callable[[str, int, int], None] | None = None) -> list[Rollout]:
    """Run the skill for every (start, effect) pair; results in (start, effect) order."""
    cfg_d = asdict(cfg)
    tasks = [(cfg_d, str(bundle_path), s, e)
             for s in range(cfg.n_starts) for e in range(cfg.n_effects)]
    total = len(tasks)
    return executor.map(validate_task, tasks,
                        on_done=(lambda k: progress("validate", k, total)) if progress else None)


def score_of(rollouts: Sequence[Rollout], n_effects: int, n_starts: int) -> float:
    """METHOD.md's score: Σ(4·success + 1·false positive) / (4·n_effects·n_starts) · 100."""
    points = sum(4 if r.outcome == SUCCESS else 1 if r.outcome == FALSE_POSITIVE else 0
                 for r in rollouts)
    return 100.0 * points / (4 * n_effects * n_starts)


@dataclass
class IterationResult:
    """Metrics of one iteration (one entry of ``metrics.json``'s ``iterations``)."""

    iteration: int
    score: float
    success_rate: dict[str, float]
    false_positives: int
    mean_movements: float
    dataset_size: int
    accepted: bool
    wall_s: float


def _metrics(cfg: FrameworkConfig, it: int, val: Sequence[Rollout], size: int,
             accepted: bool, wall: float) -> IterationResult:
    names = _discretizers(cfg).effects.values
    rate = {names[e]: float(np.mean([r.outcome == SUCCESS for r in val if r.wanted == e]))
            for e in range(cfg.n_effects)}
    moves = [len(r.moves) for r in val if r.outcome == SUCCESS]
    return IterationResult(
        iteration=it, score=score_of(val, cfg.n_effects, cfg.n_starts), success_rate=rate,
        false_positives=sum(r.outcome == FALSE_POSITIVE for r in val),
        mean_movements=float(np.mean(moves)) if moves else float("nan"),
        dataset_size=size, accepted=accepted, wall_s=wall)


def _rollouts_frame(rollouts: Sequence[Rollout]) -> pd.DataFrame:
    """Validation rollouts as a table (one row per rollout; positions as lists)."""
    return pd.DataFrame({
        "start": [r.start for r in rollouts], "wanted": [r.wanted for r in rollouts],
        "effect": [r.effect for r in rollouts], "outcome": [r.outcome for r in rollouts],
        "stop": [r.stop for r in rollouts], "moves": [list(r.moves) for r in rollouts],
        "eef": [r.eef.ravel().tolist() for r in rollouts],
        "obj": [r.obj.ravel().tolist() for r in rollouts],
    })


def _frame_rollouts(df: pd.DataFrame) -> list[Rollout]:
    out = []
    for row in df.itertuples(index=False):
        out.append(Rollout(int(row.start), [int(m) for m in row.moves],
                           np.asarray(row.eef, dtype=float).reshape(-1, 3),
                           np.asarray(row.obj, dtype=float).reshape(-1, 3),
                           effect=int(row.effect), wanted=int(row.wanted),
                           outcome=str(row.outcome), stop=str(row.stop)))
    return out


def run_framework(cfg: FrameworkConfig, run_dir: Path, executor: Executor,
                  progress: Callable[[str, int, int], None] | None = None,
                  on_iteration: Callable[[IterationResult], None] | None = None,
                  robot: dict[str, str] | None = None) -> dict[str, Any]:
    """The whole iterative loop; resumes from the newest checkpoint in `run_dir`.

    Parameters
    ----------
    cfg : FrameworkConfig
        The run's parameters.
    run_dir : Path
        Where checkpoints (``checkpoints/iter_NNN``) and bundles (``skills/``) go.
    executor : a2l.parallel.Executor
        Where rollouts run.
    progress : callable, optional
        ``progress(phase, done, total)`` during acquisition and validation.
    on_iteration : callable, optional
        Called with each finished iteration's metrics.
    robot : dict, optional
        Robot entry of the bundles.

    Returns
    -------
    dict
        ``{"iterations": [...], "final_score": float, "bundle": str, "validation":
        DataFrame of the accepted iteration's rollouts}``.
    """
    cfg.validate()
    skills_dir = run_dir / "skills"
    skills_dir.mkdir(parents=True, exist_ok=True)
    disc = _discretizers(cfg)
    ck = latest_checkpoint(run_dir)
    if ck is not None:
        last, state, frames = ck
        dataset = frames["dataset"]
        best_val = _frame_rollouts(frames["validation"])
        history = state["iterations"]
        best_score = float(state["best_score"])
        stuck = {(int(k.split(",")[0]), int(k.split(",")[1])): int(v)
                 for k, v in state["stuck"].items()}
        start_it = last + 1
    else:
        dataset, best_val, history, best_score, stuck, start_it = None, [], [], -1.0, {}, 0
    for it in range(start_it, cfg.max_iterations):
        if best_score >= 100.0:
            break
        t0 = time.perf_counter()
        if dataset is None:
            new = rollouts_to_frame(acquire(cfg, executor, it, progress), disc)
            candidate = new
        else:
            extra = extend(cfg, executor, it, best_val, stuck)
            first = int(dataset["episode"].max()) + 1 if len(dataset) else 0
            candidate = pd.concat([dataset, rollouts_to_frame(extra, disc, first)],
                                  ignore_index=True)
        bundle = skills_dir / f"iter_{it:03d}.a2lb"
        generate_skill(cfg, candidate, bundle, robot)
        val = validate(cfg, executor, bundle, progress)
        score = score_of(val, cfg.n_effects, cfg.n_starts)
        accepted = score >= best_score
        if accepted:
            dataset, best_val, best_score = candidate, val, score
            (skills_dir / "accepted.txt").write_text(bundle.name + "\n")
        for r in val:
            key = (r.start, r.wanted)
            stuck[key] = 0 if r.outcome == SUCCESS else stuck.get(key, 0) + 1
        m = _metrics(cfg, it, val, len(candidate), accepted, time.perf_counter() - t0)
        history.append(asdict(m))
        save_checkpoint(run_dir, it, {
            "iterations": history, "best_score": best_score,
            "stuck": {f"{s},{e}": n for (s, e), n in stuck.items()},
        }, {"dataset": dataset, "validation": _rollouts_frame(best_val)})
        if on_iteration:
            on_iteration(m)
    accepted_name = (skills_dir / "accepted.txt").read_text().strip()
    return {"iterations": history, "final_score": best_score,
            "bundle": str(skills_dir / accepted_name), "dataset": dataset,
            "validation": _rollouts_frame(best_val)}
