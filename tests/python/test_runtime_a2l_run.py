"""a2l-run, the C++ closed-loop runner: on the venv's PATH, documented, clear errors (exit
code, never a signal), and a bundle learned from a synthetic push dataset reproduces the 4
push effects in the virtual scene through Baxter's differential IK."""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from a2l.robot import robots_dir
from a2l.skills import (
    Discretizer,
    MovementRepertoire,
    VariableSpec,
    compile_policy,
    learn_network,
    load_bundle,
    make_skill_spec,
    push_dataset,
    save_bundle,
)

A2L_RUN = Path(sys.executable).parent / "a2l-run"
#: Start circle of the data and of the runs. 0.19 m keeps the start points off the distance
#: bin edges (0.10, 0.15 m are multiples of the 0.05 m step from a 0.20 m circle), where a
#: controller's 1e-6 m tracking error would flip bins.
RADIUS = 0.19


def run(*args: str | Path, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(A2L_RUN), *map(str, args)], capture_output=True, text=True, timeout=300, env=env
    )


@pytest.fixture(scope="module")
def push_bundle(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A push skill learned by hill-climbing + K2 from random push babbling."""
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    data = disc.discretize(push_dataset(5000, seed=0, radius=RADIUS))
    net = learn_network(data, "hc-k2")
    table = compile_policy(net, "move", disc.evidence)
    path = tmp_path_factory.mktemp("a2l_run") / "push.a2lb"
    save_bundle(make_skill_spec(table, disc, name="push"), path)
    return path


def test_runtime_a2l_run_is_installed_and_documented() -> None:
    assert A2L_RUN.is_file() and os.access(A2L_RUN, os.X_OK)
    r = run("--help")
    assert r.returncode == 0
    for opt in ("--scene", "--effect", "--episodes", "--starts", "--radius-range", "--rate",
                "--seed", "--trace", "--urdf"):
        assert opt in r.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((), "missing BUNDLE"),
        (("x.a2lb", "--scene", "mujoco"), "--scene: 'mujoco'"),
        (("x.a2lb", "--episodes", "zero"), "--episodes"),
        (("x.a2lb", "--rate", "-5"), "--rate"),
        (("x.a2lb", "--frobnicate"), "unknown option"),
        (("x.a2lb", "--starts", "grid"), "--starts: 'grid'"),
        (("x.a2lb", "--radius", "0.2"), "--starts circle"),
        (("x.a2lb", "--starts", "circle", "--radius-range", "0.1,0.2"), "--radius-range"),
        (("x.a2lb", "--radius-range", "0.3,0.1"), "0 < A <= B"),
        (("/nonexistent/skill.a2lb",), "cannot open"),
        (("x.a2lb", "--arm", "middle"), "--arm: 'middle' is not one of right, left"),
        (("x.a2lb", "--smoothing", "yes"), "--smoothing: 'yes' is not one of bundle, on, off"),
        (("x.a2lb", "--state", "light"), "--state: needs NAME=VALUE, got 'light'"),
        (("x.a2lb", "--state", "=on"), "--state: needs NAME=VALUE"),
        (("x.a2lb", "--object", "0.5,0.1"), "--object: needs X,Y,Z, got '0.5,0.1'"),
        (("x.a2lb", "--object", "1,,2,3"), "--object: needs X,Y,Z, got '1,,2,3'"),
        (("x.a2lb", "--radius-range", "0.1,,0.2"),
         "--radius-range: needs A,B, got '0.1,,0.2'"),
        (("x.a2lb", "--object", "0.5,0.1,up"), "--object: 'up' is not a finite number"),
        (("x.a2lb", "--seed", "-1"), f"--seed: '-1' is not an integer in [0, {2**62}]"),
        (("x.a2lb", "--seed", str(2**62 + 1)), f"--seed: '{2**62 + 1}' is not an integer in"),
        (("x.a2lb", "--seed"), "--seed: needs a value"),
        (("x.a2lb", "--quiet", "--object"), "--object: needs a value"),
        (("x.a2lb", "y.a2lb"), "unexpected argument 'y.a2lb' (one BUNDLE only)"),
    ],
)
def test_runtime_a2l_run_bad_arguments(args: tuple[str, ...], message: str) -> None:
    r = run(*args)
    assert r.returncode == 2, r  # an exit code, not a signal (negative)
    assert message in r.stderr


def test_runtime_a2l_run_bad_bundles(tmp_path: Path, push_bundle: Path) -> None:
    junk = tmp_path / "junk.a2lb"
    junk.write_bytes(os.urandom(5000))
    r = run(junk)
    assert r.returncode == 2 and "skill bundle" in r.stderr and "magic" in r.stderr
    cut = tmp_path / "cut.a2lb"
    cut.write_bytes(push_bundle.read_bytes()[:-3])
    r = run(cut)
    assert r.returncode == 2 and "outside the file" in r.stderr
    r = run(push_bundle, "--effect", "lift", "--no-robot")
    assert r.returncode == 2 and "'lift' is not an effect" in r.stderr
    r = run(push_bundle, "--urdf", tmp_path / "none.urdf")
    assert r.returncode == 2 and "none.urdf" in r.stderr


def test_runtime_a2l_run_reproduces_the_four_push_effects(
    tmp_path: Path, push_bundle: Path
) -> None:
    trace, summary = tmp_path / "trace.csv", tmp_path / "summary.json"
    env = {k: v for k, v in os.environ.items() if k != "A2L_ROBOTS_DIR"}
    # Without A2L_ROBOTS_DIR: a2l-run finds Baxter in the venv it is installed in.
    r = run(
        push_bundle,
        "--scene",
        "virtual",
        "--episodes",
        "16",
        "--starts",
        "circle",
        "--radius",
        RADIUS,
        "--trace",
        trace,
        "--summary",
        summary,
        env=env,
    )
    assert r.returncode == 0, r.stderr
    assert "baxter" in r.stdout and "step() time" in r.stdout and "control tick" in r.stdout
    s = json.loads(summary.read_text())
    assert set(s["effects"]) == {"left", "right", "close", "far"}
    for effect, res in s["effects"].items():
        assert res["episodes"] == 16
        assert res["success"] >= 10, (effect, res)  # measured 11 to 16 of 16
        assert 1 <= res["steps_per_action"] <= 12
    assert s["success"] >= 50  # BENCHMARKS.md: 53 of 64 (82.8 %)
    # every movement went through the IK: 5 cm at 0.25 m/s and 1 kHz is 200 ticks at least
    assert s["control_ticks"] >= 200 * s["skill_steps"]
    assert s["step_time"]["n"] > 64
    rows = list(csv.DictReader(trace.open()))
    assert rows[0].keys() >= {
        "episode",
        "effect",
        "step",
        "status",
        "movement",
        "label",
        "probability",
        "bin_effect",
        "bin_distance",
        "bin_orientation",
    }
    produced = [row for row in rows if row["status"] == "effect_produced"]
    assert len(produced) >= s["success"]
    for row in rows:
        if row["status"] == "ok":
            assert 0 < float(row["probability"]) <= 1 and row["label"]
            assert 0 <= int(row["bin_distance"]) < 3 and 0 <= int(row["bin_orientation"]) < 16


def test_runtime_a2l_run_bullet_scene_and_jsonl_trace(tmp_path: Path, push_bundle: Path) -> None:
    """The Bullet run of BENCHMARKS.md's runtime section (same bundle, 16 start points x 4
    effects, default seed): it reports 35/64 (54.7 %); the bound leaves 3 episodes of margin."""
    trace, summary = tmp_path / "trace.jsonl", tmp_path / "summary.json"
    env = dict(os.environ, A2L_ROBOTS_DIR=str(robots_dir()))
    r = run(
        push_bundle,
        "--scene",
        "bullet",
        "--episodes",
        "16",
        "--starts",
        "circle",
        "--radius",
        RADIUS,
        "--trace",
        trace,
        "--summary",
        summary,
        env=env,
    )
    assert r.returncode == 0, r.stderr
    s = json.loads(summary.read_text())
    assert s["scene"] == "bullet" and set(s["effects"]) == {"left", "right", "close", "far"}
    assert s["episodes"] == 64
    assert s["success"] >= 32, s  # measured 35 of 64
    for effect, res in s["effects"].items():
        assert res["episodes"] == 16
        assert res["success"] >= 4, (effect, res)  # measured 6 to 11 of 16
    records = [json.loads(line) for line in trace.read_text().splitlines()]
    assert {"episode", "effect", "bins", "eef", "object", "status"} <= records[0].keys()
    assert {r["effect"] for r in records} == {"left", "right", "close", "far"}
    # The summary agrees with the trace: one effect_produced record per success.
    produced = [r for r in records if r["status"] == "effect_produced"]
    assert len(produced) >= s["success"]


def test_runtime_a2l_run_at_a_fixed_rate(push_bundle: Path, tmp_path: Path) -> None:
    summary = tmp_path / "s.json"
    r = run(
        push_bundle,
        "--no-robot",
        "--episodes",
        "2",
        "--effect",
        "far",
        "--rate",
        "200",
        "--starts",
        "circle",
        "--radius",
        RADIUS,
        "--summary",
        summary,
    )
    assert r.returncode == 0, r.stderr
    s = json.loads(summary.read_text())
    # One movement per 5 ms tick without the robot: the run cannot be faster than that.
    assert s["elapsed_s"] >= s["skill_steps"] * 0.005 * 0.9
    assert s["wakeup_lateness"]["n"] == s["skill_steps"] > 0  # one timed wake-up per movement
    assert s["wakeup_lateness"]["p50_us"] >= 0.0


def test_runtime_a2l_run_high_level_state(tmp_path: Path, push_bundle: Path) -> None:
    """A skill valid only with the light on: with it off, every context is unknown."""
    spec = load_bundle(push_bundle)
    n_moves = spec.posterior.shape[-1]
    off = np.full_like(spec.posterior, 1.0 / n_moves)
    spec.posterior = np.stack([off, spec.posterior], axis=-2)  # light axis last
    spec.argmax = np.stack([np.full_like(spec.argmax, -1), spec.argmax], axis=-1)
    spec.variables = [*spec.variables, VariableSpec("light", "high_level", 2, values=("off", "on"))]
    path = save_bundle(spec, tmp_path / "light.a2lb")
    common = ("--no-robot", "--episodes", "4", "--starts", "circle", "--radius", str(RADIUS),
              "--summary")
    on, off_ = tmp_path / "on.json", tmp_path / "off.json"
    assert run(path, "--state", "light=on", *common, on).returncode == 0
    assert run(path, "--state", "light=off", *common, off_).returncode == 0
    s_on, s_off = json.loads(on.read_text()), json.loads(off_.read_text())
    assert s_on["success"] >= 8
    assert s_off["success"] == 0 and s_off["skill_steps"] == 0
    assert all(e["stops"] == {"unknown_context": 4} for e in s_off["effects"].values())
    r = run(path, "--state", "light=dim", "--no-robot")
    assert r.returncode == 2 and "'dim' is not a value" in r.stderr


def _starts(push_bundle: Path, tmp_path: Path, *args: str) -> tuple[np.ndarray, dict]:
    """Start points (episodes, 3) of a no-robot run and its summary."""
    trace, summary = tmp_path / "starts.jsonl", tmp_path / "starts.json"
    r = run(push_bundle, "--no-robot", "--effect", "far", "--episodes", "6", "--trace", trace,
            "--summary", summary, *args)
    assert r.returncode == 0, r.stderr
    first = {}
    for line in trace.read_text().splitlines():
        rec = json.loads(line)
        if rec["step"] == 0:
            first[rec["episode"]] = np.asarray(rec["eef"]) - np.asarray(rec["object"])
    return np.asarray([first[k] for k in sorted(first)]), json.loads(summary.read_text())


def test_runtime_a2l_run_draws_random_starts_by_default(push_bundle: Path,
                                                        tmp_path: Path) -> None:
    rel, s = _starts(push_bundle, tmp_path, "--seed", "5")
    assert s["starts"]["mode"] == "random" and s["starts"]["radius_range"] == [0.10, 0.25]
    assert "random (seed 5)" in s["starts"]["description"]
    dist = np.hypot(rel[:, 0], rel[:, 1])
    assert len(rel) == 6 and np.all((dist >= 0.10) & (dist <= 0.25))
    assert np.ptp(dist) > 0.01  # not a circle
    assert np.all(np.abs(rel[:, 2]) < 1e-12)  # at the box's height
    again, _ = _starts(push_bundle, tmp_path, "--seed", "5")
    assert np.array_equal(rel, again)  # seeded
    other, _ = _starts(push_bundle, tmp_path, "--seed", "6")
    assert not np.allclose(rel, other)
    narrow, s = _starts(push_bundle, tmp_path, "--radius-range", "0.12,0.13")
    assert np.all(np.abs(np.hypot(narrow[:, 0], narrow[:, 1]) - 0.125) <= 0.005 + 1e-12)


def test_runtime_a2l_run_fixed_circle_only_when_asked(push_bundle: Path, tmp_path: Path) -> None:
    rel, s = _starts(push_bundle, tmp_path, "--starts", "circle", "--radius", "0.2")
    assert s["starts"] == {"mode": "circle", "radius": 0.2,
                           "description": s["starts"]["description"]}
    angles = np.arctan2(rel[:, 1], rel[:, 0]) % (2 * np.pi)
    np.testing.assert_allclose(np.hypot(rel[:, 0], rel[:, 1]), 0.2, atol=1e-12)
    np.testing.assert_allclose(angles, 2 * np.pi * np.arange(6) / 6, atol=1e-9)  # seed 0
    turned, _ = _starts(push_bundle, tmp_path, "--starts", "circle", "--seed", "3")
    step = np.diff(np.unwrap(np.arctan2(turned[:, 1], turned[:, 0])))
    np.testing.assert_allclose(step, 2 * np.pi / 6, atol=1e-9)  # evenly spaced, turned
    assert not np.allclose(turned, rel)


def test_runtime_a2l_run_checks_the_urdf_sha256(push_bundle: Path, tmp_path: Path) -> None:
    """The bundle's robot.urdf_sha256 must be the SHA-256 of the URDF a2l-run loads."""
    import hashlib

    from a2l.robot import baxter_urdf

    urdf = baxter_urdf()
    true_hash = hashlib.sha256(urdf.read_bytes()).hexdigest()
    spec = load_bundle(push_bundle)
    robot = {"name": "baxter", "base_link": "base", "tip_link": "right_gripper"}
    spec.robot = {**robot, "urdf_sha256": true_hash}
    good = save_bundle(spec, tmp_path / "good.a2lb")
    spec.robot = {**robot, "urdf_sha256": "0" * 64}
    bad = save_bundle(spec, tmp_path / "bad.a2lb")
    common = ("--episodes", "1", "--effect", "far", "--starts", "circle", "--radius",
              str(RADIUS), "--urdf", str(urdf))

    summary = tmp_path / "s.json"
    r = run(good, *common, "--summary", summary)
    assert r.returncode == 0, r.stderr
    assert json.loads(summary.read_text())["urdf_sha256"] == true_hash

    r = run(bad, *common)
    assert r.returncode == 2
    assert true_hash in r.stderr and "0" * 64 in r.stderr and str(urdf) in r.stderr

    edited = tmp_path / "baxter.urdf"  # same robot, one byte more: another hash
    edited.write_bytes(urdf.read_bytes() + b"\n")
    edited_hash = hashlib.sha256(edited.read_bytes()).hexdigest()
    r = run(good, *common[:-1], str(edited))
    assert r.returncode == 2
    assert edited_hash in r.stderr and true_hash in r.stderr
    assert str(edited) in r.stderr

    r = run(good, *common[:-1], str(tmp_path / "missing.urdf"))
    assert r.returncode == 2 and "missing.urdf" in r.stderr


