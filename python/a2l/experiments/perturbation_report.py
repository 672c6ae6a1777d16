"""Metrics, table, report and trajectory plots of ``a2l experiment perturbations``
(:mod:`a2l.experiments.perturbations`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l.atomic import atomic_write_text
from a2l.seeds import mark_report

__all__ = ["SIGNIFICANCE", "condition_table", "results_table", "summarise", "target",
           "write_report"]

#: p-value of Fisher's exact test below which context and DS are marked as different.
SIGNIFICANCE = 0.05
_MODE_KEY = {"table": "context", "ds": "ds"}


def target(skill: str, condition: str) -> float:
    """The demonstrated skills' success target: grasps 80 %, others 95 % unperturbed and 90 %
    perturbed."""
    if "grasp" in skill:
        return 0.80
    return 0.95 if condition == "none" else 0.90


def _fisher(a: pd.DataFrame, b: pd.DataFrame) -> float:
    from scipy.stats import fisher_exact

    ka, kb = int(a.success.sum()), int(b.success.sum())
    return float(fisher_exact([[ka, len(a) - ka], [kb, len(b) - kb]])[1])


def _span(values: pd.Series) -> list[float] | None:
    v = values.dropna()
    return None if v.empty else [float(v.min()), float(v.max())]


def summarise(trials: pd.DataFrame) -> dict[str, dict[str, dict[str, Any]]]:
    """``skill -> condition -> {context, ds, mean_steps, ...}`` from ``trials.csv`` rows.

    Per condition: success rates (``context``: the table, ``ds``: the DS alone), mean
    movements of the context skill (``mean_steps``) and of the DS (``mean_steps_ds``),
    counts, Fisher's exact p-value between the two modes and whether it is below
    :data:`SIGNIFICANCE` (``differ``), stop statuses and failed seeds per mode, trials in
    which the perturbation was applied, and what was measured of the perturbation itself:
    displacement span (m), hold span (s, drawn; ``held_s``: carried out, shorter when the
    run ended during the hold), the arm's largest drift while held (m), light flips; for
    ``toggle_light`` the fraction of runs on the unperturbed one's path (``unchanged``)
    and, for a light-dependent skill, the fraction that did what the new state's
    demonstration did (``state_behaviour``).
    """
    out: dict[str, dict[str, dict[str, Any]]] = {}
    for (skill, cond), g in trials.groupby(["skill", "condition"], sort=False):
        by = {_MODE_KEY[m]: g[g["mode"] == m] for m in ("table", "ds")}
        c, d = by["context"], by["ds"]
        e: dict[str, Any] = {
            "context": float(c.success.mean()) if len(c) else float("nan"),
            "ds": float(d.success.mean()) if len(d) else float("nan"),
            "mean_steps": float(c.movements.mean()) if len(c) else float("nan"),
            "mean_steps_ds": float(d.movements.mean()) if len(d) else float("nan"),
            "trials": int(max(len(c), len(d))),
            "successes": {k: int(v.success.sum()) for k, v in by.items()},
            "fisher_p": _fisher(c, d) if len(c) and len(d) else float("nan"),
            "applied": {k: int(v.applied.sum()) for k, v in by.items()},
            "stops": {k: {str(s): int(n) for s, n in v.stop.value_counts().items()}
                      for k, v in by.items()},
            "failed_seeds": {k: [int(s) for s in v.seed[~v.success]] for k, v in by.items()},
            "seeds": [int(g.seed.min()), int(g.seed.max())],
            "target": target(str(skill), str(cond)),
            "prefix_identical": bool(g.prefix_identical.all()),
        }
        e["differ"] = bool(e["fisher_p"] < SIGNIFICANCE)
        applied = g[g.applied]
        if cond != "none":  # [successes, trials] among the trials actually perturbed
            e["applied_success"] = {k: [int(v.success[v.applied].sum()), int(v.applied.sum())]
                                    for k, v in by.items()}
        if cond == "move_object":
            e["displacement_m"] = _span(applied.displacement_m)
        elif cond == "hold":
            e["hold_s"] = _span(applied.hold_planned_s)
            e["held_s"] = _span(applied.hold_s)
            e["hold_drift_m"] = float(applied.hold_drift_m.max()) if len(applied) else None
            e["ended_during_hold"] = int((applied.hold_s < applied.hold_planned_s - 1e-9).sum())
        elif cond == "toggle_light":
            e["light_flipped"] = int((applied.light_before != applied.light_after).sum())
            e["unchanged"] = {k: float(v.same_as_none.mean()) if len(v) else float("nan")
                              for k, v in by.items()}
            if bool(g.light_dependent.any()):
                e["state_behaviour"] = {k: n / d if d else float("nan")
                                        for k, (n, d) in e["applied_success"].items()}
                e["state_behaviour_by_light"] = {
                    f"{k}:{light}": [int(x.success.sum()), len(x)]
                    for k, v in by.items()
                    for light, x in v[v.applied].groupby("light_after")}
                e["expected"] = sorted(set(map(str, applied.expected_effect)))
                e["target"] = 0.90
        out.setdefault(str(skill), {})[str(cond)] = e
    return out


def _pct(k: int, n: int) -> str:
    return f"{k}/{n} ({k / n:.0%})" if n else "-"


def condition_table(skills: dict[str, dict[str, dict[str, Any]]]) -> str:
    """Markdown table, one row per skill and one column per condition: the success rate of
    the context skill (table) / of the DS alone; ``†`` and ``✗`` as in
    :func:`results_table`."""
    conds = list(dict.fromkeys(c for v in skills.values() for c in v))
    lines = ["| skill (trials) | " + " | ".join(conds) + " |",
             "|---|" + "---|" * len(conds)]
    for skill, by in skills.items():
        cells = []
        n_skill = max((e["trials"] for e in by.values()), default=0)
        for cond in conds:
            e = by.get(cond)
            if e is None or not e["trials"]:
                cells.append("-")
                continue
            n = e["trials"]
            parts = [f"{e['successes'][k] / n:.0%}"
                     + (" ✗" if e["successes"][k] / n < e["target"] else "")
                     for k in ("context", "ds")]
            cells.append(" / ".join(parts) + (" †" if e["differ"] else ""))
        lines.append(f"| {skill} ({n_skill}) | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def results_table(skills: dict[str, dict[str, dict[str, Any]]]) -> str:
    """Markdown table: per skill and condition, context and DS success, Fisher p, steps.

    A ``†`` marks conditions where context and DS differ (p < :data:`SIGNIFICANCE`); a
    ``✗`` a success rate below its :func:`target`.
    """
    head = ["skill", "condition", "context (table)", "DS alone", "Fisher p", "steps ctx / DS",
            "perturbation measured"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for skill, conds in skills.items():
        for cond, e in conds.items():
            n = e["trials"]
            cells = []
            for k in ("context", "ds"):
                ok = e["successes"][k]
                miss = " ✗" if n and ok / n < e["target"] else ""
                cells.append(_pct(ok, n) + miss)
            mark = " †" if e["differ"] else ""
            cells.append(f"{e['fisher_p']:.3g}{mark}")
            cells.append(f"{e['mean_steps']:.1f} / {e['mean_steps_ds']:.1f}")
            cells.append(_measured(cond, e))
            lines.append(f"| {skill} | {cond} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _measured(cond: str, e: dict[str, Any]) -> str:
    ap = e["applied"]
    if cond == "none":
        return "-"
    txt = f"applied {ap['context']}+{ap['ds']}"
    if ap["context"] < e["trials"] or ap["ds"] < e["trials"]:
        (kc, nc), (kd, nd) = e["applied_success"]["context"], e["applied_success"]["ds"]
        txt += f" (success among them {kc}/{nc}, {kd}/{nd})"
    if cond == "move_object" and e.get("displacement_m"):
        lo, hi = e["displacement_m"]
        txt += f"; moved {lo * 100:.1f}-{hi * 100:.1f} cm"
    if cond == "hold" and e.get("hold_s"):
        lo, hi = e["hold_s"]
        txt += f"; held {lo:.1f}-{hi:.1f} s, drift ≤ {e['hold_drift_m'] * 1000:.1f} mm"
        if e["ended_during_hold"]:
            txt += f" ({e['ended_during_hold']} runs done during the hold)"
    if cond == "toggle_light":
        txt += f"; flipped {e['light_flipped']}"
        if "state_behaviour" in e:
            (kc, nc), (kd, nd) = e["applied_success"]["context"], e["applied_success"]["ds"]
            txt += (f"; did the new state's behaviour ({'/'.join(e['expected'])}): "
                    f"{kc}/{nc} / {kd}/{nd}")
        else:
            u = e["unchanged"]
            txt += f"; runs unchanged {u['context']:.0%} / {u['ds']:.0%}"
    return txt


def _misses(skills: dict[str, dict[str, dict[str, Any]]]) -> list[str]:
    out = []
    for skill, conds in skills.items():
        for cond, e in conds.items():
            for k in ("context", "ds"):
                n, ok = e["trials"], e["successes"][k]
                if n and ok / n < e["target"]:
                    stops = ", ".join(f"{s}: {c}" for s, c in e["stops"][k].items()
                                      if s != "effect_produced")
                    seeds = " ".join(map(str, e["failed_seeds"][k][:8]))
                    out.append(f"- {skill}, {cond}, {k}: {_pct(ok, n)} < {e['target']:.0%}; "
                               f"stops {stops}; failed seeds {seeds}"
                               f"{' ...' if len(e['failed_seeds'][k]) > 8 else ''} "
                               f"(plot `plots/{skill}_{cond}.png`)")
    return out


def _representative(frame: pd.DataFrame, skill: str, cond: str) -> int | None:
    """Seed of the plotted trial: the first whose context run failed, else whose DS run
    failed, else the first; among those where the perturbation was applied in both modes."""
    g = frame[(frame.skill == skill) & (frame.condition == cond)]
    if cond != "none":
        ok = g.groupby("seed").applied.all()
        g = g[g.seed.isin(ok[ok].index)]
    if g.empty:
        return None
    for mode in ("table", "ds"):
        bad = g[(g["mode"] == mode) & ~g.success]
        if len(bad):
            return int(bad.seed.min())
    return int(g.seed.min())


def plot_trial(path: Path, frame: pd.DataFrame, trajectories: dict[str, np.ndarray],
               skill: str, cond: str, seed: int) -> None:
    """Top view, distance to the object and height of both modes' runs of one trial, the
    perturbation's instant marked (★, dotted)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, dist, side) = plt.subplots(1, 3, figsize=(13, 3.8))
    title = []
    for mode, colour in (("table", "tab:blue"), ("ds", "tab:orange")):
        key = f"{skill}/{cond}/{mode}/{seed}"
        if f"{key}/eef" not in trajectories:
            continue
        eef, obj = trajectories[f"{key}/eef"], trajectories[f"{key}/obj"]
        row = frame[(frame.skill == skill) & (frame.condition == cond)
                    & (frame["mode"] == mode) & (frame.seed == seed)].iloc[0]
        label = "context" if mode == "table" else "DS"
        steps = np.arange(len(eef))
        gap = np.linalg.norm(eef - obj, axis=1)
        top.plot(eef[:, 0], eef[:, 1], "-o", ms=2.5, color=colour, label=f"{label} eef")
        top.plot(obj[:, 0], obj[:, 1], "s--", ms=2.5, color=colour, alpha=0.45,
                 label=f"{label} object")
        dist.plot(steps, gap, "-o", ms=2.5, color=colour, label=label)
        side.plot(steps, eef[:, 2], "-o", ms=2.5, color=colour, label=f"{label} eef")
        side.plot(steps, obj[:, 2], "s--", ms=2.5, color=colour, alpha=0.45,
                  label=f"{label} object")
        if cond != "none" and row.applied:
            a = int(row.after)
            top.plot(eef[a, 0], eef[a, 1], "r*", ms=13)
            for ax, y in ((dist, gap[a]), (side, eef[a, 2])):
                ax.axvline(a, color=colour, ls=":", lw=1.2)
                ax.plot(a, y, "r*", ms=13)
        title.append(f"{label}: {'success' if row.success else 'FAIL'} ({row.stop})")
    top.set(xlabel="x (m)", ylabel="y (m)", aspect="equal", title="top view (★ perturbation)")
    dist.set(xlabel="step", ylabel="|eef - object| (m)", title="distance to the object")
    side.set(xlabel="step", ylabel="z (m)", title="height")
    top.legend(fontsize=6, loc="best")
    side.legend(fontsize=6, loc="best")
    fig.suptitle(f"{skill}, {cond}, seed {seed} — " + "; ".join(title), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write_report(run_dir: Path, metrics: dict[str, Any], config: dict[str, Any],
                 frame: pd.DataFrame, trajectories: dict[str, np.ndarray],
                 plots: bool = True) -> str:
    """Write ``report.md`` (and the plots); return the table."""
    skills = metrics["skills"]
    table = results_table(skills)
    figures = []
    if plots:
        (run_dir / "plots").mkdir(exist_ok=True)
        for skill, conds in skills.items():
            for cond in conds:
                seed = _representative(frame, skill, cond)
                if seed is None:
                    continue
                name = f"plots/{skill}_{cond}.png"
                plot_trial(run_dir / name, frame, trajectories, skill, cond, seed)
                figures.append(f"![{skill}, {cond}, seed {seed}]({name})")
    s0, s1 = config["trial_seeds"]
    d0, d1 = config["demonstration_seeds"]
    misses = _misses(skills)
    text = "\n".join([
        "# Demonstrated skills under perturbations", "",
        "Context: " + ("ground truth (the simulator's)"
                       if config.get("context_source") == "ground_truth"
                       else "camera (perceived)") + ".", "",
        f"Command: `{config['command']}`; {metrics['wall_s']:.0f} s with "
        f"{metrics['workers']} worker(s).", "",
        f"Trial seeds {s0}-{s1} (held out: demonstrations used seeds {d0}-{d1}); every "
        "perturbation drawn from (seed, condition). Scenes: "
        + ", ".join(f"{k} in `{v}`" for k, v in config["scenes"].items()) + ". "
        f"Mid-action = after a movement between {config['window'][0]:.2f} and "
        f"{config['window'][1]:.2f} of the unperturbed run's movements (same seed and mode); "
        f"move_object {config['move_m'][0] * 100:.0f}-{config['move_m'][1] * 100:.0f} cm in a "
        f"random direction; hold {config['hold_s'][0]:.0f}-{config['hold_s'][1]:.0f} s; "
        "toggle_light switches the lamp.", "",
        "Context = the compiled table through the C++ step; DS = the bundle's DS alone. "
        "† = context and DS differ (Fisher's exact test, p < "
        f"{SIGNIFICANCE}); ✗ = below the issue's target (push and press: 95 % unperturbed, "
        "90 % perturbed; grasp: 80 %; light-dependent grasp under toggle_light: 90 % doing "
        "what the new light state's demonstration did).", "",
        table, "",
        "## Below target", "",
        *(misses or ["none"]), "",
        *([f"{f}\n" for f in figures]),
        "Per-trial rows: `trials.csv`; trajectories: `trajectories.npz` "
        "(`skill/condition/mode/seed/eef|obj`); metrics: `metrics.json`.",
    ]) + "\n"
    atomic_write_text(run_dir / "report.md", mark_report(text, config["seed_use"]))
    return table
