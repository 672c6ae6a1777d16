"""What the grasp skill's table needs: the learned grasp with one choice of
:mod:`a2l.lfd.manipulation_skills` undone at a time, on held-out trial seeds.

Variants: ``full`` (the skill as registered), ``push_default`` (the push skills' first
configuration: 5 cm moves, 3 distance bins over [0.05, 0.20] m, 16 orientations, no
smoothing; :data:`PUSH_FIRST`), ``step5`` (5 cm moves), ``dist3`` (3 distance bins over
[0.05, 0.20] m), ``no_ball`` (no context-coordinate sampling around the block), ``no_context_edges``
(hill-climbing with only ``effect -> move`` fixed), ``no_smoothing``. Prints one line per
variant: rows and the runs' stop statuses.

Usage: ``python examples/lfd_grasp_ablation.py [--trials 10] [--seed 1000]
[--variants full,push_default,...]``
"""

from __future__ import annotations

import argparse
import tempfile
from collections import Counter
from dataclasses import replace

import numpy as np

import a2l.lfd.library as library
import a2l.lfd.manipulation_skills as manip
from a2l.lfd.config import LfDConfig
from a2l.rollout.run import run_skill

#: The push skills' configuration when the manipulation skills were made (the
#: ``push_default`` row); the push default has since moved to 2 cm moves, 4 distance bins.
PUSH_FIRST = LfDConfig(smoothing=False, n_demos=8, discretization={
    "step": 0.05, "n_dist": 3, "dist_low": 0.05, "dist_high": 0.20, "n_orient": 16})

VARIANTS = ("full", "push_default", "step5", "dist3", "no_ball", "no_context_edges",
            "no_smoothing")


def run_variant(variant: str, trials: int, seed: int, out: str) -> tuple[int, Counter]:
    """Learn the grasp under `variant`, run it from seeds ``seed .. seed + trials - 1``."""
    recipe, ball, cfg = library.SKILLS["grasp"], manip._ball, None
    if variant == "push_default":
        cfg = PUSH_FIRST
    elif variant == "step5":
        cfg = manip.CONFIG.with_({"discretization.step": 0.05})
    elif variant == "dist3":
        cfg = manip.CONFIG.with_({"discretization.n_dist": 3, "discretization.dist_low": 0.05,
                                  "discretization.dist_high": 0.20})
    elif variant == "no_smoothing":
        cfg = manip.CONFIG.with_(smoothing=False)
    elif variant == "no_context_edges":
        library.SKILLS["grasp"] = replace(recipe, context_edges=False)
    elif variant == "no_ball":
        manip._ball = lambda *a, **k: np.zeros((0, 3))
    elif variant != "full":
        raise SystemExit(f"unknown variant {variant!r}; choose from {', '.join(VARIANTS)}")
    try:
        learned = library.learn_recipe("grasp", out, cfg)
        stops: Counter = Counter()
        with library.make_skill_scene("grasp", 0, cfg) as scene:
            for s in range(seed, seed + trials):
                library.reset_for_trial(scene, "grasp", s)
                stops[run_skill(scene, learned.bundle, "grasped", object_name="block").stop] += 1
        return learned.rows, stops
    finally:
        library.SKILLS["grasp"], manip._ball = recipe, ball


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=10)
    parser.add_argument("--seed", type=int, default=1000, help="first held-out trial seed")
    parser.add_argument("--variants", default=",".join(VARIANTS))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for variant in args.variants.split(","):
            rows, stops = run_variant(variant, args.trials, args.seed, f"{tmp}/{variant}")
            ok = stops.get("effect_produced", 0)
            print(f"{variant:17s} {ok}/{args.trials} grasped  rows {rows:7d}  "
                  f"stops {dict(stops)}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
