"""The C++ scenes and executor from Python: VirtualScene (docs/virtual_scene.md), BulletScene,
classify_effect against the Python effect discretizer, Executor safety checks."""

from __future__ import annotations

import numpy as np
import pytest

from a2l import Status, _core
from a2l.errors import A2LValueError
from a2l.robot import arm_spec
from a2l.skills import EffectDiscretizer


def test_runtime_virtual_scene_push_model() -> None:
    s = _core.VirtualScene()
    np.testing.assert_allclose(s.half_size, [0.035, 0.0425, 0.04])
    assert (s.table_z, s.eef_radius) == (0.0, 0.01)
    box = np.array([0.7, 0.0, 0.04])
    s.reset([0.6, 0.02, 0.04], box)
    assert not s.move([0.05, 0.0, 0.0])  # eef at 0.65: outside the grown box (0.655)
    assert s.move([0.05, 0.01, 0.0])  # dominant x: pushed until the face touches
    np.testing.assert_allclose(s.eef_position, [0.70, 0.03, 0.04])
    np.testing.assert_allclose(s.object_position, [0.70 + 0.035 + 0.01, 0.0, 0.04])
    s.reset([0.7, 0.0, 0.3], box)
    assert not s.move([0.0, 0.0, -0.26])  # vertical: never pushes, even into the box
    np.testing.assert_array_equal(s.object_position, box)
    assert s.in_contact(s.eef_position)
    with pytest.raises(A2LValueError):
        _core.VirtualScene(half_size=[0.1, -0.1, 0.1])


def test_runtime_virtual_scene_diagonal_ties() -> None:
    """A diagonal executed with a tiny error pushes like the exact diagonal (along x)."""
    box = np.array([0.0, 0.0, 0.0])
    for tol, axis in ((1e-5, 0), (0.0, 1)):
        s = _core.VirtualScene(tie_tolerance=tol)
        assert s.tie_tolerance == tol
        s.reset([-0.06, 0.06, 0.0], box)
        assert s.move([0.035355 - 1e-7, -0.035355, 0.0])  # |dy| larger by 1e-7 m
        moved = s.object_position - box
        assert moved[axis] != 0.0 and moved[1 - axis] == 0.0


def test_runtime_virtual_scene_is_deterministic() -> None:
    rng = np.random.default_rng(0)
    moves = rng.normal(0, 0.03, (500, 3))
    runs = []
    for _ in range(2):
        s = _core.VirtualScene()
        s.reset([0.1, 0.0, 0.0], [0.0, 0.0, 0.0])
        runs.append([(s.move(d), *s.object_position) for d in moves])
    assert runs[0] == runs[1]
    assert any(r[0] for r in runs[0])


def test_runtime_classify_effect_equals_python_effects() -> None:
    rng = np.random.default_rng(1)
    d = rng.normal(0, 0.05, (3000, 3))
    d[:100] *= 0.05  # below the threshold
    for n in (4, 8):
        py = EffectDiscretizer(n_effects=n).discretize(d)
        cpp = [_core.classify_effect(x, n) for x in d]
        assert py.tolist() == cpp


def test_runtime_bullet_scene_pushes_the_box() -> None:
    assert _core.bullet_scene_available()  # libbullet-dev is a build dependency (Makefile)
    s = _core.BulletScene()
    box = np.array([0.0, 0.0, 0.04])
    s.reset([0.0, -0.1, 0.04], box)
    assert s.move([0.0, 0.09, 0.0])
    d = s.object_position - box
    assert _core.classify_effect(d) == 0  # left (+y)
    assert s.object_position[2] == pytest.approx(0.04, abs=3e-3)
    before = s.physics_steps
    assert not s.move([0.0, 0.0, 0.05])  # lifting away touches nothing
    assert s.physics_steps > before


def test_runtime_executor_steps_within_limits() -> None:
    arm = arm_spec("baxter", "right")
    kin = _core.Kinematics(arm.urdf, arm.base_link, arm.tip_link)
    ex = _core.Executor(kin, np.array(arm.neutral))
    p0 = ex.position
    assert ex.set_target(p0 + [0.0, 0.05, 0.0]) == Status.ok
    n = 0
    while not ex.reached:
        assert ex.tick() == Status.ok
        assert kin.within_limits(ex.q)
        n += 1
    assert 200 <= n < 400  # 5 cm at 0.25 m/s, 1 kHz
    np.testing.assert_allclose(ex.position, p0 + [0.0, 0.05, 0.0], atol=1e-6)
    np.testing.assert_allclose(kin.fk(ex.q)[:3, 3], ex.position, atol=1e-12)
    opts = _core.ExecutorOptions()
    opts.workspace_min = p0 - 0.1
    opts.workspace_max = p0 + 0.1
    ex = _core.Executor(kin, np.array(arm.neutral), opts)
    assert ex.set_target(p0 + [0.3, 0.0, 0.0]) == Status.workspace_limit


def test_runtime_executor_scales_a_command_over_the_velocity_limits() -> None:
    arm = arm_spec("baxter", "right")
    kin = _core.Kinematics(arm.urdf, arm.base_link, arm.tip_link)
    opts = _core.ExecutorOptions()
    assert opts.scale_velocity  # the default
    opts.velocity_margin = 0.2  # a fifth of the URDF's limits: the 0.25 m/s asks more
    ex = _core.Executor(kin, np.array(arm.neutral), opts)
    target = ex.position + [0.0, 0.05, 0.0]
    assert ex.set_target(target) == Status.ok
    while not ex.reached:
        assert ex.tick() == Status.ok
        assert ex.ticks < 10000
    assert ex.scaled_ticks > 0 and ex.ticks > 250  # slowed down, and got there
    np.testing.assert_allclose(ex.position, target, atol=1e-6)
    # a joint inside its limit band is pushed back while the hand holds still, unless off
    q = np.array(arm.neutral)
    q[0] = kin.lower[0] + 0.04 * (kin.upper[0] - kin.lower[0])
    for avoidance, moved in ((0.5, True), (0.0, False)):
        band = _core.ExecutorOptions()
        band.limit_avoidance = avoidance
        ex = _core.Executor(kin, q, band)
        assert ex.set_target(ex.position) == Status.ok
        for _ in range(100):
            assert ex.tick() == Status.ok
        assert (ex.q[0] > q[0] + 1e-4) == moved
    opts.scale_velocity = False  # refused instead
    ex = _core.Executor(kin, np.array(arm.neutral), opts)
    assert ex.set_target(target) == Status.ok
    assert ex.tick() == Status.velocity_limit
    np.testing.assert_allclose(ex.q, arm.neutral)
