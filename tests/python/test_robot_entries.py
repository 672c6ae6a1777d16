"""A robot is data: the built-in robot entries, a user's arm from a robot file, the refusals
of a wrong file, and arm_spec() unchanged for its callers."""

from __future__ import annotations

import json
import math
import pickle
import re
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import a2l
from a2l.errors import A2LFileNotFoundError, A2LValueError, RobotEntryError
from a2l.robot import (
    BUILTIN_ROBOTS,
    ArmSpec,
    Mount,
    RobotEntry,
    arm_spec,
    baxter_urdf,
    check_entry,
    load_robot,
    panda_urdf,
    robot_entry,
    robots_dir,
)
from a2l.robot.descriptions import PUSHER_TIP
from a2l.robot.entries import arm_reach

#: The most the tool of a built-in neutral pose may lean from the vertical (rad): Baxter's
#: neutral, the scenes' since the start, leans 3.2 degrees; the others under 0.1 degree.
TILT = 0.06

#: A robot file for Unitree's Z1 (not a built-in robot), written as YAML in a test's folder.
Z1: dict[str, Any] = {
    "name": "z1",
    "urdf": "package://example-robot-data/robots/z1_description/urdf/z1.urdf",
    "base_link": "link00",
    "tool_link": "gripperStator",
    "neutral": [0.0, 2.01, -1.29, 0.85, 0.0, 0.0],
    "tool_down": [[0, 0, 1], [0, 1, 0], [-1, 0, 0]],
    "gripper": {"joints": ["jointGripper"], "open": [-1.0], "closed": [0.0]},
    "mount": {"xyz": [-0.4, 0.0, 0.0], "yaw": 0.0},
}


def _write(folder: Path, data: dict[str, Any], name: str = "z1.yaml") -> Path:
    path = folder / name
    path.write_text(json.dumps(data) if name.endswith(".json") else yaml.safe_dump(data))
    return path


@pytest.mark.parametrize("name", BUILTIN_ROBOTS)
def test_every_builtin_robot_loads_and_points_down_over_the_table(name: str) -> None:
    entry = robot_entry(name)
    check_entry(entry)  # the checks a robot file passes
    assert entry.name == name and entry.urdf.is_file()
    assert entry.n_joints == len(entry.neutral) == len(entry.joint_names)
    pose = entry.neutral_pose()
    assert entry.neutral_tilt is not None and entry.neutral_tilt < TILT, entry.neutral_tilt
    down = np.asarray(entry.tool_down)
    assert np.allclose(down.T @ down, np.eye(3)) and np.isclose(np.linalg.det(down), 1.0)
    assert pose[0, 3] > 0.15, "the neutral tool is in front of the base"
    assert 0.03 < entry.tool_height < 0.6, "the neutral tool is over the table top"
    assert np.linalg.norm(pose[:3, 3]) < entry.reach
    if entry.gripper is not None:
        assert len(entry.gripper.joints) == len(entry.gripper.open) == len(entry.gripper.closed)


def test_builtin_robots_are_the_asked_ones() -> None:
    assert set(BUILTIN_ROBOTS) == {"baxter", "baxter-left", "panda", "ur5", "so101", "pr2"}
    assert robot_entry("ur5").gripper is None
    assert robot_entry("pr2").n_joints == 8  # the torso lift, then the right arm
    assert robot_entry("so101").n_joints == 5
    assert robot_entry("baxter").gripper.joints == ("r_gripper_l_finger_joint",
                                                    "r_gripper_r_finger_joint")
    pr2 = robot_entry("pr2")
    pr2.reach  # noqa: B018 (measured, then carried by the copy)
    assert pickle.loads(pickle.dumps(pr2)) == pr2  # an entry goes to worker processes
    with pytest.raises(A2LValueError, match="unknown robot 'kuka'.*baxter, baxter-left"):
        robot_entry("kuka")


def test_reach_is_the_farthest_tool_point() -> None:
    """The reach is deterministic and a denser sampling (another seed) finds no farther
    point; it exceeds every sampled distance."""
    entry = robot_entry("so101")
    kin = entry.kinematics()
    dense = arm_reach(kin, np.asarray(entry.neutral), samples=20000, seed=1)
    assert entry.reach == robot_entry("so101").reach
    assert abs(dense - entry.reach) < 1e-3
    rng = np.random.default_rng(3)
    for q in rng.uniform(kin.lower, kin.upper, size=(200, kin.n_joints)):
        assert np.linalg.norm(kin.fk(q)[:3, 3]) <= entry.reach + 1e-9


