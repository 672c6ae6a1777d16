"""A user's arm from a robot file (YAML or JSON), and a robot by name or file.

A robot file is a mapping (``docs/robots.md`` has an example)::

    name: z1                      # optional; the file's stem by default
    urdf: package://example-robot-data/robots/z1_description/urdf/z1.urdf
    base_link: link00
    tool_link: gripperStator
    neutral: [0.0, 2.01, -1.29, 0.85, 0.0, 0.0]    # the chain's joints, base to tool
    tool_down: [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]  # optional
    gripper:                                       # optional
      joints: [jointGripper]
      open: [-1.0]
      closed: [0.0]
      grasp_open: [-1.2]                           # optional: opened for a grasp
    mount: {xyz: [-0.4, 0.0, 0.0], yaw: 0.0}       # degrees
    work_point: [0.0, -0.1]                        # optional: where the objects stand
    rest: {jointGripper: 0.0}                      # optional: joints outside the chain

``urdf`` is a path relative to the file's folder (or absolute), or a ``package://PKG/PATH``
URI: with PKG ``example-robot-data``, PATH inside the installed package's share folder;
otherwise ``robots/PKG/PATH`` of the installed ``example-robot-data``, then ``PKG/PATH`` in
the file's folder. ``work_point`` is in the table frame (:mod:`a2l.robot.entries`); without
it the scenes put their objects where the arm reaches best (:func:`a2l.robot.table_layout`).
Every key but ``name``, ``tool_down``, ``gripper``, ``work_point`` and ``rest`` is required,
and both ``mount.xyz`` and ``mount.yaw``, and a gripper's ``joints``, ``open`` and ``closed``
(``grasp_open``, the opening of the scenes that grasp, defaults to ``open``): nothing is
guessed. The entry is then checked against its URDF (:func:`a2l.robot.check_entry`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from a2l.errors import A2LFileNotFoundError, A2LValueError, RobotEntryError
from a2l.robot.builtin_robots import BUILTIN_ROBOTS, builtin_robot
from a2l.robot.descriptions import BAXTER_ARMS, robots_dir
from a2l.robot.entries import Gripper, Mount, RobotEntry
from a2l.robot.entry_checks import check_entry

__all__ = ["ROBOT_FILE_KEYS", "ROBOT_FILE_SUFFIXES", "arm_entry", "load_robot", "robot_entry"]

#: The keys of a robot file, required first.
ROBOT_FILE_KEYS = ("urdf", "base_link", "tool_link", "neutral", "mount", "name", "tool_down",
                   "gripper", "work_point", "rest")
_REQUIRED = ROBOT_FILE_KEYS[:5]
_GRIPPER_KEYS = ("joints", "open", "closed", "grasp_open")
_GRIPPER_REQUIRED = ("joints", "open", "closed")
_MOUNT_KEYS = ("xyz", "yaw")
#: The file name suffixes of a robot file.
ROBOT_FILE_SUFFIXES = (".yaml", ".yml", ".json")


def load_robot(path: str | os.PathLike[str]) -> RobotEntry:
    """The robot entry of a robot file (module docstring), checked against its URDF.

    Parameters
    ----------
    path : str or PathLike
        A ``.yaml``, ``.yml`` or ``.json`` file.

    Returns
    -------
    RobotEntry
        The entry (its `reach` already measured by the check).

    Raises
    ------
    a2l.A2LFileNotFoundError
        The file does not exist.
    a2l.RobotEntryError
        Naming the file and the key: not YAML or JSON, an unknown key (the valid ones
        listed), a missing key, a value of the wrong type or size, and every refusal of
        :func:`a2l.robot.check_entry`.
    """
    path = Path(path).expanduser()
    src = f"robot file '{path}'"
    if path.suffix.lower() not in ROBOT_FILE_SUFFIXES:
        raise RobotEntryError(src, "", f"unknown format '{path.suffix}': a robot file is "
                              f"{', '.join(ROBOT_FILE_SUFFIXES)}")
    if not path.is_file():
        raise A2LFileNotFoundError(f"{src} does not exist")
    data = _read(path, src)
    _check_keys(data, ROBOT_FILE_KEYS, _REQUIRED, "", src)
    gripper = data.get("gripper")
    if gripper is not None:
        _check_keys(gripper, _GRIPPER_KEYS, _GRIPPER_REQUIRED, "gripper.", src)
        wide = gripper.get("grasp_open")
        gripper = Gripper(_strings(gripper["joints"], "gripper.joints", src),
                          _numbers(gripper["open"], "gripper.open", src),
                          _numbers(gripper["closed"], "gripper.closed", src),
                          None if wide is None else _numbers(wide, "gripper.grasp_open", src))
    mount = data["mount"]
    _check_keys(mount, _MOUNT_KEYS, _MOUNT_KEYS, "mount.", src)
    tool_down = data.get("tool_down")
    if tool_down is not None:
        if not isinstance(tool_down, list) or len(tool_down) != 3:
            raise RobotEntryError(src, "tool_down", f"must be 3 rows of 3 numbers, got "
                                  f"{tool_down!r}")
        tool_down = tuple(_numbers(row, "tool_down", src, 3) for row in tool_down)
    work_point = data.get("work_point")
    if work_point is not None:
        work_point = _numbers(work_point, "work_point", src, 2)
    rest = data.get("rest") or {}
    if not isinstance(rest, Mapping):
        raise RobotEntryError(src, "rest", f"must map joint names to positions, got {rest!r}")
    rest_items = tuple((_string(k, "rest", src), _number(v, f"rest.{k}", src))
                       for k, v in rest.items())
    entry = RobotEntry(
        name=_string(data.get("name", path.stem), "name", src),
        urdf=_resolve_urdf(_string(data["urdf"], "urdf", src), path.parent, src),
        base_link=_string(data["base_link"], "base_link", src),
        tool_link=_string(data["tool_link"], "tool_link", src),
        neutral=_numbers(data["neutral"], "neutral", src),
        mount=Mount(_numbers(mount["xyz"], "mount.xyz", src, 3),  # type: ignore[arg-type]
                    _number(mount["yaw"], "mount.yaw", src)),
        tool_down=tool_down, gripper=gripper, work_point=work_point,  # type: ignore[arg-type]
        rest=rest_items)
    check_entry(entry, src)
    return entry


def robot_entry(robot: str | os.PathLike[str]) -> RobotEntry:
    """A built-in robot by name (:data:`a2l.robot.BUILTIN_ROBOTS`), or a robot file's.

    Parameters
    ----------
    robot : str or PathLike
        ``"baxter"``, ``"panda"``... or the path of a ``.yaml``, ``.yml`` or ``.json`` file.

    Raises
    ------
    a2l.A2LValueError
        Neither a built-in robot nor a robot file (both kinds listed).
    a2l.A2LFileNotFoundError, a2l.RobotEntryError
        As :func:`load_robot`.
    """
    if isinstance(robot, str) and robot in BUILTIN_ROBOTS:
        return builtin_robot(robot)
    path = Path(robot).expanduser()
    if path.suffix.lower() in ROBOT_FILE_SUFFIXES:
        return load_robot(path)
    raise A2LValueError(f"unknown robot '{robot}': neither a built-in robot "
                        f"({', '.join(BUILTIN_ROBOTS)}) nor a robot file "
                        f"({', '.join(ROBOT_FILE_SUFFIXES)})")


def arm_entry(robot: str | os.PathLike[str], arm: str = "right") -> RobotEntry:
    """:func:`robot_entry` with Baxter's arm chosen: ``"baxter"`` with `arm` ``"left"`` is
    ``"baxter-left"``; `arm` is ignored for the other robots.

    Raises
    ------
    a2l.A2LValueError
        An unknown Baxter arm, and as :func:`robot_entry`.
    """
    if robot == "baxter":
        if arm not in BAXTER_ARMS:
            raise A2LValueError(f"unknown Baxter arm '{arm}'; choose one of "
                                f"{sorted(BAXTER_ARMS)}")
        return builtin_robot("baxter" if arm == "right" else "baxter-left")
    return robot_entry(robot)


def _read(path: Path, src: str) -> dict[str, Any]:
    text = path.read_text(encoding="utf-8")
    try:
        data = json.loads(text) if path.suffix.lower() == ".json" else yaml.safe_load(text)
    except (json.JSONDecodeError, yaml.YAMLError) as exc:
        kind = "JSON" if path.suffix.lower() == ".json" else "YAML"
        raise RobotEntryError(src, "", f"not valid {kind}: {exc}") from None
    if not isinstance(data, dict):
        raise RobotEntryError(src, "", f"must hold a mapping of keys "
                              f"({', '.join(ROBOT_FILE_KEYS)}), got {type(data).__name__}")
    return data


def _check_keys(data: object, valid: tuple[str, ...], required: tuple[str, ...], prefix: str,
                src: str) -> None:
    """`data` a mapping with only `valid` keys and every `required` one."""
    if not isinstance(data, Mapping):
        raise RobotEntryError(src, prefix.rstrip("."), f"must be a mapping of "
                              f"{', '.join(valid)}, got {data!r}")
    for key in data:
        if key not in valid:
            raise RobotEntryError(src, f"{prefix}{key}", f"unknown key; the valid keys are "
                                  f"{', '.join(prefix + k for k in valid)}")
    for key in required:
        if key not in data:
            raise RobotEntryError(src, f"{prefix}{key}", f"missing (required: "
                                  f"{', '.join(prefix + k for k in required)})")


def _string(value: object, key: str, src: str) -> str:
    if not isinstance(value, str) or not value:
        raise RobotEntryError(src, key, f"must be a non-empty string, got {value!r}")
    return value


def _strings(value: object, key: str, src: str) -> tuple[str, ...]:
    if not isinstance(value, list):
        raise RobotEntryError(src, key, f"must be a list of names, got {value!r}")
    return tuple(_string(v, key, src) for v in value)


def _number(value: object, key: str, src: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise RobotEntryError(src, key, f"must be a number, got {value!r}")
    return float(value)


def _numbers(value: object, key: str, src: str, size: int | None = None) -> tuple[float, ...]:
    if not isinstance(value, list) or (size is not None and len(value) != size):
        what = f"{size} numbers" if size is not None else "a list of numbers"
        raise RobotEntryError(src, key, f"must be {what}, got {value!r}")
    return tuple(_number(v, key, src) for v in value)


def _resolve_urdf(text: str, folder: Path, src: str) -> Path:
    """The URDF file of a robot file's ``urdf`` (module docstring)."""
    if text.startswith("package://"):
        package, _, rest = text[len("package://"):].partition("/")
        tried = [robots_dir().parent / rest] if package == "example-robot-data" else []
        if package != "example-robot-data":
            tried += [robots_dir() / package / rest, folder / package / rest]
        for candidate in tried:
            if candidate.is_file():
                return candidate.resolve()
        raise RobotEntryError(src, "urdf", f"cannot resolve '{text}': no file "
                              f"{' nor '.join(repr(str(c)) for c in tried)}")
    path = Path(text).expanduser()
    path = path if path.is_absolute() else folder / path
    if not path.is_file():
        raise RobotEntryError(src, "urdf", f"no such file '{path}'")
    return path.resolve()
