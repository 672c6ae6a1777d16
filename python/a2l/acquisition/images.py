"""Behaviour descriptors from camera images (NovEB's, ``docs/method.md``): the image grey,
downsampled and normalised, or its difference with the image before the movement.

Only pixels enter a descriptor: nothing here knows what an object is.
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

__all__ = ["image_descriptor"]


def _small_grey(rgb: NDArray[np.uint8], size: int) -> NDArray[np.float64]:
    img = np.asarray(rgb)
    if img.ndim != 3 or img.shape[2] != 3 or img.dtype != np.uint8:
        raise ValueError(f"an image is an RGB array of uint8, shape (H, W, 3); got dtype "
                         f"{img.dtype}, shape {img.shape}")
    grey = cv2.cvtColor(np.ascontiguousarray(img), cv2.COLOR_RGB2GRAY)
    small = cv2.resize(grey, (size, size), interpolation=cv2.INTER_AREA)
    return small.astype(np.float64) / 255.0


def image_descriptor(after: NDArray[np.uint8], before: NDArray[np.uint8] | None = None,
                     size: int = 32) -> NDArray[np.float64]:
    """The behaviour descriptor of a movement.

    Parameters
    ----------
    after : ndarray of uint8, shape (H, W, 3)
        The camera image at the end of the movement.
    before : ndarray of uint8, shape (H, W, 3), optional
        The image before it; when given, the descriptor is the difference ``after -
        before``.
    size : int
        Side of the downsampled image (pixels).

    Returns
    -------
    ndarray, shape (size * size,)
        Grey levels in [0, 1] (no `before`) or their differences in [-1, 1].
    """
    if size < 1:
        raise ValueError(f"size must be >= 1, got {size}")
    a = _small_grey(after, size)
    if before is None:
        return a.ravel()
    if np.shape(before) != np.shape(after):
        raise ValueError(f"before and after images differ in shape: {np.shape(before)} vs "
                         f"{np.shape(after)}")
    return (a - _small_grey(before, size)).ravel()
