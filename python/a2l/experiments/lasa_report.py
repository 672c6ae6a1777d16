"""Table, report and figure of the LASA benchmark (:mod:`a2l.experiments.lasa`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["headline_table", "plot_lasa", "report_markdown", "results_table"]


def results_table(metrics: dict[str, Any]) -> str:
    """Markdown table: per shape a2l, DMP, linear and demo spread, then the means."""
    head = ["shape", "a2l DTW", "DMP DTW", "linear DTW", "demo spread DTW", "a2l SEA",
            "DMP SEA", "a2l vRMSE", "DMP vRMSE", "direction", "fit (ms)", "query (µs)",
            "converged (exact flow)",
            "converged (Euler)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    a2l, dmp, lin, spread = (metrics[k] for k in ("shapes", "dmp", "linear", "demo_spread"))
    for name in a2l:
        a, d = a2l[name], dmp[name]
        lines.append(
            f"| {name} | {a['dtw']:.2f} | {d['dtw']:.2f} | {lin[name]['dtw']:.2f} | "
            f"{spread[name]['dtw']:.2f} | {a['sea']:.0f} | {d['sea']:.0f} | "
            f"{a['vrmse']:.1f} | {d['vrmse']:.1f} | {a.get('direction', '–')} | "
            f"{a['fit_ms']:.0f} | {a['eval_us']:.2f} | "
            f"{a['converged']:.2%} | {a['converged_euler']:.2%} |")
    s = metrics["summary"]
    lines.append(
        f"| **mean** | **{s['a2l_dtw']:.2f}** | **{s['dmp_dtw']:.2f}** | "
        f"**{s['linear_dtw']:.2f}** | **{s['demo_spread_dtw']:.2f}** | {s['a2l_sea']:.0f} | "
        f"{s['dmp_sea']:.0f} | {s['a2l_vrmse']:.1f} | {s['dmp_vrmse']:.1f} | | "
        f"{s['fit_ms_median']:.0f} (median) | {s['eval_us_median']:.2f} (median) | "
        f"min {s['min_converged']:.2%} | min {s['min_converged_euler']:.2%} |")
    return "\n".join(lines)


def headline_table(metrics: dict[str, Any]) -> str:
    """One-row Markdown table of a run's ``metrics.json``: shapes, mean DTW of the DS, the
    DMP and the linear DS, the lowest convergence fraction over the shapes (exact flow and
    Euler) and the median C++ query time."""
    s = metrics["summary"]
    return "\n".join([
        "| shapes | DS DTW (mean) | DMP DTW | linear DTW | converged, lowest shape (exact "
        "flow) | converged, lowest shape (Euler) | C++ query (µs, median) |",
        "|---|---|---|---|---|---|---|",
        f"| {len(metrics['shapes'])} | {s['a2l_dtw']:.2f} | {s['dmp_dtw']:.2f} | "
        f"{s['linear_dtw']:.2f} | {s['min_converged']:.2%} | {s['min_converged_euler']:.2%} | "
        f"{s['eval_us_median']:.2f} |"])


def report_markdown(metrics: dict[str, Any], cfg: Any, command: str, plots: bool) -> str:
    """The run's ``report.md``."""
    s = metrics["summary"]
    return "\n".join([
        f"# LASA handwriting benchmark ({len(metrics['shapes'])} shapes)",
        "",
        f"Command: `{command}`; direction {cfg.direction}, K = {cfg.K}, "
        f"beta = {cfg.beta or 'schedule'}, "
        f"mu = {cfg.mu or 'schedule'}, regularisation = {cfg.regularisation:g}, "
        f"{cfg.n_starts} random starts per shape (seed {cfg.seed} + shape index), "
        f"{metrics['workers']} worker(s), {metrics['wall_s']:.0f} s.",
        "",
        f"- Mean DTW: a2l **{s['a2l_dtw']:.2f}**, DMP {s['dmp_dtw']:.2f}, linear "
        f"{s['linear_dtw']:.2f}, between demonstrations {s['demo_spread_dtw']:.2f}.",
        f"- Random starts converged (within {cfg.tolerance} of the target after "
        f"{cfg.horizon:g} demonstration durations, exact flow): "
        f"{'all, on every shape' if s['all_converged'] else 'not all'} "
        f"(lowest fraction {s['min_converged']:.2%}; largest round-trip error "
        f"|Phi(Phi^-1(x0)) - x0| {s['roundtrip_max']:.1e}). With explicit Euler at "
        f"{cfg.start_steps} steps: {'all' if s['all_converged_euler'] else 'not all'} "
        f"(lowest {s['min_converged_euler']:.2%}).",
        f"- Fit time: median {s['fit_ms_median']:.0f} ms wall, "
        f"{s['fit_cpu_ms_median']:.0f} ms CPU; C++ velocity query: median "
        f"{s['eval_us_median']:.2f} µs.",
        "",
        "Each DS is fitted to the time-aligned mean of the shape's 7 demonstrations; "
        "reproductions start at each demonstration's start (RK4, the demonstration's own "
        "step and duration) and are compared with that demonstration, and the numbers "
        "are means over the 7. The DS's speed gain leaves a reproduction "
        f"{cfg.arrival:.2%} of its line-space distance to the target after the "
        "demonstrations' mean duration. **DTW** is the mean point distance along the optimal DTW "
        "alignment (dtaidistance), in the data's units (mm); **SEA** the swept error area "
        "between time-aligned reproduction and demonstration (mm²); **vRMSE** the RMS "
        "velocity error (mm/s). The DMP (movement_primitives, "
        f"{cfg.dmp_weights} weights per dimension) imitates the same mean and starts from "
        "the same points, with the mean's end as goal (a DMP averaging the weights imitated "
        "from each demonstration reproduces the same trajectories); the linear DS "
        "xdot = -speed (x - target) is the floor; "
        "**demo spread** is the mean DTW between pairs of demonstrations of a shape. "
        f"Convergence: from starts uniform in the demonstrations' bounding box enlarged by "
        f"{cfg.enlarge:.0%}, the state after {cfg.horizon:g} demonstration durations. "
        "**converged** (the `converged` of `metrics.json`) takes it on the DS's exact flow, "
        "x(T) = Phi(target + (Phi^-1(x0) - target) exp(-speed T)): the DS's trajectories "
        "are the line-space system's mapped through Phi, so this is the DS's own "
        "convergence, free of integration error. **converged (Euler)** (`converged_euler`) "
        f"integrates with explicit Euler, {cfg.start_steps} steps over the same time: what a "
        "controller applying the field at that coarse step would do. Fit time is measured "
        "inside the run (other processes share the machine); BENCHMARKS.md has the "
        "dedicated measurement.",
        "",
        results_table(metrics),
        "",
        *(["![LASA: streamlines, demonstrations (grey), reproductions (red)](lasa.png)", ""]
          if plots else []),
        "Configuration: `config.json`; machine-readable results: `metrics.json`; one DS "
        "bundle per shape in `ds/`.",
    ]) + "\n"


def plot_lasa(results: list[dict[str, Any]], path: Path) -> None:
    """One panel per shape: DS streamlines, demonstrations, reproductions (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(results)
    cols = min(6, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(2.6 * cols, 2.6 * rows), squeeze=False)
    for ax, r in zip(axes.ravel(), results, strict=False):
        p = r["plot"]
        gx, gy = p["grid"]
        f = np.asarray(p["field"])
        ax.streamplot(gx, gy, f[..., 0], f[..., 1], color="0.75", density=0.8,
                      linewidth=0.5, arrowsize=0.5)
        for d in p["demos"]:
            ax.plot(d[:, 0], d[:, 1], color="0.3", lw=0.8)
        for rep in p["reps"]:
            ax.plot(rep[:, 0], rep[:, 1], color="tab:red", lw=0.8)
        ax.plot(*p["target"], "k*", ms=6)
        ax.set_title(f"{r['name']} (DTW {r['a2l']['dtw']:.2f})", fontsize=8)
        ax.set(xlim=(gx[0], gx[-1]), ylim=(gy[0], gy[-1]), aspect="equal")
        ax.tick_params(labelsize=5)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    fig.suptitle("LASA: DS streamlines (grey), demonstrations (dark), reproductions (red)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
