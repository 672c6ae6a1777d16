"""Every scene on every robot: the layout each robot's scenes stand in (Baxter's is the
thesis' scene to the micrometre), pushes that move the box on each built-in arm and on an
arm from a robot file, the scaled scene of a small arm, the refusals."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from a2l.errors import A2LValueError, ConfigError
from a2l.framework import FrameworkConfig
from a2l.robot import BUILTIN_ROBOTS, builtin_robot, table_layout
from a2l.robot.layout import REFERENCE_RADIUS
from a2l.rollout.env import scene_env
from a2l.sim import make_scene
from a2l.sim.config import make_config

#: The thesis' scene as the scenes typed it before robots were data (Baxter's base frame).
THESIS = {
    "table_z": -0.20, "table_center": (0.75, -0.15), "table_size": (0.7, 1.2),
    "workspace_min": (0.35, -0.75, 0.01), "workspace_max": (0.95, 0.45, 0.45),
    "camera_eye": (1.55, -0.15, 0.85), "camera_target": (0.75, -0.15, -0.2),
    "extra_camera_eyes": ((0.75, 0.95, 0.85), (0.75, -1.25, 0.85)), "step": 0.05,
    "effect_threshold": 0.01,
}
THESIS_OBJECTS = {
    "push": {"box_position": (0.62, -0.25), "box_size": (0.07, 0.085, 0.08)},
    "grasp_light": {"block_position": (0.62, -0.25), "block_size": (0.03, 0.03, 0.06),
                    "lamp_position": (0.85, -0.05), "lamp_radius": 0.03},
    "press": {"button_position": (0.62, -0.1), "lamp_position": (0.95, 0.2),
              "box_position": (0.62, -0.35), "button_size": (0.06, 0.06, 0.02),
              "button_base_height": 0.025, "button_travel": 0.02, "button_trigger": 0.008},
    "task": {"block_position": (0.62, -0.3), "box_position": (0.95, -0.6)},
}


@pytest.mark.parametrize("scene", sorted(THESIS_OBJECTS))
def test_baxter_scenes_are_the_thesis_scenes(scene: str) -> None:
    cfg = make_config(scene)
    for name, value in {**THESIS, **THESIS_OBJECTS[scene]}.items():
        assert getattr(cfg, name) == value, name  # exactly: the same floats


def test_a_field_given_wins_over_the_layout() -> None:
    cfg = make_config("push", robot="panda", box_position=(0.40, 0.10), step=0.04)
    assert cfg.box_position == (0.40, 0.10) and cfg.step == 0.04
    assert cfg.table_center == table_layout(builtin_robot("panda")).table_center


def test_the_docs_table_of_layouts_is_computed() -> None:
    """docs/robots.md's table of scales, work points and radii is what table_layout gives."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "robots.md").read_text()
    rows = re.findall(r"^\| `([\w-]+)` \| ([\d.]+) \| \(([−\d.]+), ([−\d.]+)\)[^|]* \| "
                      r"([\d.]+) \|$", text, flags=re.MULTILINE)
    assert len(rows) == 5
    for name, scale, x, y, radius in rows:
        lay = table_layout(builtin_robot(name))
        assert float(scale) == pytest.approx(lay.scale, abs=0.005), name
        point = [float(v.replace("−", "-")) for v in (x, y)]
        assert point == pytest.approx(lay.work_point, abs=0.005), name
        assert float(radius) == pytest.approx(lay.radius, abs=0.005), name


@pytest.mark.parametrize("name", BUILTIN_ROBOTS)
def test_each_robot_reaches_around_its_work_point(name: str) -> None:
    lay = table_layout(builtin_robot(name))
    assert 0 < lay.scale <= 1
    assert lay.radius >= REFERENCE_RADIUS * lay.scale - 0.02  # the disc the scale rests on
    # the table stands on the floor and the camera looks down at it from beyond
    assert lay.floor_z < lay.table_z and lay.camera_eye[2] > lay.table_z
    lo, hi = np.array(lay.workspace_min[:2]), np.array(lay.workspace_max[:2])
    assert np.all(lo < lay.work_point) and np.all(lay.work_point < hi)


