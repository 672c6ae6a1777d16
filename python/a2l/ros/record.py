"""Recording a ROS 2 run: every message a node receives or sends, in an MCAP file readable
by the ROS tools (``ros2 bag``, Foxglove; profile ``ros2``, CDR messages with their
``ros2msg`` definitions), and a Rerun recording beside it (``.rrd``,
:class:`a2l.rollout.recording.RerunRecorder`) of the skill node's steps.

The message definitions come from the installed message packages (``share/<pkg>/msg``):
the definition of a type followed by those it uses, as rosbag2 writes them.
"""

from __future__ import annotations

import os
import re
import sys
import sysconfig
import time
from functools import lru_cache
from pathlib import Path
from typing import Any

from a2l.errors import A2LValueError
from a2l.rollout.recording import RerunRecorder

__all__ = ["RosRecorder", "message_definition", "type_name"]

_PRIMITIVES = {"bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16",
               "uint16", "int32", "uint32", "int64", "uint64", "string", "wstring"}
_SEPARATOR = "=" * 80


def type_name(msg: Any) -> str:
    """``pkg/msg/Type`` of an rclpy message instance."""
    cls = type(msg)
    return f"{cls.__module__.split('.')[0]}/msg/{cls.__name__}"


def _prefixes() -> list[Path]:
    """Where message packages put ``share/<pkg>/msg``: the ament prefixes, else this
    environment's (the PyPI wheels install there; no ROS set-up script is needed)."""
    ament = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    return [Path(p) for p in (*ament, sys.prefix, sysconfig.get_path("data"), sys.base_prefix)]


def _msg_text(pkg: str, name: str) -> str:
    for prefix in _prefixes():
        path = prefix / "share" / pkg / "msg" / f"{name}.msg"
        if path.is_file():
            return path.read_text(encoding="utf-8")
    raise A2LValueError(f"no definition of {pkg}/msg/{name} under share/{pkg}/msg of "
                        f"{[str(p) for p in _prefixes()]}")


@lru_cache(maxsize=64)
def message_definition(full: str) -> str:
    """The ``ros2msg`` definition of type `full` (``pkg/msg/Type``) with its dependencies."""
    pkg, _, name = full.split("/")
    seen: set[tuple[str, str]] = set()
    parts = [_msg_text(pkg, name)]

    def visit(pkg: str, text: str) -> None:
        for line in text.splitlines():
            words = line.split("#", 1)[0].split()
            if len(words) < 2:
                continue
            base = re.sub(r"(\[[^\]]*\]|<=\d+)+$", "", words[0])
            if base in _PRIMITIVES:
                continue
            if "/" in base:
                dep = (base.split("/")[0], base.split("/")[-1])
            else:
                dep = ("std_msgs", "Header") if base == "Header" else (pkg, base)
            if dep not in seen:
                seen.add(dep)
                text_dep = _msg_text(*dep)
                parts.append(f"{_SEPARATOR}\nMSG: {dep[0]}/{dep[1]}\n{text_dep}")
                visit(dep[0], text_dep)

    visit(pkg, parts[0])
    return "\n".join(parts)


class RosRecorder:
    """An MCAP file of ROS 2 messages, written as they come, and a Rerun recording beside.

    Parameters
    ----------
    path : Path
        The ``.mcap`` file; the Rerun recording is ``path.with_suffix(".rrd")``.
    rerun : bool
        Whether to write the Rerun recording (:attr:`rerun`).
    """

    def __init__(self, path: Path, rerun: bool = True) -> None:
        from mcap.well_known import Profile
        from mcap.writer import Writer

        self.path = Path(path)
        if self.path.suffix != ".mcap":
            raise A2LValueError(f"recording '{self.path}': a ROS recording ends in .mcap")
        self.tmp = self.path.with_name(f".{self.path.name}.tmp")
        self.stream = open(self.tmp, "wb")  # noqa: SIM115 - closed in close()
        self.writer = Writer(self.stream)
        self.writer.start(profile=Profile.ROS2, library="a2l")
        self.schemas: dict[str, int] = {}
        self.channels: dict[str, int] = {}
        self.count = 0
        self.rerun = RerunRecorder(self.path.with_suffix(".rrd")) if rerun else None

    def message(self, topic: str, msg: Any) -> None:
        """Write `msg` on `topic` (a resolved name, ``/joint_states``), stamped now."""
        from mcap.well_known import MessageEncoding, SchemaEncoding
        from rclpy.serialization import serialize_message

        if topic not in self.channels:
            full = type_name(msg)
            if full not in self.schemas:
                self.schemas[full] = self.writer.register_schema(
                    name=full, encoding=SchemaEncoding.ROS2,
                    data=message_definition(full).encode())
            self.channels[topic] = self.writer.register_channel(
                topic=topic, message_encoding=MessageEncoding.CDR,
                schema_id=self.schemas[full])
        now = time.time_ns()
        self.writer.add_message(self.channels[topic], log_time=now, publish_time=now,
                                data=serialize_message(msg), sequence=self.count)
        self.count += 1

    def close(self) -> None:
        """Finish both files (each written to a temporary file, then renamed)."""
        self.writer.finish()
        self.stream.close()
        os.replace(self.tmp, self.path)
        if self.rerun is not None:
            self.rerun.close()
