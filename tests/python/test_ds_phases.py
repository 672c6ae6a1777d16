"""DS phases in a skill bundle (``ds_phases``): written by save_bundle, read back, refused
when bad (naming the phase and the field), and run by the C++ step_ds through
CppSkillRunner(mode="ds"); the table mode of the runner is the C++ step."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from a2l import A2LValueError, BundleError, _core
from a2l.lfd.ds import DiffeoDS
from a2l.skills import (
    CppSkillRunner,
    DSPhase,
    MovementRepertoire,
    SkillSpec,
    VariableSpec,
    load_ds_phases,
    save_bundle,
)

AXES = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
OBJ = np.array([0.6, -0.2, 0.1])


def _spec() -> SkillSpec:
    """effect(1) x distance(3) x light(2), 6 axis moves + open/close/stay: light off
    approaches (-x) then closes, light on moves away (+x) then stays."""
    rep = MovementRepertoire(0.05, AXES, None, ("open", "close", "stay"))
    chosen = [[rep.index_of("close"), 0], [1, 0], [1, rep.index_of("stay")]]
    post = np.full((1, 3, 2, rep.n_moves), 0.1 / (rep.n_moves - 1))
    argmax = np.zeros((1, 3, 2), dtype=np.int32)
    for d in range(3):
        for light in range(2):
            post[0, d, light, chosen[d][light]] = 0.9
            argmax[0, d, light] = chosen[d][light]
    variables = [VariableSpec("effect", "effect", 1, values=("grasped",)),
                 VariableSpec("distance", "distance", 3, low=0.05, high=0.20),
                 VariableSpec("light", "high_level", 2, values=("off", "on"))]
    return SkillSpec("grasp_light", variables, np.array(AXES), post, argmax,
                     labels=list(rep.direction_labels), actions=list(rep.actions))


def _linear(target: list[float], speed: float = 1.0) -> DiffeoDS:
    return DiffeoDS.from_maps(np.array(target), np.zeros((0, 3)), np.zeros((0, 3)),
                              np.zeros(0), speed)


def _phases() -> list[DSPhase]:
    rng = np.random.default_rng(2)
    bend = DiffeoDS.from_maps(np.array([0.0, 0.0, 0.02]),
                              np.array([0.14, 0.04, 0.10]) + 0.02 * rng.uniform(-1, 1, (3, 3)),
                              0.015 * rng.uniform(-1, 1, (3, 3)), np.full(3, 30.0))
    return [
        DSPhase("approach", bend, {"light": "off", "gripper": "open"}, "close", 0.01),
        DSPhase("lift", _linear([0.0, 0.0, 0.15]), {"gripper": "closed"}),
        DSPhase("retreat", _linear([0.15, 0.0, 0.0], 2.0), {"light": "on"}),
    ]


@pytest.fixture
def bundle(tmp_path: Path) -> Path:
    return save_bundle(_spec(), tmp_path / "g.a2lb", ds_phases=_phases())


def test_phases_round_trip(bundle: Path) -> None:
    phases = load_ds_phases(bundle)
    assert [p.name for p in phases] == ["approach", "lift", "retreat"]
    assert phases[0].when == {"gripper": "open", "light": "off"}
    assert phases[0].end_action == "close" and phases[1].end_action is None
    np.testing.assert_array_equal(phases[0].ds.centers, _phases()[0].ds.centers)
    assert phases[2].ds.speed == 2.0
    skill = _core.load_bundle(bundle)
    assert skill.ds_states == {"light": ["off", "on"], "gripper": ["open", "closed"]}
    assert skill.ds_phases[1]["when"] == {"gripper": "closed"}
    np.testing.assert_allclose(skill.ds_phases[2]["target"], [0.15, 0.0, 0.0])
    plain = save_bundle(_spec(), bundle.with_name("plain.a2lb"))
    assert load_ds_phases(plain) == [] and _core.load_bundle(plain).ds_phases == []


def test_phase_direction_reads_back_as_the_cpp_loader_reads_it(tmp_path: Path) -> None:
    """A phase written with direction ``to_line`` reads back as ``to_line`` in Python, and its
    velocity is the one the C++ loader's step_ds follows (load_ds_phases used to drop
    the stored direction and return ``to_demo``, the same maps composed the other way)."""
    rng = np.random.default_rng(5)
    maps = (np.array([0.10, 0.03, 0.08]) + 0.03 * rng.uniform(-1, 1, (4, 3)),
            0.03 * rng.uniform(-1, 1, (4, 3)), np.full(4, 20.0))
    target = np.array([0.0, 0.0, 0.02])
    line = DiffeoDS.from_maps(target, *maps, direction="to_line")
    demo = DiffeoDS.from_maps(target, *maps, direction="to_demo")
    path = save_bundle(_spec(), tmp_path / "line.a2lb",
                       ds_phases=[DSPhase("line", line), DSPhase("demo", demo)])
    phases = load_ds_phases(path)
    assert [p.ds.direction for p in phases] == ["to_line", "to_demo"]
    skill = _core.load_bundle(path)
    state = _core.SkillState(skill)
    step = skill.movements.step
    differ = 0
    for x in np.array([0.10, 0.03, 0.08]) + 0.04 * rng.uniform(-1, 1, (20, 3)):
        state.reset()
        out = _core.step_ds(skill, state, OBJ + x, OBJ, {})  # phase 0 ("line") applies
        assert _core.status_name(out.status) == "ok"
        for ds in (phases[0].ds, line):
            v = ds.velocity(x)
            np.testing.assert_allclose(out.displacement, step * v / np.linalg.norm(v),
                                       rtol=0, atol=1e-9)
        v = demo.velocity(x)
        differ += not np.allclose(out.displacement, step * v / np.linalg.norm(v), atol=1e-6)
    assert differ > 10  # to_demo moves elsewhere: the check tells the two directions apart


def test_bad_phases_are_refused_naming_phase_and_field(tmp_path: Path) -> None:
    def refused(phases: list[DSPhase], match: str, **kw: object) -> None:
        with pytest.raises(BundleError, match=match):
            save_bundle(_spec(), tmp_path / "bad.a2lb", ds_phases=phases, **kw)
        assert not (tmp_path / "bad.a2lb").exists()

    p = _phases()
    refused([p[0], DSPhase("lift", p[1].ds, {"gripper": "closed"}, tolerance=0.0)],
            r"ds_phases\.phases\[1\]\.tolerance: must be > 0")
    refused([DSPhase("x", p[1].ds, {"colour": "red"})],
            r"ds_phases\.phases\[0\]\.when\.colour: the values of state 'colour' are unknown")
    refused([DSPhase("x", p[1].ds, {"light": "dim"})],
            r"ds_phases\.phases\[0\]\.when\.light: 'dim' is not a value of the state")
    refused([p[0], DSPhase("x", p[1].ds, end_action="grip")],
            r"ds_phases\.phases\[1\]\.end_action: unknown action 'grip'")
    flat = DiffeoDS.from_maps(np.zeros(2), np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0))
    refused([DSPhase("x", flat)], r"ds_phases\.phases\[0\]\.ds\.dim: must be 3")
    refused([DSPhase("x", "not a ds")], r"ds_phases\.phases\[0\]\.ds: not a DS")
    # a state the table does not hold is accepted when its values are given
    ok = save_bundle(_spec(), tmp_path / "ok.a2lb", ds_phases=[DSPhase("x", p[1].ds,
                     {"colour": "red"})], ds_states={"colour": ("red", "blue")})
    assert _core.load_bundle(ok).ds_states == {"colour": ["red", "blue"]}


def test_ds_runner_approaches_closes_lifts(bundle: Path) -> None:
    runner = CppSkillRunner(bundle, mode="ds")
    eef = OBJ + [0.15, 0.05, 0.10]
    states = {"light": "off", "gripper": "open"}
    results = []
    for _ in range(12):
        r = runner.step(eef, OBJ, "grasped", states)
        results.append(r)
        if r.action is not None:
            break
        assert r.status == "ok" and r.movement == -1 and r.label == "ds"
        assert r.phase == "approach"
        assert np.linalg.norm(r.displacement) <= 0.05 + 1e-12
        eef = eef + r.displacement
    assert results[-1].action == "close" and results[-1].label == "close"
    assert results[-1].movement == runner.labels.index("close")
    assert np.linalg.norm(eef - (OBJ + [0, 0, 0.02])) <= 0.01
    assert runner.step(eef, OBJ, "grasped", states).status == "converged"
    lift = runner.step(eef, OBJ, "grasped", {**states, "gripper": "closed"})
    assert lift.phase == "lift" and lift.displacement[2] == pytest.approx(0.05)
    # the light turns on: the very next step follows the retreat phase
    hot = runner.step(eef, OBJ, "grasped", {"light": "on", "gripper": "open"})
    assert hot.phase == "retreat" and hot.displacement[0] > 0
    assert [t.phase for t in runner.trace()][-3:] == [0, 1, 2]
    with pytest.raises(A2LValueError, match="'dim' is not a value of state 'light'"):
        runner.step(eef, OBJ, "grasped", {"light": "dim"})
    # no state given: no phase applies
    assert runner.step(eef, OBJ, "grasped", {}).status == "unknown_context"


def test_table_runner_is_the_cpp_step(bundle: Path) -> None:
    runner = CppSkillRunner(bundle)
    skill = _core.load_bundle(bundle)
    state = _core.SkillState(skill)
    rng = np.random.default_rng(0)
    for k in range(200):
        eef = OBJ + rng.uniform(-0.25, 0.25, 3)
        light = "on" if k % 3 == 0 else "off"
        got = runner.step(eef, OBJ, "grasped", {"light": light, "gripper": "open"})
        want = _core.step(skill, state, skill.context(eef, OBJ, "grasped", {"light": light}))
        assert got.status == _core.status_name(want.status)
        assert got.movement == want.movement
        np.testing.assert_array_equal(got.displacement, want.displacement)
        assert got.probability == want.probability
        if got.status == "ok":
            assert got.label == skill.movements.labels[got.movement]
            assert (got.action is None) == (got.movement < 6)
        runner.reset()
        state.reset()
    # the light toggled mid-action switches the behaviour in the next step
    eef = OBJ + [0.12, 0.0, 0.0]
    assert runner.step(eef, OBJ, "grasped", {"light": "off"}).label == "-x"
    assert runner.step(eef, OBJ, "grasped", {"light": "on"}).label == "+x"


def test_runner_refuses_bad_modes(tmp_path: Path, bundle: Path) -> None:
    plain = save_bundle(_spec(), tmp_path / "plain.a2lb")
    with pytest.raises(BundleError, match="mode 'ds' needs DS phases"):
        CppSkillRunner(plain, mode="ds")
    with pytest.raises(A2LValueError, match="mode: 'dmp'"):
        CppSkillRunner(bundle, mode="dmp")
