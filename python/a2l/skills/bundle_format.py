"""The bundle container (``docs/bundle_format.md``): header, JSON manifest, padding and
8-byte-aligned little-endian arrays, each with its CRC-32.

:func:`pack_bundle` writes the bytes of a manifest and its arrays; :func:`read_bundle` is the
one reader: it has the C++ loader validate a file's bytes, then decodes them through their
manifest (:class:`BundleView`: the manifest, and each array with the dtype and shape its
manifest entry gives). What the manifest holds is the business of :mod:`a2l.skills.bundle`
(skills), :mod:`a2l.skills.ds_bundle` (diffeomorphic DS) and :mod:`a2l.skills.phases`
(DS phases).
"""

from __future__ import annotations

import json
import os
import struct
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from a2l import _core
from a2l.errors import A2LFileNotFoundError, BundleError
from a2l.skills.spec import BUNDLE_SCHEMA_VERSION

__all__ = ["BUNDLE_MAGIC", "BundleView", "created_by", "pack_bundle", "read_bundle"]

#: The 8 bytes every bundle starts with.
BUNDLE_MAGIC = b"A2LBNDL\x00"
_HEADER = struct.Struct("<8sIIII")  # magic, version, manifest length, manifest CRC, reserved
#: The manifest's array dtypes and their little-endian NumPy codes.
_DTYPES = {"float64": "<f8", "int32": "<i4"}

T = TypeVar("T")


def _ceil8(n: int) -> int:
    return (n + 7) // 8 * 8


def created_by() -> str:
    """The manifest's ``created_by``: ``"a2l <version>"``."""
    return f"a2l {_core.__version__}"


def pack_bundle(manifest: dict[str, Any], arrays: list[tuple[str, np.ndarray]]) -> bytes:
    """Header + manifest (with its ``arrays`` entry filled in) + padding + arrays.

    Parameters
    ----------
    manifest : dict
        Every manifest key but ``arrays``.
    arrays : list of (str, ndarray)
        Name and array (float or int: stored as float64 or int32), in blob order.

    Returns
    -------
    bytes
        The bundle (not validated: the caller hands it to the C++ loader).
    """
    blobs, entries, offset = [], {}, 0
    for name, a in arrays:
        dtype = {"f": "float64", "i": "int32"}[a.dtype.kind]
        data = np.ascontiguousarray(a, dtype=_DTYPES[dtype]).tobytes()
        offset = _ceil8(offset)
        entries[name] = {
            "dtype": dtype,
            "shape": [int(x) for x in a.shape],
            "offset": offset,
            "nbytes": len(data),
            "crc32": zlib.crc32(data),
        }
        blobs.append((offset, data))
        offset += len(data)
    manifest = {**manifest, "arrays": entries}
    try:
        text = json.dumps(manifest, allow_nan=False, ensure_ascii=False).encode("utf-8")
    except (TypeError, ValueError) as exc:
        raise BundleError(f"manifest: cannot be written as JSON ({exc})") from exc
    header = _HEADER.pack(BUNDLE_MAGIC, BUNDLE_SCHEMA_VERSION, len(text), zlib.crc32(text), 0)
    out = bytearray(header + text)
    out += b"\x00" * (_ceil8(len(out)) - len(out))
    blob = len(out)
    for off, data in blobs:
        out += b"\x00" * (blob + off - len(out))
        out += data
    return bytes(out)


@dataclass(frozen=True)
class BundleView:
    """Validated bundle bytes, decoded through their manifest.

    Attributes
    ----------
    data : bytes
        The whole bundle, already validated by the C++ loader.
    manifest : dict
        The decoded JSON manifest (with its ``arrays`` entry).
    blob : int
        Offset of the arrays' blob in `data`: ceil8(24 + manifest length).
    """

    data: bytes
    manifest: dict[str, Any]
    blob: int

    @classmethod
    def parse(cls, data: bytes) -> BundleView:
        """Decode the manifest of validated bundle bytes (header layout of the format)."""
        (_, _, mlen, _, _) = _HEADER.unpack_from(data, 0)
        manifest = json.loads(data[_HEADER.size : _HEADER.size + mlen].decode("utf-8"))
        return cls(data, manifest, _ceil8(_HEADER.size + mlen))

    def array(self, name: str) -> np.ndarray:
        """A copy of array `name`, native float64 or int32, with its manifest entry's shape.

        Raises
        ------
        KeyError
            The manifest has no array of that name.
        """
        a = self.manifest["arrays"][name]
        code = _DTYPES[a["dtype"]]
        flat = np.frombuffer(self.data, dtype=code,
                             count=int(a["nbytes"]) // np.dtype(code).itemsize,
                             offset=self.blob + int(a["offset"]))
        native = np.float64 if a["dtype"] == "float64" else np.int32
        return flat.reshape([int(s) for s in a["shape"]]).astype(native)

    @property
    def extra(self) -> dict[str, Any]:
        """The manifest's ``extra`` (a copy; empty if absent or not an object)."""
        extra = self.manifest.get("extra")
        return dict(extra) if isinstance(extra, dict) else {}


def read_bundle(path: str | os.PathLike[str],
                validate: Callable[[bytes, str], T]) -> tuple[BundleView, T]:
    """Read a bundle file, validate its bytes with the C++ loader, decode its manifest.

    Parameters
    ----------
    path : str or PathLike
        The bundle file.
    validate : callable
        ``validate(data, source)``: the C++ loader of what the caller needs
        (:func:`a2l._core.load_bundle_from_memory` for a skill,
        :func:`a2l._core.load_ds_from_memory` for a DS); it raises on any failed check.

    Returns
    -------
    view : BundleView
        The validated bytes and their manifest.
    loaded : object
        What `validate` returned (the C++ skill or DS).

    Raises
    ------
    a2l.BundleError
        Malformed, corrupted or of another schema version (from `validate`: the message
        names the field or the check).
    a2l.A2LFileNotFoundError
        The file does not exist or cannot be read.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise A2LFileNotFoundError(f"skill bundle '{path}': cannot read ({exc})") from exc
    loaded = validate(data, str(path))
    return BundleView.parse(data), loaded
