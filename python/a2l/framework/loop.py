"""The A2L iterative loop (:func:`run_framework`): acquire interactions, generate the skill,
validate it, extend the dataset, repeat; a checkpoint after each iteration.

Every random draw comes from a generator seeded by ``(seed, iteration, phase, index)``
(:func:`phase_seed`), so a run is reproducible, independent of the number of workers, and
resumable from its newest checkpoint.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from a2l.acquisition.interactions import Interactions, Rollout, interaction_rows, rollouts_table
from a2l.acquisition.protocol import drive_ahead
from a2l.framework.config import FrameworkConfig
from a2l.framework.random_babbling import BabbleTask, RandomBabbling, babble_task
from a2l.framework.result import FrameworkResult
from a2l.framework.rules import training_bundle
from a2l.framework.run_state import MOVEMENT_PHASES, RunState, movement_record
from a2l.framework.scoring import (
    FALSE_POSITIVE,
    SUCCESS,
    FreshValidation,
    IterationResult,
    heldout_metrics,
    iteration_metrics,
    miss_counts,
    score_of,
    success_of,
)
from a2l.framework.validation import validate, validate_fresh, validate_heldout
from a2l.framework.waypoints import EffectDirected, directed_outcome_task
from a2l.parallel import Executor

if TYPE_CHECKING:
    from a2l.skills.compile import PolicyTable

__all__ = ["MOVEMENT_PHASES", "FirstAcquisition", "acquire", "extend", "generate_skill",
           "import_learning_ahead", "phase_seed", "run_framework"]



def _import_learning() -> None:
    import a2l.skills.pipeline  # noqa: F401 - loads pgmpy


def import_learning_ahead(executor: Executor) -> threading.Thread | None:
    """Import the skill-learning pipeline :func:`generate_skill` needs
    (:mod:`a2l.skills.pipeline`, pgmpy: seconds) in a background thread when the rollouts
    run elsewhere (worker processes, Dask): the main process only waits for them during the
    first acquisition, and the first skill then finds the module loaded. In this process
    (one worker) the import would only slow the rollouts down: it stays where it is, at the
    first skill. Returns the thread (None when none was started)."""
    if executor.in_process:
        return None
    thread = threading.Thread(target=_import_learning, name="a2l-import-learning",
                              daemon=True)
    thread.start()
    return thread


def phase_seed(cfg: FrameworkConfig, iteration: int, phase: int, index: int) -> int:
    """The seed of draw `index` of `phase` (0: acquisition, 1: extension, 2 + j: the j-th
    stuck pair) in iteration `iteration` of the run configured by `cfg` (its ``seed``)."""
    ss = np.random.SeedSequence([cfg.seed, iteration, phase, index])
    return int(ss.generate_state(1, dtype=np.uint64)[0] >> 1)


def acquire(cfg: FrameworkConfig, executor: Executor, iteration: int,
            progress: Callable[[str, int, int], None] | None = None) -> Interactions:
    """Random babbling until ``n_starts · n_effects`` trajectories moved the object.

    Tries are made in batches (in parallel) and cut, in try order, at the point where the
    target count is reached (:class:`a2l.acquisition.RandomBabbling`): the result is the
    same for any number of workers. The movements are those of every try of the rounds
    told (rounds of ``max(16, 8 · workers)`` tries: the same count with 1 and 2 workers).
    """
    target = cfg.starts.n_starts * cfg.discretization.n_effects
    babbling = RandomBabbling(cfg, lambda i: phase_seed(cfg, iteration, 0, i), target,
                              cfg.babbling.try_cap)

    def report() -> None:
        if progress:
            progress("acquire", len(babbling.kept), target)

    drive_ahead([babbling], lambda pairs: executor.submit(babble_task, [c for _, c in pairs]),
                batch=max(16, 8 * executor.workers), ahead=_ahead(executor), on_round=report)
    return Interactions(babbling.kept, babbling.movements)


#: Rounds of babbling submitted to workers beyond the one waited for
#: (:func:`a2l.acquisition.protocol.drive_ahead`): the workers run them while the main
#: process collects a round and asks for the next, instead of waiting for it.
AHEAD = 1


#: Effect-directed tries asked of each stuck pair per round.
DIRECTED_BATCH = 32


def _pair_batches(executor: Executor, pairs: Sequence[tuple[Any, Any]]) -> int:
    """Batches of a round of effect-directed tries on workers: two per stuck pair in it (at
    least the executor's default), so that the part of a round in flight that belongs to a
    pair done meanwhile fills batches of its own, which are given up if not started
    (:meth:`a2l.parallel.Pending.drop`). Where a task runs changes none of its results."""
    strategies = len({id(s) for s, _ in pairs})
    return max(2 * strategies, Executor.BATCHES_PER_SLOT * executor.workers)


def _ahead(executor: Executor) -> int:
    """Rounds to submit in advance: none in this process (nothing would run meanwhile, and
    a round asked ahead may be dropped), :data:`AHEAD` on workers."""
    return 0 if executor.in_process else AHEAD


def extend(cfg: FrameworkConfig, executor: Executor, iteration: int,
           validation: Sequence[Rollout], stuck: dict[tuple[int, int], int],
           progress: Callable[[str, int, int], None] | None = None) -> Interactions:
    """New trajectories for iteration `iteration` (the dataset extension, ``docs/method.md``).

    - successful and false-positive validation trajectories (themselves, with
      ``extension.keep_validation``), and cut back 1 to ``extension.cut`` steps and
      extended with random movements (at most ``extension.max_extensions``);
    - for each (start, effect) pair failed ``directed.stuck_after`` iterations in a row, up
      to ``directed.per_pair`` effect-directed trajectories: random trajectories from that
      start (:func:`directed_task`; at most ``directed.steps`` movements), kept only when
      they produce that effect. The budget of a pair stuck for ``stuck_after + k``
      iterations is ``k + 1`` times that (trajectories and tries), at most
      ``directed.growth`` times: a pair whose failing context cells are outvoted by the
      rest of the dataset gets more votes each iteration.

    The movements are those of the extensions and of every effect-directed try told (the
    validation trajectories reused are not played again). `progress` is told
    ``("extend: stuck pairs", done, total)`` after each round of effect-directed tries.
    """
    ext, dr = cfg.extension, cfg.directed
    tasks = []
    moved = [v for v in validation if v.outcome in (SUCCESS, FALSE_POSITIVE)]
    cut_rng = np.random.default_rng(phase_seed(cfg, iteration, 1, -1 % 2**31))
    for i in range(min(ext.max_extensions, len(moved) * ext.cut)):
        r = moved[i % len(moved)]
        cut = int(cut_rng.integers(1, ext.cut + 1))
        prefix = tuple(r.moves[: max(0, len(r.moves) - cut)])
        tasks.append(BabbleTask(cfg, r.start, prefix, phase_seed(cfg, iteration, 1, i),
                                cfg.babbling.max_steps))
    out = list(moved) if ext.keep_validation else []
    extended = executor.map(babble_task, tasks)
    movements = sum(r.executed for r in extended)
    out += [r for r in extended if r.moved]
    pairs = sorted(p for p, n in stuck.items() if n >= dr.stuck_after)
    directed = []
    for j, (start, effect) in enumerate(pairs):
        grow = min(stuck[(start, effect)] - dr.stuck_after + 1, dr.growth)
        directed.append(EffectDirected(cfg, start, effect,
                                       lambda i, j=j: phase_seed(cfg, iteration, 2 + j, i),
                                       want=dr.per_pair * grow, cap=dr.try_cap * grow))

    def report() -> None:
        if progress:
            progress("extend: stuck pairs", sum(d.done for d in directed), len(directed))

    drive_ahead(directed, lambda pairs: executor.submit(
        directed_outcome_task, [c for _, c in pairs], batches=_pair_batches(executor, pairs)),
        batch=DIRECTED_BATCH, ahead=_ahead(executor), on_round=report)
    for d in directed:
        out.extend(d.found)
        movements += d.movements
    return Interactions(out, movements)


def generate_skill(cfg: FrameworkConfig, dataset: pd.DataFrame, bundle_path: Path,
                   robot: dict[str, str] | None = None) -> PolicyTable:
    """Learn the network from `dataset`, compile it, and save the skill bundle
    (:func:`a2l.skills.pipeline.learn_bundle`, with the structure, fixed edges, step cap and
    smoothing of `cfg`).

    Returns
    -------
    a2l.skills.PolicyTable
        The compiled table (the bundle holds the same numbers).

    Raises
    ------
    ValueError
        A ``learning.fixed_parents`` name that is no dataset column (the configuration
        refuses it first), or a dataset with no usable row.
    """
    # imported here: the pipeline loads pgmpy (seconds), which `a2l experiment push --help`
    # and the configuration checks do not need (with workers, run_framework has it imported
    # in the background meanwhile: import_learning_ahead)
    from a2l.skills.pipeline import learn_bundle

    disc = cfg.discretization.discretizer()
    learning, skill = cfg.learning, cfg.skill
    constraints: dict[str, Any] = {}
    if learning.structure == "hc-k2":  # the configuration checked the names
        constraints["fixed_parents"] = (([disc.effects.name] if learning.effect_parent else [])
                                        + list(learning.fixed_parents))
    learned = learn_bundle(dataset, disc, bundle_path, name="push",
                           structure=learning.structure, constraints=constraints, robot=robot,
                           step_cap=skill.step_cap, smoothing=skill.smoothing,
                           fallback=skill.fallback, clearance=skill.clearance,
                           clearance_ratio=skill.clearance_ratio, align=skill.align,
                           avoid_revisits=skill.avoid_revisits,
                           extra={"framework": cfg.to_dict()})
    return learned.table


#: A first acquisition: ``(config, executor, iteration, progress) -> interactions``.
FirstAcquisition = Callable[[FrameworkConfig, Executor, int,
                             Callable[[str, int, int], None] | None], Interactions]


def run_framework(cfg: FrameworkConfig, run_dir: Path, executor: Executor,
                  progress: Callable[[str, int, int], None] | None = None,
                  on_iteration: Callable[[IterationResult], None] | None = None,
                  robot: dict[str, str] | None = None,
                  first_acquisition: FirstAcquisition | None = None) -> FrameworkResult:
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
    first_acquisition : callable, optional
        Where iteration 0's interactions come from (default :func:`acquire`, random
        babbling around the object), with the robot movements they took; e.g. NovEB
        (:func:`a2l.framework.noveb_rollouts.noveb_acquire`).

    Returns
    -------
    FrameworkResult
        The iterations' metrics, the accepted skill, its dataset and validation, the
        held-out metrics (``cfg.heldout.n_starts`` starts, :func:`validate_heldout`: they
        decide nothing) and the robot movements per iteration and phase
        (:data:`MOVEMENT_PHASES`).
    """
    skills_dir = run_dir / "skills"
    skills_dir.mkdir(parents=True, exist_ok=True)
    st = RunState.resume(run_dir)
    if st.next_iteration < cfg.max_iterations and not st.done(cfg):
        import_learning_ahead(executor)
    for it in range(st.next_iteration, cfg.max_iterations):
        if st.done(cfg):
            break
        m = _iteration(cfg, executor, it, st, skills_dir / f"iter_{it:03d}.a2lb", robot,
                       progress, first_acquisition or acquire)
        st.save(run_dir, it)
        if on_iteration:
            on_iteration(m)
    accepted_name = (skills_dir / "accepted.txt").read_text().strip()
    last_accepted = max(h["iteration"] for h in st.history if h["accepted"])
    final = next((h for h in st.heldout if h["iteration"] == last_accepted), None)
    return FrameworkResult(
        iterations=st.history, final_score=st.best_score,
        bundle=str(skills_dir / accepted_name), dataset=st.dataset,
        validation=rollouts_table(st.best_val), heldout=st.heldout,
        heldout_score=final["heldout_score"] if final else None,
        heldout_success=final.get("heldout_success") if final else None,
        heldout_success_rate=final.get("heldout_success_rate") if final else None,
        heldout_validation=rollouts_table(st.best_held), movements=st.movement_log or [])


def _iteration(cfg: FrameworkConfig, executor: Executor, it: int, st: RunState,
               bundle: Path, robot: dict[str, str] | None,
               progress: Callable[[str, int, int], None] | None,
               first: FirstAcquisition) -> IterationResult:
    """One iteration: acquire (or extend), learn the skill `bundle`, validate it, accept it
    (:func:`_decide`), run the held-out starts; `st` updated in place."""
    t0 = time.perf_counter()
    phase_moves = dict.fromkeys(MOVEMENT_PHASES, 0)
    candidate = _candidate_dataset(cfg, executor, it, st, progress, first, phase_moves)
    generate_skill(cfg, candidate, bundle, robot)
    train = training_bundle(cfg, bundle)
    val = validate(cfg, executor, train, progress)
    phase_moves["validate"] = sum(r.executed for r in val)
    accepted, fresh = _decide(cfg, executor, it, st, train, val, progress, phase_moves)
    if accepted:
        st.dataset = candidate
        (bundle.parent / "accepted.txt").write_text(bundle.name + "\n")
    m = iteration_metrics(cfg, it, val, len(candidate), accepted, time.perf_counter() - t0,
                          fresh)
    st.history.append(asdict(m))
    if cfg.heldout.n_starts:
        t1 = time.perf_counter()
        held = validate_heldout(cfg, executor, bundle, progress)
        phase_moves["validate_heldout"] = sum(r.executed for r in held)
        st.heldout.append({**heldout_metrics(cfg, it, held),
                           "heldout_wall_s": time.perf_counter() - t1})
        if accepted:
            st.best_held = held
    if st.movement_log is not None:
        st.movement_log.append(movement_record(
            it, phase_moves, st.movement_log[-1] if st.movement_log else None))
    return m


def _candidate_dataset(cfg: FrameworkConfig, executor: Executor, it: int, st: RunState,
                       progress: Callable[[str, int, int], None] | None,
                       first: FirstAcquisition, phase_moves: dict[str, int]) -> pd.DataFrame:
    """Iteration `it`'s dataset: the first acquisition, or the accepted dataset extended
    from ``st.best_val`` and the stuck pairs; its movements counted in `phase_moves`."""
    disc = cfg.discretization.discretizer()
    if st.dataset is None:
        got = first(cfg, executor, it, progress)
        phase_moves["acquire"] = got.movements
        return interaction_rows(got.rollouts, disc)
    extra = extend(cfg, executor, it, st.best_val, st.stuck, progress)
    phase_moves["extend"] = extra.movements
    first_episode = int(st.dataset["episode"].max()) + 1 if len(st.dataset) else 0
    return pd.concat([st.dataset, interaction_rows(extra.rollouts, disc, first_episode)],
                     ignore_index=True)


def _decide(cfg: FrameworkConfig, executor: Executor, it: int, st: RunState, train: Path,
            val: list[Rollout], progress: Callable[[str, int, int], None] | None,
            phase_moves: dict[str, int]) -> tuple[bool, FreshValidation | None]:
    """Accept the candidate (training bundle `train`, its rollouts `val` from the training
    starts) or not, and set what the next extension grows from (``st.best_val``,
    ``st.stuck``).

    Either way, the stuck count of each (training start, effect) pair grows while it fails.
    ``validation.starts = "fixed"`` (the thesis): accepted when the training score did not
    drop; the extension grows from the accepted skill's training-start rollouts.
    ``"fresh"``: the candidate and the skill accepted so far also run from the iteration's
    fresh starts (:func:`validate_fresh`); accepted when its success rate over the training
    and the fresh starts is not lower (the accepted skill's training-start rollouts are its
    own iteration's); the extension grows from the accepted skill's rollouts from both, and
    each failed fresh pair gets effect-directed babbling (a fresh start is validated once).
    """
    score = score_of(val, cfg.discretization.n_effects, cfg.starts.n_starts)
    for r in val:
        key = (r.start, r.wanted)
        st.stuck[key] = 0 if r.outcome == SUCCESS else st.stuck.get(key, 0) + 1
    if not cfg.validation.fresh:
        accepted = score >= st.best_score
        if accepted:
            st.best_val, st.best_score = val, score
        return accepted, None
    bundles = [train]
    if st.dataset is not None:
        name = (train.parent / "accepted.txt").read_text().strip()
        bundles.append(training_bundle(cfg, train.parent / name))
    runs = validate_fresh(cfg, executor, it, bundles, progress)
    phase_moves["validate_fresh"] = sum(r.executed for run in runs for r in run)
    n = cfg.starts.n_starts
    best_fixed = [r for r in st.best_val if r.start < n]
    rate = success_of([*val, *runs[0]])
    before = success_of([*best_fixed, *runs[1]]) if len(runs) > 1 else None
    accepted = before is None or rate >= before
    if accepted:
        st.best_score, best_fixed = score, val
    kept = runs[0] if accepted else runs[1]
    st.best_val = [*best_fixed, *kept]
    st.best_rate = success_of(kept)
    st.stuck = {k: v for k, v in st.stuck.items() if k[0] < n}
    st.stuck.update({(r.start, r.wanted): cfg.directed.stuck_after for r in kept
                     if r.outcome != SUCCESS})
    return accepted, FreshValidation(success_of(runs[0]),
                                     success_of(runs[1]) if len(runs) > 1 else None,
                                     miss_counts(runs[0]))
