"""The two nodes run until done: :func:`run_skill` (``a2l ros skill``) and :func:`run_sim`
(``a2l ros sim``), each in its own process, talking over ROS 2."""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from a2l.errors import A2LError
from a2l.ros.sim_node import make_sim_node
from a2l.ros.skill_node import SkillNodeResult, make_skill_node
from a2l.ros.spin import ros_session, spin_until

__all__ = ["run_sim", "run_skill"]


def run_skill(params: dict[str, Any], args: Sequence[str] = (), record: str | None = None,
              linger: float = 0.3) -> SkillNodeResult:
    """Run the skill node with ROS parameters `params` until it stops.

    Parameters
    ----------
    params : dict
        :class:`a2l.ros.skill_node.SkillNodeConfig` fields.
    args : sequence of str
        rclpy arguments (:func:`a2l.ros.spin.ros_args`: remaps, namespace).
    record : str, optional
        Write the node's messages there (``.mcap``) and its steps to a Rerun recording
        beside it (``.rrd``; :mod:`a2l.ros.record`).
    linger : float
        Seconds to keep spinning after the stop so the final trace message goes out.

    Returns
    -------
    SkillNodeResult
        Exit code 0 at the effect, 1 on another stop, 2 on bad input, 130 on SIGINT.
    """
    recorder = None
    if record:
        from a2l.ros.record import RosRecorder

        recorder = RosRecorder(Path(record))
    with ros_session(args):
        try:
            node = make_skill_node(params, recorder)
        except (A2LError, ValueError) as exc:
            if recorder is not None:
                recorder.close()
            return SkillNodeResult(2, "bad_input", str(exc), 0)
        try:
            if not spin_until(node, lambda: node.result is not None):
                node.stop(130, "interrupted", "SIGINT")
            end = time.monotonic() + linger
            spin_until(node, lambda: time.monotonic() > end, interruptible=False)
            return node.result
        finally:
            if recorder is not None:
                recorder.close()
            node.destroy_node()


def run_sim(params: dict[str, Any], args: Sequence[str] = (), duration: float = 0.0,
            record: str | None = None) -> int:
    """Run the simulated robot until SIGINT (or `duration` seconds when > 0); exit code."""
    recorder = None
    if record:
        from a2l.ros.record import RosRecorder

        recorder = RosRecorder(Path(record), rerun=False)
    with ros_session(args):
        try:
            node = make_sim_node(params, recorder)
        except (A2LError, ValueError) as exc:
            print(f"a2l ros sim: error: {exc}", file=sys.stderr)
            return 2
        yaw = getattr(node.scene.config, "gripper_yaw", 0.0)
        print(f"a2l ros sim: {node.scene.name} scene, robot {node.robot}, joints "
              f"{node.joint_names[0]}..., "
              f"objects {list(node.pub_obj)}, command {node.cfg.command}, trial "
              f"{node.trial or 'none'}, gripper turned {yaw:g} degrees", flush=True)
        end = time.monotonic() + duration
        try:
            spin_until(node, lambda: duration > 0 and time.monotonic() > end)
        finally:
            node.close()
            if recorder is not None:
                recorder.close()
            node.destroy_node()
    return 0
