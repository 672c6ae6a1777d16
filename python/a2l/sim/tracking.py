"""Objects the hand hides: where an object is, from the part of it the cameras still see.

The cameras locate an object by its top face (:mod:`a2l.sim.perception`). A hand over the
object hides that face: a wide hand (the Panda's 21 cm) hides most of it as it comes near,
and a grasp hides all of it. The centre of what is left of the face is then off by up to
1.5 cm, and lower by what the hand hides (the side faces are lower): a grasp that reads it
reaches for the table beside the block.

So each object keeps a :class:`Footprint`, the rectangle of its top face and its height the
last time a camera saw at least ``min_visible`` of the face. While it is hidden in part,
the footprint moves by the least displacement that puts every point the cameras see of the
object (top and side faces: the sides stand on the footprint) inside it: an object nothing
moved stays where it was seen, one pushed while in part hidden moves with its visible
edges, one lifted rises with its visible top. An object no camera sees is where it was last
seen. A reset, or an object placed or removed by the scene, forgets its footprint.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

__all__ = ["OUTLIERS", "TOLERANCE", "Footprint", "Sighting"]

#: How far a point seen may lie outside a footprint before it moves it (m): about a pixel of
#: the default camera at the table (2-3 mm), so that pixel noise moves nothing.
TOLERANCE = 0.003

#: The share (percent) of the points seen at each end of a side that :meth:`Footprint.follow`
#: leaves out.
OUTLIERS = 2.0


@dataclass(frozen=True)
class Sighting:
    """What the cameras saw of one object in one look.

    Attributes
    ----------
    position : tuple of 3 float
        Its centre from the top-face points (:meth:`a2l.sim.perception.Perception.estimate`).
    visible : float
        The share of its top face they cover (at most 1).
    top : ndarray, shape (n, 3)
        The top-face points of every view looked at, joined.
    points : ndarray, shape (m, 3)
        Every segmented point of the object in those views (top and side faces).
    flat : bool
        Whether `top` lies at one height (:meth:`a2l.sim.perception.Perception.is_flat`):
        when the hand hides the whole top face, `top` holds the side faces, whose
        rectangle may still be as large as the top's.
    """

    position: tuple[float, float, float]
    visible: float
    top: NDArray[np.float64]
    points: NDArray[np.float64]
    flat: bool = True

    def well_seen(self, min_visible: float) -> bool:
        """At least `min_visible` of the top face seen, and it is a top face."""
        return self.visible >= min_visible and self.flat


@dataclass(frozen=True)
class Footprint:
    """An object's top face on the table, as last seen: a rectangle and its centre's height.

    Attributes
    ----------
    center : tuple of 2 float
        ``(x, y)`` (m).
    size : tuple of 2 float
        The rectangle's sides (m), along its own axes.
    angle : float
        The turn of its first side from the x axis (degrees, OpenCV's ``minAreaRect``).
    z : float
        The height of the object's centre (m).
    """

    center: tuple[float, float]
    size: tuple[float, float]
    angle: float
    z: float

    @classmethod
    def of(cls, top: NDArray[np.float64], z: float) -> Footprint:
        """The footprint of top-face points `top` (n, 3), the centre at height `z`."""
        (cx, cy), (w, h), angle = cv2.minAreaRect(top[:, :2].astype(np.float32))
        return cls((float(cx), float(cy)), (float(w), float(h)), float(angle), float(z))

    @property
    def position(self) -> tuple[float, float, float]:
        """The centre ``(x, y, z)``."""
        return (self.center[0], self.center[1], self.z)

    def follow(self, points: NDArray[np.float64], z_seen: float,
               tolerance: float = TOLERANCE) -> Footprint:
        """This footprint moved by the least displacement that puts every point of `points`
        (m, 3) within `tolerance` of it; its height the higher of its own and `z_seen` (the
        height a hidden top face gives is too low, a lifted object's higher).

        Along each side, the points allow the displacements in ``[last - s/2, first + s/2]``
        (their extent along that side without the :data:`OUTLIERS` percent at each end:
        pixels on an edge take the depth of what is behind them; ``s`` its length plus twice
        `tolerance`); the one nearest zero is taken. Points wider apart than the side (an
        object turned, or something of its colour beside it) centre it between them.
        """
        c, s = np.cos(np.radians(self.angle)), np.sin(np.radians(self.angle))
        d = points[:, :2] - np.asarray(self.center)
        along = (d[:, 0] * c + d[:, 1] * s, -d[:, 0] * s + d[:, 1] * c)
        shift = []
        for q, side in zip(along, self.size, strict=True):
            first, last = np.percentile(q, (OUTLIERS, 100 - OUTLIERS))
            lo = float(last) - side / 2 - tolerance
            hi = float(first) + side / 2 + tolerance
            shift.append((lo + hi) / 2 if lo > hi else min(max(0.0, lo), hi))
        du, dv = shift
        center = (self.center[0] + du * c - dv * s, self.center[1] + du * s + dv * c)
        return Footprint(center, self.size, self.angle, max(self.z, float(z_seen)))