def _push_once(scene: object, start: np.ndarray, direction: tuple[int, int, int],
               moves: int) -> np.ndarray:
    home = np.asarray(scene.ground_truth()["objects"]["box"])  # type: ignore[attr-defined]
    scene.reset(eef=home + start, objects={"box": home[:2]})  # type: ignore[attr-defined]
    for _ in range(moves):
        assert scene.execute(direction)  # type: ignore[attr-defined]
    return np.asarray(scene.ground_truth()["objects"]["box"]) - home  # type: ignore


@pytest.mark.parametrize("name", [n for n in BUILTIN_ROBOTS if n != "baxter"])
def test_a_push_moves_the_box_on_each_robot(name: str) -> None:
    """From 0.10 m (scaled) behind the box, four movements along +x push it along +x, and
    the camera sees it where it is."""
    scene = make_scene("push", seed=0, robot=name)
    try:
        s = scene.config.layout().scale
        moved = _push_once(scene, np.array([-0.10 * s, 0.0, 0.0]), (1, 0, 0), 4)
        assert moved[0] > 0.05 * s and abs(moved[1]) < 0.5 * moved[0]
        seen = scene.perceive()["objects"]["box"]
        true = scene.ground_truth()["objects"]["box"]
        assert np.linalg.norm(np.subtract(seen, true)[:2]) < 0.01 * s
    finally:
        scene.close()


def test_a_small_arm_gets_a_scaled_scene() -> None:
    lay = table_layout(builtin_robot("so101"))
    assert 0.3 < lay.scale < 0.8  # the SO-101 reaches about a third of a Panda
    cfg = make_config("push", robot="so101")
    assert cfg.step == pytest.approx(0.05 * lay.scale, abs=1e-6)
    assert cfg.box_size == pytest.approx(tuple(v * lay.scale for v in THESIS_OBJECTS["push"]
                                               ["box_size"]), abs=1e-6)
    assert cfg.box_position == lay.work_point
    eye = np.subtract(cfg.camera_eye, cfg.camera_target)
    assert np.linalg.norm(eye) == pytest.approx(lay.scale * np.hypot(0.80, 1.05), abs=1e-5)


def test_an_arm_from_a_robot_file_pushes(tmp_path: Path) -> None:
    """UFactory's xArm7, not a built-in robot, mounted turned by 90 degrees: its file names
    no work point, the layout finds one beside the base, and the push scene pushes its box
    along both axes, the camera (placed in the turned table frame) seeing it."""
    path = tmp_path / "xarm.json"
    path.write_text(json.dumps({
        "urdf": "package://example-robot-data/robots/xarm_description/urdf/xarm7.urdf",
        "base_link": "link_base", "tool_link": "link_eef",
        "neutral": [0.0, -0.02, 0.0, 0.67, 0.0, 0.69, 0.0],
        "tool_down": [[1, 0, 0], [0, -1, 0], [0, 0, -1]],
        "mount": {"xyz": [-0.45, 0.0, 0.0], "yaw": 90}}))
    scene = make_scene("push", seed=0, robot=str(path))
    try:
        lay = scene.config.layout()
        assert lay.table_yaw == -90 and lay.table_center == (0.0, -0.45)
        assert lay.camera_eye[1] < lay.table_center[1] - 0.5  # beyond the table
        # along the base's x (across the table), then its -y (away from the base)
        for start, direction, axis in (((-0.10, 0.0, 0.0), (1, 0, 0), 0),
                                       ((0.0, 0.10, 0.0), (0, -1, 0), 1)):
            moved = _push_once(scene, np.array(start), direction, 4)
            assert abs(moved[axis]) > 0.05 and np.sign(moved[axis]) == sum(direction)
            seen = scene.perceive()["objects"]["box"]
            true = scene.ground_truth()["objects"]["box"]
            assert np.linalg.norm(np.subtract(seen, true)[:2]) < 0.01
    finally:
        scene.close()


