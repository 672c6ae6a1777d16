"""The C++ skill runtime from Python (a2l._core): table lookups equal the Python compiled
table on every evidence combination, bins equal the Python discretizer, and step() returns a
status (never a guess) for unknown contexts."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from a2l import Status, _core
from a2l.errors import A2LValueError
from a2l.skills import (
    Discretizer,
    HighLevelState,
    MovementRepertoire,
    compile_policy,
    learn_network,
    make_skill_spec,
    push_dataset,
    save_bundle,
)


@pytest.fixture(scope="module")
def learned(tmp_path_factory: pytest.TempPathFactory):
    """A push skill learned (hand-coded structure) with a high-level state in the table."""
    disc = Discretizer(
        movements=MovementRepertoire(planar=True),
        high_level=(HighLevelState("light", ("off", "on")),),
    )
    raw = push_dataset(600, seed=4)
    rng = np.random.default_rng(4)
    raw["light"] = np.where(rng.random(len(raw)) < 0.5, "off", "on")
    data = disc.discretize(raw)
    net = learn_network(data, "hand-coded")
    table = compile_policy(net, "move", disc.evidence)
    spec = make_skill_spec(table, disc, name="push")
    path = tmp_path_factory.mktemp("bundles") / "push.a2lb"
    save_bundle(spec, path)
    return disc, table, spec, _core.load_bundle(path)


def test_runtime_lookup_equals_the_python_table_on_every_combination(learned) -> None:
    _, table, _, skill = learned
    assert [v.name for v in skill.variables] == table.variables
    assert "light" in table.variables
    ct = skill.table
    assert tuple(ct.shape) == table.shape
    labels = skill.movements.labels
    n = 0
    for idx in itertools.product(*(range(k) for k in table.shape)):
        evidence = {v: table.states[v][i] for v, i in zip(table.variables, idx, strict=True)}
        m = ct.lookup(list(idx))
        expected = table.argmax(evidence)
        assert (None if m < 0 else labels[m]) == expected, evidence
        row = ct.posterior_row(ct.row_index(list(idx)))
        post = table.posterior(evidence)
        assert row == [post[label] for label in labels]
        n += 1
    assert n == ct.n_rows == int(np.prod(table.shape))
    assert (table.argmax_indices >= 0).any() and (table.argmax_indices < 0).any()


def test_runtime_bins_equal_the_python_discretizer(learned) -> None:
    disc, _, _, skill = learned
    rng = np.random.default_rng(0)
    obj = rng.uniform(-1, 1, (2000, 3))
    eef = obj + rng.normal(0, 0.15, (2000, 3))
    py = disc.context_bins(eef, obj)
    d = skill.discretizer
    for i in range(len(obj)):
        status, bins = d.discretize(_core.Context(eef[i], obj[i], effect=1, high_level=[0] * 5))
        assert status == Status.ok
        for axis, v in enumerate(skill.variables):
            if v.name in py:
                assert bins[axis] == py[v.name][i], (v.name, i)


def test_runtime_step_matches_the_table_and_records_a_trace(learned) -> None:
    _, table, _, skill = learned
    state = _core.SkillState(skill, trace_capacity=64)
    rng = np.random.default_rng(1)
    obj = np.array([0.7, 0.0, 0.04])
    ok = 0
    for _ in range(500):
        eef = obj + np.r_[rng.uniform(-0.25, 0.25, 2), 0.0]
        effect = ["left", "right", "close", "far"][int(rng.integers(4))]
        light = ["off", "on"][int(rng.integers(2))]
        state.reset()
        ctx = skill.context(eef, obj, effect=effect, high_level={"light": light})
        out = _core.step(skill, state, ctx)
        _, bins = skill.discretizer.discretize(ctx)
        expected = skill.table.lookup(bins)
        if expected < 0:
            assert out.status == Status.unknown_context and out.movement == -1
            continue
        ok += 1
        assert out.status == Status.ok and out.movement == expected
        row = skill.table.posterior_row(skill.table.row_index(bins))
        assert out.probability == row[expected]
        np.testing.assert_allclose(out.displacement, skill.movements.displacement(expected))
        assert np.linalg.norm(out.displacement) == pytest.approx(0.05)
        assert out.record.bins == bins and out.record.movement == expected
    assert ok > 50
    assert state.trace_size == 64 and state.trace_dropped == 500 - 64
    records = state.trace()
    assert [r.step for r in records] == [0] * 64  # reset before every step
    assert records[-1].to_dict()["status"] == records[-1].status


def test_runtime_unknown_contexts_are_statuses_not_guesses(learned) -> None:
    _, _, _, skill = learned
    state = _core.SkillState(skill)
    obj = np.array([0.7, 0.0, 0.04])
    eef = obj + [0.0, 0.09, 0.0]
    light_axis = skill.discretizer.find("light")
    effect_axis = skill.discretizer.effect_axis
    cases = [
        _core.Context([np.nan, 0, 0], obj),
        _core.Context(eef, [0.7, np.inf, 0.04]),
        _core.Context(eef, obj, effect=4),
        _core.Context(eef, obj, effect=-1),
        _core.Context(eef, obj, high_level=[2 if i == light_axis else 0 for i in range(16)]),
    ]
    for ctx in cases:
        out = _core.step(skill, state, ctx)
        assert out.status == Status.unknown_context
        assert out.movement == -1 and out.probability == 0.0
    assert state.steps == 0
    assert effect_axis == 0
    produced = skill.context(eef, obj, effect="left", effect_produced=True)
    assert _core.step(skill, state, produced).status == Status.effect_produced
    with pytest.raises(A2LValueError, match="not a value of variable 'light'"):
        skill.context(eef, obj, high_level={"light": "dim"})
    with pytest.raises(A2LValueError, match="not a value of variable 'effect'"):
        skill.context(eef, obj, effect="lift")


def test_runtime_step_cap_and_random_contexts_throw_nothing(learned) -> None:
    _, _, _, skill = learned
    state = _core.SkillState(skill)
    rng = np.random.default_rng(2)
    statuses = set()
    vals = np.array([np.nan, np.inf, -np.inf, 1e300, -1e300, 0.0])
    for i in range(20000):
        eef = rng.uniform(-0.5, 0.5, 3)
        if i % 7 == 0:
            eef[rng.integers(3)] = vals[rng.integers(len(vals))]
        ctx = _core.Context(
            eef,
            [0.0, 0.0, 0.0],
            effect=int(rng.integers(-2, 6)),
            high_level=[int(x) for x in rng.integers(-1, 3, 16)],
        )
        if state.steps >= skill.step_cap:
            assert _core.step(skill, state, ctx).status == Status.step_cap
            state.reset()
        statuses.add(_core.step(skill, state, ctx).status)
    assert {Status.ok, Status.unknown_context} <= statuses


def test_runtime_smoothing_switch(learned) -> None:
    _, _, _, skill = learned
    assert skill.smoothing is False
    state = _core.SkillState(skill)
    state.smoothing = _core.Smoothing.on
    obj = np.array([0.7, 0.0, 0.04])
    rng = np.random.default_rng(3)
    seen_ok = 0
    for _ in range(300):
        ctx = skill.context(
            obj + np.r_[rng.uniform(-0.2, 0.2, 2), 0.0],
            obj,
            effect="far",
            high_level={"light": "on"},
        )
        state.reset()
        out = _core.step(skill, state, ctx)
        if out.status == Status.ok:
            seen_ok += 1
            assert 0.0 < out.probability <= 1.0
        else:
            assert out.status == Status.unknown_context
    assert seen_ok > 0


def test_runtime_repr_and_properties(learned, tmp_path: Path) -> None:
    _, _, spec, skill = learned
    assert "push" in repr(skill)
    assert skill.effect_values == ["left", "right", "close", "far"]
    assert skill.movements.directions.shape == (8, 3)
    np.testing.assert_array_equal(skill.movements.directions, spec.directions)
    assert skill.table.posterior().flags.writeable is False
    assert skill.uniform_tolerance == spec.uniform_tolerance
    assert _core.BUNDLE_SCHEMA_VERSION == 4


def test_runtime_fallback_answers_a_cell_without_data_and_the_trace_marks_it(
        learned, tmp_path: Path) -> None:
    """A learned skill written with ``fallback="nearest"``: every cell of the table the
    dataset never reached (a uniform row) steps to its nearest informative cell of the same
    effect and light, through the bundle writer, the C++ loader and the Python runner; the
    same bundle without the fallback stops there with ``unknown_context``."""
    from dataclasses import replace

    from a2l.skills.runner import CppSkillRunner

    disc, _, spec, plain = learned
    path = tmp_path / "fallback.a2lb"
    save_bundle(replace(spec, fallback="nearest"), path)
    runner = CppSkillRunner(path)
    skill = runner.skill
    assert (skill.fallback, plain.fallback) == ("nearest", "none")
    table = skill.table
    uniform = [r for r in range(table.n_rows) if table.argmax(r) < 0]
    assert uniform, "the fixture's dataset leaves some cells without data"
    shape = [v.n_bins for v in skill.variables]
    obj = np.array([0.7, 0.0, 0.04])
    checked = 0
    for r in uniform:
        f = skill.fallback_row(r)
        assert f >= 0 and table.argmax(f) >= 0
        bins = np.unravel_index(r, shape)
        fb = np.unravel_index(f, shape)
        for axis, v in enumerate(skill.variables):   # same effect and light
            if v.name in ("effect", "light"):
                assert bins[axis] == fb[axis]
        # a context in that cell: the centre of its distance and orientation bins
        names = [v.name for v in skill.variables]
        d = 0.075 + 0.05 * bins[names.index("distance")]
        n_or = shape[names.index("orientation")]
        yaw = -np.pi + 2 * np.pi / n_or * bins[names.index("orientation")]
        eef = obj + d * np.array([np.cos(yaw), np.sin(yaw), 0.0])
        effect = int(bins[names.index("effect")])
        light = ("off", "on")[bins[names.index("light")]]
        runner.reset()
        out = runner.step(eef, obj, effect, {"light": light})
        ctx_bins = runner.trace()[-1].bins
        if list(ctx_bins) != [int(b) for b in bins]:
            continue  # the planar context cannot reach this inclination/distance cell
        assert out.ok and out.fallback
        # the fallback row's most probable movement that ends between min(d, the first
        # distance bin's edge) and max(d, the range's upper end) from the object
        dv = skill.variables[names.index("distance")]
        near, reach = dv.low + (dv.high - dv.low) / dv.n_bins, dv.high
        dirs = np.asarray(spec.directions, dtype=float)
        ends = np.linalg.norm(eef - obj + spec.step * dirs / np.linalg.norm(
            dirs, axis=1, keepdims=True), axis=1)
        allowed = (ends <= max(d, reach) + 1e-12) & (ends >= min(d, near) - 1e-12)
        post = np.asarray(table.posterior()).reshape(-1, len(dirs))[f]
        want = int(np.argmax(np.where(allowed, post, -1.0))) if allowed.any() else \
            table.argmax(f)
        assert out.movement == want
        assert runner.trace()[-1].fallback is True
        state = _core.SkillState(plain)
        ctx = plain.context(eef, obj, effect, {"light": light})
        assert _core.step(plain, state, ctx).status == Status.unknown_context
        checked += 1
    assert checked >= 1


def test_runtime_approach_fallback_heads_for_the_nearest_cell_with_data(
        tmp_path: Path) -> None:
    """A planar skill written with ``fallback="approach"``: from a cell without data the
    step takes, of the movements that end between min(d, the first distance bin's edge) and
    max(d, the range's upper end), the one ending nearest the centre of the fallback cell
    (the middle of its distance bin, at its orientation bin's middle angle), never the one
    that undoes the previous movement when another is allowed; the trace marks it."""
    from dataclasses import replace

    from a2l.skills.runner import CppSkillRunner

    # the fixture's skill without its inclination variable: effect, distance, orientation
    # and light, as the push framework's skills (its cells' centres are planar points)
    disc = Discretizer(
        movements=MovementRepertoire(planar=True), inclination=None,
        high_level=(HighLevelState("light", ("off", "on")),),
    )
    raw = push_dataset(600, seed=4)
    rng = np.random.default_rng(4)
    raw["light"] = np.where(rng.random(len(raw)) < 0.5, "off", "on")
    net = learn_network(disc.discretize(raw), "hand-coded")
    spec = make_skill_spec(compile_policy(net, "move", disc.evidence), disc, name="push")
    path = tmp_path / "approach.a2lb"
    save_bundle(replace(spec, fallback="approach"), path)
    runner = CppSkillRunner(path)
    skill = runner.skill
    assert skill.fallback == "approach"
    table = skill.table
    names = [v.name for v in skill.variables]
    assert "inclination" not in names  # a planar skill: the cells' centres are points
    shape = [v.n_bins for v in skill.variables]
    dv = skill.variables[names.index("distance")]
    n_or = shape[names.index("orientation")]
    near, reach = dv.low + (dv.high - dv.low) / dv.n_bins, dv.high
    dirs = np.asarray(spec.directions, dtype=float)
    disp = spec.step * dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    obj = np.array([0.7, 0.0, 0.04])

    def centre(bins: tuple[int, ...]) -> np.ndarray:
        d = dv.low + (bins[names.index("distance")] + 0.5) * (dv.high - dv.low) / dv.n_bins
        yaw = -np.pi + 2 * np.pi / n_or * bins[names.index("orientation")]
        return d * np.array([np.cos(yaw), np.sin(yaw), 0.0])

    checked = 0
    for r in (r for r in range(table.n_rows) if table.argmax(r) < 0):
        bins = tuple(int(b) for b in np.unravel_index(r, shape))
        target = centre(tuple(int(b) for b in np.unravel_index(skill.fallback_row(r), shape)))
        rel = centre(bins)
        effect = bins[names.index("effect")]
        light = ("off", "on")[bins[names.index("light")]]
        for previous in (None, 0):
            runner.reset()
            if previous is not None:  # one movement first, from a cell with data
                start = rel - disp[previous]
                first = runner.step(obj + start, obj, effect, {"light": light})
                if not first.ok or first.fallback or first.movement != previous:
                    continue
            out = runner.step(obj + rel, obj, effect, {"light": light})
            if list(runner.trace()[-1].bins) != list(bins):
                continue
            assert out.ok and out.fallback
            d = np.linalg.norm(rel)
            ends = np.linalg.norm(rel + disp, axis=1)
            allowed = (ends <= max(d, reach) + 1e-12) & (ends >= min(d, near) - 1e-12)
            undo = np.linalg.norm(disp + disp[previous], axis=1) < 1e-9 \
                if previous is not None else np.zeros(len(disp), bool)
            ok = allowed & ~undo if (allowed & ~undo).any() else allowed
            gap = np.linalg.norm((rel + disp - target)[:, :2], axis=1)
            assert ok[out.movement]  # the nearest to the target (equal ones: either)
            assert gap[out.movement] <= np.min(np.where(ok, gap, np.inf)) + 1e-9
            checked += 1
    assert checked >= 10
