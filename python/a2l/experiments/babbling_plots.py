"""Plots and tables of the babbling experiment: end-effector positions visited over the table
(objects drawn), moved share and distinct outcomes against evaluations, means and spreads."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from a2l.experiments.babbling_world import WorldConfig, object_homes
from a2l.sim import make_config

__all__ = ["plot_progress", "plot_visits", "summary_table"]

def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_visits(paths: dict[str, list[np.ndarray]], world: WorldConfig, path: Path) -> None:
    """End-effector positions visited over the table, one panel per method (PNG).

    `paths` maps a method to its end-effector paths (each of shape (m, 3)); the boxes are
    drawn at their start positions.
    """
    plt = _plt()
    from matplotlib.colors import LogNorm

    sim = make_config("push", robot=world.robot)
    boxes = object_homes(world, sim)
    box = sim.box_size  # every box's footprint (x, y) (m): the push scene's box
    fig, axes = plt.subplots(1, len(paths), figsize=(max(5.0, 3.6 * len(paths)), 3.0),
                             squeeze=False)
    for ax, (method, ps) in zip(axes[0], paths.items(), strict=True):
        pts = np.vstack(ps) if ps else np.zeros((0, 3))
        ax.hist2d(pts[:, 1], pts[:, 0], bins=(32, 24),
                  range=((world.low[1] - 0.05, world.high[1] + 0.05),
                         (world.low[0] - 0.05, world.high[0] + 0.05)), cmap="Blues", norm=LogNorm())
        for _name, (x, y) in boxes.items():
            ax.add_patch(plt.Rectangle((y - box[1] / 2, x - box[0] / 2), box[1], box[0],
                                       color="tab:purple", alpha=0.8))
        ax.plot(world.start[1], world.start[0], "k^", ms=6)
        ax.set(title=f"{method} ({len(ps)} trajectories)", xlabel="y (m, robot's left ←)",
               ylabel="x (m, far ↑)", aspect="equal")
        ax.invert_xaxis()
    fig.suptitle(f"End-effector positions visited, {world.scene} (boxes: purple; start: ▲; "
                 "log colour scale)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_progress(runs: dict[str, list[dict[str, Any]]], path: Path) -> None:
    """Moved share (so far) and distinct outcomes against evaluations (PNG): per method,
    the mean over its runs (its seeds) and their range."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.4))
    for method, ms in runs.items():
        n = min(len(m["generations"]) for m in ms)
        x = np.array([g["evaluations"] for g in ms[0]["generations"][:n]])
        for ax, key in zip(axes, ("moved_share_so_far", "distinct_outcomes"), strict=True):
            y = np.array([[g[key] for g in m["generations"][:n]] for m in ms], dtype=float)
            line = ax.plot(x, y.mean(axis=0), label=f"{method} ({len(ms)} seed(s))")[0]
            ax.fill_between(x, y.min(axis=0), y.max(axis=0), color=line.get_color(),
                            alpha=0.2)
    axes[0].set(xlabel="evaluations", ylabel="share that moved an object (so far)", ylim=(0, 1))
    axes[1].set(xlabel="evaluations", ylabel="distinct outcomes")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary_table(runs: dict[str, list[dict[str, Any]]]) -> str:
    """Markdown table: per method, mean ± standard deviation over seeds (and min-max)."""
    lines = ["| method | seeds | evaluations | moved share | distinct outcomes | "
             "archive | evaluations/s |", "|---|---|---|---|---|---|---|"]
    for method, ms in runs.items():
        t = [m["totals"] for m in ms]

        def stat(key: str, pct: bool = False, t: list[dict[str, Any]] = t) -> str:
            v = np.array([x[key] for x in t if x.get(key) is not None], dtype=float)
            if len(v) == 0:
                return "—"
            f = (lambda a: f"{100 * a:.1f} %") if pct else (lambda a: f"{a:.1f}")
            return f"{f(v.mean())} ± {f(v.std())} ({f(v.min())}–{f(v.max())})"

        lines.append(f"| {method} | {len(ms)} | {t[0]['evaluations']} | "
                     f"{stat('moved_share', True)} | {stat('distinct_outcomes')} | "
                     f"{stat('archive_size')} | {stat('evaluations_per_s')} |")
    return "\n".join(lines)
