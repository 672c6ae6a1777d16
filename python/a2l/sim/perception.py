"""Camera perception: a PyBullet camera over the table and OpenCV colour segmentation.

The camera gives an RGB image and a depth buffer (an RGB-D camera). Each object has its
own colour: OpenCV segments its hue, the segmented pixels are lifted to 3-D with the depth
buffer, and the object's position is the centre of its top face (the highest segmented
points) lowered by half the object's height. The light's state is read from the pixels of
the lamp: lit (saturated yellow) or not.

A scene has a main camera facing the robot from beyond the table and side cameras; the
share of each object's top face a camera sees tells when the arm hides it, and only then
are the side cameras rendered, the top-face points of every view joined (see
:class:`a2l.sim.bullet.BulletScene`).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.sim._pybullet import p
from a2l.sim.scene import Scene

__all__ = ["Camera", "ColorTarget", "Perception", "hue_of", "perception_errors"]


def hue_of(rgba: ArrayLike) -> int:
    """OpenCV hue (0-179) of an RGBA colour with components in [0, 1]."""
    c = np.clip(np.asarray(rgba, dtype=float)[:3] * 255.0, 0, 255).astype(np.uint8)
    return int(cv2.cvtColor(c.reshape(1, 1, 3), cv2.COLOR_RGB2HSV)[0, 0, 0])


class Camera:
    """A pinhole camera rendered by PyBullet, with its pixel -> 3-D back-projection.

    Parameters
    ----------
    client : int
        PyBullet physics client id.
    width, height : int
        Image size (pixels).
    eye, target : array_like, shape (3,)
        Camera position and the point it looks at (world frame, m).
    fov : float
        Vertical field of view (degrees).
    near, far : float
        Clipping planes (m).
    """

    def __init__(self, client: int, width: int, height: int, eye: ArrayLike,
                 target: ArrayLike, fov: float, near: float = 0.1, far: float = 4.0) -> None:
        self.client = client
        self.width, self.height = int(width), int(height)
        self.eye = np.asarray(eye, dtype=float)
        self.target = np.asarray(target, dtype=float)
        fwd = self.target - self.eye
        up = (0.0, 0.0, 1.0) if abs(fwd[2]) < 0.99 * np.linalg.norm(fwd) else (1.0, 0.0, 0.0)
        self.view = p.computeViewMatrix(self.eye.tolist(), self.target.tolist(), up,
                                        physicsClientId=client)
        self.proj = p.computeProjectionMatrixFOV(fov, self.width / self.height, near, far,
                                                 physicsClientId=client)
        self._px_per_m = 2.0 * np.tan(np.radians(fov) / 2.0) / self.height
        v = np.asarray(self.view, dtype=float).reshape(4, 4).T
        pr = np.asarray(self.proj, dtype=float).reshape(4, 4).T
        self._pv = pr @ v
        self._inv_pv = np.linalg.inv(self._pv)
        # pixel (row r, column c) <-> NDC (2c / W - 1, 1 - 2 (r + 1) / H): the convention of
        # PyBullet's software renderer, calibrated against ground truth (a +-0.5 px
        # change here biases perceived positions by 1.5-3 mm)
        u = (2.0 * np.arange(self.width) / self.width) - 1.0
        w = 1.0 - (2.0 * (np.arange(self.height) + 1.0) / self.height)
        self._ndc_x, self._ndc_y = np.meshgrid(u, w)
        # the software renderer also in the GUI: the pixel convention calibrated below is
        # its own, and perception must not depend on how the scene is watched
        self.renderer = p.ER_TINY_RENDERER

    def render(self) -> tuple[NDArray[np.uint8], NDArray[np.float32]]:
        """Render one frame.

        Returns
        -------
        rgb : ndarray of uint8, shape (height, width, 3)
        depth : ndarray of float32, shape (height, width)
            OpenGL depth buffer values in [0, 1] (non-linear); see :meth:`lift`.
        """
        _, _, rgba, depth, _ = p.getCameraImage(
            self.width, self.height, self.view, self.proj, renderer=self.renderer,
            flags=p.ER_NO_SEGMENTATION_MASK, physicsClientId=self.client)
        rgb = np.asarray(rgba, dtype=np.uint8).reshape(self.height, self.width, 4)[..., :3]
        return np.ascontiguousarray(rgb), np.asarray(depth, dtype=np.float32).reshape(
            self.height, self.width)

    def lift(self, rows: NDArray[np.intp], cols: NDArray[np.intp],
             depth: NDArray[np.float32]) -> NDArray[np.float64]:
        """World points (n, 3) of pixels ``(rows[i], cols[i])`` from a depth buffer."""
        ndc = np.stack([self._ndc_x[rows, cols], self._ndc_y[rows, cols],
                        2.0 * depth[rows, cols].astype(float) - 1.0,
                        np.ones(rows.shape[0])])
        h = self._inv_pv @ ndc
        return (h[:3] / h[3]).T

    def pixel_size(self, point: ArrayLike) -> float:
        """Side (m) of one pixel's footprint at `point` (3,), facing the camera."""
        return float(np.linalg.norm(np.asarray(point, dtype=float) - self.eye) * self._px_per_m)

    def project(self, points: ArrayLike) -> NDArray[np.float64]:
        """Pixel coordinates (n, 2) as (column, row) of world points (n, 3)."""
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        h = self._pv @ np.vstack([pts.T, np.ones(pts.shape[0])])
        ndc = h[:2] / h[3]
        col = (ndc[0] + 1.0) * self.width / 2.0 - 0.5
        row = (1.0 - ndc[1]) * self.height / 2.0 - 0.5
        return np.stack([col, row], axis=1)


