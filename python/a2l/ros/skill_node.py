"""The skill node: a skill bundle run on a robot through ROS 2 (``a2l ros skill``).

The robot is any robot entry (:func:`a2l.ros.robot.node_robot`: its chain, joint names and
``tool_down``); a bundle learned for another robot is refused.

Every ``joint_states`` message is a control tick. When the arm is not carrying out a movement,
the tick reads the context (the end-effector by the C++ forward kinematics of the joint
positions, the object's pose, the high-level states), asks the effect test whether the wanted
effect is produced (:mod:`a2l.ros.effects`: a push, ``grasped``, ``pressed``), then runs the
C++ skill step (:class:`a2l.skills.runner.CppSkillRunner`, the one step ``a2l-run`` and the
Python rollouts run) and publishes its movement twice: as a Cartesian target
(``target_pose``) and as a joint trajectory computed by the C++ executor's differential IK
(``joint_trajectory``), plus one trace record (``skill/trace``); an action of the step
(``close``, ``open``) goes to ``gripper/command``. A movement is over when the end-effector
is within ``goal_tolerance`` of its target (after an action, once ``states/gripper`` says
the gripper did it), or after ``movement_timeout`` (a push held back by the object): then
the next tick steps again.

Both commands carry the orientation the skill was learned with: the gripper pointing down
(the arm's :attr:`a2l.robot.ArmSpec.down`), turned about the vertical by the bundle's scene
setting ``gripper_yaw`` (:attr:`a2l.skills.spec.SkillSpec.scene_settings`; the sideways
pushes learn with 90 degrees), as every movement of the simulated scenes asks for it
(:func:`a2l.robot.gripper.gripper_down`). The trajectory's IK turns the gripper toward it at
most ``max_angular_speed``; an arm whose gripper starts more than ``orientation_tolerance``
from it is refused (bad input) before any command. The scene settings that concern the world
(where the arm starts, the objects) are the robot's, or ``a2l ros sim --bundle``'s.

The node stops at the effect (exit code 0), at a stop status of the step (``step_cap``,
``unknown_context``: 1), after ``timeout`` (1), on SIGINT (130), and on bad input (2): a
bundle for another robot, an input topic silent for ``input_timeout``, a pose or a joint
position that is not finite, a gripper turned away from the skill's orientation at the start,
an effect the node cannot test from its topics. After a stop it publishes no command. Topics
and frames: :mod:`a2l.ros.topics`, ``docs/ros.md``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from a2l import _core
from a2l.errors import A2LError, A2LValueError
from a2l.rollout.effect_tests import Progress
from a2l.ros import topics as T
from a2l.ros.effects import bundle_effect
from a2l.ros.orientation import commanded_orientation
from a2l.ros.robot import check_robot, skill_object
from a2l.ros.spin import declare_config, overrides
from a2l.skills.runner import CppSkillRunner

__all__ = ["SkillNodeConfig", "SkillNodeResult", "make_skill_node"]


@dataclass(frozen=True)
class SkillNodeConfig:
    """The skill node's ROS parameters (their names and defaults).

    Attributes
    ----------
    bundle : str
        The skill bundle (.a2lb).
    effect : str
        The wanted effect: a push (left, right, close, far), grasped or pressed
        (:mod:`a2l.ros.effects`).
    robot : str
        The robot whose joints joint_states carries: a built-in name or a robot file's path;
        empty: the bundle's robot when it is a built-in one, else Baxter.
    arm : str
        Baxter's arm (right, left: robot baxter-left).
    object : str
        The object the skill acts on (its pose on objects/<object>/pose); empty: the
        object of the demonstrated skill of the bundle's name (block for grasp, button for
        press), else box.
    frame : str
        The frame of poses in and out (the arm's base frame); empty: the robot's base link
        (Baxter's: base).
    startup_timeout : float
        Seconds to wait for the first message of every input topic, and for a subscriber
        on joint_trajectory or target_pose (the robot's driver: a command sent before it
        listens would be lost).
    input_timeout : float
        Seconds an input topic may stay silent between two messages.
    movement_timeout : float
        Seconds a movement may take before the next step is taken from where the arm is.
    timeout : float
        Seconds the whole run may take.
    goal_tolerance : float
        A movement is over within this distance of its target (m).
    trajectory_period : float
        Sample period of the joint trajectory (s).
    max_speed : float
        End-effector speed of the joint trajectory (m/s).
    gripper_yaw : float
        Turn of the downward-pointing gripper about the vertical that both commands carry
        (degrees, in [-180, 180]); NaN (the default): the bundle's scene setting, 0 if it
        names none.
    orientation_tolerance : float
        Most angle between the gripper's orientation at the start and the commanded one
        (rad); more is bad input (turn the gripper first).
    max_angular_speed : float
        Most rate at which the joint trajectory turns the gripper toward the commanded
        orientation (rad/s).
    """

    bundle: str = ""
    effect: str = ""
    robot: str = ""
    arm: str = "right"
    object: str = ""
    frame: str = ""
    startup_timeout: float = 30.0
    input_timeout: float = 5.0
    movement_timeout: float = 3.0
    timeout: float = 120.0
    goal_tolerance: float = 0.005
    trajectory_period: float = 0.004
    max_speed: float = 0.25
    gripper_yaw: float = math.nan
    orientation_tolerance: float = 0.5
    max_angular_speed: float = 0.5


@dataclass
class SkillNodeResult:
    """How a run ended: exit code, stop status, message, steps taken."""

    code: int
    status: str
    message: str
    steps: int


def make_skill_node(params: dict[str, Any], recorder: Any = None) -> Any:
    """The rclpy node (its class is made here: rclpy is imported only when a node is made)."""
    from geometry_msgs.msg import PoseStamped
    from rclpy.node import Node
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Bool, String
    from trajectory_msgs.msg import JointTrajectory

    class SkillNode(Node):
        def __init__(self) -> None:
            super().__init__("a2l_skill", parameter_overrides=overrides(params))
            self.cfg = declare_config(self, SkillNodeConfig)
            self.recorder = recorder
            self.result: SkillNodeResult | None = None
            self.t0 = time.monotonic()
            self.runner = CppSkillRunner(self.cfg.bundle)
            self._setup_skill()
            self.object = skill_object(str(self.runner.skill.name), self.cfg.object)
            self.js: Any = None
            self.js_time = -1.0
            self.obj: Any = None
            self.obj_time = -1.0
            self.states: dict[str, tuple[str, float]] = {}
            self.last: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
            self.var_names = [str(v.name) for v in self.runner.skill.variables]
            self.start_obj: NDArray[np.float64] | None = None
            self.start_states: dict[str, str] = {}
            self.target: NDArray[np.float64] | None = None
            self.awaited: tuple[str, str] | None = None  # the state an action waits for
            self.cmd_time = 0.0
            self.k = 0
            qos = 10
            self.create_subscription(JointState, T.JOINT_STATES, self._on_joints, qos)
            self.create_subscription(PoseStamped, T.object_topic(self.object),
                                     self._on_object, qos)
            for s in self.state_names:
                self.create_subscription(Bool, T.state_topic(s),
                                         lambda m, s=s: self._on_state(s, m), qos)
            self.pub_traj = self.create_publisher(JointTrajectory, T.JOINT_TRAJECTORY, qos)
            self.pub_pose = self.create_publisher(PoseStamped, T.TARGET_POSE, qos)
            self.pub_grip = self.create_publisher(Bool, T.GRIPPER, qos)
            self.pub_trace = self.create_publisher(String, T.TRACE, qos)
            self.create_timer(0.05, self._watchdog)

        # --- set-up ------------------------------------------------------------------
        def _setup_skill(self) -> None:
            cfg = self.cfg
            effect = bundle_effect(list(self.runner.skill.effect_values), cfg.effect)
            self.test = effect.test
            if not 0 < cfg.goal_tolerance < self.runner.step_length / 2:
                raise A2LValueError(f"goal_tolerance {cfg.goal_tolerance} must be in (0, "
                                    f"{self.runner.step_length / 2}) (half a movement)")
            spec = check_robot(self.runner, cfg.robot, cfg.arm)
            self.frame = cfg.frame or spec.base_link
            if not 0 < cfg.orientation_tolerance <= math.pi:
                raise A2LValueError(f"orientation_tolerance {cfg.orientation_tolerance} must "
                                    "be in (0, pi] rad")
            if not cfg.max_angular_speed > 0:
                raise A2LValueError(f"max_angular_speed {cfg.max_angular_speed} must be > 0")
            self.aim = commanded_orientation(str(self.runner.path), spec.down, cfg.gripper_yaw)
            self.get_logger().info(f"commanded orientation: {self.aim.describe()}")
            self.kin = _core.Kinematics(str(spec.urdf), spec.base_link, spec.tip_link)
            self.joint_names = list(self.kin.joint_names)
            opts = _core.ExecutorOptions()
            opts.period = cfg.trajectory_period
            opts.max_speed = cfg.max_speed
            opts.max_angular_speed = cfg.max_angular_speed
            opts.position_tolerance = 1e-4
            opts.watchdog_ticks = 5000
            self.ik = _core.Executor(self.kin, np.asarray(spec.neutral), opts)
            self.state_names = [str(v.name) for v in self.runner.skill.variables
                                if v.kind.name == "high_level"]
            # the states the effect test reads, beside the table's (a press reads the light)
            self.state_names += [s for s in effect.states if s not in self.state_names]
            for s in self.state_names:
                T.bool_to_state(s, False)  # a clear error for a state with no Bool mapping

        # --- inputs ------------------------------------------------------------------
        def _record(self, topic: str, msg: Any) -> None:
            if self.recorder is not None:
                self.recorder.message(self.resolve_topic_name(topic), msg)

        def _rerun(self, status: str, label: str = "", movement: int = -1,
                   bins: list[int] | None = None, target: Any = None) -> None:
            rerun = getattr(self.recorder, "rerun", None)
            if rerun is None or self.last is None:
                return
            eef, obj = self.last
            rerun.step(self.k, eef, obj, seconds=time.monotonic() - self.t0, label=label,
                       movement=movement, status=status, target=target,
                       bins=None if bins is None else dict(zip(self.var_names, bins,
                                                                strict=False)),
                       object_name=self.object)

        def _on_object(self, msg: Any) -> None:
            self._record(T.object_topic(self.object), msg)
            self.obj, self.obj_time = msg, time.monotonic()

        def _on_state(self, name: str, msg: Any) -> None:
            self._record(T.state_topic(name), msg)
            self.states[name] = (T.bool_to_state(name, msg.data), time.monotonic())

        def _on_joints(self, msg: Any) -> None:
            self._record(T.JOINT_STATES, msg)
            self.js, self.js_time = msg, time.monotonic()
            if self.result is None:
                self._guard(self._tick)

        def _guard(self, fn: Any) -> None:
            try:
                fn()
            except A2LError as exc:
                self.stop(2, "bad_input", str(exc))

        def _watchdog(self) -> None:
            if self.result is not None:
                return
            now = time.monotonic()
            if now - self.t0 > self.cfg.timeout:
                self.stop(1, "timeout", f"no effect within timeout {self.cfg.timeout} s")
                return
            silent = self._silent(now)
            if silent:
                self.stop(2, "bad_input", silent)

        def _silent(self, now: float) -> str | None:
            """What has been silent too long (an input topic, the robot's driver), or None."""
            cfg = self.cfg
            last = {self.resolve_topic_name(T.JOINT_STATES): self.js_time,
                    self.resolve_topic_name(T.object_topic(self.object)): self.obj_time}
            for s in self.state_names:
                last[self.resolve_topic_name(T.state_topic(s))] = self.states.get(
                    s, ("", -1.0))[1]
            late = now - self.t0 > cfg.startup_timeout
            for topic, t in last.items():
                if t < 0 and late:
                    return f"no message on {topic} within startup_timeout {cfg.startup_timeout} s"
                if t >= 0 and now - t > cfg.input_timeout:
                    return f"no message on {topic} within input_timeout {cfg.input_timeout} s"
            if late and self._driver_awaited():
                return (f"no subscriber on {self.resolve_topic_name(T.JOINT_TRAJECTORY)} or "
                        f"{self.resolve_topic_name(T.TARGET_POSE)} within startup_timeout "
                        f"{cfg.startup_timeout} s (is the robot's driver running?)")
            return None

        def _driver_awaited(self) -> bool:
            """Whether the first command still waits for the robot's driver: nothing
            subscribes to the commands yet (a command published before its subscription is
            matched would be lost: the topics keep no history)."""
            return self.k == 0 and (self.pub_traj.get_subscription_count() == 0
                                    and self.pub_pose.get_subscription_count() == 0)

        # --- the control tick ----------------------------------------------------------
        def _tick(self) -> None:
            if (self.obj is None or any(s not in self.states for s in self.state_names)
                    or self._driver_awaited()):
                return  # waiting for the first messages and the driver (the watchdog times out)
            q = T.joint_positions(self.js, self.joint_names)
            obj = T.pose_position(self.obj, self.frame)
            eef = np.asarray(self.kin.fk(q)[:3, 3], dtype=float)
            self.last = (eef, obj)
            now = time.monotonic()
            if self.target is not None:
                waiting = (self.awaited is not None and self.states[self.awaited[0]][0]
                           != self.awaited[1])
                if ((waiting or np.linalg.norm(eef - self.target) > self.cfg.goal_tolerance)
                        and now - self.cmd_time < self.cfg.movement_timeout):
                    return  # still moving, or the gripper not yet where it was sent
                self.target, self.awaited = None, None
            states = {s: v for s, (v, _) in self.states.items()}
            if self.start_obj is None:
                self.aim.check_start(np.asarray(self.kin.fk(q))[:3, :3],
                                     self.cfg.orientation_tolerance)
                self.start_obj, self.start_states = obj.copy(), dict(states)
            done, ok = self.test(Progress(self.cfg.effect, obj - self.start_obj,
                                          self.start_obj, obj, eef, self.start_states, states,
                                          None))
            if done:
                changed = {k: v for k, v in states.items() if self.start_states.get(k) != v}
                self.stop(0 if ok else 1, "effect_produced" if ok else "effect_failed",
                          f"object moved {_xyz(obj - self.start_obj)} m"
                          + "".join(f", {k} {v}" for k, v in changed.items()))
                return
            if self.k >= self.runner.step_cap:
                self.stop(1, "step_cap", f"{self.k} steps without the effect")
                return
            t = time.perf_counter()
            out = self.runner.step(eef, obj, self.cfg.effect, states)
            step_s = time.perf_counter() - t
            rec = self.runner.trace()[-1]
            if out.status != "ok":
                self._trace(rec, out.status, "", step_s, None)
                self.stop(1, out.status, f"the skill step stopped: {out.status}")
                return
            if out.action is not None:
                self._trace(rec, "ok", out.action, step_s, None)
                if out.action in ("open", "close"):
                    self.pub_grip.publish(Bool(data=out.action == "close"))
                    if "gripper" in self.states:  # the next step once the robot says so
                        self.awaited = ("gripper", T.bool_to_state("gripper",
                                                                   out.action == "close"))
                self.cmd_time, self.target = now, eef.copy()
            else:
                target = eef + np.asarray(out.displacement, dtype=float)
                self._command(q, target, rec, out.label, step_s)
            self.k += 1

        def _command(self, q: NDArray[np.float64], target: NDArray[np.float64],
                     rec: _core.TraceRecord, label: str, step_s: float) -> None:
            ex = self.ik
            t_ik = time.perf_counter()
            ex.reset(q)
            status = ex.set_orientation(self.aim.rotation)
            if status == _core.Status.ok:
                status = ex.set_target(target)
            points = []
            while status == _core.Status.ok and not ex.reached:
                status = ex.tick()
                points.append(np.asarray(ex.q, dtype=float))
            ik_s = time.perf_counter() - t_ik
            if status != _core.Status.ok:
                name = _core.status_name(status)
                self._trace(rec, name, label, step_s, None)
                self.stop(1, name, f"target {_xyz(target)}: {name}")
                return
            stamp = self.get_clock().now().to_msg()
            traj = T.joint_trajectory(self.joint_names, points, self.cfg.trajectory_period,
                                      stamp, self.frame)
            pose = T.pose_stamped(target, stamp, self.frame, self.aim.quaternion)
            self.pub_traj.publish(traj)
            self.pub_pose.publish(pose)
            latency = time.time() - T.stamp_seconds(self.js.header.stamp)
            self._record(T.JOINT_TRAJECTORY, traj)
            self._record(T.TARGET_POSE, pose)
            self._trace(rec, "ok", label, step_s, latency, target, ik_s)
            self._rerun("ok", label, rec.movement, list(rec.bins), target)
            self.cmd_time, self.target = time.monotonic(), target

        def _trace(self, rec: _core.TraceRecord, status: str, label: str, step_s: float,
                   latency: float | None, target: NDArray[np.float64] | None = None,
                   ik_s: float | None = None) -> None:
            msg = String(data=T.trace_json({
                "step": self.k, "bins": list(rec.bins), "movement": rec.movement,
                "label": label, "probability": rec.probability, "status": status,
                "phase": rec.phase, "step_us": step_s * 1e6,
                "ik_us": None if ik_s is None else ik_s * 1e6,
                "latency_ms": None if latency is None else latency * 1e3,
                "target": None if target is None else target}))
            self.pub_trace.publish(msg)
            self._record(T.TRACE, msg)

        def stop(self, code: int, status: str, message: str) -> None:
            """End the run: no command is published after this."""
            if self.result is not None:
                return
            self.result = SkillNodeResult(code, status, message, self.k)
            for pub in (self.pub_traj, self.pub_pose, self.pub_grip):
                self.destroy_publisher(pub)
            msg = String(data=T.trace_json({"step": self.k, "status": status,
                                            "message": message, "final": True}))
            self.pub_trace.publish(msg)
            self._record(T.TRACE, msg)
            self._rerun(status)

    return SkillNode()


def _xyz(v: NDArray[np.float64]) -> str:
    return "(" + ", ".join(f"{x:.3f}" for x in v) + ")"

