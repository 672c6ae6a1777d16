"""ROS 2 bridge: end-to-end latency from a joint state to the command for it, through ROS 2
(the skill node in its own process), beside the C++ step time measured in the same run.

The benchmark process is a kinematic robot (Baxter's right arm): it publishes one
``joint_states`` message, the skill node (``a2l ros skill``, a learned ``push_far`` bundle)
answers with a ``joint_trajectory``, the robot jumps to its last point and publishes the next
joint state at once. The latency is the time from sending a joint state to receiving the
command it caused (both ends in this process: one clock), so it holds two DDS hops, the
node's forward kinematics, the effect test, the C++ step, the C++ executor's IK of the
trajectory and the messages' (de)serialisation. The node's own trace gives, for the same
steps, the C++ step's time as the node measured it (``step_us``: the pybind11 call included)
and the trajectory's IK time (``ik_us``); the bare C++ step (``a2l._core.step`` on a prepared
context) is timed in this process on the contexts the node saw. The box stays where it is, so
each run ends at a stop of the step or of the IK (the arm pushed through the box reaches a
joint velocity limit); RUNS runs of the node are pooled.
"""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np

TITLE = "ROS 2 bridge (a2l ros skill: joint state -> command latency, C++ step time)"
PACKAGES = ("ros-rclpy", "ros-rmw-fastrtps-cpp")

RUNS = 10  # skill node processes, one after the other
N_STEPS = 10_000  # calls of the bare C++ step timed in this process


class _Robot:
    def __init__(self) -> None:
        import rclpy
        from geometry_msgs.msg import PoseStamped
        from sensor_msgs.msg import JointState
        from std_msgs.msg import String
        from trajectory_msgs.msg import JointTrajectory

        from a2l import _core
        from a2l.robot import arm_spec

        self.rclpy = rclpy
        self.node = rclpy.create_node("bench_robot")
        spec = arm_spec("baxter", "right")
        kin = self.kin = _core.Kinematics(str(spec.urdf), spec.base_link, spec.tip_link)
        self.names = list(kin.joint_names)
        self.neutral = np.asarray(spec.neutral, dtype=float)
        self.box = kin.fk(self.neutral)[:3, 3] + np.array([0.15, 0.0, 0.0])
        self.js_t, self.pose_t = JointState, PoseStamped
        self.pub_js = self.node.create_publisher(JointState, "joint_states", 10)
        self.pub_box = self.node.create_publisher(PoseStamped, "objects/box/pose", 10)
        self.node.create_subscription(JointTrajectory, "joint_trajectory", self._on_cmd, 10)
        self.node.create_subscription(String, "skill/trace", self._on_trace, 10)
        self.reset()

    def reset(self) -> None:
        self.q = self.neutral.copy()
        self.sent = 0.0
        self.latencies: list[float] = []
        self.traces: list[dict] = []
        self.contexts: list[tuple[np.ndarray, np.ndarray]] = []

    def publish(self) -> None:
        stamp = self.node.get_clock().now().to_msg()
        pose = self.pose_t()
        pose.header.stamp, pose.header.frame_id = stamp, "base"
        pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = map(float, self.box)
        self.pub_box.publish(pose)
        js = self.js_t(name=self.names, position=[float(v) for v in self.q])
        js.header.stamp = stamp
        self.sent = time.perf_counter()
        self.pub_js.publish(js)
        self.contexts.append((self.kin.fk(self.q)[:3, 3].copy(), self.box.copy()))

    def _on_cmd(self, msg) -> None:
        self.latencies.append(time.perf_counter() - self.sent)
        self.q = np.asarray(msg.points[-1].positions, dtype=float)
        self.publish()

    def _on_trace(self, msg) -> None:
        self.traces.append(json.loads(msg.data))

    def run(self, proc: subprocess.Popen) -> None:
        last = 0.0
        while proc.poll() is None:
            self.rclpy.spin_once(self.node, timeout_sec=0.01)
            if time.perf_counter() - self.sent > 0.5 and time.perf_counter() - last > 0.5:
                last = time.perf_counter()
                self.publish()  # start (or restart) the exchange
        end = time.perf_counter() + 0.5
        while time.perf_counter() < end:
            self.rclpy.spin_once(self.node, timeout_sec=0.01)


