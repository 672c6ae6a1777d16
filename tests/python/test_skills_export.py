"""make_skill_spec (the bundle content) and the synthetic push dataset."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from a2l._core import VirtualScene

from a2l.skills import (
    Discretizer,
    MovementRepertoire,
    OrientationBins,
    SkillSpec,
    compile_policy,
    learn_network,
    make_skill_spec,
    push_dataset,
)


def _learned(seed: int = 0, n: int = 800):
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    net = learn_network(disc.discretize(push_dataset(n, seed=seed)), "hc-k2")
    return disc, net


def test_push_dataset_follows_the_acquisition_protocol() -> None:
    raw = push_dataset(400, seed=5)
    again = push_dataset(400, seed=5)
    assert raw.equals(again)  # seeded
    assert raw["episode"].nunique() == 400
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    data = disc.discretize(raw)
    assert data.attrs["dropped_rows"] == 0  # every kept step has a movement and an effect
    assert set(data["effect"]) == {"left", "right", "close", "far"}
    steps = raw.groupby("episode")["step"].agg(["min", "max", "count"])
    assert (steps["min"] == 0).all() and (steps["max"] <= 6).all()
    assert (steps["count"] == steps["max"] + 1).all()
    first = raw[raw["step"] == 0]
    r = np.hypot(first["eef_x"] - first["obj_x"], first["eef_y"] - first["obj_y"])
    np.testing.assert_allclose(r, 0.2)
    # the box only moves on the last step of a trajectory: before it, it is at its start
    np.testing.assert_allclose(
        raw[["obj_x", "obj_y", "obj_z"]], np.tile([0.7, 0.0, 0.04], (len(raw), 1))
    )
    # an effect is a displacement along one axis (the push model moves the box along one)
    e = raw[["effect_dx", "effect_dy"]].to_numpy()
    assert (np.min(np.abs(e), axis=1) == 0).all() and (np.max(np.abs(e), axis=1) >= 0.01).all()
    # every trajectory replays bit for bit in the C++ virtual scene; only its last step pushes
    scene = VirtualScene()
    for _, g in list(raw.groupby("episode"))[:100]:
        eef = g[["eef_x", "eef_y", "eef_z"]].to_numpy()
        scene.reset(eef[0], g[["obj_x", "obj_y", "obj_z"]].to_numpy()[0])
        for t, d in enumerate(g[["move_dx", "move_dy", "move_dz"]].to_numpy()):
            np.testing.assert_array_equal(scene.eef_position, eef[t])
            assert scene.move(d) == (t == len(g) - 1)
        moved = np.asarray(scene.object_position) - [0.7, 0.0, 0.04]
        np.testing.assert_array_equal(moved, g[["effect_dx", "effect_dy", "effect_dz"]].iloc[0])


def test_make_skill_spec() -> None:
    disc, net = _learned()
    table = compile_policy(net, "move", disc.evidence)
    spec = make_skill_spec(table, disc, name="push", step_cap=20, extra={"seed": 0})
    assert isinstance(spec, SkillSpec)
    assert [v.name for v in spec.variables] == table.variables
    assert all(v.kind == v.name for v in spec.variables)  # default names are the kinds
    for v in spec.variables:
        assert v.n_bins == table.shape[table.variables.index(v.name)]
        if v.kind == "distance":
            assert (v.low, v.high) == (0.05, 0.20)
        if v.kind == "effect":
            assert v.values == ("left", "right", "close", "far")
    assert spec.posterior.dtype == np.float64 and spec.posterior.flags.c_contiguous
    assert spec.argmax.dtype == np.int32 and spec.argmax.shape == spec.posterior.shape[:-1]
    assert spec.posterior.shape[-1] == len(spec.labels) == len(spec.directions) == 8
    for label, d in zip(spec.labels, spec.directions, strict=True):
        assert disc.movements.labels.index(label) == disc.movements.discretize(d[None])[0]
    np.testing.assert_allclose(spec.posterior.sum(axis=-1), 1.0, atol=1e-12)
    uniform = np.all(np.abs(spec.posterior - 1 / 8) <= spec.uniform_tolerance, axis=-1)
    np.testing.assert_array_equal(spec.argmax == -1, uniform)
    assert spec.step == 0.05 and spec.step_cap == 20 and spec.robot is None
    assert spec.extra["seed"] == 0 and spec.extra["discretizer"]["move"]["planar"] is True


def test_make_skill_spec_rejects_a_mismatched_discretizer() -> None:
    disc, net = _learned(1, 300)
    table = compile_policy(net, "move", disc.evidence)
    assert "orientation" in table.variables
    renamed = dataclasses.replace(table, target_states=[f"m{i}" for i in range(8)])
    with pytest.raises(ValueError, match=r"\['m0'.*not movement labels"):
        make_skill_spec(renamed, disc, name="push")
    other = Discretizer(
        distance=None,
        orientation=None,
        inclination=None,
        movements=MovementRepertoire(planar=True),
    )
    with pytest.raises(ValueError, match="not a variable of the discretizer"):
        make_skill_spec(table, other, name="push")
    coarse = Discretizer(orientation=OrientationBins(8), movements=MovementRepertoire(planar=True))
    with pytest.raises(ValueError, match="'orientation': table states"):
        make_skill_spec(table, coarse, name="push")
    with pytest.raises(ValueError, match="not the movement variable"):
        make_skill_spec(dataclasses.replace(table, target="action"), disc, name="push")
