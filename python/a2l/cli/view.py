"""``a2l view FILE.rrd``: open a Rerun recording (``--record`` of ``a2l skill run``, ``a2l ros
skill`` and every ``a2l experiment``) in the Rerun viewer (the ``rerun`` of ``rerun-sdk``,
the ``ros`` extra); ``--web`` serves the web viewer instead of opening a window."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

from jsonargparse import Namespace

from a2l.cli.args import UsageError
from a2l.cli.parser import Parser, add_config_option

__all__ = ["RRD_MAGIC", "add_view_parser", "check_recording"]

#: The first bytes of a Rerun recording file.
RRD_MAGIC = b"RRF"


def check_recording(path: Path) -> None:
    """Fail with a usage error naming the problem unless `path` is a Rerun recording."""
    if path.suffix == ".mcap":
        raise UsageError("FILE", f"'{path}' is an MCAP file of ROS 2 messages: open it with "
                         "Foxglove or ros2 bag; a2l view opens the .rrd beside it")
    if path.suffix != ".rrd":
        raise UsageError("FILE", f"'{path}': a Rerun recording ends in .rrd")
    if not path.is_file():
        raise UsageError("FILE", f"'{path}' is not a file")
    with path.open("rb") as f:
        if f.read(len(RRD_MAGIC)) != RRD_MAGIC:
            raise UsageError("FILE", f"'{path}' is not a Rerun recording (no RRF header)")


def _cmd_view(ns: Namespace) -> int:
    path = Path(ns.file)
    check_recording(path)
    try:
        import rerun  # noqa: F401
    except ImportError:
        raise UsageError("FILE", "rerun-sdk is not installed: pip install 'a2l[ros]'") from None
    argv = [sys.executable, "-m", "rerun", *(["--serve-web"] if ns.web else []), str(path)]
    return subprocess.call(argv)


def add_view_parser(sub: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """The ``view`` subcommand."""
    p = Parser(prog="a2l view", description="Open a Rerun recording (.rrd) of a run in the "
               "Rerun viewer: the robot's links, the objects, the end-effector path, the "
               "camera, the context bins, the movements and the effect over time.")
    p.add_argument("file", metavar="FILE", help="the recording (.rrd)")
    p.add_argument("--web", action="store_true",
                   help="serve the web viewer over HTTP instead of opening a window")
    add_config_option(p)
    sub.add_subcommand("view", p, help="open a Rerun recording of a run")
    commands[("view",)] = (p, _cmd_view)
