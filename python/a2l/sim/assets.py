"""Files the simulated world loads: a copy of the robot's URDF drawn with its collision
shapes (fast camera frames)."""

from __future__ import annotations

import copy
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from a2l.robot.descriptions import cached_urdf

__all__ = ["collision_render_urdf", "mesh_vertices"]

_GREY = "0.55 0.55 0.55 1"


def mesh_vertices(path: Path) -> np.ndarray | None:
    """Vertices (n, 3) of a COLLADA (its first vertex array, as Baxter's meshes store
    them) or STL mesh file, or None if it cannot be read."""
    try:
        if path.suffix.lower() == ".dae":
            text = path.read_text(errors="replace")
            arrays = re.findall(r"<float_array[^>]*>([^<]*)</float_array>", text)
            if not arrays:
                return None
            return np.asarray(arrays[0].split(), dtype=float).reshape(-1, 3)
        if path.suffix.lower() == ".stl":
            data = path.read_bytes()
            if data[:5].lower() == b"solid":
                nums = re.findall(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)", data)
                return np.asarray(nums, dtype=float)
            n = int(np.frombuffer(data[80:84], dtype="<u4")[0])
            rec = np.frombuffer(data[84 : 84 + 50 * n], dtype=np.uint8).reshape(n, 50)
            return rec[:, 12:48].copy().view("<f4").reshape(-1, 3).astype(float)
    except (OSError, ValueError):
        return None
    return None


def _mesh_to_box(vis: ET.Element, base: Path) -> None:
    """Replace a visual's mesh by the box around its first vertex array (in place).

    The collision meshes of Baxter's torso and pedestal have thousands of triangles; their
    bounding boxes draw in a fraction of the time and hide the same part of the scene.
    """
    geom = vis.find("geometry")
    mesh = geom.find("mesh") if geom is not None else None
    if geom is None or mesh is None:
        return
    path = Path(mesh.get("filename", ""))
    if not path.is_absolute():
        path = base / path
    verts = mesh_vertices(path)
    if verts is None or verts.size == 0:
        return
    scale = np.asarray([float(v) for v in mesh.get("scale", "1 1 1").split()])
    lo, hi = verts.min(axis=0) * scale, verts.max(axis=0) * scale
    lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
    centre, size = (lo + hi) / 2, np.maximum(hi - lo, 1e-4)
    origin = vis.find("origin")
    if origin is None:
        origin = ET.SubElement(vis, "origin", {"xyz": "0 0 0", "rpy": "0 0 0"})
    if any(float(v) != 0.0 for v in origin.get("rpy", "0 0 0").split()):
        return  # a rotated mesh: keep it (Baxter has none)
    xyz = np.asarray([float(v) for v in origin.get("xyz", "0 0 0").split()]) + centre
    origin.set("xyz", " ".join(f"{v:.6g}" for v in xyz))
    geom.remove(mesh)
    ET.SubElement(geom, "box", {"size": " ".join(f"{v:.6g}" for v in size)})


def collision_render_urdf(urdf: str | os.PathLike[str]) -> Path:
    """A copy of `urdf` whose visual elements are its collision shapes, in grey.

    PyBullet's software renderer (DIRECT mode) draws primitive shapes far faster than
    Baxter's visual meshes; the physics is unchanged (the collision elements are kept).
    Collision meshes (Baxter's torso and pedestal) are drawn as their bounding boxes.
    Written once per source content into ``~/.cache/a2l/urdf`` (atomically).

    Parameters
    ----------
    urdf : str or PathLike
        A URDF PyBullet can load (absolute mesh paths).

    Returns
    -------
    Path
        The rewritten copy.
    """
    src = Path(urdf)
    text = src.read_text()
    root = ET.fromstring(text)
    for link in root.iter("link"):
        for vis in link.findall("visual"):
            link.remove(vis)
        for i, col in enumerate(link.findall("collision")):
            vis = ET.Element("visual", {"name": f"{link.get('name')}_cv{i}"})
            for child in col:
                if child.tag in ("origin", "geometry"):
                    vis.append(copy.deepcopy(child))
            _mesh_to_box(vis, src.parent)
            mat = ET.SubElement(vis, "material", {"name": "a2l_collision_grey"})
            ET.SubElement(mat, "color", {"rgba": _GREY})
            link.insert(0, vis)
    return cached_urdf(f"{src.stem}-collision-render", ET.tostring(root, encoding="unicode"))
