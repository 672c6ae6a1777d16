"""The push experiment's run directory presentation: the iterations' table, the plots
(score, validation trajectories, inferred policy) and ``report.md``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from a2l.framework import FrameworkConfig, FrameworkResult
from a2l.rollout.env import LEGACY_SCENES, ROBOT_SCENES

__all__ = [
    "context_label",
    "context_source",
    "headline_table",
    "plot_policy",
    "plot_scores",
    "plot_trajectories",
    "movements_table",
    "report_markdown",
    "results_table",
    "with_heldout",
]


def with_heldout(history: list[dict[str, Any]], *records: list[dict[str, Any]]
                 ) -> list[dict[str, Any]]:
    """The iterations' metrics with each one's other records merged in, as ``metrics.json``
    holds them: the held-out metrics (``heldout_score``, ``heldout_success_rate``, ...)
    and the robot movements (``robot_movements`` per phase, ``robot_movements_total``,
    ``robot_movements_training``), each a list of dicts with an ``iteration`` key
    (:func:`a2l.framework.run_framework`'s ``heldout`` and ``movements``)."""
    out = [dict(m) for m in history]
    for rec in records:
        by_it = {h["iteration"]: h for h in rec}
        for m in out:
            m.update({k: v for k, v in by_it.get(m["iteration"], {}).items()
                      if k != "iteration"})
    return out


def _pct(x: float | None) -> str:
    return "—" if x is None or np.isnan(x) else f"{x:.0%}"


def results_table(history: list[dict[str, Any]]) -> str:
    """Markdown table of the iterations' metrics, led by the success rate (a false positive
    is a failure): from the held-out starts overall and per effect when the iterations have
    them (else per effect from the training starts), then from the training starts, then
    the score (``docs/method.md``), the held-out score, and the robot movements made so far
    when they were counted."""
    if not history:
        return "(no iteration)"
    held = all("heldout_score" in m for m in history)
    held_rate = held and all("heldout_success" in m for m in history)
    rates = "heldout_success_rate" if held else "success_rate"
    effects = list(history[0][rates])
    moves = all("robot_movements_total" in m for m in history)
    fresh = any(m.get("fresh_success") is not None for m in history)
    head = ["iteration", *(["held-out success"] if held_rate else []),
            *(f"{'held-out ' if held else ''}{e}" for e in effects),
            *(["held-out false positives"] if held else []),
            *(["success (fresh starts)", "accepted skill there"] if fresh else []),
            "success (training starts)", "score", *(["held-out score"] if held else []),
            "false positives", "movements/action", "dataset rows", "accepted",
            *(["movements"] if moves else []), "wall (s)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for m in history:
        cells = [str(m["iteration"]),
                 *([f"**{_pct(m['heldout_success'])}**"] if held_rate else []),
                 *(_pct(m[rates][e]) for e in effects),
                 *([str(m["heldout_false_positives"])] if held else []),
                 *([_pct(m.get("fresh_success")), _pct(m.get("fresh_accepted_success"))]
                   if fresh else []),
                 _pct(m.get("success")), f"{m['score']:.1f}",
                 *([f"{m['heldout_score']:.1f}"] if held else []),
                 str(m["false_positives"]),
                 "—" if np.isnan(m["mean_movements"]) else f"{m['mean_movements']:.1f}",
                 str(m["dataset_size"]), "yes" if m["accepted"] else "no",
                 *([f"{m['robot_movements_total']:,}"] if moves else []),
                 f"{m['wall_s']:.1f}"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _overall(rates: dict[str, float] | None) -> str:
    """The success rate over every effect (equal starts per effect: the mean), as %."""
    if not rates:
        return "—"
    return f"{100 * float(np.mean(list(rates.values()))):.1f} %"


def headline_table(runs: list[dict[str, Any]]) -> str:
    """Markdown table, one row per run (``metrics.json`` of each): scene, effects, seed,
    iterations run, final score and success rate (the last accepted iteration's), held-out
    score and success rate (from the held-out starts), robot movements to the end, and the
    held-out misses by cause (``heldout_miss_causes``, :mod:`a2l.experiments.push_misses`;
    "—" for a run without them)."""
    head = ["scene", "effects", "seed", "iterations run", "final score", "success rate",
            "held-out score", "held-out success rate", "robot movements",
            "held-out misses by cause"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for m in runs:
        its = m["iterations"]
        last = ([i for i in its if i["accepted"]] or its)[-1]
        held = m.get("heldout_score")
        moves = its[-1].get("robot_movements_total")
        lines.append("| " + " | ".join([
            _scene(m), str(m["n_effects"]), str(m["seed"]), str(len(its)),
            f"{m['final_score']:.1f}", _overall(last.get("success_rate")),
            "—" if held is None else f"{held:.1f}", _overall(last.get("heldout_success_rate")),
            "—" if moves is None else f"{moves:,}", _causes(m.get("heldout_miss_causes"))])
            + " |")
    return "\n".join(lines)


def _robot_lines(cfg: FrameworkConfig) -> list[str]:
    """The report's lines on the robot of a PyBullet run: where its scene stands, and the
    scale when its arm reaches less than the thesis' scene needs."""
    if cfg.scene not in ROBOT_SCENES:
        return []
    from a2l.robot import robot_entry, table_layout

    lay = table_layout(robot_entry(cfg.robot))
    line = (f"Robot: {lay.robot}; the box at ({lay.work_point[0]:.3f}, "
            f"{lay.work_point[1]:.3f}) m in its base frame, {lay.radius:.2f} m of reachable "
            "table around it")
    if lay.scale < 1:
        line += (f"; the scene is scaled by {lay.scale:.2f} to its reach (the box, the "
                 f"movement ({cfg.discretization.step:.3f} m), the start rings, the bins)")
    return [line + ".", ""]


def _scene(m: dict[str, Any]) -> str:
    """The scene of a run's metrics, with its robot when the scene takes one (``bullet``):
    an earlier run's scene name (:data:`a2l.rollout.env.LEGACY_SCENES`) as the scene and
    robot it names now, so that its row reads as a run of today's."""
    scene, robot = LEGACY_SCENES.get(m["scene"], (m["scene"], m.get("robot")))
    return f"{scene} ({robot})" if scene in ROBOT_SCENES and robot else str(scene)


def _causes(causes: dict[str, int] | None) -> str:
    """``{cause: n}`` as ``n cause, ...`` (most first), "—" when not recorded."""
    if causes is None:
        return "—"
    if not causes:
        return "none"
    return ", ".join(f"{n} {c}" for c, n in sorted(causes.items(), key=lambda kv: -kv[1]))


def movements_table(history: list[dict[str, Any]]) -> list[str]:
    """Lines of the report's table of robot movements per iteration and phase (none when
    they were not counted: a run resumed from a checkpoint older than the count)."""
    from a2l.framework.loop import MOVEMENT_PHASES

    if not history or not all("robot_movements" in m for m in history):
        return []
    last = history[-1]
    # the fresh starts' column only for a run that validated from them
    phases = [p for p in MOVEMENT_PHASES if p != "validate_fresh"
              or any(m["robot_movements"].get(p) for m in history)]
    lines = [
        f"Robot movements: **{last['robot_movements_total']:,}** discrete movements in all "
        f"({last['robot_movements_training']:,} for training, the rest from the held-out "
        "starts, which only measure); every movement the scene executed, those of the "
        "trajectories thrown away included (`metrics.json`: `robot_movements` per phase, "
        "`robot_movements_total` and `robot_movements_training` cumulative).",
        "",
        "| iteration | " + " | ".join(f"`{p}`" for p in phases)
        + " | total so far | training so far |",
        "|" + "---|" * (len(phases) + 3),
    ]
    for m in history:
        cells = [f"{m['robot_movements'].get(p, 0):,}" for p in phases]
        lines.append(f"| {m['iteration']} | " + " | ".join(cells)
                     + f" | {m['robot_movements_total']:,} | "
                     f"{m['robot_movements_training']:,} |")
    return [*lines, ""]


def plot_scores(history: list[dict[str, Any]], path: Path) -> None:
    """Per iteration (PNG): the training score (the thesis' figure, 8 training starts), and
    the success rates (%) from the held-out starts, which only measure, and from the
    iteration's fresh validation starts, which decide acceptance (when the run has them);
    an open marker is an iteration whose skill was not accepted."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    it = [m["iteration"] for m in history]
    fig, ax = plt.subplots(figsize=(5.6, 3.4))
    ax.plot(it, [m["score"] for m in history], "o-", label="score (training starts)")
    series = [("heldout_success", "s-", "success, held-out starts"),
              ("fresh_success", "^:", "success, fresh validation starts")]
    for key, style, label in series:
        if all(m.get(key) is not None for m in history):
            ax.plot(it, [100 * m[key] for m in history], style, label=label)
    rejected = [m["iteration"] for m in history if not m["accepted"]]
    if rejected:
        ax.plot(rejected, [next(h["score"] for h in history if h["iteration"] == i)
                           for i in rejected], "o", mfc="white", color="C0",
                label="not accepted")
    ax.set(xlabel="iteration", ylabel="score / success (%)", ylim=(0, 105),
           title="A2L push: per iteration")
    ax.set_xticks(it)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_trajectories(cfg: FrameworkConfig, validation: Any, path: Path,
                      title: str = "Validation trajectories") -> None:
    """Validation trajectories over the table, one panel per effect (PNG).

    Successful ones are solid, false positives dashed, fails dotted; the box at the start
    is grey.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = cfg.discretization.discretizer().effects.values
    n = len(names)
    cols = 4
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    style = {"success": ("-", 1.0), "false_positive": ("--", 0.6), "fail": (":", 0.4)}
    for e, ax in enumerate(axes.ravel()):
        if e >= n:
            ax.axis("off")
            continue
        sel = validation[validation["wanted"] == e]
        ok = int((sel["outcome"] == "success").sum())
        for row in sel.itertuples(index=False):
            eef = np.asarray(row.eef).reshape(-1, 3)
            obj = np.asarray(row.obj).reshape(-1, 3)
            ls, alpha = style.get(row.outcome, (":", 0.4))
            ax.plot(eef[:, 1] - obj[0, 1], eef[:, 0] - obj[0, 0], ls, alpha=alpha, lw=1.2)
            ax.plot(eef[0, 1] - obj[0, 1], eef[0, 0] - obj[0, 0], "k.", ms=4)
        ax.add_patch(plt.Rectangle((-0.0425, -0.035), 0.085, 0.07, color="0.6"))
        ax.set(title=f"{names[e]}: {ok}/{len(sel)}", xlim=(0.28, -0.28), ylim=(-0.28, 0.28),
               aspect="equal")
        ax.set_xlabel("y (m, robot's left ←)")
        ax.set_ylabel("x (m, far ↑)")
    fig.suptitle(f"{title} (solid: success, dashed: false positive, dotted: fail)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_policy(cfg: FrameworkConfig, bundle: Path, path: Path) -> None:
    """The movement the skill infers over the table, per effect (PNG).

    On a grid of end-effector positions around the object, the C++ step (the one the
    robot runs) gives the movement; arrows show it, colour its probability.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from a2l.skills.runner import CppSkillRunner

    disc = cfg.discretization.discretizer()
    runner = CppSkillRunner(str(bundle))
    names = disc.effects.values
    g = np.linspace(-0.24, 0.24, 13)
    cols = 4
    rows = (len(names) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    for e, ax in enumerate(axes.ravel()):
        if e >= len(names):
            ax.axis("off")
            continue
        xs, ys, us, vs, ps = [], [], [], [], []
        for x in g:
            for y in g:
                if abs(x) < 0.04 and abs(y) < 0.045:
                    continue
                runner.reset()
                out = runner.step(np.array([x, y, 0.0]), np.zeros(3), e)
                if not out.ok:
                    continue
                d = disc.movements.displacement(out.movement)
                xs.append(y)
                ys.append(x)
                us.append(d[1])
                vs.append(d[0])
                ps.append(out.probability)
        q = ax.quiver(xs, ys, us, vs, ps, cmap="viridis", clim=(0, 1), scale=1.0,
                      scale_units="xy", angles="xy", width=0.006)
        ax.add_patch(plt.Rectangle((-0.0425, -0.035), 0.085, 0.07, color="0.6"))
        ax.set(title=names[e], xlim=(0.27, -0.27), ylim=(-0.27, 0.27), aspect="equal")
    fig.colorbar(q, ax=axes.ravel().tolist(), shrink=0.7, label="P(movement)")
    fig.suptitle("Inferred movement over the discretized context (object at the centre)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def context_source(cfg: FrameworkConfig) -> str:
    """Where the run's rollouts read the object from: ``"perceived"`` (the camera) or
    ``"ground_truth"`` (a ``source`` in the scene settings overrides ``context_source``)."""
    return str(dict(cfg.scene_config).get("source") or dict(cfg.scene_config).get(
        "context_source") or cfg.context_source)


def context_label(cfg: FrameworkConfig) -> str:
    """Where the run's rollouts read the object from, as the report names it."""
    src = context_source(cfg)
    if cfg.scene == "virtual":
        return f"{src} (the virtual scene has no camera: its true state)"
    return "camera (perceived)" if src == "perceived" else "ground truth (the simulator's)"


def report_markdown(cfg: FrameworkConfig, result: FrameworkResult, run_dir: Path,
                    history: list[dict[str, Any]], miss_lines: list[str] | None = None) -> str:
    """The run directory's ``report.md``: final and held-out scores, the iterations' table,
    the robot movements per phase, the plots and, when given, the held-out misses' section
    (`miss_lines`, :func:`a2l.experiments.push_misses.misses_markdown`)."""
    held = result.heldout_score
    final = next((m for m in history if m["iteration"] == _accepted_iteration(history)), {})
    rate = final.get("heldout_success")
    per_effect = ", ".join(f"{e} {_pct(v)}"
                           for e, v in final.get("heldout_success_rate", {}).items())
    misses = final.get("heldout_misses")
    heldout_lines = [] if held is None else [
        *([f"Success rate of the final skill from the held-out starts: **{_pct(rate)}** "
           f"({per_effect}; a false positive is a failure)"
           + (f"; misses: {_misses_text(misses)}" if misses else "") + ". "]
          if rate is not None else []),
        f"Held-out score: **{held:.1f}**, from {cfg.heldout.n_starts} "
        f"start positions no phase of training used (uniform angle, distance "
        f"{cfg.heldout.r_low:.2f}-{cfg.heldout.r_high:.2f} m from the object, their own "
        f"seed stream); the score above is from the {cfg.starts.n_starts} training starts "
        "the skill was validated and extended from "
        + (f"(at {cfg.starts.r_low:.2f}-{cfg.starts.r_high:.2f} m)."
           if cfg.starts.layout == "ring" else f"(on the {cfg.starts.radius:.2f} m circle)."),
        "",
    ]
    return "\n".join([
        f"# A2L push experiment ({cfg.scene} scene, {cfg.discretization.n_effects} effects, "
        f"seed {cfg.seed})",
        "",
        f"Context: {context_label(cfg)}.",
        "",
        *_robot_lines(cfg),
        f"Final score: **{result.final_score:.1f}** after {len(result.iterations)} "
        f"iteration(s); final skill `{Path(result.bundle).relative_to(run_dir)}` "
        "(copied to `skills/push.a2lb`).",
        "",
        *heldout_lines,
        results_table(history),
        "",
        *movements_table(history),
        "![score per iteration](score.png)",
        "",
        "![validation trajectories](trajectories.png)",
        "",
        *(["![held-out trajectories](heldout_trajectories.png)", ""]
          if held is not None else []),
        "![inferred movement](policy.png)",
        "",
        *(miss_lines or []),
        "Configuration: `config.json`; machine-readable results: `metrics.json`.",
    ]) + "\n"


def _accepted_iteration(history: list[dict[str, Any]]) -> int | None:
    """The last accepted iteration (the final skill's), or None."""
    acc = [m["iteration"] for m in history if m.get("accepted")]
    return acc[-1] if acc else None


def _misses_text(misses: dict[str, int]) -> str:
    """``heldout_misses`` in words: ``3 false positives, 2 unknown_context, ...``."""
    names = {"false_positive": "false positives", "with_fallback": "with a fallback step"}
    return ", ".join(f"{n} {names.get(k, k)}" for k, n in misses.items())