@pytest.mark.parametrize("name", BUILTIN_ROBOTS)
def test_every_scene_puts_its_objects_on_each_robots_table(name: str) -> None:
    """An object placed from the work point that would leave the table is moved onto it
    (the press scene's lamp on the Panda and the UR5); Baxter's stay the thesis' (above)."""
    for scene in ("push", "grasp", "grasp_light", "press", "task"):
        cfg = make_config(scene, robot=name)
        lo = np.subtract(cfg.table_center, np.divide(cfg.table_size, 2))
        hi = np.add(cfg.table_center, np.divide(cfg.table_size, 2))
        for field in ("box_position", "block_position", "button_position", "lamp_position"):
            xy = getattr(cfg, field, None)
            if xy is not None:
                assert np.all(lo + 0.03 <= xy) and np.all(xy <= hi - 0.03), (scene, field)
    if name == "panda":  # 0.45 m left of the work point was 0.16 m off the table's edge
        assert make_config("press", robot=name).lamp_position == (0.75, 0.55)


def test_the_grasp_scene_refuses_an_arm_without_gripper() -> None:
    with pytest.raises(A2LValueError, match="robot 'ur5' has no gripper: the grasp scene"):
        make_scene("grasp", seed=0, robot="ur5")


def test_the_panda_grasps_with_its_fingers_wide_open_and_pushes_with_them_half_open() -> None:
    import pybullet as p

    widths = {}
    for name in ("push", "grasp", "grasp_light"):
        scene = make_scene(name, seed=0, robot="panda")
        try:
            scene.reset()
            widths[name] = sum(p.getJointState(scene._robot, j, physicsClientId=scene._client)[0]
                               for j in scene._fingers)
        finally:
            scene.close()
    # between the fingers: 4 cm to push, 8 cm (the stop) to grasp (docs/robots.md)
    assert widths["push"] == pytest.approx(0.04, abs=2e-3)
    assert widths["grasp"] == pytest.approx(0.08, abs=2e-3)
    assert widths["grasp_light"] == pytest.approx(0.08, abs=2e-3)


def test_the_so101_pushes_with_its_jaw_closed_and_opens_it_to_grasp() -> None:
    import pybullet as p

    reach, jaw = {}, {}
    for name in ("push", "grasp"):
        scene = make_scene(name, seed=0, robot="so101")
        try:
            scene.reset()
            c, r, g = scene._client, scene._robot, scene._fingers[0]
            jaw[name] = p.getJointState(r, g, physicsClientId=c)[0]
            link = next(j for j in range(p.getNumJoints(r, physicsClientId=c)) if p.getJointInfo(
                r, j, physicsClientId=c)[12].decode() == "moving_jaw_so101_v1_link")
            lo, hi = p.getAABB(r, link, physicsClientId=c)
            tool = scene.eef_position()
            reach[name] = max(abs(lo[1] - tool[1]), abs(hi[1] - tool[1]))
        finally:
            scene.close()
    assert jaw["push"] == pytest.approx(-0.1745, abs=0.01)
    assert jaw["grasp"] == pytest.approx(0.6, abs=0.01)
    # open, the moving jaw reaches 8.9 cm beside the tool point: farther than the scaled push
    # box (4.5 cm wide) needs, it swept the box from 8 cm off (docs/robots.md)
    assert reach["push"] < 0.055 < 0.08 < reach["grasp"]


def test_an_unknown_robot_is_named() -> None:
    with pytest.raises(A2LValueError, match="unknown robot 'kuka'"):
        make_config("push", robot="kuka")


def test_the_framework_runs_the_bullet_scene_on_its_robot() -> None:
    cfg = FrameworkConfig(scene="bullet", robot="panda", context_source="ground_truth")
    env = scene_env(cfg)
    assert env.scene.config.robot == "panda"
    assert env.scene.robot_entry.name == "panda"
    with pytest.raises(ConfigError, match="scene 'baxter' is Baxter's; for robot 'panda'"):
        FrameworkConfig(scene="baxter", robot="panda")
    with pytest.raises(ConfigError, match="names a robot: give it as the robot field"):
        FrameworkConfig(scene="bullet", robot="panda", scene_config={"robot": "ur5"})