def _bare_step(bundle: Path, contexts: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Microseconds of one ``a2l._core.step`` call on each context (the state reset before
    each, outside the timing), N_STEPS calls in all."""
    from a2l import _core
    from a2l.skills.runner import CppSkillRunner

    runner = CppSkillRunner(bundle)
    ctxs = [runner.skill.context(e, o, "far", {}) for e, o in contexts]
    out = np.empty(N_STEPS)
    for i in range(N_STEPS):
        ctx = ctxs[i % len(ctxs)]
        runner.state.reset()
        t = time.perf_counter()
        _core.step(runner.skill, runner.state, ctx)
        out[i] = time.perf_counter() - t
    return out * 1e6


def run() -> str:
    from a2l.lfd.library import learn_recipe

    os.environ["ROS_DOMAIN_ID"] = str(random.SystemRandom().randint(1, 100))
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    import rclpy

    lat, step_us, ik_us, node_ms, stops, contexts = [], [], [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        bundle = learn_recipe("push_far", Path(tmp)).bundle
        rclpy.init()
        robot = _Robot()
        try:
            for _ in range(RUNS):
                robot.reset()
                proc = subprocess.Popen(
                    [sys.executable, "-m", "a2l.cli", "ros", "skill", str(bundle),
                     "--effect", "far", "--timeout", "60"],
                    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                robot.run(proc)
                proc.communicate(timeout=30)
                # the first command of a run waits for discovery: left out
                lat += robot.latencies[1:]
                steps = [t for t in robot.traces if t.get("status") == "ok"]
                step_us += [t["step_us"] for t in steps]
                ik_us += [t["ik_us"] for t in steps]
                node_ms += [t["latency_ms"] for t in steps[1:]]
                contexts += robot.contexts
                final = [t for t in robot.traces if t.get("final")]
                stops.append(final[-1]["status"] if final else "none")
        finally:
            robot.node.destroy_node()
            rclpy.shutdown()
        bare_us = _bare_step(bundle, contexts)
    lat_ms = np.asarray(lat) * 1e3

    def row(name: str, v: np.ndarray, unit: str) -> str:
        return (f"| {name} | {len(v)} | {np.median(v):.3f} {unit} | "
                f"{np.percentile(v, 99):.3f} {unit} | {np.max(v):.3f} {unit} |")

    return "\n".join([
        f"{RUNS} runs of the skill node (stops: "
        f"{', '.join(f'{k} {v}' for k, v in Counter(stops).items())}); Fast DDS, localhost "
        "discovery, default QoS (reliable, depth 10). The first command of each run "
        "(discovery) is left out.",
        "",
        "| what | samples | median | p99 | max |",
        "|---|---|---|---|---|",
        row("joint state sent -> its command received (round trip through ROS 2)",
            lat_ms, "ms"),
        row("in the node: joint state stamp -> command sent", np.asarray(node_ms), "ms"),
        row("skill step in the node (`CppSkillRunner.step`)", np.asarray(step_us), "µs"),
        row("C++ executor IK of the trajectory (in the node)", np.asarray(ik_us), "µs"),
        row("bare C++ step `a2l._core.step` on the same contexts, called from Python",
            bare_us, "µs"),
        "",
        "The skill step in the node is `CppSkillRunner.step`: the context built from names, "
        "the C++ step, its result converted; the bare C++ step is the pybind11 call alone "
        "(the step in C++ without Python: the runtime section).",
        f"Median round trip / median bare step: {np.median(lat_ms) * 1e3 / np.median(bare_us):.0f}"
        f"x; / median step in the node: {np.median(lat_ms) * 1e3 / np.median(step_us):.0f}x. "
        "The step is not what limits a control loop through ROS 2: the transport, the Python "
        "node and the message handling are.",
    ])
