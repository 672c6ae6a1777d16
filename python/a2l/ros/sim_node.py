"""A simulated robot behind the skill node's topics (``a2l ros sim``): a PyBullet scene of
:mod:`a2l.sim` (on any robot the scenes take: Baxter's right arm by default, or the robot the
bundle was learned for; ``robot`` names another, or a robot file) as a ROS 2 node.

It publishes, at ``rate`` Hz and after every command, the arm's ``joint_states``, one
``objects/<name>/pose`` per object (position from the scene's ground truth or its cameras;
orientation identity) and one ``states/<name>`` per high-level state with a Bool mapping
(:data:`a2l.ros.topics.BOOL_STATES`: the light, the gripper). It carries out
``joint_trajectory`` (``command="joint"``, the scene's ``follow_joint_trajectory``) or
``target_pose`` (``command="pose"``, a straight line of the end-effector,
:meth:`a2l.sim.Scene.move_by`) and ``gripper/command``. The physics runs while a command is
carried out (faster than real time), and the node publishes the new state when it is done.

The world starts as ``a2l skill run`` starts it: ``trial`` places the object and the arm as a
trial of a demonstrated skill, in that skill's scene settings (the sideways pushes turn the
gripper 90 degrees: :func:`a2l.lfd.library.make_skill_scene`); ``bundle`` takes the scene
settings its skill was learned with (:attr:`a2l.skills.spec.SkillSpec.scene_settings`) and,
without ``trial``, the trial of the skill of its name; ``gripper_yaw`` overrides the turn.

At exit it writes its ground truth (``truth`` file, JSON): the objects at the start and at
the end, the effect of the episode, and every command received with its stamp.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from a2l.atomic import atomic_write_text
from a2l.errors import A2LValueError
from a2l.ros import topics as T
from a2l.ros.spin import declare_config, overrides

__all__ = ["SimNodeConfig", "make_sim_node"]

COMMANDS = ("joint", "pose")


@dataclass(frozen=True)
class SimNodeConfig:
    """The simulated robot's ROS parameters.

    Attributes
    ----------
    scene : str
        The a2l.sim scene (a PyBullet one: push, press, grasp, grasp_light); empty: the
        trial skill's scene, else push.
    robot : str
        The robot: a built-in name or a robot file's path; empty: the robot the bundle was
        learned for when it is a built-in one, else Baxter.
    trial : str
        Place the object and the arm as a trial of this demonstrated skill, in its scene
        settings (push_far...; empty: the bundle's skill if it is one, else the scene's own
        reset).
    bundle : str
        A skill bundle whose scene settings the scene takes (the gripper's turn its skill
        was learned with) and, without trial, whose skill of the library's name sets the
        trial.
    gripper_yaw : float
        Turn of the downward-pointing gripper about the vertical (degrees); NaN (the
        default): the bundle's, else the trial skill's, else 0.
    seed : int
        Scene and trial seed.
    step : float
        Movement length of the scene (m).
    rate : float
        State publishing rate (Hz).
    command : str
        Which command to carry out: joint (joint_trajectory) or pose (target_pose).
    source : str
        Object poses from ground_truth or perceived (the cameras).
    frame : str
        The frame of the poses; empty: the robot's base link (Baxter's: base).
    truth : str
        Where to write the ground truth at exit (JSON; empty: nowhere).
    """

    scene: str = ""
    robot: str = ""
    trial: str = ""
    bundle: str = ""
    gripper_yaw: float = math.nan
    seed: int = 0
    step: float = 0.02
    rate: float = 50.0
    command: str = "joint"
    source: str = "ground_truth"
    frame: str = ""
    truth: str = ""


def make_sim_node(params: dict[str, Any], recorder: Any = None) -> Any:
    """The simulated robot's rclpy node; ``node.close()`` writes the truth file."""
    from geometry_msgs.msg import PoseStamped
    from rclpy.node import Node
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Bool
    from trajectory_msgs.msg import JointTrajectory

    from a2l.lfd.library import reset_for_trial
    from a2l.rollout.world import observe

    class SimNode(Node):
        def __init__(self) -> None:
            super().__init__("a2l_sim", parameter_overrides=overrides(params))
            cfg = self.cfg = declare_config(self, SimNodeConfig)
            if cfg.command not in COMMANDS:
                raise A2LValueError(f"command {cfg.command!r} is not one of {COMMANDS}")
            self.recorder = recorder
            self.trial, self.scene = sim_scene(cfg)
            if not hasattr(self.scene, "follow_joint_trajectory"):
                self.scene.close()
                raise A2LValueError(f"scene {self.scene.name!r} has no arm; use a PyBullet "
                                    "scene")
            self.robot = self.scene.robot_entry.name
            self.frame = cfg.frame or self.scene.robot_entry.base_link
            if self.trial:
                reset_for_trial(self.scene, self.trial, cfg.seed)
            self.joint_names = list(self.scene.kinematics.joint_names)
            self.start = self.scene.ground_truth()
            self.commands: list[dict[str, Any]] = []
            self.pub_js = self.create_publisher(JointState, T.JOINT_STATES, 10)
            self.pub_obj = {n: self.create_publisher(PoseStamped, T.object_topic(n), 10)
                            for n in self.scene.object_names}
            self.pub_state = {s: self.create_publisher(Bool, T.state_topic(s), 10)
                              for s in self.scene.state_names if s in T.BOOL_STATES}
            if cfg.command == "joint":
                self.create_subscription(JointTrajectory, T.JOINT_TRAJECTORY,
                                         self._on_trajectory, 10)
            else:
                self.create_subscription(PoseStamped, T.TARGET_POSE, self._on_pose, 10)
            self.create_subscription(Bool, T.GRIPPER, self._on_gripper, 10)
            self.create_timer(1.0 / cfg.rate, self.publish_state)

        def _log(self, topic: str, msg: Any, note: str) -> None:
            self.commands.append({"topic": topic, "stamp": T.stamp_seconds(msg.header.stamp)
                                  if hasattr(msg, "header") else None,
                                  "received": time.time(), "result": note})

        def _on_trajectory(self, msg: Any) -> None:
            try:
                index = [list(msg.joint_names).index(n) for n in self.joint_names]
            except ValueError:
                self._log(T.JOINT_TRAJECTORY, msg, f"refused: joints {list(msg.joint_names)}")
                return
            t = [0.0] + [T.stamp_seconds(p.time_from_start) for p in msg.points]
            q = [self.scene.joint_positions()] + [
                np.asarray(p.positions, dtype=float)[index] for p in msg.points]
            try:
                err = self.scene.follow_joint_trajectory(t, np.asarray(q))
            except A2LValueError as exc:
                self._log(T.JOINT_TRAJECTORY, msg, f"refused: {exc}")
                return
            self._log(T.JOINT_TRAJECTORY, msg, f"ok: final joint error {err:.4f} rad")
            self.publish_state()

        def _on_pose(self, msg: Any) -> None:
            try:
                target = T.pose_position(msg, self.frame)
            except A2LValueError as exc:
                self._log(T.TARGET_POSE, msg, f"refused: {exc}")
                return
            res = self.scene.move_by(target - self.scene.eef_position())
            self._log(T.TARGET_POSE, msg, f"{res.status}")
            self.publish_state()

        def _on_gripper(self, msg: Any) -> None:
            (self.scene.close_gripper if msg.data else self.scene.open_gripper)()
            self._log(T.GRIPPER, msg, "ok")
            self.publish_state()

        def publish_state(self) -> None:
            """Publish joint states, object poses and high-level states now."""
            stamp = self.get_clock().now().to_msg()
            obs = observe(self.scene, self.cfg.source)
            js = JointState(name=self.joint_names,
                            position=[float(v) for v in self.scene.joint_positions()])
            js.header.stamp, js.header.frame_id = stamp, self.frame
            for name, pub in self.pub_obj.items():
                xyz = obs["objects"].get(name)
                if xyz is None:
                    continue  # not seen: no message
                msg = T.pose_stamped(xyz, stamp, self.frame)
                pub.publish(msg)
                self._record(T.object_topic(name), msg)
            for s, pub in self.pub_state.items():
                msg = Bool(data=T.state_to_bool(s, obs["states"][s]))
                pub.publish(msg)
                self._record(T.state_topic(s), msg)
            self.pub_js.publish(js)
            self._record(T.JOINT_STATES, js)

        def _record(self, topic: str, msg: Any) -> None:
            if self.recorder is not None:
                self.recorder.message(self.resolve_topic_name(topic), msg)

        def truth(self) -> dict[str, Any]:
            """The ground truth: start and end objects, the episode's effect, commands."""
            end = self.scene.ground_truth()
            return {"scene": self.scene.name, "robot": self.robot, "seed": self.cfg.seed,
                    "trial": self.trial,
                    "gripper_yaw": getattr(self.scene.config, "gripper_yaw", None),
                    "start": {n: list(map(float, v)) for n, v in self.start["objects"].items()},
                    "end": {n: list(map(float, v)) for n, v in end["objects"].items()},
                    "effect": self.scene.observe_effect(since="episode",
                                                        source="ground_truth"),
                    "eef": [float(v) for v in self.scene.eef_position()],
                    "commands": self.commands}

        def close(self) -> None:
            """Write the truth file (if asked) and release the scene."""
            if self.cfg.truth:
                atomic_write_text(self.cfg.truth, json.dumps(self.truth(), indent=1))
            self.scene.close()

    return SimNode()


