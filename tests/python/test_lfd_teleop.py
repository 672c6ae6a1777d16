"""Teleoperation recorder: commands fed headless to a DIRECT-mode scene, the recording in
the demonstration format, the key map of the GUI and ``a2l demo-record --keys``."""

from __future__ import annotations

import numpy as np
import pytest

from a2l.cli import main
from a2l.errors import A2LValueError
from a2l.lfd import load_demonstrations
from a2l.lfd.manipulation import replay
from a2l.lfd.teleop import COMMANDS, TeleopRecorder, key_command, run_commands
from a2l.rollout.effect_tests import scene_outcome
from a2l.sim import make_scene
from a2l.sim._pybullet import p


def test_a_teleoperated_grasp_is_recorded_in_segments_and_replays(tmp_path) -> None:
    with make_scene("grasp", context_source="ground_truth") as scene:
        block = np.asarray(scene.ground_truth()["objects"]["block"])
        scene.reset(eef=block + [0.02, 0.0, 0.08])
        rec = run_commands(scene, ["up", "record", "back*2", "down*9", "gripper", "up*7",
                                   "record"])
        assert scene_outcome("grasped")(scene)  # the teleoperated grasp itself worked
        assert len(rec.recordings) == 1
        reach, lift = rec.recordings[0]
        assert reach.frame == lift.frame == "object"
        assert reach.states == {"gripper": "open"} and lift.states == {"gripper": "closed"}
        # 1 cm per move, relative to the block: 2 back then 9 down from (0.02, 0, 0.09)
        assert len(reach.positions) == 12 and len(lift.positions) == 8
        assert np.allclose(reach.positions[0], [0.02, 0.0, 0.09], atol=0.003)
        assert np.allclose(reach.positions[-1], [0.0, 0.0, 0.0], atol=0.003)
        assert np.allclose(np.diff(reach.positions[:3], axis=0), [[-0.01, 0, 0]] * 2,
                           atol=0.002)
        assert np.allclose(lift.positions[-1] - lift.positions[0], [0, 0, 0.07], atol=0.005)
        assert np.all(np.diff(reach.times) > 0) and lift.times[0] > reach.times[-1]
        # the recorded demonstration reproduces the grasp
        rec.save(tmp_path / "grasp.csv")
        demo = load_demonstrations(tmp_path / "grasp.csv")
        assert [d.states for d in demo] == [reach.states, lift.states]
        assert replay(scene, demo, "block")
        assert scene_outcome("grasped")(scene)


def test_moves_outside_the_workspace_are_logged_and_leave_no_sample() -> None:
    with make_scene("press", context_source="ground_truth") as scene:
        rec = TeleopRecorder(scene, step=0.05)
        rec.handle("record")
        for _ in range(12):
            rec.handle("down")
        failed = [line for line in rec.log if "workspace_limit" in line]
        assert failed
        rec.handle("record")
        (seg,) = rec.recordings[0]
        assert len(seg.positions) == 1 + 12 - len(failed)
        assert np.all(np.linalg.norm(np.diff(seg.positions, axis=0), axis=1) > 0.04)
        assert seg.states == {"gripper": "open", "light": "off"}
        lowest = scene.config.table_z + scene.config.workspace_min[2]
        assert scene.eef_position()[2] >= lowest - 1e-3
        # a recording without a move is not kept
        rec.handle("record")
        assert "nothing recorded" in rec.handle("record")
        assert rec.handle("quit") == "quit" and rec.finished
        with pytest.raises(A2LValueError, match="quit"):
            rec.handle("up")


def test_bad_commands_and_scenes_are_refused() -> None:
    with make_scene("grasp", context_source="ground_truth") as scene:
        rec = TeleopRecorder(scene)
        with pytest.raises(A2LValueError, match="unknown teleoperation command 'jump'"):
            rec.handle("jump")
        with pytest.raises(A2LValueError, match="nothing recorded"):
            rec.save("unused.csv")
        with pytest.raises(A2LValueError, match="no object 'box'"):
            TeleopRecorder(scene, obj="box")
        with pytest.raises(A2LValueError, match="repeat count"):
            run_commands(scene, ["up*x"])
    with make_scene("virtual") as virtual, pytest.raises(A2LValueError, match="PyBullet"):
        TeleopRecorder(virtual)


def test_gui_keys_map_to_commands() -> None:
    mapped = {key_command(k) for k in (p.B3G_UP_ARROW, p.B3G_DOWN_ARROW, p.B3G_LEFT_ARROW,
                                       p.B3G_RIGHT_ARROW, p.B3G_PAGE_UP, p.B3G_PAGE_DOWN,
                                       p.B3G_SPACE, p.B3G_RETURN, ord("q"))}
    assert mapped == set(COMMANDS)
    assert key_command(ord("x")) is None


def test_demo_record_command_headless(tmp_path, capsys) -> None:
    out = tmp_path / "press.csv"
    code = main(["demo-record", "--scene", "press", "--out", str(out), "--start",
                 "0,0,0.05", "--keys", "record,down*6,record"])
    assert code == 0
    (seg,) = load_demonstrations(out)
    assert np.allclose(seg.positions[0], [0, 0, 0.05], atol=0.003)
    assert seg.positions[-1][2] < 0.0  # went down on the button
    assert "saved to" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exc:
        main(["demo-record", "--scene", "press", "--out", str(out), "--keys", "fly"])
    assert exc.value.code == 2
    assert "unknown teleoperation command 'fly'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["demo-record", "--scene", "press", "--out", str(tmp_path / "x.txt"),
              "--keys", "up"])
    assert "--out" in capsys.readouterr().err
