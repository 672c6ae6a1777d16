"""a2l-run on grasp and press skills: the C++ virtual scene's grasp semantics (the object
follows a closed gripper that reached it) and press semantics (going down on the button
toggles the light), the gripper and the light as high-level states that follow the scene,
--mode ds (the bundle's DS phases), and skills learned from scripted demonstrations."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from a2l import _core
from a2l.lfd.ds import DiffeoDS
from a2l.lfd.library import learn_recipe
from a2l.robot import robots_dir
from a2l.skills import (
    DSPhase,
    MovementRepertoire,
    SkillSpec,
    VariableSpec,
    load_bundle,
    save_bundle,
)

A2L_RUN = Path(sys.executable).parent / "a2l-run"
AXES = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]


def run(*args: str | Path) -> tuple[subprocess.CompletedProcess, dict]:
    out = Path(args[0]).with_suffix(".summary.json")
    r = subprocess.run([str(A2L_RUN), *map(str, args), "--summary", str(out), "--quiet"],
                       capture_output=True, text=True, timeout=300,
                       env={**os.environ, "A2L_ROBOTS_DIR": str(robots_dir())})
    return r, (json.loads(out.read_text()) if r.returncode == 0 else {})


def _linear(target: list[float]) -> DiffeoDS:
    return DiffeoDS.from_maps(np.array(target), np.zeros((0, 3)), np.zeros((0, 3)),
                              np.zeros(0))


@pytest.fixture(scope="module")
def ds_grasp(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """grasp_light as DS phases (no table information): light on -> the retreat pose, then
    stay; gripper open -> the grasp point (bent by 4 maps), then close; closed -> lift."""
    rep = MovementRepertoire(0.05, AXES, None, ("open", "close", "stay"))
    variables = [VariableSpec("effect", "effect", 2, values=("grasped", "away")),
                 VariableSpec("light", "high_level", 2, values=("off", "on"))]
    post = np.full((2, 2, rep.n_moves), 1.0 / rep.n_moves)
    spec = SkillSpec("grasp_light", variables, np.array(AXES), post,
                     np.full((2, 2), -1, np.int32), labels=list(rep.direction_labels),
                     actions=list(rep.actions), step_cap=40)
    rng = np.random.default_rng(1)
    bend = DiffeoDS.from_maps(np.array([0.0, 0.0, -0.01]),
                              np.array([0.0, 0.0, 0.10]) + 0.03 * rng.uniform(-1, 1, (4, 3)),
                              0.02 * rng.uniform(-1, 1, (4, 3)), np.full(4, 20.0))
    phases = [DSPhase("retreat", _linear([-0.12, 0.0, 0.16]), {"light": "on"}, "stay"),
              DSPhase("approach", bend, {"gripper": "open"}, "close", 0.005),
              DSPhase("lift", _linear([0.0, 0.0, 0.12]), {"gripper": "closed"})]
    return save_bundle(spec, tmp_path_factory.mktemp("tasks") / "gl.a2lb", ds_phases=phases)


@pytest.fixture(scope="module")
def learned(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """grasp and press learned from scripted demonstrations (a2l.lfd: DS -> vector field ->
    dataset -> network -> compiled table)."""
    out = tmp_path_factory.mktemp("learned")
    return {name: learn_recipe(name, out).bundle for name in ("grasp", "press")}


def test_ds_phases_grasp_or_wait_by_the_light(ds_grasp: Path) -> None:
    r, s = run(ds_grasp, "--mode", "ds", "--no-robot", "--effect", "grasped")
    assert r.returncode == 0, r.stderr
    assert s["task"] == "grasp" and s["mode"] == "ds"
    assert s["effects"]["grasped"]["success"] == 8  # approach, close, lift: 7 steps each
    assert s["effects"]["grasped"]["steps_per_action"] == 7
    r, s = run(ds_grasp, "--mode", "ds", "--no-robot", "--effect", "away", "--state", "light=on")
    assert s["effects"]["away"]["success"] == 8
    # through Baxter's differential IK
    r, s = run(ds_grasp, "--mode", "ds", "--effect", "grasped", "--episodes", "4")
    assert r.returncode == 0, r.stderr
    assert s["effects"]["grasped"]["success"] >= 3 and s["control_ticks"] > 0


def test_ds_trace_names_phases_and_actions(ds_grasp: Path, tmp_path: Path) -> None:
    trace = tmp_path / "t.jsonl"
    r, _ = run(ds_grasp, "--mode", "ds", "--no-robot", "--effect", "grasped", "--episodes", "1",
               "--trace", trace)
    assert r.returncode == 0, r.stderr
    rows = [json.loads(line) for line in trace.read_text().splitlines()]
    assert [row["phase"] for row in rows[:1]] == ["approach"]
    labels = [row["label"] for row in rows]
    k = labels.index("close")
    assert set(labels[:k]) == {"ds"} and rows[k]["phase"] == "approach"
    assert {row["phase"] for row in rows[k + 1:]} == {"lift"}  # until the block is 5 cm up


def test_learned_skills_reproduce_their_effect_in_the_virtual_scene(
        learned: dict[str, Path]) -> None:
    r, s = run(learned["press"], "--episodes", "16", "--no-robot")
    assert r.returncode == 0, r.stderr
    assert s["task"] == "press" and s["effects"]["pressed"]["success"] >= 14  # measured 16
    r, s = run(learned["press"], "--episodes", "8")  # through Baxter's IK
    assert s["effects"]["pressed"]["success"] >= 7
    r, s = run(learned["grasp"], "--episodes", "16", "--no-robot")
    assert s["task"] == "grasp" and s["effects"]["grasped"]["success"] >= 12  # measured 14
    # their DS phases (a2l.lfd writes one per behaviour), through Baxter's IK
    for name, effect in (("grasp", "grasped"), ("press", "pressed")):
        r, s = run(learned[name], "--episodes", "16", "--mode", "ds")
        assert s["mode"] == "ds" and s["effects"][effect]["success"] >= 14  # measured 16


def test_bad_modes_and_tasks(learned: dict[str, Path], ds_grasp: Path, tmp_path: Path) -> None:
    plain = save_bundle(load_bundle(learned["press"]), tmp_path / "plain.a2lb")  # no phases
    r, _ = run(plain, "--mode", "ds", "--no-robot")
    assert r.returncode == 2 and "has no DS phases" in r.stderr
    r, _ = run(ds_grasp, "--scene", "bullet", "--no-robot")
    assert r.returncode == 2 and "--scene virtual" in r.stderr
    for args, msg in ((("--mode", "dmp"), "--mode: 'dmp'"), (("--task", "pour"), "--task")):
        r, _ = run(ds_grasp, *args)
        assert r.returncode == 2 and msg in r.stderr


def test_virtual_scene_binding_grasp_and_press() -> None:
    s = _core.VirtualScene(half_size=[0.015, 0.015, 0.03], table_z=-0.03,
                           object_kind=_core.ObjectKind.graspable)
    s.reset([0.0, 0.0, 0.005], [0.0, 0.0, 0.0])
    assert s.set_gripper(True) and s.holding
    assert s.move([0.0, 0.0, 0.06])
    np.testing.assert_allclose(s.object_position, [0.0, 0.0, 0.06])
    b = _core.VirtualScene(half_size=[0.03, 0.03, 0.01], object_kind=_core.ObjectKind.button)
    b.reset([0.0, 0.0, 0.1], [0.0, 0.0, 0.0])
    b.move([0.0, 0.0, -0.09])
    assert b.light_on and b.presses == 1