def sim_scene(cfg: SimNodeConfig) -> tuple[str, Any]:
    """The trial (a skill's name or "") and the scene of `cfg`: on its robot (the bundle's
    when empty, :func:`a2l.ros.robot.node_robot`), the trial skill's scene when `cfg` names
    none, with the scene settings the scene has (:func:`a2l.sim.settings_for`) of, first,
    ``gripper_yaw`` (when not NaN), then the bundle's, then the trial skill's recipe
    (:func:`a2l.lfd.library.make_skill_scene`).

    Raises
    ------
    a2l.A2LValueError
        A trial that is not a demonstrated skill; a bundle that does not load
        (:class:`a2l.BundleError`); a setting out of its range; an unknown robot, or a
        bundle learned for another one.
    """
    from a2l.lfd.library import SKILLS, make_skill_scene
    from a2l.ros.robot import node_robot
    from a2l.sim import make_scene, settings_for
    from a2l.skills.bundle import load_bundle

    trial, settings, learned_for = cfg.trial, {}, None
    if cfg.bundle:
        spec = load_bundle(cfg.bundle)
        settings, learned_for = spec.scene_settings, spec.robot
        if not trial and spec.name in SKILLS:
            trial = spec.name
    if not math.isnan(cfg.gripper_yaw):
        settings["gripper_yaw"] = cfg.gripper_yaw
    if trial and trial not in SKILLS:
        raise A2LValueError(f"trial {trial!r} is not a demonstrated skill; known: "
                            f"{', '.join(SKILLS)}")
    entry = node_robot(cfg.robot, learned_for)
    entry.check_learned_for(learned_for, f"skill bundle '{cfg.bundle}'")
    robot = cfg.robot or entry.name
    scene = cfg.scene or (SKILLS[trial].scene if trial else "push")
    common = {"seed": cfg.seed, "step": cfg.step, "context_source": cfg.source,
              **settings_for(scene, settings)}
    if trial:  # the trial skill's own settings under those
        return trial, make_skill_scene(trial, scene=scene, robot=robot, **common)
    return trial, make_scene(scene, robot=robot, **common)