def _panda_bundle(push_bundle: Path, tmp_path: Path) -> Path:
    """The push bundle, recorded as learned on the Panda (name, URDF hash, chain)."""
    from a2l.robot import robot_entry, urdf_sha256

    panda = robot_entry("panda")
    spec = load_bundle(push_bundle)
    spec.robot = {"name": "panda", "urdf_sha256": urdf_sha256(panda.urdf),
                  "base_link": panda.base_link, "tip_link": panda.tool_link}
    return save_bundle(spec, tmp_path / "panda_push.a2lb")


def test_runtime_a2l_run_on_the_panda_from_its_exported_robot_file(
    tmp_path: Path, push_bundle: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`a2l robot export panda` then `a2l-run --robot`: the Panda's arm moves the push scene's
    box (5.9 cm tall under its hand) at its work point, in both scenes, as Baxter's does (the
    skill acts relative to the box: 53/64 virtual and 35/64 Bullet on both arms)."""
    from a2l.cli import main

    robot, baxter = tmp_path / "panda.json", tmp_path / "baxter.json"
    assert main(["robot", "export", "panda", "--out", str(robot)]) == 0
    assert main(["robot", "export", "baxter", "--out", str(baxter)]) == 0
    with pytest.raises(SystemExit) as exc:
        main(["robot", "export", "nobot"])
    assert exc.value.code == 2 and "unknown robot 'nobot'" in capsys.readouterr().err
    desc = json.loads(robot.read_text())
    bundle = _panda_bundle(push_bundle, tmp_path)
    for scene, least in (("virtual", 50), ("bullet", 32)):
        trace, summary = tmp_path / f"{scene}.jsonl", tmp_path / f"{scene}.json"
        r = run(bundle, "--robot", robot, "--scene", scene, "--episodes", "16", "--starts",
                "circle", "--radius", RADIUS, "--trace", trace, "--summary", summary)
        assert r.returncode == 0, r.stderr
        assert "panda_link0 -> panda_hand_tcp (7 joints)" in r.stdout
        s = json.loads(summary.read_text())
        assert s["robot_file"] == {"path": str(robot), "name": "panda", "scene_scale": 1.0}
        assert s["urdf_sha256"] == desc["urdf_sha256"]
        assert s["success"] >= least, (scene, s["success"])
        assert s["control_ticks"] >= 200 * s["skill_steps"]  # every movement through the IK
        first = json.loads(trace.read_text().splitlines()[0])
        scene_desc = desc["scene"]
        assert scene_desc["push_box_size"][2] < 0.06  # the Panda's box, lowered
        np.testing.assert_allclose(first["object"], [
            *scene_desc["work_point"], scene_desc["table_z"] + scene_desc["push_box_size"][2] / 2],
            atol=1e-9)
    # a bundle of the Panda's on Baxter (the default robot), and on a Baxter robot file
    r = run(bundle, "--episodes", "1")
    assert r.returncode == 2 and desc["urdf_sha256"] in r.stderr
    r = run(bundle, "--robot", baxter, "--episodes", "1")
    assert r.returncode == 2
    assert "learned for robot 'panda', not for the robot 'baxter'" in r.stderr


def test_runtime_a2l_run_refuses_a_bad_robot_file(tmp_path: Path, push_bundle: Path) -> None:
    from a2l.sim.resolved_robot import resolved_robot

    good = resolved_robot("panda")

    def refused(edit: dict, *extra: str) -> str:
        path = tmp_path / "robot.json"
        path.write_text(json.dumps({k: v for k, v in {**good, **edit}.items()
                                    if v is not ...}))
        r = run(push_bundle, "--robot", path, "--episodes", "1", *extra)
        assert r.returncode == 2, r
        return r.stderr

    robot_file = {k: ... for k in ("format", "version", "urdf_sha256", "joint_names", "scene")}
    assert "format: missing; a2l-run takes a robot resolved by" in refused(
        {**robot_file, "mount": {"xyz": [-0.45, 0, 0], "yaw": 0}})  # a robot file, unresolved
    assert "tool_link: missing" in refused({"tool_link": ...})
    assert "scene.work_point: must hold 2 numbers, got 1" in refused(
        {"scene": {**good["scene"], "work_point": [0.4]}})
    assert "tool_down: not a rotation" in refused({"tool_down": [[1, 0, 0]] * 3})
    assert "it was exported with; export the robot again" in refused({"urdf_sha256": "0" * 64})
    names = list(good["joint_names"])
    assert "joint_names: panda_joint2, panda_joint1" in refused(
        {"joint_names": [names[1], names[0], *names[2:]]})
    assert "unknown link 'hand'" in refused({"tool_link": "hand"})
    assert "--arm: chooses Baxter's arm" in refused({}, "--arm", "left")
