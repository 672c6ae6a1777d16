"""Metrics, figure and report of ``a2l experiment tasks`` (:mod:`a2l.experiments.tasks`)."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l.atomic import atomic_write_bytes, atomic_write_text
from a2l.seeds import mark_report

__all__ = ["results_table", "summarise", "write_report"]


def _rate(rows: pd.DataFrame) -> float | None:
    return float(rows["success"].mean()) if len(rows) else None


def _median(values: pd.Series) -> float | None:
    v = values.dropna()
    return float(np.median(v)) if len(v) else None


def summarise(frame: pd.DataFrame) -> dict[str, dict[str, Any]]:
    """Per task: success rates without and with faults, replans, timings, failures.

    Parameters
    ----------
    frame : pandas.DataFrame, shape (n_trials, n_columns)
        The rows of :func:`a2l.experiments.tasks.trial_task`.

    Returns
    -------
    dict
        ``task -> {success_rate, success_rate_with_faults (over the trials whose fault was
        applied), mean_replans (with faults applied), mean_replans_without_faults,
        replans_without_faults (their sum), trials_replanned_without_faults,
        faults_not_applied (fault trials whose fault could not be applied: counted apart,
        in no success rate but success_rate_fault_not_applied), not_applied: [{seed, why,
        success}], plan_ms (median of the first plan of each trial),
        plan_ms_total (median per trial, replans included), transit_ms (median per
        transit), wall_s (mean per trial), mean_skills, trials, trials_with_faults,
        failures: [{seed, fault, unmet, last_skill, message, stops}]}``; a rate is None
        when its condition was not run.
    """
    out: dict[str, dict[str, Any]] = {}
    for task, rows in frame.groupby("task", sort=False):
        clean = rows[~rows["fault"]]
        applied = rows["fault"] & rows["fault_applied"].astype(bool)
        faulty, not_applied = rows[applied], rows[rows["fault"] & ~applied]
        per_transit = rows["transit_ms"] / rows["transits"].where(rows["transits"] > 0)
        fails = rows[~rows["success"]]
        out[str(task)] = {
            "success_rate": _rate(clean), "success_rate_with_faults": _rate(faulty),
            "mean_replans": float(faulty["replans"].mean()) if len(faulty) else None,
            "mean_replans_without_faults": float(clean["replans"].mean()) if len(clean)
            else None,
            "replans_without_faults": int(clean["replans"].sum()),
            "trials_replanned_without_faults": int((clean["replans"] > 0).sum()),
            "faults_not_applied": int(len(not_applied)),
            "success_rate_fault_not_applied": _rate(not_applied),
            "plan_ms": _median(rows["plan_ms_first"]),
            "plan_ms_total": _median(rows["plan_ms"]),
            "transit_ms": _median(per_transit),
            "wall_s": float(rows["wall_s"].mean()),
            "mean_skills": float(rows["skills_run"].mean()),
            "plan_lengths": sorted({int(n) for n in rows["plan_len"]}),
            "trials": int(len(clean)), "trials_with_faults": int(len(faulty)),
            "failures": [{"seed": int(r.seed), "fault": bool(r.fault), "unmet": r.unmet,
                          "last_skill": r.last_skill, "message": r.message, "stops": r.stops}
                         for r in fails.itertuples()],
            "not_applied": [{"seed": int(r.seed), "why": r.fault_not_applied,
                             "success": bool(r.success)} for r in not_applied.itertuples()],
        }
    return out


def _pct(v: float | None) -> str:
    return "-" if v is None else f"{100 * v:.0f} %"


def results_table(tasks: dict[str, dict[str, Any]]) -> str:
    """The Markdown table of :func:`summarise`'s result."""
    lines = ["| task | skills | success | replans without fault | success with fault | "
             "replans with fault | fault not applied | plan ms | transit ms | s/trial |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name, m in tasks.items():
        lens = "/".join(str(n) for n in m["plan_lengths"])
        replans = "-" if m["mean_replans"] is None else f"{m['mean_replans']:.2f}"
        plan = "-" if m["plan_ms"] is None else f"{m['plan_ms']:.0f}"
        transit = "-" if m["transit_ms"] is None else f"{m['transit_ms']:.0f}"
        clean = (f"{m['replans_without_faults']} in {m['trials']}" if m["trials"] else "-")
        lines.append(f"| {name} | {lens} | {_pct(m['success_rate'])} ({m['trials']}) | "
                     f"{clean} | "
                     f"{_pct(m['success_rate_with_faults'])} ({m['trials_with_faults']}) | "
                     f"{replans} | {m['faults_not_applied']} | {plan} | {transit} | "
                     f"{m['wall_s']:.1f} |")
    return "\n".join(lines)


def plot(path: Path, frame: pd.DataFrame, tasks: dict[str, dict[str, Any]]) -> None:
    """``tasks.png``: success per task and condition, replans, planning and transit times."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(tasks)
    x = np.arange(len(names))
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    for i, (key, label) in enumerate((("success_rate", "without fault"),
                                      ("success_rate_with_faults", "with fault"))):
        vals = [100 * (tasks[n][key] or 0.0) for n in names]
        ax[0].bar(x + (i - 0.5) * 0.38, vals, 0.38, label=label)
    ax[0].axhline(90, color="k", lw=0.8, ls="--")
    ax[0].axhline(80, color="grey", lw=0.8, ls=":")
    ax[0].set_xticks(x, names, rotation=12, fontsize=8)
    ax[0].set_ylabel("success (%)")
    ax[0].set_ylim(0, 105)
    ax[0].legend(fontsize=8, loc="lower left")
    ax[0].set_title("task success (targets 90 % / 80 %)")
    applied = frame["fault"] & frame["fault_applied"].astype(bool)
    for i, fault in enumerate((False, True)):
        cond = applied if fault else ~frame["fault"]
        counts = [frame[(frame["task"] == n) & cond]["replans"] for n in names]
        ax[1].bar(x + (i - 0.5) * 0.38, [c.mean() if len(c) else 0.0 for c in counts], 0.38,
                  label="with fault" if fault else "without fault")
    ax[1].set_xticks(x, names, rotation=12, fontsize=8)
    ax[1].set_ylabel("mean replans per trial")
    ax[1].legend(fontsize=8)
    ax[1].set_title("replanning")
    per_transit = frame["transit_ms"] / frame["transits"].where(frame["transits"] > 0)
    data = [frame.loc[frame["task"] == n, "plan_ms_first"].dropna() for n in names]
    data += [per_transit[frame["task"] == n].dropna() for n in names]
    ax[2].boxplot([d.to_numpy() for d in data], showfliers=True)
    ax[2].set_xticks(np.arange(1, len(data) + 1),
                     [f"plan\n{n[:10]}" for n in names] + [f"transit\n{n[:10]}" for n in names],
                     fontsize=7)
    ax[2].set_ylabel("ms")
    ax[2].set_yscale("log")
    ax[2].set_title("planner call (first plan) / OMPL transit")
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    plt.close(fig)
    atomic_write_bytes(path, buf.getvalue())


def write_report(run_dir: Path, metrics: dict[str, Any], config: dict[str, Any],
                 frame: pd.DataFrame, plots: bool = True) -> str:
    """Write ``report.md`` (and ``tasks.png``); return the results table."""
    tasks = metrics["tasks"]
    table = results_table(tasks)
    if plots:
        plot(run_dir / "tasks.png", frame, tasks)
    s0, s1 = config["trial_seeds"]
    spec = "\n".join(f"- `{n}`: {c['description']}; block starts in {c['start_region']}, "
                     f"gripper {c['gripper']}, light {c['light'] or 'drawn'}; fault: "
                     f"{c['fault']}" for n, c in config["tasks"].items())
    fails = []
    for name, m in tasks.items():
        for f in m["failures"]:
            fails.append(f"- {name} seed {f['seed']}{' (fault)' if f['fault'] else ''}: "
                         f"unmet {f['unmet'] or '-'}; last {f['last_skill'] or '-'}; "
                         f"{f['message'] or ''} [{f['stops']}]")
    skipped = [f"- {name} seed {f['seed']}: {f['why']} (task "
               f"{'reached' if f['success'] else 'not reached'})"
               for name, m in tasks.items() for f in m["not_applied"]]
    text = "\n".join([
        "# Planned tasks with the learned skills", "",
        "Context: " + ("ground truth (the simulator's)"
                       if config.get("context_source") == "ground_truth"
                       else "camera (perceived)") + ".", "",
        f"Command: `{config['command']}`; {metrics['wall_s']:.0f} s with "
        f"{metrics['workers']} worker(s) (skills learned in {metrics['learn_s']:.0f} s).", "",
        f"Trial seeds {s0}-{s1} (held out), planner {config['planner']}; the block starts "
        f"within ± {100 * config['jitter_m']:.0f} cm of its region's centre.", "", spec, "",
        "Skills = plan length of the first plan; replans without fault = replans summed "
        "over the fault-free trials, in that many trials; success with fault = over the "
        "trials whose fault was applied; fault not applied = fault trials whose fault could "
        "not be applied (below); plan ms = the first planner call, median; transit ms = OMPL "
        "planning per transit, median; replans counted in the success.", "", table, "",
        *(["![tasks](tasks.png)", ""] if plots else []),
        "## Failures", "", *(fails or ["none"]), "",
        "## Faults not applied", "",
        "A fault follows only a step that carried out as planned and must leave the world "
        "disagreeing with the plan; a fault trial where it could not be applied is in no "
        "success rate above.", "", *(skipped or ["none"]), ""])
    atomic_write_text(run_dir / "report.md", mark_report(text, config["seed_use"]))
    return table
