"""Table, report and figure of the LASA benchmark (:mod:`a2l.experiments.lasa`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["headline_table", "plot_lasa", "report_markdown", "results_table", "tuning_table"]


def results_table(metrics: dict[str, Any]) -> str:
    """Markdown table: per shape (tuning shapes marked †) the DS and the DMP under both
    protocols, the linear floor, the demonstrations' spread, the direction and fit errors,
    the query time and the integrated convergence; then the means over the reported
    (non-tuning) shapes and over all."""
    head = ["shape", "DS DTW (all)", "DMP DTW (all)", "DS DTW (held-out)",
            "DMP DTW (held-out)", "linear DTW", "demo spread", "DS SEA", "DMP SEA",
            "DS vRMSE", "DMP vRMSE", "direction (all / held-out)",
            "fit mean error (kept / other)", "fit (ms)", "query median / p99.9 (µs)",
            "converged (Euler, 1 kHz)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    a2l, dmp, lin, spread = (metrics[k] for k in ("shapes", "dmp", "linear", "demo_spread"))
    tuned = set((metrics.get("tuning") or {}).get("shapes", []))
    for name in a2l:
        a, d = a2l[name], dmp[name]
        mark = " †" if name in tuned else ""
        lines.append(
            f"| {name}{mark} | {a['dtw']:.2f} | {d['dtw']:.2f} | {a['heldout_dtw']:.2f} | "
            f"{d['heldout_dtw']:.2f} | {lin[name]['dtw']:.2f} | {spread[name]['dtw']:.2f} | "
            f"{a['sea']:.0f} | {d['sea']:.0f} | {a['vrmse']:.1f} | {d['vrmse']:.1f} | "
            f"{a['direction']} / {a['heldout_direction']} | "
            f"{a['fit_mean_error']:.2f} / {a['other_direction_mean_error']:.2f} | "
            f"{a['fit_ms']:.0f} | {a['eval_us']:.2f} / {a['eval_p999_us']:.1f} | "
            f"{a['converged']:.2%} |")
    for key, label in (("summary", "reported"), ("summary_all", "all")):
        s = metrics[key]
        if not s["n_shapes"]:
            continue
        lines.append(
            f"| **mean, {label} ({s['n_shapes']})** | **{s['a2l_dtw']:.2f}** | "
            f"**{s['dmp_dtw']:.2f}** | **{s['a2l_heldout_dtw']:.2f}** | "
            f"**{s['dmp_heldout_dtw']:.2f}** | {s['linear_dtw']:.2f} | "
            f"{s['demo_spread_dtw']:.2f} | {s['a2l_sea']:.0f} | {s['dmp_sea']:.0f} | "
            f"{s['a2l_vrmse']:.1f} | {s['dmp_vrmse']:.1f} | "
            f"{s['directions']['to_line']} to_line, {s['directions']['to_demo']} to_demo | | "
            f"{s['fit_ms_median']:.0f} (median) | {s['eval_us_median']:.2f} (median) / "
            f"{s['eval_p999_us_max']:.1f} (max) | min {s['min_converged']:.2%} |")
    return "\n".join(lines)


def tuning_table(tuning: dict[str, Any]) -> str:
    """Markdown: every candidate setting of each method and its mean held-out DTW on the
    tuning shapes, the kept one in bold."""
    from a2l.experiments.lasa_tuning import DMP_CANDIDATES, DS_CANDIDATES

    lines = ["| method | setting | mean held-out DTW (tuning shapes) |", "|---|---|---|"]
    for method, cands, key in (("DS", DS_CANDIDATES, "ds_dtw"),
                               ("DMP", DMP_CANDIDATES, "dmp_dtw")):
        best = int(np.argmin(tuning[key]))
        for i, (c, v) in enumerate(zip(cands, tuning[key], strict=True)):
            text = ", ".join(f"{k} {'schedule' if x is None else x}" for k, x in c.items())
            cell = f"**{v:.3f}** (kept)" if i == best else f"{v:.3f}"
            lines.append(f"| {method} | {text} | {cell} |")
    return "\n".join(lines)


def headline_table(metrics: dict[str, Any]) -> str:
    """One-row Markdown table of a run's ``metrics.json``: the reported (non-tuning) shapes'
    mean DTW of the DS and the tuned DMP under the held-out and the all-demonstrations
    protocols, the linear DS, the lowest integrated convergence fraction over all shapes and
    the median C++ query time at points in the demonstrations' bounding boxes."""
    s, a = metrics["summary"], metrics["summary_all"]
    tuned = len((metrics.get("tuning") or {}).get("shapes", []))
    return "\n".join([
        "| shapes reported (tuning) | DS DTW, held-out | DMP DTW, held-out (tuned) | "
        "DS DTW, all demos | DMP DTW, all demos | linear DTW | converged, lowest shape "
        "(Euler at 1 kHz, 1 % of scale) | C++ query (µs, median) |",
        "|---|---|---|---|---|---|---|---|",
        f"| {s['n_shapes']} ({tuned}) | {s['a2l_heldout_dtw']:.2f} | "
        f"{s['dmp_heldout_dtw']:.2f} | {s['a2l_dtw']:.2f} | {s['dmp_dtw']:.2f} | "
        f"{s['linear_dtw']:.2f} | {a['min_converged']:.2%} | {a['eval_us_median']:.2f} |"])


