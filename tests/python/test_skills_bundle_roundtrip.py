"""Learned skill → bundle → C++ runtime: same bins, same table, same movements."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from a2l import _core
from a2l.errors import BundleError
from a2l.rollout.recording import step_bins
from a2l.skills import (
    Discretizer,
    DistanceBins,
    HighLevelState,
    MovementRepertoire,
    OffsetBins,
    compile_policy,
    known_structure_dataset,
    learn_network,
    load_bundle,
    make_skill_spec,
    push_dataset,
    save_bundle,
)
from a2l.skills.bundle_format import BundleView


def _contexts(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Random positions, a third of them exactly on bin boundaries of the default bins."""
    rng = np.random.default_rng(seed)
    obj = rng.uniform(-1, 1, (n, 3))
    rel = rng.normal(0, 0.15, (n, 3))
    k = n // 3
    d = 0.05 + 0.05 * rng.integers(0, 4, k)  # distance boundaries 0.05, 0.10, 0.15, 0.20
    theta = -np.pi + (rng.integers(0, 16, k) + 0.5) * 2 * np.pi / 16  # orientation boundaries
    phi = rng.integers(0, 9, k) * np.pi / 8  # inclination boundaries
    rel[:k] = d[:, None] * np.stack(
        [np.sin(phi) * np.cos(theta), np.sin(phi) * np.sin(theta), np.cos(phi)], axis=1
    )
    return obj + rel, obj


def test_cpp_bins_equal_python_bins() -> None:
    disc = Discretizer()
    eef, obj = _contexts(3000, 0)
    py = disc.context_bins(eef, obj)
    r = eef - obj
    d = np.sqrt((r * r).sum(axis=1))
    theta = np.array([math.atan2(y, x) for x, y in r[:, :2]])
    phi = np.array([math.atan2(math.sqrt(x * x + y * y), z) for x, y, z in r])
    D = _core.Discretizer
    cpp_d = [D.distance_bin(x, 0.05, 0.20, 3) for x in d]
    cpp_o = [D.orientation_bin(x, 16) for x in theta]
    cpp_i = [D.inclination_bin(x, 8) for x in phi]
    assert py["distance"].tolist() == cpp_d
    assert py["orientation"].tolist() == cpp_o
    assert py["inclination"].tolist() == cpp_i


@pytest.mark.parametrize("offsets", [False, True])
def test_learned_push_skill_round_trip(tmp_path: Path, offsets: bool) -> None:
    strips = (OffsetBins.strip("x", 0.045), OffsetBins.strip("y", 0.0525)) if offsets else ()
    disc = Discretizer(movements=MovementRepertoire(planar=True), offsets=strips)
    # the hand-coded structure keeps every context variable (the synthetic pushes do not
    # depend on the offsets, so hill-climbing would leave them out of the table)
    net = learn_network(disc.discretize(push_dataset(1500, seed=2)),
                        "hand-coded" if offsets else "hc-k2")
    table = compile_policy(net, "move", disc.evidence)
    spec = make_skill_spec(table, disc, name="push")
    path = save_bundle(spec, tmp_path / "push.a2l")
    back = load_bundle(path)
    np.testing.assert_array_equal(back.posterior, table.values)
    np.testing.assert_array_equal(back.argmax, table.argmax_indices)
    assert [v.name for v in back.variables] == table.variables
    assert back.labels == list(disc.movements.labels)
    assert [(v.kind, v.low, v.high) for v in back.variables if v.kind.startswith("offset")] == [
        (b.kind, b.low, b.high) for b in strips]

    skill = _core.load_bundle(path)
    assert skill.n_moves == 8 and skill.effect_values == list(disc.effects.values)
    np.testing.assert_array_equal(np.asarray(skill.table.argmax()), table.argmax_indices)
    eef, obj = _contexts(2000, 1)
    py_bins = disc.context_bins(eef, obj)
    rng = np.random.default_rng(3)
    effects = rng.integers(0, 4, len(eef))
    axes = {v.name: i for i, v in enumerate(skill.variables)}
    for i in range(len(eef)):
        ctx = skill.context(eef[i], obj[i], effect=int(effects[i]))
        status, bins = skill.discretizer.discretize(ctx)
        ev = {"effect": disc.effects.values[effects[i]]}
        ev.update({v: int(py_bins[v][i]) for v in table.variables if v != "effect"})
        assert [bins[axes[v]] for v in table.variables] == [
            table.index(ev)[k] for k in range(len(table.variables))
        ]
        best = table.argmax(ev)
        assert skill.table.lookup(bins) == (-1 if best is None else table.target_states.index(best))