def test_baxter_stands_where_the_scenes_put_it() -> None:
    """Baxter's mount is the scenes' table seen from its base (the table frame's origin is
    the centre of the table top)."""
    from a2l.sim.scene_config import SceneConfig

    cfg = SceneConfig()
    mount = robot_entry("baxter").mount
    assert mount == Mount((-cfg.table_center[0], -cfg.table_center[1], -cfg.table_z), 0.0)
    assert robot_entry("baxter-left").mount == mount


def test_arm_spec_returns_what_it_returned_before() -> None:
    assert arm_spec("baxter") == arm_spec("baxter", "right") == ArmSpec(
        baxter_urdf(), "base", "right_gripper", (0.08, -1.0, 1.19, 1.94, -0.67, 1.03, 0.5),
        ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0)))
    assert arm_spec("baxter", "left") == ArmSpec(
        baxter_urdf(), "base", "left_gripper", (-0.08, -1.0, -1.19, 1.94, 0.67, 1.03, -0.5),
        ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0)))
    assert arm_spec("panda") == ArmSpec(
        panda_urdf(), "panda_link0", "panda_hand_tcp",
        (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785),
        ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)))
    spec = arm_spec("baxter")
    assert all(type(v) is float for v in spec.neutral)
    assert all(type(v) is float for row in spec.down for v in row)
    with pytest.raises(ValueError, match="unknown Baxter arm 'middle'"):
        arm_spec("baxter", "middle")
    with pytest.raises(ValueError, match="no built-in arm for robot 'kuka'"):
        arm_spec("kuka")
    assert arm_spec("ur5").tip_link == "a2l_pusher_tip"  # a rod on the flange


def test_an_entry_without_tool_down_has_no_arm_spec(tmp_path: Path) -> None:
    entry = load_robot(_write(tmp_path, {k: v for k, v in Z1.items() if k != "tool_down"}))
    assert entry.tool_down is None and entry.neutral_tilt is None
    with pytest.raises(A2LValueError, match="robot 'z1' has no tool_down"):
        entry.arm_spec()


def test_a_robot_file_of_an_arm_not_built_in_loads(tmp_path: Path) -> None:
    entry = robot_entry(_write(tmp_path, Z1))
    assert isinstance(entry, RobotEntry) and entry.name == "z1"
    assert entry.urdf == (robots_dir() / "z1_description" / "urdf" / "z1.urdf").resolve()
    assert entry.joint_names == ("joint1", "joint2", "joint3", "joint4", "joint5", "joint6")
    assert entry.neutral_tilt is not None and entry.neutral_tilt < 0.01
    assert 0.1 < entry.tool_height < 0.3 and 0.5 < entry.reach < 1.2
    # its kinematics work: FK at the neutral pose, IK back to it
    kin = a2l.Kinematics(entry.urdf, entry.base_link, entry.tool_link)
    target = kin.fk(np.asarray(entry.neutral))
    target[:3, 3] += [0.03, 0.02, -0.05]
    q = kin.ik(target, np.asarray(entry.neutral))
    assert np.allclose(kin.fk(q), target, atol=1e-5)
    spec = entry.arm_spec()
    assert (spec.base_link, spec.tip_link, spec.neutral) == ("link00", "gripperStator",
                                                             entry.neutral)
    # no grasp_open: a grasp opens the gripper as far as a push does
    assert entry.gripper.grasp_open is None and entry.gripper.opening(True) == (-1.0,)
    wide = robot_entry(_write(tmp_path, {**Z1, "gripper": {**Z1["gripper"],
                                                           "grasp_open": [-1.2]}}, "z1w.yaml"))
    assert (wide.gripper.opening(False), wide.gripper.opening(True)) == ((-1.0,), (-1.2,))


