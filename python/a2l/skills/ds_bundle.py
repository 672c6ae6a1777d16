"""Bundles of a diffeomorphic DS: the ``ds`` section (:class:`DSArrays`), alone (kind
``"ds"``, :func:`save_ds_bundle`) or beside a skill table (``bundle_bytes(spec, ds=...)``).

Its maps are validated by the C++ loader (:func:`a2l._core.load_ds`), which names a bad
map's index.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from a2l import _core
from a2l.atomic import atomic_write_bytes
from a2l.errors import BundleError
from a2l.skills.bundle_format import created_by, pack_bundle, read_bundle
from a2l.skills.spec import BUNDLE_SCHEMA_VERSION

__all__ = ["DSArrays", "ds_bundle_bytes", "load_ds_bundle", "save_ds_bundle"]


@dataclass(frozen=True)
class DSArrays:
    """The maps of a diffeomorphic DS as a bundle stores them (``docs/bundle_format.md``).

    Attributes
    ----------
    target : ndarray, shape (d,)
        The attractor, d in {2, 3}.
    centers, vectors : ndarray, shape (K, d)
        Centers and displacements of the K maps, in application order.
    rhos : ndarray, shape (K,)
        Inverse widths, rho_i * ||v_i|| < sqrt(e/2).
    speed : float
        Gain of the line-space system (> 0).
    direction : str
        ``"to_demo"`` (the composed maps carry the line space onto the demonstration) or
        ``"to_line"`` (the demonstration onto the line: an explicit velocity query).
    """

    target: np.ndarray
    centers: np.ndarray
    vectors: np.ndarray
    rhos: np.ndarray
    speed: float = 1.0
    direction: str = "to_demo"

    def section(self) -> tuple[dict[str, Any], list[tuple[str, np.ndarray]]]:
        """The manifest's ``ds`` entry and the arrays (name, float64 array) it needs.

        Raises
        ------
        a2l.BundleError
            Shapes that do not fit together (the loader checks the values).
        """
        target = np.asarray(self.target, dtype=np.float64)
        centers = np.asarray(self.centers, dtype=np.float64)
        vectors = np.asarray(self.vectors, dtype=np.float64)
        rhos = np.asarray(self.rhos, dtype=np.float64)
        if target.ndim != 1 or target.shape[0] not in (2, 3):
            raise BundleError(f"ds.target: shape must be (2,) or (3,), got {target.shape}")
        d, k = target.shape[0], (rhos.shape[0] if rhos.ndim == 1 else -1)
        if k < 0:
            raise BundleError(f"arrays.ds_rhos: shape must be (K,), got {rhos.shape}")
        for name, a in (("ds_centers", centers), ("ds_vectors", vectors)):
            if a.shape != (k, d):
                raise BundleError(f"arrays.{name}: shape must be ({k}, {d}), got {a.shape}")
        if self.direction not in ("to_demo", "to_line"):
            raise BundleError(f"ds.direction: must be 'to_demo' or 'to_line', "
                              f"got {self.direction!r}")
        try:
            speed = float(self.speed)
            entry = {"dim": d, "n_maps": k, "speed": speed, "direction": str(self.direction),
                     "target": [float(x) for x in target]}
            json.dumps(entry, allow_nan=False)
        except (TypeError, ValueError) as exc:
            raise BundleError(f"ds: target and speed must be finite numbers ({exc})") from exc
        return entry, [("ds_centers", centers), ("ds_vectors", vectors), ("ds_rhos", rhos)]


def ds_bundle_bytes(
    ds: DSArrays, name: str = "ds", metadata: dict[str, Any] | None = None
) -> bytes:
    """The bytes of a bundle holding only a diffeomorphic DS (kind ``"ds"``).

    Parameters
    ----------
    ds : DSArrays
        The maps (target (d,), centers and vectors (K, d), rhos (K,), speed).
    name : str
        The bundle's name.
    metadata : dict, optional
        JSON-serialisable data stored as the manifest's ``extra`` (e.g. the fitting
        parameters, the demonstrations' frame).

    Returns
    -------
    bytes
        The bundle, validated by the C++ loader.

    Raises
    ------
    a2l.BundleError
        Shapes that do not fit, non-finite values, or a map breaking the invertibility bound
        (the message names the map's index).
    """
    entry, arrays = ds.section()
    manifest: dict[str, Any] = {
        "schema_version": BUNDLE_SCHEMA_VERSION,
        "kind": "ds",
        "name": str(name),
        "created_by": created_by(),
        "ds": entry,
        "extra": dict(metadata or {}),
    }
    data = pack_bundle(manifest, arrays)
    _core.load_ds_from_memory(data, f"<bundle of DS '{name}'>")  # the validator
    return data


def save_ds_bundle(
    path: str | os.PathLike[str],
    ds: DSArrays,
    name: str = "ds",
    metadata: dict[str, Any] | None = None,
) -> Path:
    """Write a bundle holding only a diffeomorphic DS, atomically.

    Parameters
    ----------
    path : str or PathLike
        Destination file (missing parent directories are created).
    ds : DSArrays
        The maps.
    name : str
        The bundle's name.
    metadata : dict, optional
        JSON-serialisable data stored as the manifest's ``extra``.

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    a2l.BundleError
        The DS does not make a valid bundle; nothing is written.
    """
    return atomic_write_bytes(path, ds_bundle_bytes(ds, name=name, metadata=metadata))


def load_ds_bundle(path: str | os.PathLike[str]) -> tuple[Any, dict[str, Any]]:
    """Read the DS of a bundle (kind ``"ds"``, or a skill bundle holding one).

    Parameters
    ----------
    path : str or PathLike
        The bundle file.

    Returns
    -------
    ds : a2l._core.DiffeoDS
        The DS, loaded and validated by the C++ loader.
    metadata : dict
        The manifest's ``extra`` (empty if absent).

    Raises
    ------
    a2l.BundleError
        Malformed, corrupted, of another schema version, without a DS, or with a map breaking
        the invertibility bound (the message names the field or the map's index).
    a2l.A2LFileNotFoundError
        The file does not exist or cannot be read.
    """
    view, ds = read_bundle(path, _core.load_ds_from_memory)
    return ds, view.extra
