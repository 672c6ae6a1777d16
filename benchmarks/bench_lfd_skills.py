"""Demonstrated skills: dataset generation and learning time per skill (a2l.lfd.library)."""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from a2l.lfd.config import DEFAULT
from a2l.lfd.library import SKILLS, learn_recipe, skill_config

TITLE = "Demonstrated skills: dataset generation and learning time per skill"
REPEATS = 3  # learnings per skill; each figure is the median of these
PHASES = ("fit", "dataset", "learn", "compile", "save")


def run() -> str:
    learn_recipe(next(iter(SKILLS)), tempfile.mkdtemp())  # imports (pgmpy) out of the timing
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in SKILLS:
            runs: dict[str, list[float]] = {k: [] for k in (*PHASES, "total", "cpu")}
            for _ in range(REPEATS):
                t0, c0 = time.perf_counter(), time.process_time()
                learned = learn_recipe(name, Path(tmp))
                runs["total"].append(time.perf_counter() - t0)
                runs["cpu"].append(time.process_time() - c0)
                for k in PHASES:
                    runs[k].append(learned.timings[k])
            med = {k: float(np.median(v)) * 1e3 for k, v in runs.items()}
            cfg = skill_config(name)
            n_demos = sum(len(b.demos) for b in SKILLS[name].behaviours(cfg, 0))
            own = "DEFAULT" if cfg == DEFAULT else (
                f"own: step {cfg.step * 100:g} cm, {cfg.discretization.n_orient} x "
                f"{cfg.discretization.n_dist} bins")
            rows.append(f"| {name} | {own} | {n_demos} | {learned.rows} | "
                        f"{int(np.prod(learned.table.shape))} | "
                        + " | ".join(f"{med[k]:.0f}" for k in PHASES)
                        + f" | {med['total']:.0f} | {med['cpu']:.0f} |")
    return "\n".join([
        "From the scripted demonstrations to the skill bundle, each skill with its own "
        "configuration (`a2l.lfd.library.skill_config`: the push skills use "
        f"`a2l.lfd.config.DEFAULT`: grid {DEFAULT.resolution * 100:g} cm, tube "
        f"{DEFAULT.tube * 100:g} cm, blend {DEFAULT.blend * 100:g} cm, step "
        f"{DEFAULT.step * 100:g} cm, {DEFAULT.discretization.n_orient} orientation x "
        f"{DEFAULT.discretization.n_dist} "
        f"distance bins, {DEFAULT.maps} maps per DS; the manipulation skills their own, finer "
        "near the object, column *configuration*): `a2l.lfd.library.learn_recipe`, "
        f"{REPEATS} times per skill, medians (ms). Phases: *fit* one DS per demonstration "
        "plus the DS of their mean; *dataset* the grid, the DS velocities, the movements and "
        "the discretizer; *learn* hill-climbing with K2 and the BDeu parameters (pgmpy); "
        "*compile* the table; *save* the bundle (validated by the C++ loader). *CPU* is this "
        "process's CPU time (on a shared machine the wall time includes waiting for a "
        "core).",
        "",
        "| skill | configuration | demonstrations | rows | table cells | fit | dataset | learn "
        "| compile | save | total | CPU |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
        *rows,
    ])
