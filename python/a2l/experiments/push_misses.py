"""Why the held-out rollouts of a push skill missed, read from their trajectories.

Each missed (start, wanted effect) rollout of the held-out validation is replayed through
the C++ step (:class:`~a2l.skills.runner.CppSkillRunner`: the same decisions, and which
steps were fallback steps) and given one cause (:data:`CAUSES`):

- ``detour contact``: a false positive where the gripper touched the box before it was on
  the side it pushes from for the wanted effect (it was going round the box);
- ``off-centre push``: a false positive where the gripper was on the pushing side, moving
  towards the box, but the box went another way (the contact was off its axis);
- ``two-cell loop``: the step cap after the gripper went back and forth between two places;
- ``wandering``: the step cap without such a loop;
- ``out of reach``: a movement the arm could not carry out (at the first step: a start at
  the rim of the arm's reach);
- ``camera-only effect``: the robot saw an effect (camera context) that did not happen;
- ``no data``: the step stopped in a cell without data (``unknown_context``, no fallback).

:func:`miss_table` gives one row per miss, :func:`misses_markdown` the report's table and
:func:`plot_misses` the figure of the missed trajectories.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l.framework.config import FrameworkConfig

__all__ = ["CAUSES", "miss_causes", "miss_table", "misses_markdown", "plot_misses",
           "run_misses_markdown"]

#: The causes a miss is given, in the report's order.
CAUSES = ("detour contact", "off-centre push", "two-cell loop", "wandering", "out of reach",
          "camera-only effect", "no data", "other")

_SIDES = {(1, 0): "+x (far)", (-1, 0): "-x (close)", (0, 1): "+y (left)",
          (0, -1): "-y (right)"}


def _side(v: np.ndarray) -> str:
    """The side of the box a planar offset `v` (shape (2,)) is on, by its dominant axis."""
    k = int(np.argmax(np.abs(v)))
    key = (int(np.sign(v[0])), 0) if k == 0 else (0, int(np.sign(v[1])))
    return _SIDES.get(key, "?")


def _fallback_steps(runner: Any, eef: np.ndarray, obj: np.ndarray, wanted: int
                    ) -> list[bool]:
    """Which of a rollout's steps were fallback steps: its contexts replayed through the
    C++ step (`eef`, `obj`: shape (n, 3), the positions before each movement)."""
    runner.reset()
    flags = []
    for k in range(len(eef)):
        out = runner.step(eef[k], obj[k], wanted)
        if not out.ok:
            break
        flags.append(bool(out.fallback))
    return flags


def _cause(row: Any, rel: np.ndarray, directions: np.ndarray, wanted_dir: np.ndarray
           ) -> tuple[str, str]:
    """(cause, detail) of one missed rollout; `rel`: eef - object before each movement and
    after the last, shape (n + 1, 2)."""
    moves = list(row.moves)
    if row.outcome == "false_positive":
        before = rel[-2] if len(rel) >= 2 else rel[-1]
        u = directions[moves[-1]][:2] if moves else np.zeros(2)
        side = before / max(np.linalg.norm(before), 1e-9)
        behind = float(side @ wanted_dir) < -0.5 and float(u @ wanted_dir) > 0.0
        return (("off-centre push" if behind else "detour contact"),
                f"last movement from the {_side(before)} side")
    if row.stop == "step_cap":
        tail = np.round(rel[-6:] / 0.01).astype(int)
        places = {tuple(p) for p in tail}
        return ("two-cell loop" if len(places) <= 2 else "wandering"), ""
    if row.stop == "unreachable":
        k = len(moves)
        return "out of reach", ("at the first movement" if k == 0 else f"after {k} movements")
    if row.stop == "moved":
        return "camera-only effect", ""
    if row.stop == "unknown_context":
        return "no data", ""
    return "other", str(row.stop)


def miss_table(cfg: FrameworkConfig, heldout: pd.DataFrame, bundle: str | Path
               ) -> pd.DataFrame:
    """One row per missed held-out rollout, with its cause.

    Parameters
    ----------
    cfg : FrameworkConfig
        The run's configuration.
    heldout : DataFrame
        The held-out rollouts (the run's ``heldout.parquet``: ``start, wanted, outcome,
        stop, moves, true_effect, eef, obj``; ``eef``/``obj`` flattened, shape (3 n,)).
    bundle : path
        The skill the rollouts ran (the fallback steps are found by replaying it).

    Returns
    -------
    DataFrame
        ``start, r, side, wanted, happened, cause, detail, steps, fallback_steps``, in
        (start, wanted) order; ``r`` is the start's distance from the box (m), ``side`` the
        box's side it is on, ``happened`` the effect the box made (``none``).
    """
    from a2l.skills.runner import CppSkillRunner

    disc = cfg.discretization.discretizer()
    names = disc.effects.values
    directions = np.asarray(disc.movements.directions, dtype=float)
    directions = directions / np.maximum(np.linalg.norm(directions, axis=1, keepdims=True),
                                         1e-12)
    runner = CppSkillRunner(str(bundle))
    from a2l.skills.effects import EFFECT_DIRECTIONS

    rows = []
    for row in heldout[heldout["outcome"] != "success"].itertuples(index=False):
        eef = np.asarray(row.eef, dtype=float).reshape(-1, 3)
        obj = np.asarray(row.obj, dtype=float).reshape(-1, 3)
        rel = (eef - obj)[:, :2]
        wanted = int(row.wanted)
        w = np.asarray(EFFECT_DIRECTIONS[names[wanted]], dtype=float)
        cause, detail = _cause(row, rel, directions, w / max(np.linalg.norm(w), 1e-12))
        flags = _fallback_steps(runner, eef[:len(row.moves)], obj[:len(row.moves)], wanted)
        true = int(row.true_effect)
        rows.append({"start": int(row.start), "r": float(np.linalg.norm(rel[0])),
                     "side": _side(rel[0]), "wanted": names[wanted],
                     "happened": names[true] if true >= 0 else "none",
                     "cause": cause, "detail": detail, "steps": len(row.moves),
                     "fallback_steps": int(sum(flags))})
    cols = ["start", "r", "side", "wanted", "happened", "cause", "detail", "steps",
            "fallback_steps"]
    return pd.DataFrame(rows, columns=cols)


def misses_markdown(table: pd.DataFrame, n_rollouts: int, figure: bool = True
                    ) -> list[str]:
    """The report's section on the held-out misses: counts per cause, then one line per
    miss (`table` from :func:`miss_table`, of `n_rollouts` held-out rollouts), and the link
    to ``heldout_misses.png`` when `figure`."""
    if table.empty:
        return ["No held-out miss.", ""]
    counts = table["cause"].value_counts()
    order = [c for c in CAUSES if c in counts.index]
    with_fb = table[table["fallback_steps"] > 0]["cause"].value_counts()
    lines = [f"## Held-out misses ({len(table)} of {n_rollouts} rollouts), from their "
             "trajectories", "",
             "| cause | misses | of them with a fallback step |", "|---|---|---|"]
    lines += [f"| {c} | {int(counts[c])} | {int(with_fb.get(c, 0))} |" for c in order]
    lines += ["", "Causes: *detour contact*, the gripper touched the box before reaching "
              "the side it pushes from for the wanted effect; *off-centre push*, it pushed "
              "from that side but the box went another way; *two-cell loop*, the step cap "
              "after going back and forth between two places; *wandering*, the step cap "
              "otherwise; *out of reach*, a movement the arm could not carry out; "
              "*camera-only effect*, the camera saw an effect that did not happen; *no "
              "data*, a cell without data and no fallback.", "",
              "| start | distance (m) | side | wanted | the box did | cause | steps | "
              "fallback steps |", "|---|---|---|---|---|---|---|---|"]
    for r in table.itertuples(index=False):
        cause = f"{r.cause} ({r.detail})" if r.detail else r.cause
        lines.append(f"| {r.start} | {r.r:.3f} | {r.side} | {r.wanted} | {r.happened} | "
                     f"{cause} | {r.steps} | {r.fallback_steps} |")
    return lines + ["", *(["![missed held-out trajectories](heldout_misses.png)", ""]
                          if figure else [])]


def miss_causes(table: pd.DataFrame) -> dict[str, int]:
    """``{cause: misses}`` of a :func:`miss_table` (``metrics.json``'s
    ``heldout_miss_causes``), most first."""
    return {str(k): int(v) for k, v in table["cause"].value_counts().items()}


def plot_misses(cfg: FrameworkConfig, heldout: pd.DataFrame, table: pd.DataFrame,
                path: Path) -> None:
    """The missed held-out trajectories over the table, one panel per wanted effect,
    coloured by cause (PNG); the start is a dot, the end a cross."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = cfg.discretization.discretizer().effects.values
    colours = dict(zip(CAUSES, plt.get_cmap("tab10").colors, strict=False))
    missed = heldout[heldout["outcome"] != "success"].reset_index(drop=True)
    n = len(names)
    cols = 4
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.4 * cols, 3.4 * rows + 0.6),
                             squeeze=False)
    used: set[str] = set()
    for e, ax in enumerate(axes.ravel()):
        if e >= n:
            ax.axis("off")
            continue
        for k, row in enumerate(missed.itertuples(index=False)):
            if int(row.wanted) != e:
                continue
            cause = str(table["cause"].iloc[k])
            used.add(cause)
            eef = np.asarray(row.eef).reshape(-1, 3)
            obj = np.asarray(row.obj).reshape(-1, 3)
            ys, xs = eef[:, 1] - obj[0, 1], eef[:, 0] - obj[0, 0]
            ax.plot(ys, xs, "-", color=colours[cause], lw=1.2, alpha=0.8)
            ax.plot(ys[0], xs[0], ".", color=colours[cause], ms=7)
            ax.plot(ys[-1], xs[-1], "x", color=colours[cause], ms=6)
        ax.add_patch(plt.Rectangle((-0.0425, -0.035), 0.085, 0.07, color="0.6"))
        ax.set(title=f"wanted {names[e]}", xlim=(0.28, -0.28), ylim=(-0.28, 0.28),
               aspect="equal")
        ax.set_xlabel("y (m, robot's left ←)")
        ax.set_ylabel("x (m, far ↑)")
    handles = [plt.Line2D([], [], color=colours[c], label=c) for c in CAUSES if c in used]
    if handles:
        fig.legend(handles=handles, loc="lower center", ncol=len(handles), frameon=False)
    fig.suptitle("Missed held-out rollouts by cause (dot: start, cross: end)")
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run_misses_markdown(run_dirs: Sequence[Path], fig_dir: Path) -> list[str]:
    """The held-out misses of push runs, run by run, for a results page: each run's misses
    section (:func:`misses_markdown`, from its ``heldout_misses.csv``) and its figure, copied
    into `fig_dir` as ``heldout_misses-<run>.png`` and linked as ``<fig_dir name>/<file>``;
    a run without the table is named as such."""
    import json
    import shutil

    lines = ["## Every held-out miss, from its trajectory", ""]
    for d in map(Path, run_dirs):
        m = json.loads((d / "metrics.json").read_text())
        lines += [f"### Run `{d.name}`: {m['scene']}, {m['n_effects']} effects, seed "
                  f"{m['seed']}", ""]
        csv = d / "heldout_misses.csv"
        if not csv.is_file():
            lines += ["No `heldout_misses.csv` (a run made before the misses were "
                      "explained).", ""]
            continue
        table = pd.read_csv(csv, keep_default_na=False)
        n = m["heldout"]["starts"] * m["n_effects"]
        section = misses_markdown(table, n, figure=False)
        if section[0].startswith("## "):  # under the run's heading: a line, not a heading
            section[0] = f"**{section[0][3:]}**"
        lines += section
        png = d / "heldout_misses.png"
        if png.is_file():
            fig_dir.mkdir(parents=True, exist_ok=True)
            dst = fig_dir / f"heldout_misses-{d.name}.png"
            shutil.copyfile(png, dst)
            lines += [f"![missed held-out trajectories, {d.name}]({fig_dir.name}/{dst.name})",
                      ""]
    return lines
