"""What the cameras saw right after a reset is reused when a later reset puts the world in
the same state (same frames to the bit), and only then."""

from __future__ import annotations

import numpy as np

from a2l.sim import make_scene
from a2l.sim.perception import Camera


def test_a_start_met_again_is_not_rendered_again(monkeypatch) -> None:
    renders = []
    orig = Camera.render
    monkeypatch.setattr(Camera, "render", lambda cam: renders.append(cam) or orig(cam))
    with make_scene("push", seed=0, object_jitter=0.0, context_source="perceived") as s:
        home = np.asarray(s.ground_truth()["objects"]["box"])
        start = home + [0.0, 0.15, 0.0]  # beside the box: the main camera sees it whole
        s.reset(eef=start, objects={"box": home[:2]})
        first, n = s.perceive(), len(renders)
        assert n >= 1
        s.execute((0, -1, 0))
        s.perceive()
        assert len(renders) > n  # after a movement: rendered
        n = len(renders)
        s.reset(eef=start, objects={"box": home[:2]})  # its snapshot perceives
        assert s.perceive() == first
        assert len(renders) == n  # the same start: nothing rendered
        fresh = s._look()  # what a render gives now: the same, to the bit
        assert {n: v.position for n, v in fresh[0].items()} == first["objects"]
        n = len(renders)
        s.reset(eef=start, objects={"box": home[:2] + [0.02, 0.0]})
        moved = s.perceive()
        assert len(renders) > n  # another state: rendered
        assert moved["objects"]["box"][0] > first["objects"]["box"][0] + 0.015


def test_the_lamp_state_is_part_of_the_start() -> None:
    with make_scene("press", seed=0, object_jitter=0.0, context_source="perceived") as s:
        s.reset()
        assert s.perceive()["states"]["light"] == "off"
        s.reset()
        s.perturb("toggle", state="light")  # lit, then reset: the light goes back off
        s.reset()
        assert s.perceive()["states"]["light"] == "off"
        key_off = s._world_key()
        s.perturb("toggle", state="light")
        assert s._world_key() != key_off
