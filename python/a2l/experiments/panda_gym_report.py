"""What ``a2l experiment panda-gym`` writes besides its metrics: the learning curve's plot
(:func:`plot_curve`), ``report.md`` (:func:`report_markdown`) and the Rerun recording of
the evaluation episodes (:func:`record_episodes`)."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from a2l.experiments.panda_gym_eval import MISS_CAUSES, Episode

__all__ = ["plot_curve", "record_episodes", "report_markdown"]


def plot_curve(metrics: Mapping[str, Any], path: str | os.PathLike[str]) -> Path:
    """The learning curve: success on the curve episodes after each iteration against the
    learning env steps so far, the final evaluation as a star, the budget as a line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curve = metrics["learning_curve"]
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.plot([p["env_steps"] for p in curve], [100 * p["success"] for p in curve], "o-",
            label=f"accepted skill, {curve[0]['episodes']} episodes per point")
    ax.plot([metrics["env_steps_learning"]], [100 * metrics["success_rate"]], "*",
            markersize=14, label=f"final skill, {metrics['eval_episodes']} episodes")
    ax.axvline(metrics["budget"], color="grey", linestyle=":", label="learning budget")
    ax.set_xlabel("learning env steps (every env.step of babbling, validation, extension)")
    ax.set_ylabel(f"success on {metrics['env_id']} (%)")
    ax.set_ylim(0, 100)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(f"a2l in {metrics['env_id']}, seed {metrics['seed']}")
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def report_markdown(metrics: Mapping[str, Any], figure: bool = True) -> str:
    """``report.md``: the result, the learning curve (table and plot), the misses by cause."""
    m = metrics
    lines = [
        f"# a2l in {m['env_id']}",
        "",
        f"Push skills learned inside `{m['env_id']}` ({m['n_effects']} effects, learning "
        f"seed {m['seed']}), judged on {m['eval_episodes']} of its own episodes (evaluation "
        f"seed {m['eval_seed']}: its reset distribution, its `is_success`, its step limit "
        "with the approach included).",
        "",
        "| success | episodes | learning env steps | budget | iteration | steps per episode "
        "(median) | steps per success (median) | learning wall (s) | evaluation wall (s) |",
        "|---|---|---|---|---|---|---|---|---|",
        f"| {m['success_rate']:.1%} | {m['eval_episodes']} | {m['env_steps_learning']:,} | "
        f"{m['budget']:,} | {m['final_iteration']} | {m['steps_per_episode']:.0f} | "
        + (f"{m['steps_per_success']:.0f}" if m["steps_per_success"] is not None else "–")
        + f" | {m['wall_s']['learning']:.0f} | {m['wall_s']['evaluation']:.0f} |",
        "",
        f"Learning rollouts start at their start positions as the environment's reset puts "
        f"its arm (`placement = {m['placement']}`): {m['resets']:,} resets and "
        f"{m['placements']:,} arm placements, which are no env steps; every `env.step` is "
        "counted.",
        "",
        "## Learning curve",
        "",
        "| iteration | learning env steps | accepted skill | success | episodes | training "
        "score | fresh-start success |",
        "|---|---|---|---|---|---|---|",
    ]
    for p in m["learning_curve"]:
        fresh = p.get("fresh_success")
        lines.append(f"| {p['iteration']} | {p['env_steps']:,} | {p['bundle']} | "
                     f"{p['success']:.0%} | {p['episodes']} | {p['score']:.1f} | "
                     + (f"{fresh:.0%}" if fresh is not None else "–") + " |")
    if figure:
        lines += ["", "![learning curve](learning_curve.png)"]
    misses = m["miss_causes"]
    lines += ["", "## Misses by cause", ""]
    if misses:
        lines += ["| cause | episodes |", "|---|---|"]
        lines += [f"| {c} | {misses[c]} |" for c in MISS_CAUSES if c in misses]
        lines += ["", "Causes, in the order they are tested: approach (the cube never "
                  "moved), off the table, skill stopped, push off the axis (a push moved the "
                  "cube more than 45° from its effect's direction), overshoot (the last push "
                  "took it past the goal), step budget (still on its way at the step limit). "
                  "Every episode: `episodes.csv`."]
    else:
        lines.append("None.")
    return "\n".join(lines) + "\n"


def record_episodes(path: str | os.PathLike[str], episodes: Sequence[Episode],
                    runs: Mapping[int, Any], bundle: str | os.PathLike[str]) -> Path:
    """The evaluation episodes as a Rerun recording (``a2l view``): per episode the
    end-effector and cube paths, the goal, the effect of each movement, the outcome."""
    from a2l.rollout.recording import RerunRecorder, record_trajectories

    rec = RerunRecorder(path, name="a2l experiment panda-gym")
    trajectories, notes, labels, others = {}, {}, {}, {}
    for ep in episodes:
        run = runs[ep.index]
        key = f"episode {ep.index}"
        trajectories[key] = (run.eef, run.obj)
        goal = np.append(run.goal, run.obj[0, 2])
        others[key] = {"goal": np.tile(goal, (len(run.obj), 1))}
        labels[key] = list(run.effects)
        notes[key] = (f"episode {ep.index} (reset seed {ep.reset_seed}): "
                      + ("success" if ep.success else f"miss, {ep.cause}")
                      + f" in {ep.steps} steps; effects {ep.effects or '-'}; skill {bundle}")
    record_trajectories(rec, trajectories, notes, object_name="object", labels=labels,
                        others=others)
    return rec.close()
