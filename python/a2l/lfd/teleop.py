"""Teleoperation: record demonstrations by moving Baxter's end-effector with the keyboard.

In the PyBullet GUI (``a2l demo-record --scene grasp --out demos.csv``):

==========================  =====================================================
key                         command
==========================  =====================================================
Up / Down arrow             ``forward`` / ``back``: +x / -x (away from / towards the robot)
Left / Right arrow          ``left`` / ``right``: +y / -y
Page Up / Page Down         ``up`` / ``down``: +z / -z
Space                       ``gripper``: open or close the gripper
Return                      ``record``: start / stop recording
q or Escape                 ``quit``: save and leave
==========================  =====================================================

Each move is one step of ``step`` (1 cm by default) through the C++ IK. What is recorded is
the part-1 demonstration format (:mod:`a2l.lfd.demonstration`): the end-effector relative
to the object, at the simulated time of each sample, with the scene's high-level states.
A recording is cut into segments where the gripper toggles (the convention of
:mod:`a2l.lfd.manipulation`: one :class:`Demonstration` per stretch of constant states,
each relative to the object's position at its start).

The core, :class:`TeleopRecorder`, takes commands, not key codes, so it runs headless
(tests feed it commands in a DIRECT-mode scene); :func:`run_gui` maps the GUI's key events
to commands.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from a2l.errors import A2LValueError
from a2l.lfd.demonstration import Demonstration, save_demonstrations
from a2l.rollout.protocol import ArmSceneProtocol
from a2l.sim import make_scene
from a2l.sim.keyboard import (
    KEY_CODES,
    WindowClosed,
    keys_pressed,
    take_keyboard,
    window_guard,
)

__all__ = ["COMMANDS", "MOVES", "TeleopRecorder", "key_command", "record_demonstrations",
           "run_commands", "run_gui"]

#: The end-effector moves of the commands (signs per axis, world frame).
MOVES: dict[str, tuple[int, int, int]] = {
    "forward": (1, 0, 0), "back": (-1, 0, 0), "left": (0, 1, 0), "right": (0, -1, 0),
    "up": (0, 0, 1), "down": (0, 0, -1),
}
#: Every command the recorder takes.
COMMANDS: tuple[str, ...] = (*MOVES, "gripper", "record", "quit")
#: Key code -> command (the table of the module's docstring).
_KEY_TABLE: dict[int, str] = {
    KEY_CODES[key]: command for key, command in (
        ("up", "forward"), ("down", "back"), ("left", "left"), ("right", "right"),
        ("page_up", "up"), ("page_down", "down"), ("space", "gripper"), ("return", "record"),
        ("q", "quit"), ("escape", "quit"))}


def key_command(key: int) -> str | None:
    """The command of a PyBullet key code (see the module's table), or ``None``."""
    return _KEY_TABLE.get(int(key))


class TeleopRecorder:
    """Moves the end-effector on command and records demonstrations.

    Parameters
    ----------
    scene : a2l.sim.bullet.BulletScene
        A PyBullet scene (GUI or DIRECT), already reset.
    obj : str, optional
        The object the demonstrations are expressed relative to (default: the scene's
        primary object).
    step : float
        Length of one move (m).

    Attributes
    ----------
    recordings : list of list of Demonstration
        The finished recordings, each a list of segments.
    log : list of str
        What each command did, for a human (failed moves say why).
    """

    def __init__(self, scene: ArmSceneProtocol, obj: str | None = None, step: float = 0.01
                 ) -> None:
        if not hasattr(scene, "close_gripper"):
            raise A2LValueError(f"teleoperation needs a PyBullet scene with a gripper, not "
                                f"'{getattr(scene, 'name', scene)}'")
        if not (np.isfinite(step) and 0 < step <= 0.1):
            raise A2LValueError(f"step must be in (0, 0.1] m, got {step!r}")
        self.scene = scene
        self.obj = obj or scene.primary_object
        if self.obj not in scene.object_names:
            raise A2LValueError(f"no object '{self.obj}' in scene '{scene.name}'; it has "
                                f"{sorted(scene.object_names)}")
        self.step = float(step)
        self.recordings: list[list[Demonstration]] = []
        self.log: list[str] = []
        self.finished = False
        self._segments: list[Demonstration] | None = None
        self._points: list[NDArray[np.float64]] = []
        self._times: list[float] = []
        self._origin = np.zeros(3)
        self._states: dict[str, str] = {}

    # --- state --------------------------------------------------------------------------
    @property
    def recording(self) -> bool:
        """Whether a recording is running."""
        return self._segments is not None

    def _now(self) -> float:
        """Simulated time (s) of the scene."""
        return self.scene.sim_time

    def _object(self) -> NDArray[np.float64]:
        return np.asarray(self.scene.ground_truth()["objects"][self.obj], dtype=float)

    def _sample(self) -> None:
        t = self._now()
        if self._times and t <= self._times[-1]:
            t = self._times[-1] + 1e-3
        self._points.append(self.scene.eef_position() - self._origin)
        self._times.append(t)

    def _begin_segment(self) -> None:
        self._origin = self._object()
        self._states = dict(self.scene.ground_truth()["states"])
        self._points, self._times = [], []
        self._sample()

    def _end_segment(self) -> None:
        assert self._segments is not None
        if len(self._points) >= 2:
            self._segments.append(Demonstration(np.array(self._points), np.array(self._times),
                                                "object", self._states))

    # --- commands -------------------------------------------------------------------------
    def handle(self, command: str) -> str:
        """Carry out one command; returns what it did (also appended to :attr:`log`)."""
        if command not in COMMANDS:
            raise A2LValueError(f"unknown teleoperation command '{command}'; choose one of "
                                f"{list(COMMANDS)}")
        if self.finished:
            raise A2LValueError("the recorder has quit")
        if command in MOVES:
            d = np.asarray(MOVES[command], dtype=float) * self.step
            before = self.scene.eef_position()
            res = self.scene.move_by(d)
            msg = f"{command}: " + ("ok" if res else f"not carried out ({res.status}: "
                                                     f"{res.message})")
            # a sample where the end-effector went (none when it did not move)
            if self.recording and np.linalg.norm(self.scene.eef_position() - before) > 1e-3:
                self._sample()
        elif command == "gripper":
            if self.recording:
                self._end_segment()
            closed = self.scene.ground_truth()["states"]["gripper"] == "closed"
            if closed:
                self.scene.open_gripper()
            else:
                self.scene.close_gripper()
            msg = f"gripper: {'open' if closed else 'closed'}"
            if self.recording:
                self._begin_segment()
        elif command == "record":
            if self.recording:
                msg = self._stop()
            else:
                self._segments = []
                self._begin_segment()
                msg = "record: started"
        else:
            if self.recording:
                self._stop()
            self.finished = True
            msg = "quit"
        self.log.append(msg)
        return msg

    def _stop(self) -> str:
        self._end_segment()
        segments = self._segments or []
        self._segments = None
        if not segments:
            return "record: stopped, nothing recorded (no move)"
        self.recordings.append(segments)
        return (f"record: stopped, recording {len(self.recordings)} with "
                f"{len(segments)} segment(s)")

    def demonstrations(self) -> list[Demonstration]:
        """Every segment of every finished recording, in order (what :meth:`save` writes)."""
        return [seg for rec in self.recordings for seg in rec]

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the finished recordings (``.csv`` or ``.parquet``), atomically."""
        demos = self.demonstrations()
        if not demos:
            raise A2LValueError("nothing recorded: start and stop a recording (Return) "
                                "around some moves")
        return save_demonstrations(path, demos)


def run_commands(scene: ArmSceneProtocol, commands: Iterable[str], obj: str | None = None,
                 step: float = 0.01) -> TeleopRecorder:
    """Feed a sequence of commands to a recorder (headless use and tests).

    A command may carry a repeat count, ``"down*5"``.
    """
    rec = TeleopRecorder(scene, obj, step)
    for item in commands:
        name, _, count = item.strip().partition("*")
        try:
            n = int(count) if count else 1
        except ValueError:
            raise A2LValueError(f"bad repeat count in command '{item}'") from None
        for _ in range(n):
            rec.handle(name)
    if rec.recording:
        rec.handle("record")
    return rec


def run_gui(scene: ArmSceneProtocol, out: str | os.PathLike[str], obj: str | None = None,
            step: float = 0.01) -> TeleopRecorder:
    """Teleoperate in the PyBullet GUI until ``quit`` (or the window closes); save to `out`.

    Returns the recorder; nothing is written when nothing was recorded.
    """
    take_keyboard(scene)
    rec = TeleopRecorder(scene, obj, step)
    print("teleoperation: arrows move in x/y, Page Up/Down in z, Space toggles the gripper, "
          "Return starts/stops recording, q quits", flush=True)
    while not rec.finished:
        try:
            for key in keys_pressed(scene):
                command = key_command(key)
                if command is not None:
                    print(rec.handle(command), flush=True)
            with window_guard():
                scene.settle(1.0 / 60.0)
        except WindowClosed:
            break
    if rec.recording:
        rec.handle("record")
    if rec.recordings:
        rec.save(out)
        print(f"saved {len(rec.demonstrations())} segment(s) of {len(rec.recordings)} "
              f"recording(s) to {out}", flush=True)
    return rec


def record_demonstrations(scene_name: str, out: str | os.PathLike[str], seed: int = 0,
                          keys: Iterable[str] | None = None,
                          start: Iterable[float] | None = None,
                          step: float = 0.01) -> TeleopRecorder:
    """What ``a2l demo-record`` does: build the scene, teleoperate, save to `out`.

    Parameters
    ----------
    scene_name : str
        A PyBullet scene (``grasp``, ``grasp_light``, ``press``, ``push``).
    out : path
        Demonstration file (``.csv`` or ``.parquet``); written when something was recorded.
    seed : int
        Scene seed.
    keys : iterable of str, optional
        Commands to run headless (DIRECT mode) instead of opening the GUI.
    start : (3,) floats, optional
        Start of the end-effector relative to the scene's primary object (m).
    step : float
        Length of one move (m).
    """
    if scene_name == "virtual":
        raise A2LValueError("teleoperation needs a PyBullet scene, not 'virtual'")
    with make_scene(scene_name, seed=seed, gui=keys is None,
                    context_source="ground_truth") as scene:
        if start is not None:
            rel = np.asarray(list(start), dtype=float).reshape(3)
            scene.reset(eef=np.asarray(scene.ground_truth()["objects"][scene.primary_object])
                        + rel)
        if keys is None:
            return run_gui(scene, out, step=step)
        rec = run_commands(scene, keys, step=step)
        if rec.recordings:
            rec.save(out)
        for line in rec.log:
            print(line)
        print(f"{len(rec.recordings)} recording(s), {len(rec.demonstrations())} segment(s)"
              + (f" saved to {out}" if rec.recordings else ": nothing saved"))
        return rec
