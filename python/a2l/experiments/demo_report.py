"""The demo's numbers as a table: what ``a2l demo`` wrote to its run directory's
``demo.json`` (:data:`a2l.experiments.demo.SUMMARY_FILE`), one row per part."""

from __future__ import annotations

from typing import Any

__all__ = ["summary_table"]


def _pct(v: float | None) -> str:
    return "—" if v is None else f"{100 * v:.1f} %"


def _world(p: dict[str, Any]) -> str:
    seen = p.get("seen_cm")
    return (f"box pushed {p['moved_cm']:.1f} cm in {p['moves']} movements"
            + (f" (the camera saw {seen:.1f} cm)" if seen is not None else ""))


def _experiment(p: dict[str, Any]) -> str:
    scores = " → ".join(f"{s:.1f}" for s in p["scores"])
    return (f"score per iteration {scores}; success {_pct(p.get('success'))} on the training "
            f"starts, {_pct(p.get('heldout_success'))} from held-out starts")


def _runtime(p: dict[str, Any]) -> str:
    return (f"{p['success']} of {p['episodes']} episodes from random starts; step() "
            f"{p['step_p50_us']:.2f} µs, control tick {p['tick_p50_us']:.2f} µs (medians)")


def _lfd(p: dict[str, Any]) -> str:
    x, y = p["produced_cm"]
    return (f"{p['skill']}: {p['stop']} after {p['movements']} movements, box moved "
            f"{x:+.1f} cm in x, {y:+.1f} cm in y, with the box moved and the light switched")


def _task(p: dict[str, Any]) -> str:
    fault = ", ".join(p["faults"]) or "none applied"
    return (f"{p['task']}: {'goal reached' if p['success'] else 'goal missed'} in "
            f"{p['skills']} steps, {p['replans']} replan(s); fault {fault}")


#: Each part's name in the table and how its numbers read.
PARTS = {"world": ("1. Baxter pushes a box (C++ IK)", _world),
         "experiment": ("2. push experiment (Baxter, 4 effects)", _experiment),
         "runtime": ("3. a2l-run (C++ runtime)", _runtime),
         "lfd": ("4. demonstrated push, perturbed", _lfd),
         "task": ("5. planned task with a fault", _task)}


def summary_table(summary: dict[str, Any]) -> str:
    """The demo's parts as a Markdown table (part, outcome, wall time), and a total row.

    Parameters
    ----------
    summary : dict
        The contents of ``demo.json``.

    Returns
    -------
    str
        The table; a part that did not run (an earlier one failed) is absent, a failed one
        says so with its exit code.
    """
    rows = ["| part | what it printed | wall (s) |", "|---|---|---|"]
    for key, (label, fmt) in PARTS.items():
        p = summary["parts"].get(key)
        if p is None:
            continue
        text = fmt(p) if p["rc"] == 0 else f"FAILED (exit code {p['rc']})"
        rows.append(f"| {label} | {text} | {p['wall_s']:.0f} |")
    rows.append(f"| whole demo (seed {summary['seed']}, {summary['workers']} workers) | "
                f"{sum(p['rc'] == 0 for p in summary['parts'].values())} of {len(PARTS)} parts "
                f"passed | {summary['wall_s']:.0f} |")
    return "\n".join(rows)
