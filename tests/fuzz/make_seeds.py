"""Write a few small valid skill bundles as the seed corpus of tests/fuzz/fuzz_bundle.cpp.

Usage: ``python tests/fuzz/make_seeds.py DIR``
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from a2l.skills import SkillSpec, VariableSpec, save_bundle


def spec(seed: int, variables: list[VariableSpec], n_moves: int, robot: bool) -> SkillSpec:
    rng = np.random.default_rng(seed)
    shape = tuple(v.n_bins for v in variables)
    post = rng.random((*shape, n_moves)) + 0.01
    post /= post.sum(axis=-1, keepdims=True)
    uniform = rng.random(shape) < 0.3
    post[uniform] = 1.0 / n_moves
    argmax = np.where(uniform, -1, post.argmax(axis=-1)).astype(np.int32)
    dirs = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [1, 1, 0], [0, 0, -1]])
    return SkillSpec(
        name=f"seed{seed}",
        variables=variables,
        directions=dirs[:n_moves],
        posterior=post,
        argmax=argmax,
        labels=[f"m{i}" for i in range(n_moves)],
        smoothing=bool(seed % 2),
        robot={
            "name": "baxter",
            "urdf_sha256": "0" * 64,
            "base_link": "base",
            "tip_link": "right_gripper",
        }
        if robot
        else None,
    )


def main() -> None:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    eff = VariableSpec("effect", "effect", 2, values=("left", "far"))
    dist = VariableSpec("distance", "distance", 2, low=0.05, high=0.2)
    ori = VariableSpec("orientation", "orientation", 4)
    inc = VariableSpec("inclination", "inclination", 2)
    light = VariableSpec("light", "high_level", 2, values=("off", "on"))
    save_bundle(spec(0, [eff, dist, ori], 4, False), out / "seed0.a2lb")
    save_bundle(spec(1, [eff, ori, inc, light], 6, True), out / "seed1.a2lb")
    save_bundle(spec(2, [dist], 2, False), out / "seed2.a2lb")
    save_bundle(spec(3, [], 3, True), out / "seed3.a2lb")


if __name__ == "__main__":
    main()
