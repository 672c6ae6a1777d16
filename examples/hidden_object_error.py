"""Perception error while the hand hides the object, with and without tracking.

A grasp's approach, as the camera sees it: for each of N trial seeds the object is placed as
the grasp skill's trial places it and seen with the hand away, then the open hand is put
over it (up to 3 cm off its centre, seeded) at 12, 6 and 1 cm above its centre, and the
perceived position is compared with PyBullet's truth: from the visible part of the top face
alone (``track_hidden`` off), and from the footprint followed (on, the default;
``a2l.sim.tracking``). Prints the error per height and writes a figure.

Usage: ``python examples/hidden_object_error.py [--robot panda] [--skill grasp] [--n 40]
[--seed 3000] [--out FILE.png]``
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from a2l.lfd.library import make_skill_scene, reset_for_trial  # noqa: E402

#: Heights of the hand over the object's centre (m).
HEIGHTS = (0.12, 0.06, 0.01)


def errors(robot: str, skill: str, n: int, seed: int, track: bool) -> np.ndarray:
    """Errors (n, len(HEIGHTS)) in mm; NaN where the object was not located."""
    out = np.full((n, len(HEIGHTS)), np.nan)
    rng = np.random.default_rng(seed)
    with make_skill_scene(skill, 0, robot=robot, context_source="perceived") as scene:
        scene.config = replace(scene.config, track_hidden=track)
        name = next(iter(scene.ground_truth()["objects"]))
        for i in range(n):
            obj = reset_for_trial(scene, skill, seed + i)["object"]
            scene.perceive()
            off = np.append(rng.uniform(-0.03, 0.03, 2), 0.0)
            for k, h in enumerate(HEIGHTS):
                scene.place_arm(obj + off + [0.0, 0.0, h])
                seen = scene.perceive()["objects"].get(name)
                if seen is not None:
                    truth = scene.ground_truth()["objects"][name]
                    out[i, k] = 1000 * float(np.linalg.norm(np.subtract(seen, truth)))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--skill", default="grasp")
    parser.add_argument("--n", type=int, default=40, help="trial seeds")
    parser.add_argument("--seed", type=int, default=3000, help="first trial seed")
    parser.add_argument("--out", default=None, help="figure (PNG)")
    args = parser.parse_args()
    runs = {track: errors(args.robot, args.skill, args.n, args.seed, track)
            for track in (False, True)}
    print(f"{args.robot}, {args.skill}: error (mm) of {args.n} placements, hand over the "
          "object")
    print("| tracking | height (cm) | located | median | p90 | max | > 5 mm |")
    print("|---|---|---|---|---|---|---|")
    for track, e in runs.items():
        for k, h in enumerate(HEIGHTS):
            col = e[:, k][~np.isnan(e[:, k])]
            print(f"| {'on' if track else 'off'} | {100 * h:g} | {col.size}/{args.n} | "
                  f"{np.median(col):.1f} | {np.percentile(col, 90):.1f} | {col.max():.1f} | "
                  f"{int((col > 5).sum())} |")
    if args.out:
        fig, ax = plt.subplots(figsize=(7, 3.6))
        for j, (track, e) in enumerate(runs.items()):
            cols = [e[:, k][~np.isnan(e[:, k])] for k in range(len(HEIGHTS))]
            pos = np.arange(len(HEIGHTS)) * 3 + j
            ax.boxplot(cols, positions=pos, widths=0.8, patch_artist=True,
                       boxprops={"facecolor": "tab:green" if track else "tab:red"})
        ax.set_xticks(np.arange(len(HEIGHTS)) * 3 + 0.5,
                      [f"{100 * h:g} cm" for h in HEIGHTS])
        ax.set_xlabel("hand above the object's centre")
        ax.set_ylabel("||perceived - true|| (mm)")
        ax.set_title(f"{args.robot}, {args.skill} object: visible part (red) / tracked (green)")
        fig.tight_layout()
        fig.savefig(args.out, dpi=100)
        print(f"figure: {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
