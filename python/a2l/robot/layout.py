"""Where a robot's scenes stand: the table, the work point, the scale and the cameras,
computed from its entry (:class:`~a2l.robot.RobotEntry`) and what its arm reaches.

The scenes' world frame is the robot's base frame. The table (a top of
:data:`TABLE_SIZE` at :data:`TABLE_HEIGHT` above the floor) stands where the entry's mount
says. The **work point**, where the objects stand, is the entry's ``work_point`` or, without
one, the point of the table top farthest from anything the arm cannot reach with its tool
pointing down (the centre of the largest disc of reachable points, found on a grid by the
C++ IK from the neutral pose). The **scale** is the largest such disc's radius over
:data:`REFERENCE_RADIUS` (what Baxter has in the thesis' scene), at most 1: an arm
that reaches less (the SO-101) gets a scene shrunk about its work point: objects, movement
length, start ring, thresholds, cameras. Baxter's layout is the thesis' scene to the
micrometre (a test holds it to the values the scenes used before robots were data).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections import deque
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from a2l import _core
from a2l.atomic import atomic_write_text
from a2l.errors import A2LValueError
from a2l.robot.descriptions import urdf_sha256
from a2l.robot.entries import RobotEntry

__all__ = ["REFERENCE_RADIUS", "TABLE_HEIGHT", "TABLE_SIZE", "TableLayout", "reachable_disc",
           "table_layout"]

#: Height (m) of the table top above the floor (Baxter's pedestal bottom to the thesis' top).
TABLE_HEIGHT = 0.72418
#: Depth (along the table frame's x) and width (m) of the table top; not scaled.
TABLE_SIZE = (0.7, 1.2)
#: Radius (m) of reachable table a scene of scale 1 has around its work point: Baxter's
#: largest disc is 0.222 m (measured by :func:`reachable_disc`), rounded down. The thesis'
#: start ring (0.10-0.25 m) reaches past it: some starts are at the rim of reach.
REFERENCE_RADIUS = 0.20
#: Height (m) of the tool above the table top where reach is tested, at scale 1: the centre
#: of the push box, the height the pushes move at.
TEST_HEIGHT = 0.04
#: The version of the reach test (:func:`reachable_disc`), part of its cache's key: a change
#: of the algorithm must not read what an earlier one wrote.
LAYOUT_VERSION = 2
#: Spacing (m) of the grid of tested points at scale 1.
GRID = 0.02
#: Largest joint change (rad) from a reached grid point's IK solution to its neighbour's,
#: 2 cm apart (scaled with the spacing), for the neighbour to count as reached: a larger
#: one is a change of IK branch (the scenes refuse a waypoint 1 cm on whose solution is
#: 0.5 rad away).
BRANCH_JUMP = 1.0
# The thesis' scene around its work point (table frame, m, at scale 1): the camera looks at
# a point 0.13 m beyond and 0.10 m left of it, from 0.80 m farther and 1.05 m up; the side
# cameras from 1.10 m either side; the end-effector's workspace bounds.
_TARGET = (0.13, 0.10)
_EYE = (0.80, 0.0, 1.05)
_SIDE_EYES = ((0.0, 1.10, 1.05), (0.0, -1.10, 1.05))
_WORKSPACE = ((-0.27, -0.50, 0.01), (0.33, 0.70, 0.45))


@dataclass(frozen=True)
class TableLayout:
    """A robot's scene geometry in its base frame (m); see :mod:`a2l.robot.layout`.

    Attributes
    ----------
    robot : str
        The entry's name.
    scale : float
        In (0, 1]: lengths of the scene relative to the thesis' (1 for arms that reach as
        far as Baxter around the work point).
    radius : float
        Radius of the largest disc of reachable table around the work point (m); for an
        entry with a ``work_point``, the largest over the table (it sets the scale).
    table_z, floor_z : float
        Heights of the table top and of the floor.
    table_center, table_size : tuple of 2 float
        Centre ``(x, y)`` and size ``(depth, width)`` of the table top.
    table_yaw : float
        Turn (degrees) of the table's x axis from the base's (minus the mount's yaw).
    work_point : tuple of 2 float
        Where the objects stand ``(x, y)``.
    camera_eye, camera_target : tuple of 3 float
        The main camera.
    extra_camera_eyes : tuple of 2 (x, y, z)
        The side cameras (looking at `camera_target`).
    workspace_min, workspace_max : tuple of 3 float
        The end-effector's bounds, ``z`` relative to the table top.
    """

    robot: str
    scale: float
    radius: float
    table_z: float
    floor_z: float
    table_center: tuple[float, float]
    table_size: tuple[float, float]
    table_yaw: float
    work_point: tuple[float, float]
    camera_eye: tuple[float, float, float]
    camera_target: tuple[float, float, float]
    extra_camera_eyes: tuple[tuple[float, float, float], ...]
    workspace_min: tuple[float, float, float]
    workspace_max: tuple[float, float, float]

    def place(self, offset: tuple[float, float]) -> tuple[float, float]:
        """The point ``(x, y)`` at `offset` (table frame, m at scale 1) from the work point,
        scaled, in the base frame (rounded to the micrometre)."""
        return _offset(self.work_point, offset, self.table_yaw, self.scale)


def _offset(origin: tuple[float, ...], offset: tuple[float, ...], yaw: float, scale: float
            ) -> tuple[float, float]:
    """The point ``(x, y)`` of the base frame at `offset` (table frame, scaled by `scale`)
    from `origin`, the table turned by `yaw` degrees from the base (to the micrometre)."""
    a = math.radians(yaw)
    c, s = math.cos(a), math.sin(a)
    dx, dy = scale * offset[0], scale * offset[1]
    return _round2(np.asarray(origin[:2], dtype=float) + np.array([c * dx - s * dy,
                                                                    s * dx + c * dy]))


def _round2(v: NDArray[np.float64] | tuple[float, ...]) -> tuple[float, float]:
    return (round(float(v[0]), 6), round(float(v[1]), 6))


def reachable_disc(entry: RobotEntry, spacing: float, height: float,
                   within: tuple[float, float, float, float] | None = None
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Points of the table top (grid of `spacing` m, in the table frame) and, for each, the
    radius (m) of the largest disc around it of points the arm reaches with its tool pointing
    down at `height` m above the top, and within the table.

    Parameters
    ----------
    entry : RobotEntry
        The robot.
    spacing, height : float
        Grid spacing and tool height above the table top (m).
    within : tuple of 4 float, optional
        ``(x_min, x_max, y_min, y_max)`` (table frame): points outside are taken as out of
        reach without running the IK (a finer pass around what a coarse one found).

    Returns
    -------
    points : ndarray, shape (n, 2)
        Grid points on the table top (table frame).
    radius : ndarray, shape (n,)
        0 where the arm does not reach the point; else the distance to the nearest grid point
        it does not reach or to the table's edge. Reached means as a movement reaches it:
        from a neighbour, without a change of IK branch (:data:`BRANCH_JUMP`).
    """
    kin = _core.Kinematics(entry.urdf, entry.base_link, entry.tool_link)
    down = np.eye(4)
    if entry.tool_down is not None:
        down[:3, :3] = np.asarray(entry.tool_down)
    inv = np.linalg.inv(entry.mount.pose())
    hx, hy = TABLE_SIZE[0] / 2, TABLE_SIZE[1] / 2
    xs = np.arange(-hx + spacing / 2, hx, spacing)
    ys = np.arange(-hy + spacing / 2, hy, spacing)
    points = np.array([(x, y) for x in xs for y in ys])
    ok = _reached(kin, down, inv, xs, ys, height, np.asarray(entry.neutral, dtype=float),
                  BRANCH_JUMP * spacing / GRID, within).reshape(-1)
    edge = np.minimum.reduce([points[:, 0] + hx, hx - points[:, 0], points[:, 1] + hy,
                              hy - points[:, 1]])
    radius = np.zeros(len(points))
    bad = points[~ok]
    for i in np.flatnonzero(ok):
        near = np.sqrt(((bad - points[i]) ** 2).sum(axis=1)).min() if len(bad) else np.inf
        radius[i] = min(edge[i], near - spacing / 2)
    return points, np.maximum(radius, 0.0)


def _reached(kin: _core.Kinematics, down: NDArray[np.float64], inv: NDArray[np.float64],
             xs: NDArray[np.float64], ys: NDArray[np.float64], height: float,
             neutral: NDArray[np.float64], jump: float,
             within: tuple[float, float, float, float] | None) -> NDArray[np.bool_]:
    """Which grid points (len(xs), len(ys)) the tool reaches pointing down as a movement
    would: from the point nearest below the neutral tool (IK from the neutral pose), each
    neighbour by IK seeded with the solution of a reached point, kept when no joint moves
    more than `jump` rad (a continuous joint's turn by 2 pi is no move); a point first
    refused is tried again from each neighbour reached later."""
    continuous = ~np.isfinite(np.asarray(kin.lower))

    def solve(i: int, j: int, seed: NDArray[np.float64]) -> NDArray[np.float64] | None:
        x, y = float(xs[i]), float(ys[j])
        if within is not None and not (within[0] <= x <= within[1]
                                       and within[2] <= y <= within[3]):
            return None
        target = down.copy()
        target[:3, 3] = (inv @ np.array([x, y, height, 1.0]))[:3]
        q, rep = kin.ik_report(target, seed)
        if rep.status != _core.Status.ok:
            return None
        q = np.asarray(q, dtype=float)
        dq = q - seed
        dq[continuous] = (dq[continuous] + math.pi) % (2 * math.pi) - math.pi
        return q if np.abs(dq).max() <= jump else None

    tool = np.linalg.inv(inv) @ kin.fk(neutral)[:, 3]  # the neutral tool in the table frame
    order = np.argsort([(x - tool[0]) ** 2 + (y - tool[1]) ** 2 for x in xs for y in ys])
    reached = np.zeros((len(xs), len(ys)), dtype=bool)
    sols: dict[tuple[int, int], NDArray[np.float64]] = {}
    queue: deque[tuple[int, int]] = deque()
    for k in order[:64]:  # the first point near the neutral tool that the IK reaches
        i, j = divmod(int(k), len(ys))
        x, y = float(xs[i]), float(ys[j])
        target = down.copy()
        target[:3, 3] = (inv @ np.array([x, y, height, 1.0]))[:3]
        q, rep = kin.ik_report(target, neutral)
        if rep.status == _core.Status.ok and (within is None or (
                within[0] <= x <= within[1] and within[2] <= y <= within[3])):
            reached[i, j], sols[(i, j)] = True, np.asarray(q, dtype=float)
            queue.append((i, j))
            break
    while queue:
        i, j = queue.popleft()
        for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if 0 <= a < len(xs) and 0 <= b < len(ys) and not reached[a, b]:
                q = solve(a, b, sols[(i, j)])
                if q is not None:
                    reached[a, b], sols[(a, b)] = True, q
                    queue.append((a, b))
    return reached


def _cache_file(entry: RobotEntry, spacing: float, height: float,
                within: tuple[float, ...] | None) -> Path:
    key = json.dumps([LAYOUT_VERSION, urdf_sha256(entry.urdf), entry.base_link,
                      entry.tool_link, entry.neutral, entry.mount.xyz, entry.mount.yaw,
                      entry.tool_down, TABLE_SIZE, round(spacing, 9), round(height, 9), within,
                      BRANCH_JUMP])
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    name = hashlib.sha256(key.encode()).hexdigest()[:20]
    return Path(root) / "a2l" / "layout" / f"{name}.json"


def _disc(entry: RobotEntry, spacing: float, height: float,
          within: tuple[float, float, float, float] | None = None
          ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`reachable_disc`, kept in ``~/.cache/a2l/layout`` by the content of what it
    reads (the URDF's hash, the chain, the neutral pose, the mount, the grid): a second
    process reads it instead of running the IK again."""
    path = _cache_file(entry, spacing, height, within)
    try:
        data = json.loads(path.read_text())
        return np.asarray(data["points"], dtype=float), np.asarray(data["radius"], dtype=float)
    except (OSError, ValueError, KeyError):
        pass
    points, radius = reachable_disc(entry, spacing, height, within)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps({"points": points.tolist(), "radius": radius.tolist()}))
    return points, radius


def _pick(points: NDArray[np.float64], radius: NDArray[np.float64]) -> int:
    """The grid point of the largest radius; ties (within a grid step) go to the one nearest
    the table's centre line (y = 0), then nearest the robot."""
    best = radius.max()
    near = np.flatnonzero(radius >= best - 1e-9)
    return int(min(near, key=lambda i: (round(abs(points[i, 1]), 6), points[i, 0])))


@lru_cache(maxsize=32)
def table_layout(entry: RobotEntry) -> TableLayout:
    """The scene geometry of `entry` (module docstring); computed once per entry and process
    (a few seconds of IK for an entry without a ``work_point``).

    Raises
    ------
    a2l.A2LValueError
        The arm reaches no point of the table top with its tool pointing down.
    """
    height, spacing = TEST_HEIGHT, GRID
    points, radius = _disc(entry, spacing, height)
    if radius.max() <= 0:
        raise A2LValueError(
            f"robot '{entry.name}' reaches no point of the table top with its tool pointing "
            f"down (tested {TEST_HEIGHT} m above it): check its mount (xyz {entry.mount.xyz}) "
            f"and tool_down")
    scale = min(1.0, float(radius.max()) / REFERENCE_RADIUS)
    if scale < 1.0:  # a small arm: test again at its own height and finer, near its reach
        seen = points[radius > 0]
        pad = 3 * spacing
        within = (round(float(seen[:, 0].min()) - pad, 6), round(float(seen[:, 0].max()) + pad, 6),
                  round(float(seen[:, 1].min()) - pad, 6), round(float(seen[:, 1].max()) + pad, 6))
        height, spacing = TEST_HEIGHT * scale, GRID * max(scale, 0.25)
        points, radius = _disc(entry, spacing, height, within)
        scale = min(1.0, float(radius.max()) / REFERENCE_RADIUS)
    if entry.work_point is not None:
        work_table = np.asarray(entry.work_point, dtype=float)
        disc = float(radius.max())
    else:
        k = _pick(points, radius)
        work_table, disc = points[k], float(radius[k])
    pose = np.linalg.inv(entry.mount.pose())  # the table frame in the base frame
    yaw = -entry.mount.yaw
    table_z = round(float(pose[2, 3]), 6)
    work = _round2(pose @ np.array([work_table[0], work_table[1], 0.0, 1.0]))
    target = _offset(work, _TARGET, yaw, scale)

    def eye(offset: tuple[float, float, float]) -> tuple[float, float, float]:
        return (*_offset(target, offset, yaw, scale), round(table_z + scale * offset[2], 6))

    lo, hi = _WORKSPACE
    corners = np.array([_offset(work, c, yaw, scale)
                        for c in (lo[:2], hi[:2], (lo[0], hi[1]), (hi[0], lo[1]))])
    return TableLayout(
        robot=entry.name, scale=scale, radius=disc, table_z=table_z,
        floor_z=round(table_z - TABLE_HEIGHT, 6), table_center=_round2(pose[:2, 3]),
        table_size=TABLE_SIZE, table_yaw=yaw, work_point=work,
        camera_eye=eye(_EYE), camera_target=(*target, table_z),
        extra_camera_eyes=tuple(eye(e) for e in _SIDE_EYES),
        workspace_min=(*_round2(corners.min(axis=0)), round(scale * lo[2], 6)),
        workspace_max=(*_round2(corners.max(axis=0)), round(scale * hi[2], 6)))
