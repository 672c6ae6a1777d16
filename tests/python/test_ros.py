"""a2l.ros: the simulated robot and the skill node, each in its own process, push the box
over ROS 2 (Baxter, the Panda) and grasp the block (the Panda, with its gripper commands);
bad input ends the skill node with a clear message and no command after it.

Every test gets its own random ROS_DOMAIN_ID (the processes of one pytest run draw from
disjoint ranges) and localhost-only discovery, so tests running at once and test runs of
other people on the same machine do not cross-talk.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import random
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("rclpy", reason="the ros extra (pip install 'a2l[ros]') is not installed")

from a2l.rollout.effect_tests import PUSH_DISTANCE  # noqa: E402

A2L = [sys.executable, "-m", "a2l.cli"]


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from a2l.lfd.library import learn_recipe

    return learn_recipe("push_far", tmp_path_factory.mktemp("ros")).bundle


@pytest.fixture(scope="module")
def sideways(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A sideways push learned from demonstrations (its bundle keeps the gripper's turn, 90
    degrees, it was learned with), as tests/python/test_cli_skill.py learns it."""
    from a2l.lfd.library import learn_recipe

    return learn_recipe("push_right", tmp_path_factory.mktemp("ros-sideways")).bundle


@pytest.fixture(scope="module")
def panda(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A push and the grasp learned for the Panda (their bundles record it)."""
    from a2l.lfd.library import learn_recipe

    out = tmp_path_factory.mktemp("ros-panda")
    return {name: learn_recipe(name, out, robot="panda").bundle
            for name in ("push_far", "grasp")}


@pytest.fixture
def domain(monkeypatch: pytest.MonkeyPatch) -> int:
    """A random ROS domain of this test, discovery on localhost only; the pytest processes
    of one run (pytest-xdist, ``make test``) draw from disjoint ranges of domains 1-100, so
    two of its tests running at once never share one."""
    worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0")[2:]
    count = max(1, int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")))
    span = max(1, 100 // count)
    index = (int(worker) if worker.isdigit() else 0) % count
    d = 1 + index * span + random.SystemRandom().randrange(span)
    monkeypatch.setenv("ROS_DOMAIN_ID", str(d))
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    monkeypatch.delenv("ROS_LOCALHOST_ONLY", raising=False)
    return d


def _stop(proc: subprocess.Popen[str], timeout: float = 20.0) -> str:
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=timeout)
    return out


def run_over_ros(sim_args: list[str], skill_args: list[str], ready: str
                 ) -> tuple[subprocess.CompletedProcess[str], str]:
    """``a2l ros sim SIM_ARGS`` in one process, ``a2l ros skill SKILL_ARGS`` in another
    once the sim is up (its first line starts with `ready`): the skill's completed process
    and the sim's output, the sim stopped (SIGINT) and checked to exit 0."""
    sim = subprocess.Popen([*A2L, "ros", "sim", *sim_args], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
    try:
        assert sim.stdout is not None
        first = sim.stdout.readline()  # the scene is built and the node is up
        assert first.startswith(ready), first
        skill = subprocess.run([*A2L, "ros", "skill", *skill_args, "--timeout", "90"],
                               capture_output=True, text=True, timeout=150)
    finally:
        sim_out = _stop(sim)
    assert sim.returncode == 0, sim_out
    assert skill.returncode == 0, skill.stdout + skill.stderr
    assert skill.stdout.startswith("success: stop effect_produced")
    return skill, first + sim_out


@pytest.mark.timeout(180)
@pytest.mark.parametrize(("robot", "command"), [
    pytest.param("baxter", "joint", marks=pytest.mark.slow), ("panda", "pose")])
def test_sim_and_skill_node_push_the_box_over_ros(bundle: Path, panda: dict[str, Path],
                                                  domain: int, tmp_path: Path, robot: str,
                                                  command: str) -> None:
    """Baxter commanded in joints (and recorded), the Panda by Cartesian targets: each
    robot's scene and skill node take the robot the bundle was learned for."""
    truth = tmp_path / "truth.json"
    push = bundle if robot == "baxter" else panda["push_far"]
    record = ["--record", str(tmp_path / "push.mcap")] if command == "joint" else []
    start = ["--trial", "push_far"] if robot == "baxter" else ["--bundle", str(push)]
    run_over_ros([*start, "--seed", "1000", "--command", command, "--truth", str(truth)],
                 [str(push), "--effect", "far", *record],
                 f"a2l ros sim: push scene, robot {robot}, joints ")
    t = json.loads(truth.read_text())
    assert (t["robot"], t["trial"]) == (robot, "push_far")
    moved = np.subtract(t["end"]["box"], t["start"]["box"])
    # the simulator's ground truth: pushed far (+x) at least the push distance, mostly along x
    assert t["effect"] == "far"
    assert moved[0] >= PUSH_DISTANCE and abs(moved[1]) < moved[0] / 2
    topic = "joint_trajectory" if command == "joint" else "target_pose"
    assert t["commands"] and {c["topic"] for c in t["commands"]} == {topic}
    if record:
        check_recording(tmp_path / "push.mcap", len(t["commands"]))


@pytest.mark.timeout(180)
def test_the_panda_grasps_the_block_over_ros(panda: dict[str, Path], domain: int,
                                             tmp_path: Path) -> None:
    """The grasp's close goes out on gripper/command, the sim closes the Panda's hand, the
    node sees it on states/gripper and lifts: the simulator's block is grasped, 5 cm up."""
    truth = tmp_path / "truth.json"
    skill, _ = run_over_ros(
        ["--bundle", str(panda["grasp"]), "--seed", "1000", "--truth", str(truth)],
        [str(panda["grasp"]), "--effect", "grasped", "--robot", "panda"],
        "a2l ros sim: grasp scene, robot panda, joints panda_joint1..., objects ['block']")
    assert ", gripper closed" in skill.stdout
    t = json.loads(truth.read_text())
    assert (t["robot"], t["trial"], t["effect"]) == ("panda", "grasp", "grasped")
    assert t["end"]["block"][2] - t["start"]["block"][2] >= 0.05
    topics = [c["topic"] for c in t["commands"]]
    assert set(topics) == {"joint_trajectory", "gripper/command"}
    # moves down, closes once, then lifts
    close = topics.index("gripper/command")
    assert 0 < close < len(topics) - 1 and topics.count("gripper/command") == 1


@pytest.mark.slow
@pytest.mark.timeout(180)
def test_a_sideways_push_runs_over_ros_with_the_gripper_turned_as_it_was_learned(
        sideways: Path, domain: int, tmp_path: Path) -> None:
    """The sim takes the bundle's scene settings (the turn, the trial of push_right), the
    skill node commands the turned gripper in both commands, and the box goes right."""
    from mcap_ros2.reader import read_ros2_messages
    from scipy.spatial.transform import Rotation

    from a2l import _core
    from a2l.robot import arm_spec, gripper_down, rotation_angle

    truth, mcap = tmp_path / "truth.json", tmp_path / "push.mcap"
    sim = subprocess.Popen([*A2L, "ros", "sim", "--bundle", str(sideways), "--seed", "1000",
                            "--truth", str(truth)],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        assert sim.stdout is not None
        ready = sim.stdout.readline()
        assert ready.startswith("a2l ros sim: push scene"), ready
        assert "trial push_right, gripper turned 90 degrees" in ready, ready
        skill = subprocess.run([*A2L, "ros", "skill", str(sideways), "--effect", "right",
                                "--timeout", "90", "--record", str(mcap)],
                               capture_output=True, text=True, timeout=150)
    finally:
        sim_out = _stop(sim)
    assert sim.returncode == 0, sim_out
    assert skill.returncode == 0, skill.stdout + skill.stderr
    assert "turned 90 degrees (as the skill was learned)" in skill.stdout + skill.stderr
    t = json.loads(truth.read_text())
    assert t["trial"] == "push_right" and t["gripper_yaw"] == 90.0
    moved = np.subtract(t["end"]["box"], t["start"]["box"])
    # the simulator's ground truth: pushed right (-y) at least the push distance
    assert t["effect"] == "right"
    assert -moved[1] >= PUSH_DISTANCE and abs(moved[0]) < -moved[1] / 2
    # both commands carry the turn: the Cartesian target exactly, the trajectory's end
    # (the C++ IK turning toward it) within a degree; unturned would be 90 degrees off
    aim, unturned = gripper_down(90.0), gripper_down(0.0)
    spec = arm_spec("baxter", "right")
    kin = _core.Kinematics(str(spec.urdf), spec.base_link, spec.tip_link)

    def angle(a: np.ndarray, b: np.ndarray) -> float:
        return float(np.degrees(rotation_angle(a, b)))

    poses = trajs = 0
    for m in read_ros2_messages(str(mcap)):
        if m.channel.topic == "/target_pose":
            o = m.ros_msg.pose.orientation
            r = Rotation.from_quat([o.x, o.y, o.z, o.w]).as_matrix()
            assert angle(r, aim) < 1e-4 and angle(r, unturned) > 89.9
            poses += 1
        elif m.channel.topic == "/joint_trajectory":
            r = np.asarray(kin.fk(np.asarray(m.ros_msg.points[-1].positions)))[:3, :3]
            assert angle(r, aim) < 1.0, angle(r, aim)
            trajs += 1
    assert poses == trajs == len(t["commands"]) > 0


def test_the_skill_node_commands_the_turn_of_the_bundle_or_of_its_parameter(
        sideways: Path, bundle: Path) -> None:
    from a2l.errors import A2LValueError
    from a2l.robot import GRIPPER_DOWN, arm_spec, gripper_down, rotation_angle
    from a2l.ros.orientation import commanded_orientation

    for path, yaw, expect, source in ((sideways, math.nan, 90.0, "as the skill was learned"),
                                      (sideways, 0.0, 0.0, "the gripper_yaw parameter"),
                                      (bundle, math.nan, 0.0, "the bundle names no turn")):
        aim = commanded_orientation(str(path), GRIPPER_DOWN, yaw)
        assert (aim.yaw, aim.source) == (expect, source)
        assert rotation_angle(aim.rotation, gripper_down(expect)) < 1e-12
    aim = commanded_orientation(str(sideways), GRIPPER_DOWN)
    assert aim.settings == {"gripper_yaw": 90.0}
    w, x, y, z = aim.quaternion  # 180 degrees about an axis in the table plane
    assert abs(w) < 1e-12 and abs(z) < 1e-12 and abs(x * x + y * y - 1) < 1e-12
    aim.check_start(gripper_down(90.0 + 20.0), 0.5)  # 20 degrees off: within 0.5 rad
    with pytest.raises(A2LValueError, match="the gripper starts 40 degrees from"):
        aim.check_start(gripper_down(90.0 - 40.0), 0.5)
    with pytest.raises(A2LValueError, match="gripper_yaw 200.0 must be in"):
        commanded_orientation(str(sideways), GRIPPER_DOWN, 200.0)
    # each arm's own "down": the unturned aim is near its neutral pose (Baxter's neutral
    # gripper is 16.5 degrees off, the fake arm's start; the Panda's points straight down)
    from a2l import _core

    for robot, most in (("baxter", 0.3), ("panda", 1e-3)):
        spec = arm_spec(robot)
        kin = _core.Kinematics(str(spec.urdf), spec.base_link, spec.tip_link)
        aim = commanded_orientation(str(bundle), spec.down)
        assert rotation_angle(aim.rotation, kin.fk(np.asarray(spec.neutral))[:3, :3]) < most


def test_the_sim_node_takes_the_scene_settings_of_a_bundle_or_a_trial(
        sideways: Path, bundle: Path) -> None:
    from a2l.errors import A2LValueError
    from a2l.ros.sim_node import SimNodeConfig, sim_scene

    for cfg, trial, yaw in (
            (SimNodeConfig(bundle=str(sideways)), "push_right", 90.0),
            (SimNodeConfig(bundle=str(sideways), gripper_yaw=0.0), "push_right", 0.0),
            (SimNodeConfig(bundle=str(sideways), trial="push_far"), "push_far", 90.0),
            (SimNodeConfig(trial="push_left"), "push_left", 90.0),
            (SimNodeConfig(bundle=str(bundle)), "push_far", 0.0),
            (SimNodeConfig(), "", 0.0)):
        got, scene = sim_scene(cfg)
        with scene:
            assert (got, scene.config.gripper_yaw) == (trial, yaw), cfg
    with pytest.raises(A2LValueError, match="'lift' is not a demonstrated skill"):
        sim_scene(SimNodeConfig(trial="lift"))


def check_recording(path: Path, n: int) -> None:
    """The skill node's recording of a push of `n` movements, read back: the MCAP file's
    topics, message types and counts, and the Rerun recording's steps beside it."""
    from mcap_ros2.reader import read_ros2_messages

    msgs = list(read_ros2_messages(str(path)))
    counts = Counter((m.channel.topic, m.schema.name) for m in msgs)
    assert counts[("/joint_trajectory", "trajectory_msgs/msg/JointTrajectory")] == n
    assert counts[("/target_pose", "geometry_msgs/msg/PoseStamped")] == n
    assert counts[("/skill/trace", "std_msgs/msg/String")] == n + 1  # + the final record
    assert counts[("/joint_states", "sensor_msgs/msg/JointState")] > n
    assert counts[("/objects/box/pose", "geometry_msgs/msg/PoseStamped")] > n
    assert len(counts) == 5
    traces = [json.loads(m.ros_msg.data) for m in msgs if m.channel.topic == "/skill/trace"]
    assert [r["step"] for r in traces[:-1]] == list(range(n))
    assert traces[-1]["final"] and traces[-1]["status"] == "effect_produced"
    traj = next(m.ros_msg for m in msgs if m.channel.topic == "/joint_trajectory")
    assert list(traj.joint_names)[0] == "right_s0" and len(traj.points) > 1
    from a2l.rollout.recording import read_recording

    cols = read_recording(path.with_suffix(".rrd"))
    assert cols["step"] == list(range(n + 1))
    assert sum(v is not None for v in cols["/rollout/0/world/objects/box:Boxes3D:centers"]) \
        == n + 1


class FakeRobot:
    """A kinematic arm in the test process: publishes Baxter's right arm joints and the box
    (or a NaN box, or none), jumps to the end of each joint trajectory it receives (with
    `listen` False it takes no commands: no driver runs)."""

    def __init__(self, box: str = "ok", nan_after: int = 3, listen: bool = True) -> None:
        import rclpy
        from geometry_msgs.msg import PoseStamped
        from sensor_msgs.msg import JointState
        from std_msgs.msg import String
        from trajectory_msgs.msg import JointTrajectory

        from a2l import _core
        from a2l.robot import arm_spec

        rclpy.init()
        self.node = rclpy.create_node("fake_robot")
        spec = arm_spec("baxter", "right")
        kin = _core.Kinematics(str(spec.urdf), spec.base_link, spec.tip_link)
        self.names = list(kin.joint_names)
        self.q = np.asarray(spec.neutral, dtype=float)
        # the box 15 cm in front of the end-effector, as at the start of a push far
        self.box_xyz = kin.fk(self.q)[:3, 3] + np.array([0.15, 0.0, 0.0])
        self.box, self.nan_after = box, nan_after
        self.jump = True  # carry out a trajectory at once (False: ignore it)
        self.commands: list[float] = []
        self.final: float | None = None
        self.final_step = -1  # the steps the node took, from its final trace record
        self.msgs = (JointState, PoseStamped)
        self.pub_js = self.node.create_publisher(JointState, "joint_states", 10)
        self.pub_box = self.node.create_publisher(PoseStamped, "objects/box/pose", 10)
        if listen:
            self.node.create_subscription(JointTrajectory, "joint_trajectory", self._on_traj,
                                          10)
        self.node.create_subscription(String, "skill/trace", self._on_trace, 10)
        self.node.create_timer(0.02, self._publish)

    def _on_traj(self, msg: Any) -> None:
        self.commands.append(time.monotonic())
        if self.jump:
            self.q = np.asarray(msg.points[-1].positions, dtype=float)

    def _on_trace(self, msg: Any) -> None:
        record = json.loads(msg.data)
        if record.get("final"):
            self.final, self.final_step = time.monotonic(), record["step"]

    def _publish(self) -> None:
        js_t, pose_t = self.msgs
        stamp = self.node.get_clock().now().to_msg()
        if self.box != "missing":
            pose = pose_t()
            pose.header.stamp, pose.header.frame_id = stamp, "base"
            xyz = self.box_xyz
            if self.box == "nan" and len(self.commands) >= self.nan_after:
                xyz = np.array([np.nan, xyz[1], xyz[2]])
            pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = map(float, xyz)
            self.pub_box.publish(pose)
        js = js_t(name=self.names, position=[float(v) for v in self.q])
        js.header.stamp = stamp
        self.pub_js.publish(js)

    def spin_while(self, proc: subprocess.Popen[str], limit: float, after: float = 1.0
                   ) -> None:
        import rclpy

        end = time.monotonic() + limit
        while proc.poll() is None and time.monotonic() < end:
            rclpy.spin_once(self.node, timeout_sec=0.02)
        end = time.monotonic() + after  # anything the node still sends arrives here
        while time.monotonic() < end:
            rclpy.spin_once(self.node, timeout_sec=0.02)

    def close(self) -> None:
        import rclpy

        self.node.destroy_node()
        rclpy.shutdown()


def run_against(robot: FakeRobot, *argv: str) -> tuple[int, str, str]:
    """Run ``a2l ros skill ARGV`` against `robot` until it ends (then close the robot):
    exit code, stdout, stderr."""
    try:
        proc = subprocess.Popen([*A2L, "ros", "skill", *argv], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        robot.spin_while(proc, 60)
        out, err = proc.communicate(timeout=20)
    finally:
        robot.close()
    return proc.returncode, out, err


@pytest.mark.slow
@pytest.mark.timeout(120)
@pytest.mark.parametrize(("box", "expect"), [
    ("missing", "no message on /objects/box/pose within startup_timeout 4.0 s"),
    ("nan", "is not finite"),
])
def test_bad_input_ends_the_skill_node_without_a_command_after_it(
        bundle: Path, domain: int, box: str, expect: str) -> None:
    robot = FakeRobot(box)
    code, out, err = run_against(robot, str(bundle), "--effect", "far",
                                 "--startup_timeout", "4", "--movement_timeout", "0.5")
    assert code == 2, out + err
    assert "a2l ros skill: error:" in err and expect in err
    assert robot.final is not None  # the stop was announced on skill/trace
    if box == "missing":
        assert robot.commands == []
    else:
        assert len(robot.commands) >= robot.nan_after  # it ran, then the NaN came
    assert all(t <= robot.final for t in robot.commands)


@pytest.mark.timeout(120)
def test_the_skill_node_waits_for_the_drivers_subscription(bundle: Path, domain: int) -> None:
    """Inputs flow but nothing subscribes to the commands: the node sends none (it would be
    lost) and stops at startup_timeout naming both command topics."""
    robot = FakeRobot(listen=False)
    code, out, err = run_against(robot, str(bundle), "--effect", "far",
                                 "--startup_timeout", "4")
    assert code == 2, out + err
    assert ("no subscriber on /joint_trajectory or /target_pose within startup_timeout 4.0 s"
            in err), err
    assert robot.final is not None and robot.final_step == 0  # no step, so no command


@pytest.mark.slow
@pytest.mark.timeout(120)
@pytest.mark.parametrize(("how", "code", "stop"), [("sigint", 130, "interrupted"),
                                                   ("timeout", 1, "timeout")])
def test_sigint_and_timeout_stop_the_skill_node_cleanly(bundle: Path, domain: int, how: str,
                                                       code: int, stop: str) -> None:
    robot = FakeRobot()
    robot.jump = False  # the arm never reaches its target: the node waits for the movement
    try:
        proc = subprocess.Popen([*A2L, "ros", "skill", str(bundle), "--effect", "far",
                                 "--movement_timeout", "100",
                                 "--timeout", "100" if how == "sigint" else "8"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        end = time.monotonic() + 60
        while not robot.commands and time.monotonic() < end and proc.poll() is None:
            robot.spin_while(proc, 0.1, after=0.0)
        if how == "sigint":
            proc.send_signal(signal.SIGINT)
        robot.spin_while(proc, 30)
        out, err = proc.communicate(timeout=20)
    finally:
        robot.close()
    assert proc.returncode == code, out + err
    assert f"stop {stop}" in out
    assert len(robot.commands) == 1 and robot.final is not None
    assert all(t <= robot.final for t in robot.commands)


def test_a_bundle_for_another_robot_is_refused(panda: dict[str, Path], domain: int) -> None:
    res = subprocess.run([*A2L, "ros", "skill", str(panda["push_far"]), "--effect", "far",
                          "--robot", "baxter"], capture_output=True, text=True, timeout=60)
    assert res.returncode == 2
    assert "was learned for robot 'panda'" in res.stderr and "'baxter'" in res.stderr


def test_each_node_takes_the_robot_its_bundle_was_learned_for(
        bundle: Path, panda: dict[str, Path], tmp_path: Path) -> None:
    """No robot given: the bundle's (the skill node's arm spec, the sim's scene); a robot
    file's robot must be named; a bundle for another robot is refused by the sim too."""
    from a2l.errors import A2LValueError
    from a2l.ros.robot import check_robot, node_robot, skill_object
    from a2l.ros.sim_node import SimNodeConfig, sim_scene
    from a2l.skills import load_bundle, load_ds_phases, save_bundle
    from a2l.skills.runner import CppSkillRunner

    spec = check_robot(CppSkillRunner(str(panda["grasp"])), "")
    assert (spec.base_link, spec.tip_link) == ("panda_link0", "panda_hand_tcp")
    assert check_robot(CppSkillRunner(str(bundle)), "").tip_link == "right_gripper"
    assert node_robot("", None).name == "baxter"
    assert node_robot("baxter", None, arm="left").name == "baxter-left"
    assert (skill_object("grasp", ""), skill_object("press", ""),
            skill_object("mine", ""), skill_object("grasp", "cup")) == (
        "block", "button", "box", "cup")
    with pytest.raises(A2LValueError, match="arm 'left' is Baxter's"):
        node_robot("panda", None, arm="left")
    z1 = load_bundle(panda["push_far"])
    other = tmp_path / "z1.a2lb"
    save_bundle(dataclasses.replace(z1, robot={**z1.robot, "name": "z1"}), other,
                ds_phases=load_ds_phases(panda["push_far"]))
    with pytest.raises(A2LValueError, match="learned for robot 'z1', not a built-in one"):
        check_robot(CppSkillRunner(str(other)), "")
    trial, scene = sim_scene(SimNodeConfig(bundle=str(panda["grasp"])))
    with scene:
        assert (trial, scene.name, scene.robot_entry.name) == ("grasp", "grasp", "panda")
    with pytest.raises(A2LValueError, match="learned for robot 'panda'"):
        sim_scene(SimNodeConfig(bundle=str(panda["grasp"]), robot="baxter"))


@pytest.mark.slow
@pytest.mark.timeout(120)
def test_a_gripper_turned_away_from_the_skills_orientation_is_refused(
        sideways: Path, domain: int) -> None:
    """The fake arm holds Baxter's neutral pose, its fingers along y: the sideways push
    (learned with them along x) refuses to start, and commands nothing."""
    robot = FakeRobot()
    code, out, err = run_against(robot, str(sideways), "--effect", "right")
    assert code == 2, out + err
    assert "a2l ros skill: error: the gripper starts" in err
    assert "turned 90 degrees: as the skill was learned); turn it there first" in err
    assert robot.commands == [] and robot.final is not None


def test_the_node_tests_pushes_grasps_and_presses_from_its_topics() -> None:
    """The effect tests the node runs without a simulator, and the effects it refuses."""
    from a2l.errors import A2LValueError
    from a2l.rollout.effect_tests import Progress
    from a2l.ros.effects import bundle_effect, node_effect

    def progress(effect: str, obj: list[float], eef: list[float], start: dict[str, str],
                 now: dict[str, str]) -> Progress:
        o = np.array(obj, dtype=float)
        return Progress(effect, o, np.zeros(3), o, np.array(eef, dtype=float), start, now,
                        None)  # type: ignore[arg-type]

    grasped = node_effect("grasped")
    assert grasped.states == ("gripper",) and node_effect("pressed").states == ("light",)
    held = {"gripper": "closed"}
    assert grasped.test(progress("grasped", [0, 0, 0.06], [0, 0, 0.05], {}, held)) == (
        True, True)
    for obj, eef, now in (([0, 0, 0.04], [0, 0, 0.03], held),     # not 5 cm up yet
                          ([0, 0, 0.06], [0, 0, 0.05], {"gripper": "open"}),
                          ([0, 0, 0.06], [0.2, 0, 0.05], held)):  # not in the hand
        assert grasped.test(progress("grasped", obj, eef, {}, now)) == (False, False)
    pressed = node_effect("pressed").test
    assert pressed(progress("pressed", [0, 0, 0], [0, 0, 0], {"light": "off"},
                            {"light": "on"})) == (True, True)
    assert pressed(progress("pressed", [0, 0, 0], [0, 0, 0], {"light": "on"},
                            {"light": "on"})) == (False, False)
    assert node_effect("far").test(progress("far", [0.06, 0, 0], [0, 0, 0], {}, {})) == (
        True, True)
    with pytest.raises(A2LValueError, match="effect 'away': the ROS node tests the effects "
                       "left, right, close, far, grasped, pressed"):
        bundle_effect(["grasped", "away"], "away")
    with pytest.raises(A2LValueError, match="effect 'lifted' is not one of the bundle's: "
                       "left, right, close, far"):
        bundle_effect(["left", "right", "close", "far"], "lifted")


def test_bad_arguments_are_usage_errors(tmp_path: Path, bundle: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    from a2l.cli import main

    for argv, message in (
            (["skill", str(tmp_path / "none.a2lb"), "--effect", "far"], "is not a file"),
            (["skill", str(bundle), "--effect", "far", "--remap", "joint_states"],
             "write it as from:=to"),
            (["sim", "--record", str(tmp_path / "run.txt")], "ends in .mcap"),
            (["sim", "--bundle", str(tmp_path / "none.a2lb")], "--bundle: '")):
        with pytest.raises(SystemExit) as info:
            main(["ros", *argv])
        assert info.value.code == 2
        assert message in capsys.readouterr().err
