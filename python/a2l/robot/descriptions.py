"""Locate robot descriptions and make PyBullet-loadable copies of them."""

from __future__ import annotations

import hashlib
import importlib.metadata
import os
import re
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from a2l.atomic import atomic_write_text
from a2l.errors import A2LFileNotFoundError, URDFError
from a2l.robot.gripper import GRIPPER_DOWN

__all__ = [
    "BAXTER_ARMS",
    "ArmSpec",
    "baxter_urdf",
    "panda_urdf",
    "pusher_urdf",
    "pybullet_urdf",
    "resolve_urdf",
    "robots_dir",
    "urdf_sha256",
]

_PACKAGE = "example-robot-data"
_ROBOTS_SUFFIX = ("share", "example-robot-data", "robots")


@dataclass(frozen=True)
class ArmSpec:
    """One arm of a robot: the chain the kinematics and the skills use (the view of a
    :class:`~a2l.robot.RobotEntry` that :func:`~a2l.robot.arm_spec` gives).

    Attributes
    ----------
    urdf : Path
        The robot's URDF.
    base_link, tip_link : str
        First and last links of the arm's chain.
    neutral : tuple of float
        A neutral joint configuration, shape (n,), used to seed IK.
    down : tuple of tuple of float
        Orientation (3, 3) of the tip link pointing down with the fingers closing along the
        base's y axis (:func:`a2l.robot.gripper.gripper_down` turns it about the vertical).
    """

    urdf: Path
    base_link: str
    tip_link: str
    neutral: tuple[float, ...]
    down: tuple[tuple[float, ...], ...] = tuple(map(tuple, GRIPPER_DOWN.tolist()))


#: Baxter's arms: chains from the base to each gripper's end point, and a neutral pose
#: (arm in front of the robot, gripper pointing down).
BAXTER_ARMS: dict[str, tuple[str, str, tuple[float, ...]]] = {
    "right": ("base", "right_gripper", (0.08, -1.0, 1.19, 1.94, -0.67, 1.03, 0.5)),
    "left": ("base", "left_gripper", (-0.08, -1.0, -1.19, 1.94, 0.67, 1.03, -0.5)),
}


@lru_cache(maxsize=1)
def robots_dir() -> Path:
    """Directory ``robots/`` of the installed ``example-robot-data``.

    Found through the package's installed file list (:mod:`importlib.metadata`), so it
    works in any virtual environment or prefix.

    Returns
    -------
    Path
        The directory that holds ``baxter_description/``, ``panda_description/``, ...

    Raises
    ------
    a2l.A2LFileNotFoundError
        ``example-robot-data`` is not installed.
    """
    try:
        dist = importlib.metadata.distribution(_PACKAGE)
    except importlib.metadata.PackageNotFoundError as exc:
        raise A2LFileNotFoundError(
            f"the Python package '{_PACKAGE}' is not installed: pip install {_PACKAGE}"
        ) from exc
    for f in dist.files or ():
        parts = Path(str(f)).parts
        for i in range(len(parts) - len(_ROBOTS_SUFFIX) + 1):
            if parts[i : i + len(_ROBOTS_SUFFIX)] == _ROBOTS_SUFFIX:
                return Path(dist.locate_file(Path(*parts[: i + len(_ROBOTS_SUFFIX)]))).resolve()
    raise A2LFileNotFoundError(f"'{_PACKAGE}' is installed but holds no robots/ directory")


def _robot_urdf(description: str, file: str) -> Path:
    path = robots_dir() / description / "urdf" / file
    if not path.is_file():
        raise A2LFileNotFoundError(f"'{path}' is missing from the installed '{_PACKAGE}'")
    return path


def baxter_urdf() -> Path:
    """Path of Baxter's URDF inside the installed ``example-robot-data``.

    Its meshes are ``package://`` URIs: use :func:`pybullet_urdf` to get a copy PyBullet
    can load.
    """
    return _robot_urdf("baxter_description", "baxter.urdf")


def panda_urdf() -> Path:
    """Path of the Franka Panda URDF inside the installed ``example-robot-data``."""
    return _robot_urdf("panda_description", "panda.urdf")


def resolve_urdf(robot: str | os.PathLike[str]) -> Path:
    """Turn a robot name (``"baxter"``, ``"panda"``) or a URDF path into a URDF path.

    Raises
    ------
    a2l.A2LFileNotFoundError
        The path does not exist.
    """
    if isinstance(robot, str) and robot in ("baxter", "panda"):
        return baxter_urdf() if robot == "baxter" else panda_urdf()
    path = Path(robot).expanduser()
    if not path.is_file():
        raise A2LFileNotFoundError(f"URDF file '{path}' does not exist")
    return path.resolve()


