"""The discretization study: the push experiment over orientation × distance bins
(``a2l experiment discretization``)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from a2l.atomic import atomic_write_text
from a2l.experiments.push import final_validation, record_validations, run_push_experiment
from a2l.framework import FrameworkConfig
from a2l.progress import print_tables
from a2l.rundir import make_run_dir, write_json
from a2l.seeds import mark_report, seed_record

__all__ = ["run_discretization_study"]


def run_discretization_study(out: str | Path | None = None,
                             base: FrameworkConfig | None = None,
                             orientations: tuple[int, ...] = (8, 16, 24, 32),
                             distances: tuple[int, ...] = (3, 4, 5), workers: int = 1,
                             quiet: bool = False, record: str | Path | None = None
                             ) -> dict[str, Any]:
    """The authors' parametrization sweep: orientation × distance bins.

    Each combination runs the push experiment (virtual scene by default) with the same
    seed; the table reports final score, iterations and movements per action, and the
    selected default is the best score, then the fewest iterations, then the fewest
    movements. With `record`, every combination's final validation goes to one Rerun
    recording (``.rrd``), as ``a2l experiment push --record`` writes one run's, under
    ``o<orientations>-d<distances>/rollout/<i>/``.

    Returns
    -------
    dict
        ``{"rows": [...], "selected": {"n_orient", "n_dist"}}`` (also ``metrics.json``).
    """
    base = base or FrameworkConfig()
    run_dir = make_run_dir("discretization", out)
    write_json(run_dir / "config.json", {"experiment": "discretization",
                                         "framework": base.to_dict(),
                                         "orientations": list(orientations),
                                         "distances": list(distances),
                                         "seed_use": seed_record("discretization",
                                                              [base.seed])})
    rows = []
    for o in orientations:
        for d in distances:
            cfg = base.with_({"discretization.n_orient": o, "discretization.n_dist": d})
            sub = run_push_experiment(cfg, run_dir / f"o{o}-d{d}", workers=workers,
                                      quiet=True, plots=False)
            last_ok = [m for m in sub["iterations"] if m["accepted"]][-1]
            rows.append({"n_orient": o, "n_dist": d, "final_score": sub["final_score"],
                         "iterations": len(sub["iterations"]),
                         "movements_per_action": last_ok["mean_movements"]})
            if not quiet:
                print(f"orientation {o:2d} x distance {d}: score {sub['final_score']:.1f}, "
                      f"{len(sub['iterations'])} iteration(s)")
    if record is not None:
        record_validations(record, {f"o{r['n_orient']}-d{r['n_dist']}": final_validation(
            run_dir / f"o{r['n_orient']}-d{r['n_dist']}") for r in rows},
            name="a2l experiment discretization")
    best = min(rows, key=lambda r: (-r["final_score"], r["iterations"],
                                    np.nan_to_num(r["movements_per_action"], nan=1e9)))
    selected = {"n_orient": best["n_orient"], "n_dist": best["n_dist"]}
    table = ["| orientation bins | distance bins | final score | iterations | "
             "movements/action |", "|---|---|---|---|---|"]
    for r in rows:
        mark = " **(selected)**" if (r["n_orient"], r["n_dist"]) == tuple(selected.values()) \
            else ""
        table.append(f"| {r['n_orient']} | {r['n_dist']} | {r['final_score']:.1f}{mark} | "
                     f"{r['iterations']} | {r['movements_per_action']:.2f} |")
    write_json(run_dir / "metrics.json", {"rows": rows, "selected": selected})
    atomic_write_text(run_dir / "report.md", mark_report(
        "# Discretization study\n\n"
        f"Scene {base.scene}, {base.discretization.n_effects} effects, seed {base.seed}.\n\n"
        + "\n".join(table) + "\n", seed_record("discretization", [base.seed])))
    if not quiet:
        print_tables("\n".join(table))
        print(f"selected: {json.dumps(selected)}; run directory: {run_dir}")
    return {"rows": rows, "selected": selected, "run_dir": str(run_dir)}
