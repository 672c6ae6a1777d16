"""How often an effect-directed trajectory produces each effect, random walk vs waypoints.

From each of the framework's 8 start positions, runs `--tries` trajectories of each
``directed_mode`` (``random``: uniformly random movements; ``waypoints``: random via-points
around the object, then a random point on it) in a scene, at most ``directed_steps``
movements each, and counts the effect each produced. The pairs that stay stuck in the
iterative framework are those where the start lies on the wrong side of the box for the
effect: there, the hit rate decides how many tries a stuck pair needs. Prints the table and
writes a figure (hit rate per start and effect, both modes).

Usage: ``python examples/directed_babbling.py [--scene virtual] [--tries 1000] [--seed 0]
[--out docs/directed_babbling.png]``
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from a2l.framework import DirectedTask, FrameworkConfig, directed_task, phase_seed  # noqa: E402

MODES = ("random", "waypoints")


def hit_rates(scene: str, tries: int, seed: int) -> tuple[dict[str, np.ndarray],
                                                           dict[str, np.ndarray]]:
    """Effect shares and mean movements per try.

    Returns
    -------
    rates : dict mode -> ndarray, shape (n_starts, n_effects + 1)
        Share of tries that produced each effect; the last column: no effect.
    moves : dict mode -> ndarray, shape (n_starts,)
        Mean movements per try.
    """
    rates, moves = {}, {}
    for mode in MODES:
        cfg = FrameworkConfig(scene=scene, seed=seed, directed={"mode": mode})
        n_starts, n_effects = cfg.starts.n_starts, cfg.discretization.n_effects
        counts = np.zeros((n_starts, n_effects + 1))
        n_moves = np.zeros(n_starts)
        for s in range(n_starts):
            for i in range(tries):
                r = directed_task(DirectedTask(cfg, s, phase_seed(cfg, 0, 2 + s, i),
                                               cfg.directed.steps))
                counts[s, r.effect] += 1        # effect -1 (none) lands in the last column
                n_moves[s] += len(r.moves)
        rates[mode], moves[mode] = counts / tries, n_moves / tries
    return rates, moves


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=("virtual", "baxter"), default="virtual")
    parser.add_argument("--tries", type=int, default=1000, help="tries per start and mode")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs"
                                             / "directed_babbling.png"))
    args = parser.parse_args()
    rates, moves = hit_rates(args.scene, args.tries, args.seed)
    names = FrameworkConfig(scene=args.scene).discretization.discretizer().effects.values
    n_starts = rates[MODES[0]].shape[0]
    print(f"{args.scene} scene, {args.tries} tries per start and mode; hit rate % "
          f"(random / waypoints), movements per try")
    print("start  " + "  ".join(f"{n:>13}" for n in names) + "   movements")
    rnd, wp = rates["random"], rates["waypoints"]
    for s in range(n_starts):
        cells = "  ".join(f"{100 * rnd[s, e]:5.1f} / {100 * wp[s, e]:5.1f}"
                          for e in range(len(names)))
        print(f"{s:>5}  {cells}   {moves['random'][s]:4.1f} / {moves['waypoints'][s]:4.1f}")
    # The hardest pair of each start (its rarest effect) is what a stuck pair waits for.
    for mode in MODES:
        rarest = rates[mode][:, :-1].min(axis=1)
        print(f"{mode:>9}: rarest effect per start, mean {100 * rarest.mean():.2f} %")

    fig, axes = plt.subplots(1, len(names), figsize=(3.2 * len(names), 3.0), sharey=True)
    x = np.arange(n_starts)
    for e, ax in enumerate(np.atleast_1d(axes)):
        for k, mode in enumerate(MODES):
            ax.bar(x + (k - 0.5) * 0.4, 100 * rates[mode][:, e], width=0.4, label=mode)
        ax.set_title(names[e])
        ax.set_xlabel("start (45° apart, 0 on +x)")
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set_xticks(x)
    np.atleast_1d(axes)[0].set_ylabel("tries that produce it (%)")
    np.atleast_1d(axes)[0].legend(title="directed.mode")
    fig.suptitle(f"Effect-directed babbling, {args.scene} scene: {args.tries} tries per start "
                 f"(at most {FrameworkConfig().directed.steps} movements)")
    fig.tight_layout()
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