def report_markdown(metrics: dict[str, Any], cfg: Any, command: str, plots: bool) -> str:
    """The run's ``report.md``."""
    s = metrics["summary"]
    tuning = metrics.get("tuning")
    return "\n".join([
        f"# LASA handwriting benchmark ({len(metrics['shapes'])} shapes)",
        "",
        f"Command: `{command}`; direction {cfg.direction}, K = {cfg.K}, "
        f"beta = {cfg.beta or 'schedule'}, mu = {cfg.mu or 'schedule'}, "
        f"regularisation = {cfg.regularisation:g}, arrival {cfg.arrival:g}; DMP "
        f"{cfg.dmp_weights} weights per dimension, regularisation {cfg.dmp_regularisation:g}; "
        f"{cfg.n_starts} random starts per shape (seed {cfg.seed} + shape index), "
        f"{metrics['workers']} worker(s), {metrics['wall_s']:.0f} s.",
        "",
        *([f"Settings chosen on the tuning shapes {', '.join(tuning['shapes'])} (†, drawn "
           f"with seed {tuning['seed']}) by the mean held-out DTW, the same number of "
           "candidates for both methods:", "", tuning_table(tuning), ""] if tuning else
          ["No tuning (`--tune false`): the settings given.", ""]),
        f"- Mean over the {s['n_shapes']} reported shapes, held-out protocol (learn from "
        f"demonstrations 1-4, DTW on 5-7): DS **{s['a2l_heldout_dtw']:.2f}**, DMP "
        f"{s['dmp_heldout_dtw']:.2f} (the DS better on {s['heldout_wins']} of "
        f"{s['n_shapes']}); all demonstrations: DS **{s['a2l_dtw']:.2f}**, DMP "
        f"{s['dmp_dtw']:.2f}, linear {s['linear_dtw']:.2f}, between demonstrations "
        f"{s['demo_spread_dtw']:.2f}.",
        f"- Converged (explicit Euler at {cfg.control_dt * 1e3:g} ms, within "
        f"{cfg.tolerance:.0%} of the demonstrations' scale within {cfg.horizon:g} "
        f"durations): {'every start, on every shape' if s['all_converged'] else 'not all'} "
        f"(lowest fraction {s['min_converged']:.2%}).",
        f"- Fit time: median {s['fit_ms_median']:.0f} ms wall, "
        f"{s['fit_cpu_ms_median']:.0f} ms CPU; C++ velocity query at points in each "
        f"demonstration's bounding box: median {s['eval_us_median']:.2f} µs, largest p99.9 "
        f"{s['eval_p999_us_max']:.1f} µs (timed inside the run, other processes sharing "
        "the machine).",
        "",
        "DTW is the mean point distance along the optimal DTW alignment (dtaidistance), in "
        "the data's units (mm); SEA the swept error area between time-aligned reproduction "
        "and demonstration (mm²); vRMSE the RMS velocity error (mm/s); both for the "
        "all-demonstrations protocol. Each method learns the time-aligned mean of its "
        "training demonstrations and reproduces every scored demonstration from its start "
        "(DS: RK4 with the demonstration's own step) over its duration; the DMP "
        "(movement_primitives) gets the mean's end as goal. Direction: `auto` fits both "
        "and keeps the smaller mean fit error (both shown). Convergence: starts uniform in "
        f"the demonstrations' bounding box enlarged by {cfg.enlarge:.0%}, integrated by "
        "explicit Euler at the runtime's control period, converged when within the "
        "tolerance of the target (the runtime's test).",
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