@dataclass(frozen=True)
class ColorTarget:
    """An object perception looks for.

    Attributes
    ----------
    name : str
        Object name.
    rgba : tuple of 4 float
        Its colour.
    half_height : float
        Half its height (m): the centre lies this far below the top face.
    top_area : float
        Area of its top face (m^2), to tell how much of it a camera sees (0: unknown).
    """

    name: str
    rgba: tuple[float, float, float, float]
    half_height: float
    top_area: float = 0.0


class Perception:
    """OpenCV segmentation of coloured objects and of a lamp in a :class:`Camera`'s frames.

    Parameters
    ----------
    camera : Camera
        Where frames come from.
    targets : list of ColorTarget
        Objects to locate; their hues must differ by more than ``2 * hue_tolerance``.
    lamp_rgba : tuple of 4 float, optional
        The lamp's colour when lit; ``None`` when the scene has no light.
    hue_tolerance : int
        Half-width of a hue band (OpenCV units, 0-179).
    min_saturation, min_value : int
        Pixels greyer or darker than this (0-255) are never an object.
    min_pixels : int
        Fewer segmented pixels than this: the object is not seen.
    top_band : float
        Points within this height (m) of an object's highest point form its top face.
    """

    def __init__(self, camera: Camera, targets: list[ColorTarget],
                 lamp_rgba: tuple[float, float, float, float] | None = None,
                 hue_tolerance: int = 8, min_saturation: int = 110, min_value: int = 40,
                 min_pixels: int = 6, top_band: float = 0.002) -> None:
        self.camera = camera
        self.targets = list(targets)
        self.lamp_rgba = lamp_rgba
        self.hue_tolerance = hue_tolerance
        self.min_saturation = min_saturation
        self.min_value = min_value
        self.min_pixels = min_pixels
        self.top_band = top_band
        self._hues = {t.name: hue_of(t.rgba) for t in self.targets}
        self._lamp_hue = hue_of(lamp_rgba) if lamp_rgba is not None else None
        self._kernel = np.ones((3, 3), np.uint8)

    def _mask(self, hsv: NDArray[np.uint8], hue: int) -> NDArray[np.bool_]:
        h = hsv[..., 0].astype(np.int16)
        dh = np.abs(h - hue)
        dh = np.minimum(dh, 180 - dh)
        m = ((dh <= self.hue_tolerance) & (hsv[..., 1] >= self.min_saturation)
             & (hsv[..., 2] >= self.min_value)).astype(np.uint8)
        m = cv2.morphologyEx(m, cv2.MORPH_OPEN, self._kernel)
        return m.astype(bool)

    def segment(self, rgb: NDArray[np.uint8], depth: NDArray[np.float32]
                ) -> tuple[dict[str, NDArray[np.float64]], dict[str, bool]]:
        """Every target seen in one frame, and the lamp state.

        Returns
        -------
        points : dict of str to ndarray, shape (n, 3)
            For every target seen (at least ``min_pixels`` pixels), the world points of its
            segmented pixels.
        lamp : dict
            ``{"light_on": bool}`` when the scene has a lamp, else empty.
        """
        hsv = cv2.cvtColor(rgb, cv2.COLOR_RGB2HSV)
        points: dict[str, NDArray[np.float64]] = {}
        for t in self.targets:
            rows, cols = np.nonzero(self._mask(hsv, self._hues[t.name]))
            if rows.shape[0] >= self.min_pixels:
                points[t.name] = self.camera.lift(rows, cols, depth)
        lamp: dict[str, bool] = {}
        if self._lamp_hue is not None:
            lit = int(self._mask(hsv, self._lamp_hue).sum())
            lamp["light_on"] = lit >= self.min_pixels
        return points, lamp

    def top_face(self, pts: NDArray[np.float64]) -> NDArray[np.float64]:
        """The points of `pts` (n, 3) within ``top_band`` of its highest point (98th
        percentile of the heights); all of them when fewer than ``min_pixels`` are."""
        z_top = float(np.percentile(pts[:, 2], 98))
        top = pts[pts[:, 2] >= z_top - self.top_band]
        return top if top.shape[0] >= self.min_pixels else pts

    def is_flat(self, face: NDArray[np.float64]) -> bool:
        """Whether points `face` (n, 3) lie at one height (their 2nd to 98th height
        percentiles within twice ``top_band``): a top face, not the side faces
        :meth:`top_face` returns when the top is hidden."""
        low, high = np.percentile(face[:, 2], (2, 98))
        return bool(high - low <= 2 * self.top_band)

    def top_faces(self, rgb: NDArray[np.uint8], depth: NDArray[np.float32]
                  ) -> tuple[dict[str, NDArray[np.float64]], dict[str, bool]]:
        """The top face of every target seen in one frame (:meth:`top_face` of its
        :meth:`segment` points, shape (n, 3) each), and the lamp state."""
        points, lamp = self.segment(rgb, depth)
        return {name: self.top_face(pts) for name, pts in points.items()}, lamp

    def estimate(self, name: str, face: NDArray[np.float64]
                 ) -> tuple[tuple[float, float, float], float]:
        """Centre of target `name` from points (n, 3) of its top face, and the share of
        the face they cover.

        The centre is that of the smallest rectangle around the points (unlike their mean
        it is not pulled toward the camera, where pixels are denser), lowered by half the
        target's height from the face's height (98th percentile of the points). The share
        is the rectangle's area over the target's ``top_area``, at most 1 (1 when
        ``top_area`` is unknown): an arm in front of the object lowers it. `face` may join
        the points several cameras saw (see :meth:`a2l.sim.bullet.BulletScene.perceive`).
        """
        t = next(t for t in self.targets if t.name == name)
        z_top = float(np.percentile(face[:, 2], 98))
        (cx, cy), (w, h), _ = cv2.minAreaRect(face[:, :2].astype(np.float32))
        # the rectangle joins pixel centres: it is about one pixel short on each axis
        px = self.camera.pixel_size((cx, cy, z_top))
        visible = min(1.0, (w + px) * (h + px) / t.top_area) if t.top_area > 0 else 1.0
        return (float(cx), float(cy), z_top - t.half_height), visible

    def locate(self, rgb: NDArray[np.uint8], depth: NDArray[np.float32]
               ) -> tuple[dict[str, tuple[float, float, float]], dict[str, bool],
                          dict[str, float]]:
        """Object positions and lamp state in one frame.

        Returns
        -------
        objects : dict of str to (x, y, z)
            Centre of every target seen (world frame, m).
        lamp : dict
            ``{"light_on": bool}`` when the scene has a lamp, else empty.
        visible : dict of str to float
            For every target seen, the share of its top face the camera sees
            (:meth:`estimate`).
        """
        faces, lamp = self.top_faces(rgb, depth)
        objects: dict[str, tuple[float, float, float]] = {}
        visible: dict[str, float] = {}
        for name, face in faces.items():
            objects[name], visible[name] = self.estimate(name, face)
        return objects, lamp, visible


