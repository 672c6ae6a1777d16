"""Files the simulated world loads: a copy of the robot's URDF drawn with its collision
shapes (fast camera frames)."""

from __future__ import annotations

import copy
import hashlib
import os
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

__all__ = ["collision_render_urdf"]

_GREY = "0.55 0.55 0.55 1"


def _cache_dir() -> Path:
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    return Path(root) / "a2l" / "urdf"


def collision_render_urdf(urdf: str | os.PathLike[str]) -> Path:
    """A copy of `urdf` whose visual elements are its collision shapes, in grey.

    PyBullet's software renderer (DIRECT mode) draws primitive shapes far faster than
    Baxter's visual meshes; the physics is unchanged (the collision elements are kept).
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
            mat = ET.SubElement(vis, "material", {"name": "a2l_collision_grey"})
            ET.SubElement(mat, "color", {"rgba": _GREY})
            link.insert(0, vis)
    out_text = ET.tostring(root, encoding="unicode")
    digest = hashlib.sha256(out_text.encode()).hexdigest()[:16]
    out_dir = _cache_dir()
    out_dir.mkdir(parents=True, exist_ok=True)
    out = out_dir / f"{src.stem}-collision-render-{digest}.urdf"
    if not out.is_file():
        fd, tmp = tempfile.mkstemp(dir=out_dir, suffix=".urdf.tmp")
        with os.fdopen(fd, "w") as f:
            f.write(out_text)
        os.replace(tmp, out)
    return out
