"""What a Baxter movement does does not change: a fixed set of 96 movements (16 episodes of
6, from starts around the box) gives the statuses, effects and physics step counts recorded
in tests/python/data/baxter_movements.json (see its "about")."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from a2l.sim import make_scene

REFERENCE = Path(__file__).parent / "data" / "baxter_movements.json"


def test_fixed_movements_give_the_recorded_statuses_and_effects() -> None:
    episodes = json.loads(REFERENCE.read_text())["episodes"]
    got, want = [], []
    with make_scene("push", seed=0, object_jitter=0.0, context_source="ground_truth") as scene:
        home = np.asarray(scene.ground_truth()["objects"]["box"])
        for ep in episodes:
            scene.reset(eef=home + ep["offset"], objects={"box": home[:2]})
            for k, move in enumerate(ep["moves"]):
                tick = scene._tick
                status = scene.execute(tuple(move)).status
                got.append((status, scene.observe_effect(source="ground_truth"),
                            scene._tick - tick))
                want.append((ep["status"][k], ep["effect"][k], ep["physics_steps"][k]))
    assert len(got) == 96
    assert got == want
    assert sum(effect != "none" for _, effect, _ in want) >= 20  # movements that push the box