def perception_errors(scene: Scene, n: int = 200, seed: int = 0, name: str | None = None,
                      margin: float = 0.02) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Perceived minus true position of an object placed at `n` random spots on the table.

    Parameters
    ----------
    scene : a2l.sim.bullet.BulletScene
        A PyBullet scene; it is reset for every spot (the arm at its neutral pose).
    n : int
        Number of spots, uniform over the table top (object footprint `margin` m inside
        the edges).
    seed : int
        Seed of the spots.
    name : str, optional
        The object; the scene's primary movable object by default.

    Returns
    -------
    positions : ndarray, shape (n, 3)
        True object centres.
    errors : ndarray, shape (n, 3)
        Perceived - true (m); NaN where the camera did not see the object.
    """
    rng = np.random.default_rng(seed)
    cfg = scene.config
    obj = name or scene.movable_names[0]
    size = getattr(cfg, f"{obj}_size")
    (cx, cy), (sx, sy) = cfg.table_center, cfg.table_size
    hx, hy = size[0] / 2 + margin, size[1] / 2 + margin
    positions = np.empty((n, 3))
    errors = np.empty((n, 3))
    for i in range(n):
        xy = rng.uniform([cx - sx / 2 + hx, cy - sy / 2 + hy],
                         [cx + sx / 2 - hx, cy + sy / 2 - hy])
        scene.reset(objects={obj: xy})
        positions[i] = scene.ground_truth()["objects"][obj]
        seen = scene.perceive()["objects"].get(obj)
        errors[i] = np.nan if seen is None else np.asarray(seen) - positions[i]
    return positions, errors
