"""Write a few small valid bundles as the seed corpus of tests/fuzz/fuzz_bundle.cpp.

Skill bundles (one with movement actions, one with DS phases), DS-only bundles (d = 2 and
d = 3; one of direction ``"to_line"``) and a skill with a DS (the ``ds`` section).

Usage: ``python tests/fuzz/make_seeds.py DIR``
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from a2l.atomic import atomic_write_bytes
from a2l.skills import SkillSpec, VariableSpec, save_bundle
from a2l.skills.bundle import bundle_bytes
from a2l.skills.ds_bundle import DSArrays, save_ds_bundle
from a2l.skills.phases import DSPhase

_BOUND = float(np.sqrt(np.e / 2.0))


def spec(
    seed: int,
    variables: list[VariableSpec],
    n_moves: int,
    robot: bool,
    actions: tuple[str, ...] = (),
) -> SkillSpec:
    rng = np.random.default_rng(seed)
    shape = tuple(v.n_bins for v in variables)
    n_dirs, n_moves = n_moves, n_moves + len(actions)
    post = rng.random((*shape, n_moves)) + 0.01
    post /= post.sum(axis=-1, keepdims=True)
    uniform = rng.random(shape) < 0.3
    post[uniform] = 1.0 / n_moves
    argmax = np.where(uniform, -1, post.argmax(axis=-1)).astype(np.int32)
    dirs = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [1, 1, 0], [0, 0, -1]])
    return SkillSpec(
        name=f"seed{seed}",
        variables=variables,
        directions=dirs[:n_dirs],
        posterior=post,
        argmax=argmax,
        labels=[f"m{i}" for i in range(n_dirs)],
        actions=list(actions),
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


def ds(seed: int, d: int, k: int, direction: str = "to_demo") -> DSArrays:
    """K random maps in [-1, 1]^d with rho * ||v|| in [0.2, 0.9] * sqrt(e/2)."""
    rng = np.random.default_rng(seed)
    vectors = 0.3 * rng.uniform(-1.0, 1.0, (k, d))
    mu = rng.uniform(0.2, 0.9, k)
    return DSArrays(
        target=0.1 * rng.uniform(-1.0, 1.0, d),
        centers=rng.uniform(-1.0, 1.0, (k, d)),
        vectors=vectors,
        rhos=mu * _BOUND / np.linalg.norm(vectors, axis=1),
        speed=1.0 + seed,
        direction=direction,
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
    save_ds_bundle(out / "seed4.a2lb", ds(4, 2, 6), name="ds2")
    save_ds_bundle(out / "seed5.a2lb", ds(5, 3, 4), name="ds3", metadata={"K": 4})
    save_ds_bundle(out / "seed6.a2lb", ds(6, 2, 0), name="linear")
    save_ds_bundle(out / "seed10.a2lb", ds(10, 2, 5, "to_line"), name="ds2_to_line")
    atomic_write_bytes(out / "seed7.a2lb", bundle_bytes(spec(7, [dist], 2, False), ds=ds(7, 3, 3)))
    gripper = VariableSpec("gripper", "high_level", 2, values=("open", "closed"))
    actions = ("open", "close", "stay")
    save_bundle(spec(8, [eff, dist, light, gripper], 6, False, actions), out / "seed8.a2lb")
    phases = [
        DSPhase("approach", ds(9, 3, 3), {"light": "off", "gripper": "open"}, "close", 0.01),
        DSPhase("lift", ds(10, 3, 0), {"gripper": "closed"}, None, 0.02),
        DSPhase("any", ds(11, 3, 2, "to_line")),
    ]
    save_bundle(spec(9, [eff, light], 6, True, actions), out / "seed9.a2lb", ds_phases=phases)


if __name__ == "__main__":
    main()