def test_a_json_robot_file_with_a_relative_urdf_loads(tmp_path: Path) -> None:
    """xArm7 from a copy of its URDF next to the file (a path relative to the file's folder);
    the URDF keeps a xacro leftover (``${prefix}link_eef``, commented out) urdfdom skips."""
    src = robots_dir() / "xarm_description" / "urdf" / "xarm7.urdf"
    assert "${prefix}link_eef" in src.read_text()
    (tmp_path / "urdf").mkdir()
    shutil.copy(src, tmp_path / "urdf" / "xarm7.urdf")
    data = {"urdf": "urdf/xarm7.urdf", "base_link": "link_base", "tool_link": "link_eef",
            "neutral": [0.0, -0.02, 0.0, 0.67, 0.0, 0.69, 0.0],
            "tool_down": [[1, 0, 0], [0, -1, 0], [0, 0, -1]],
            "mount": {"xyz": [-0.45, 0.0, 0.0], "yaw": 90}}
    entry = load_robot(_write(tmp_path, data, "xarm.json"))
    assert entry.name == "xarm" and entry.gripper is None and entry.n_joints == 7
    assert entry.urdf == (tmp_path / "urdf" / "xarm7.urdf").resolve()
    assert entry.neutral_tilt is not None and entry.neutral_tilt < 0.01
    assert entry.mount.yaw == 90.0
    assert np.allclose(entry.mount.pose()[:3, :3] @ [1, 0, 0], [0, 1, 0])


def _edit(key: str, value: Any) -> dict[str, Any]:
    """Z1 with `key` (``a.b`` for a nested key) set to `value`, or removed when `value` is
    :data:`_DROP`."""
    data = json.loads(json.dumps(Z1))
    *outer, last = key.split(".")
    where = data
    for k in outer:
        where = where[k]
    if value is _DROP:
        del where[last]
    else:
        where[last] = value
    return data


_DROP = object()

BAD_FILES = [
    # (key, value, the key the error names, what the message says)
    ("neutrall", [0.0], "neutrall", r"unknown key; the valid keys are urdf, base_link, "
     r"tool_link, neutral, mount, name, tool_down, gripper"),
    ("gripper.opn", [0.0], "gripper.opn", r"unknown key; the valid keys are gripper.joints"),
    ("tool_link", _DROP, "tool_link", r"missing \(required: urdf, base_link"),
    ("mount.yaw", _DROP, "mount.yaw", r"missing"),
    ("base_link", "link99", "base_link", r"unknown link 'link99': the URDF '.*z1.urdf' has "
     r"the links world, link00, link01"),
    ("tool_link", "hand", "tool_link", r"unknown link 'hand'.*gripperStator, gripperMover"),
    ("neutral", [0.0, 1.0, -1.0, 0.5, 0.0], "neutral", r"5 values, but the chain 'link00' "
     r"-> 'gripperStator' has 6 movable joints \(joint1, joint2, joint3, joint4, joint5, "
     r"joint6\)"),
    ("neutral", [0.0, 2.0, -1.3, 0.85, 0.0, math.nan], "neutral", r"values must be finite"),
    ("neutral", [0.0, 2.0, -1.3, 0.85, 0.0, "up"], "neutral", r"must be a number, got 'up'"),
    ("neutral", [0.0, -1.0, -1.3, 0.85, 0.0, 0.0], "neutral", r"joint 'joint2' at -1 is "
     r"outside its limits \[0, 2.967"),
    ("mount.xyz", [0.0, math.inf, 0.0], "mount.xyz", r"must be 3 finite numbers"),
    ("mount.xyz", [0.0, 0.0], "mount.xyz", r"must be 3 numbers"),
    ("tool_down", [[1, 0, 0], [0, 1, 0], [0, 0, 2]], "tool_down", r"not a rotation matrix"),
    ("tool_down", [[1, 0, 0], [0, 1, 0], [0, 0, -1]], "tool_down",
     r"not a rotation matrix: .*det R = -1"),
    ("tool_down", [[1, 0, 0], [0, 1, 0]], "tool_down", r"must be 3 rows of 3 numbers"),
    ("gripper.joints", ["jointGrip"], "gripper.joints", r"'jointGrip' is not a joint of the "
     r"URDF '.*z1.urdf': its movable joints are joint1, .*jointGripper"),
    ("gripper.joints", ["gripperStator"], "gripper.joints", r"is not a movable joint"),
    ("gripper.joints", ["joint6"], "gripper.joints", r"'joint6' is a joint of the arm's chain"),
    ("gripper.open", [-1.0, 0.0], "gripper.open", r"2 values for the 1 gripper.joints"),
    ("gripper.closed", [0.5], "gripper.closed", r"joint 'jointGripper' at 0.5 is outside"),
    ("mount.xyz", [-0.4, 0.0, -0.5], "mount.xyz", r"the tool is 0.35. m below the table top"),
    ("mount.xyz", [-0.4, 0.0, 3.0], "mount.xyz", r"the table top below the neutral tool is "
     r"3.0.. m from the base, beyond the arm's reach 0.8"),
    ("urdf", "missing.urdf", "urdf", r"no such file '.*missing.urdf'"),
    ("urdf", "package://nowhere_description/urdf/x.urdf", "urdf",
     r"cannot resolve 'package://nowhere_description/urdf/x.urdf'"),
    ("urdf", 3, "urdf", r"must be a non-empty string, got 3"),
    ("gripper.grasp_open", [-1.0, 0.0], "gripper.grasp_open",
     r"2 values for the 1 gripper.joints"),
    ("gripper.grasp_open", [0.5], "gripper.grasp_open", r"joint 'jointGripper' at 0.5 is "
     r"outside"),
    ("gripper", ["jointGripper"], "gripper", r"must be a mapping of joints, open, closed, "
     r"grasp_open"),
    ("rest", {"jointGrip": 0.0}, "rest.jointGrip", r"unknown joint: '.*z1.urdf' has the "
     r"joints .*jointGripper"),
    ("rest", [0.0], "rest", r"must map joint names to positions"),
    ("work_point", [0.5, 0.0], "work_point", r"\(0.5, 0\) is off the table top"),
    ("work_point", [0.0], "work_point", r"must be 2 numbers"),
]