def urdf_sha256(path: str | os.PathLike[str]) -> str:
    """SHA-256 of a URDF file's bytes (hex), as stored in skill bundles."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


_PACKAGE_URI = re.compile(r'filename="package://([^/"]+)/([^"]*)"')


def _cache_dir() -> Path:
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    return Path(root) / "a2l" / "urdf"


def cached_urdf(stem: str, text: str) -> Path:
    """A generated URDF kept in ``~/.cache/a2l/urdf`` as ``<stem>-<content hash>.urdf``.

    Written once per content, atomically; the path of the existing copy otherwise.
    """
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    out_dir = _cache_dir()
    out_dir.mkdir(parents=True, exist_ok=True)
    out = out_dir / f"{stem}-{digest}.urdf"
    if not out.is_file():
        atomic_write_text(out, text)
    return out


def pybullet_urdf(path: str | os.PathLike[str] | None = None) -> Path:
    """A copy of a URDF whose ``package://`` mesh URIs are absolute paths.

    PyBullet resolves ``package://`` only next to the file; the copy is written once per
    source content (atomically: temporary file, then rename) in ``~/.cache/a2l/urdf``.

    Parameters
    ----------
    path : str or PathLike, optional
        The URDF; Baxter's by default.

    Returns
    -------
    Path
        The rewritten copy (or `path` itself when it has no ``package://`` URIs).

    Raises
    ------
    a2l.URDFError
        A ``package://`` URI names a package that cannot be found.
    """
    src = baxter_urdf() if path is None else resolve_urdf(path)
    text = src.read_text()
    if "package://" not in text:
        return src
    robots = robots_dir()

    def replace(m: re.Match[str]) -> str:
        package, rest = m.group(1), m.group(2)
        candidates = [robots.parent / rest] if package == _PACKAGE else []
        candidates += [robots / package / rest, src.parent.parent / rest]
        for c in candidates:
            if c.is_file():
                return f'filename="{c}"'
        raise URDFError(f"URDF '{src}': cannot resolve mesh 'package://{package}/{rest}'")

    return cached_urdf(src.stem, _PACKAGE_URI.sub(replace, text))


#: The link :func:`pusher_urdf` adds at the tip of the pusher.
PUSHER_TIP = "a2l_pusher_tip"


def pusher_urdf(urdf: str | os.PathLike[str], parent: str, axis: tuple[float, float, float],
                length: float, radius: float) -> Path:
    """A copy of `urdf` with a pusher: a rod of `length` and `radius` (m) fixed to link
    `parent` along `axis` (3,) of its frame, and a link :data:`PUSHER_TIP` at its end (the
    tool point of an arm whose flange would otherwise push with its wrist). Written once per
    content in ``~/.cache/a2l/urdf``; ``package://`` URIs are kept, so :func:`pybullet_urdf`
    resolves its meshes as the original's.

    Raises
    ------
    a2l.URDFError
        `urdf` has no link `parent`, or already a link :data:`PUSHER_TIP`.
    """
    import math
    import xml.etree.ElementTree as ET

    src = Path(urdf)
    root = ET.fromstring(src.read_text())
    links = {link.get("name") for link in root.iter("link")}
    if parent not in links or PUSHER_TIP in links:
        raise URDFError(f"URDF '{src}': no link '{parent}' to fix a pusher to, or one is "
                        "there already")
    a = [float(v) for v in axis]
    n = math.sqrt(sum(v * v for v in a))
    a = [v / n for v in a]
    # the rod's cylinder lies along z: turn z onto the axis (about the axis z x a)
    angle = math.acos(max(-1.0, min(1.0, a[2])))
    turn = (-a[1], a[0], 0.0) if abs(a[2]) < 1 - 1e-12 else (1.0, 0.0, 0.0)
    rpy = _rpy_of_axis_angle(turn, angle)
    mid = " ".join(f"{v * length / 2:.6g}" for v in a)
    tip = " ".join(f"{v * length:.6g}" for v in a)
    rod = ET.SubElement(root, "link", {"name": "a2l_pusher"})
    for tag in ("visual", "collision"):
        el = ET.SubElement(rod, tag)
        ET.SubElement(el, "origin", {"xyz": mid, "rpy": " ".join(f"{v:.6g}" for v in rpy)})
        geom = ET.SubElement(el, "geometry")
        ET.SubElement(geom, "cylinder", {"radius": f"{radius:.6g}", "length": f"{length:.6g}"})
    inertial = ET.SubElement(rod, "inertial")
    ET.SubElement(inertial, "origin", {"xyz": mid, "rpy": "0 0 0"})
    ET.SubElement(inertial, "mass", {"value": "0.1"})
    ET.SubElement(inertial, "inertia", {"ixx": "1e-4", "ixy": "0", "ixz": "0", "iyy": "1e-4",
                                        "iyz": "0", "izz": "1e-5"})
    ET.SubElement(root, "link", {"name": PUSHER_TIP})
    for name, (par, child, xyz) in {"a2l_pusher_joint": (parent, "a2l_pusher", "0 0 0"),
                                    "a2l_pusher_tip_joint": ("a2l_pusher", PUSHER_TIP, tip)
                                    }.items():
        joint = ET.SubElement(root, "joint", {"name": name, "type": "fixed"})
        ET.SubElement(joint, "parent", {"link": par})
        ET.SubElement(joint, "child", {"link": child})
        ET.SubElement(joint, "origin", {"xyz": xyz, "rpy": "0 0 0"})
    stem = f"{src.stem}-pusher"
    return cached_urdf(stem, ET.tostring(root, encoding="unicode"))


def _rpy_of_axis_angle(axis: tuple[float, float, float], angle: float
                       ) -> tuple[float, float, float]:
    """Roll, pitch, yaw (rad, URDF's fixed-axis x-y-z) of a turn by `angle` about `axis`."""
    import numpy as np

    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    r = np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx
    pitch = float(np.arcsin(-np.clip(r[2, 0], -1, 1)))
    roll = float(np.arctan2(r[2, 1], r[2, 2]))
    yaw = float(np.arctan2(r[1, 0], r[0, 0]))
    return roll, pitch, yaw