def test_a_small_arms_run_scales_the_lengths_left_at_their_defaults() -> None:
    scale = table_layout(builtin_robot("so101")).scale
    cfg = FrameworkConfig(scene="bullet", robot="so101", starts={"r_high": 0.2})
    assert cfg.discretization.step == pytest.approx(0.05 * scale, abs=1e-6)
    assert cfg.heldout.r_high == pytest.approx(0.25 * scale, abs=1e-6)
    assert cfg.skill.clearance == pytest.approx(0.10 * scale, abs=1e-6)
    assert cfg.skill.align == pytest.approx(0.05 * scale, abs=1e-6)
    assert cfg.starts.r_high == 0.2  # given: kept
    assert FrameworkConfig.from_dict(cfg.to_dict()) == cfg  # a saved run reloads unchanged
    panda = FrameworkConfig(scene="bullet", robot="panda")
    assert panda.discretization == FrameworkConfig().discretization  # scale 1


def test_a_skill_learned_for_another_robot_is_refused() -> None:
    from a2l.robot import baxter_urdf, urdf_sha256

    record = {"name": "baxter", "urdf_sha256": urdf_sha256(baxter_urdf())}
    builtin_robot("baxter").check_learned_for(record, "skill bundle 'push.a2lb'")
    builtin_robot("panda").check_learned_for(None, "a virtual scene's skill")
    with pytest.raises(A2LValueError, match="skill bundle 'push.a2lb' was learned for robot "
                       "'baxter' .* not for 'panda' \\(panda.urdf\\)"):
        builtin_robot("panda").check_learned_for(record, "skill bundle 'push.a2lb'")
    with pytest.raises(A2LValueError, match="learned for robot 'baxter' \\(URDF sha256 abab"):
        builtin_robot("baxter").check_learned_for({**record, "urdf_sha256": "ab" * 32}, "x")


def test_a_pusher_rod_is_added_to_a_urdf_and_its_link_checked() -> None:
    import a2l
    from a2l.errors import URDFError
    from a2l.robot import robots_dir
    from a2l.robot.descriptions import PUSHER_TIP, pusher_urdf

    src = robots_dir() / "ur_description" / "urdf" / "ur5_robot.urdf"
    kin = a2l.Kinematics(pusher_urdf(src, "tool0", (0.0, 0.0, 1.0), 0.12, 0.015), "tool0",
                         PUSHER_TIP)
    assert np.allclose(kin.fk(np.zeros(0))[:3, 3], [0.0, 0.0, 0.12])  # the rod's tip
    with pytest.raises(URDFError, match="no link 'tool9' to fix a pusher to"):
        pusher_urdf(src, "tool9", (0.0, 0.0, 1.0), 0.12, 0.015)


def test_a_box_the_hand_would_clip_is_lowered_below_it() -> None:
    """The Panda's hand comes 3.4 cm above its tool point: the layout's 8 cm push box is
    lowered so that, pushed at mid-height, its top stays under the hand; a size given stays."""
    from a2l.sim._pybullet import p
    from a2l.sim.bullet.build import BOX_MARGIN

    def gap(**config: object) -> float:
        """Distance (m) of the hand from the box, the tool point 9 cm beside the box."""
        scene = make_scene("push", seed=0, robot="panda", context_source="ground_truth",
                           **config)
        try:
            if not config:
                clearance = scene.tool_clearance()
                assert 0.02 < clearance < 0.05
                assert scene.config.box_size[2] == pytest.approx(2 * clearance - BOX_MARGIN,
                                                                 abs=1e-6)
            home = np.asarray(scene.ground_truth()["objects"]["box"])
            scene.reset(eef=home + np.array([0.0, -0.09, 0.0]), objects={"box": home[:2]})
            hand = scene._link_index["panda_hand"]
            return min(q[8] for q in p.getClosestPoints(
                scene._robot, scene._objects["box"].body, 0.1, hand,
                physicsClientId=scene._client))
        finally:
            scene.close()

    assert gap() > 0.005  # over the box's edge, clear of it
    assert gap(box_size=(0.07, 0.085, 0.08)) < 0.0  # given, kept: the hand cuts its top


def test_the_push_report_says_where_the_robots_scene_stands() -> None:
    from a2l.experiments.push_report import _robot_lines

    small = _robot_lines(FrameworkConfig(scene="bullet", robot="so101"))[0]
    assert small.startswith("Robot: so101; the box at (") and "scaled by 0.5" in small
    assert "scaled" not in _robot_lines(FrameworkConfig(scene="bullet", robot="panda"))[0]
    assert _robot_lines(FrameworkConfig(scene="virtual")) == []