@pytest.mark.parametrize(("key", "value", "named", "message"), BAD_FILES,
                         ids=[f"{b[0]}-{i}" for i, b in enumerate(BAD_FILES)])
def test_a_wrong_robot_file_is_refused_naming_the_file_and_the_key(
        tmp_path: Path, key: str, value: Any, named: str, message: str) -> None:
    path = _write(tmp_path, _edit(key, value))
    with pytest.raises(RobotEntryError) as info:
        load_robot(path)
    text = str(info.value)
    assert text.startswith(f"robot file '{path}': {named}: "), text
    assert re.search(message, text), text
    assert info.value.key == named


def test_a_missing_or_unreadable_robot_file_is_refused(tmp_path: Path) -> None:
    with pytest.raises(A2LFileNotFoundError, match="robot file '.*nothere.yaml' does not"):
        load_robot(tmp_path / "nothere.yaml")
    with pytest.raises(A2LFileNotFoundError, match="nothere.json"):
        robot_entry(tmp_path / "nothere.json")
    bad = tmp_path / "bad.yaml"
    bad.write_text("urdf: [unclosed\n")
    with pytest.raises(RobotEntryError, match=r"robot file '.*bad.yaml': not valid YAML"):
        load_robot(bad)
    bad.write_text("- a list\n")
    with pytest.raises(RobotEntryError, match=r"must hold a mapping of keys \(urdf"):
        load_robot(bad)
    with pytest.raises(RobotEntryError, match=r"unknown format '.txt'"):
        load_robot(tmp_path / "arm.txt")
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><link name='a'></robot>")
    with pytest.raises(RobotEntryError, match=r"urdf: '.*broken.urdf' is not XML"):
        load_robot(_write(tmp_path, _edit("urdf", "broken.urdf")))


def test_the_docs_table_of_builtin_robots_is_computed() -> None:
    """docs/robots.md lists every built-in robot with its URDF, chain, joints, reach and tool
    height as computed."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "robots.md").read_text()
    rows = {m.group(1): m.groups() for m in re.finditer(
        r"^\| `([\w-]+)` \| `([^`]+)` \| `([^`]+)` → `([^`]+)` \| (\d+) \| ([\d.]+) \| "
        r"([\d.]+) \|", text, flags=re.MULTILINE)}
    assert set(rows) == set(BUILTIN_ROBOTS)
    for name, (_, urdf, base, tool, joints, reach, height) in rows.items():
        entry = robot_entry(name)
        if entry.tool_link == PUSHER_TIP:  # the URDF with a pusher rod: a generated copy
            assert entry.urdf.name.startswith(Path(urdf).stem + "-pusher-")
        else:
            assert entry.urdf == robots_dir() / urdf
        assert (base, tool, int(joints)) == (entry.base_link, entry.tool_link, entry.n_joints)
        assert (reach, height) == (f"{entry.reach:.2f}", f"{entry.tool_height:.2f}"), name
    z1 = yaml.safe_load(re.search(r"```yaml\n(.*?)```", text, flags=re.S).group(1))
    assert z1 == Z1, "the robot file example is the one the tests load"