def test_distance_edges_round_trip(tmp_path: Path) -> None:
    """A skill whose distance has explicit edges: the bundle keeps them, the C++ loader reads
    them, and the runtime's step bins every context as the Python learning side did (on
    the edges too), so it looks up the row Python compiled."""
    edges = (0.07, 0.10, 0.15)
    disc = Discretizer(distance=DistanceBins(edges=edges),
                       movements=MovementRepertoire(planar=True))
    net = learn_network(disc.discretize(push_dataset(1500, seed=2)), "hand-coded")
    table = compile_policy(net, "move", disc.evidence)
    assert "distance" in table.variables
    path = save_bundle(make_skill_spec(table, disc, name="push"), tmp_path / "push.a2l")
    back = load_bundle(path)
    (dist,) = [v for v in back.variables if v.kind == "distance"]
    assert (dist.n_bins, dist.edges, dist.low, dist.high) == (4, edges, 0.05, 0.20)
    manifest = BundleView.parse(path.read_bytes()).manifest
    (entry,) = [v for v in manifest["variables"] if v["kind"] == "distance"]
    assert entry == {"name": "distance", "kind": "distance", "n_bins": 4, "low": 0.05,
                     "high": 0.2, "edges": [0.07, 0.1, 0.15]}

    skill = _core.load_bundle(path)
    axes = {v.name: i for i, v in enumerate(skill.variables)}
    assert skill.variables[axes["distance"]].edges == list(edges)
    eef, obj = _contexts(2000, 1)
    rng = np.random.default_rng(5)
    k = 600  # exactly on an edge (d = |rx|) and just below one
    on = np.asarray(edges)[rng.integers(0, 3, k)]
    on[::2] = np.nextafter(on[::2], 0.0)
    eef[:k] = obj[:k] + np.c_[on * rng.choice([-1.0, 1.0], k), np.zeros((k, 2))]
    py_bins = disc.context_bins(eef, obj)
    assert set(py_bins["distance"].tolist()) == {0, 1, 2, 3}
    effects = rng.integers(0, 4, len(eef))
    for i in range(len(eef)):
        ctx = skill.context(eef[i], obj[i], effect=int(effects[i]))
        status, bins = skill.discretizer.discretize(ctx)
        assert bins[axes["distance"]] == py_bins["distance"][i], i
        ev = {"effect": disc.effects.values[effects[i]]}
        ev.update({v: int(py_bins[v][i]) for v in table.variables if v != "effect"})
        best = table.argmax(ev)
        assert skill.table.lookup(bins) == (-1 if best is None else table.target_states.index(best))
    # recording's bins of a loaded skill (a2l.rollout.recording.step_bins) agree too
    assert [b["distance"] for b in step_bins(skill, eef[:50], obj[:50])] == \
        py_bins["distance"][:50].tolist()


def test_a_bundle_writer_refuses_edges_off_a_distance(tmp_path: Path) -> None:
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    net = learn_network(disc.discretize(push_dataset(300, seed=2)), "hand-coded")
    spec = make_skill_spec(compile_policy(net, "move", disc.evidence), disc, name="push")
    i = [v.kind for v in spec.variables].index("orientation")
    spec.variables[i] = dataclasses.replace(spec.variables[i], edges=(1.0,))
    with pytest.raises(BundleError, match=r"variables\[\d\] \('orientation'\)\.edges: only a "
                       "distance variable may have edges"):
        save_bundle(spec, tmp_path / "x.a2l")


def test_high_level_state_round_trip(tmp_path: Path) -> None:
    disc = Discretizer(high_level=(HighLevelState("light", ("off", "on")),))
    df, _ = known_structure_dataset(
        5000, seed=4, discretizer=disc, move_parents=("effect", "light")
    )
    net = learn_network(df, "hc-k2")
    table = compile_policy(net, "move", disc.evidence)
    assert table.variables == ["effect", "light"]
    skill = _core.load_bundle(save_bundle(make_skill_spec(table, disc, name="x"), tmp_path / "x"))
    for e, effect in enumerate(disc.effects.values):
        for light in ("off", "on"):
            ctx = skill.context([0.1, 0, 0], [0, 0, 0], effect=effect, high_level={"light": light})
            _, bins = skill.discretizer.discretize(ctx)
            best = table.argmax({"effect": effect, "light": light})
            assert skill.table.lookup(bins) == table.target_states.index(best)
            assert bins == [e, ("off", "on").index(light)]
