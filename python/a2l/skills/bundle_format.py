"""The bundle container (``docs/bundle_format.md``): header, JSON manifest, padding and
8-byte-aligned little-endian arrays, each with its CRC-32.

:func:`pack_bundle` writes the bytes of a manifest and its arrays; :func:`read_manifest`
and :func:`bundle_array` decode bytes the C++ loader has already validated. What the
manifest holds is the business of :mod:`a2l.skills.bundle` (skills) and
:mod:`a2l.skills.ds_bundle` (diffeomorphic DS).
"""

from __future__ import annotations

import json
import struct
import zlib
from typing import Any

import numpy as np

from a2l import _core
from a2l.errors import BundleError
from a2l.skills.spec import BUNDLE_SCHEMA_VERSION

__all__ = ["BUNDLE_MAGIC", "bundle_array", "created_by", "pack_bundle", "read_manifest"]

#: The 8 bytes every bundle starts with.
BUNDLE_MAGIC = b"A2LBNDL\x00"
_HEADER = struct.Struct("<8sIIII")  # magic, version, manifest length, manifest CRC, reserved


def _ceil8(n: int) -> int:
    return (n + 7) // 8 * 8


def created_by() -> str:
    """The manifest's ``created_by``: ``"a2l <version>"``."""
    return f"a2l {_core.__version__}"


def pack_bundle(manifest: dict[str, Any], arrays: list[tuple[str, np.ndarray]]) -> bytes:
    """Header + manifest (with its ``arrays`` entry filled in) + padding + arrays."""
    blobs, entries, offset = [], {}, 0
    for name, a in arrays:
        dtype = {"f": "float64", "i": "int32"}[a.dtype.kind]
        data = np.ascontiguousarray(a, dtype="<f8" if dtype == "float64" else "<i4").tobytes()
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


def read_manifest(data: bytes) -> tuple[dict[str, Any], int]:
    """The manifest of validated bundle bytes and the offset where the arrays start."""
    (_, _, mlen, _, _) = _HEADER.unpack_from(data, 0)
    manifest = json.loads(data[_HEADER.size : _HEADER.size + mlen].decode("utf-8"))
    return manifest, _ceil8(_HEADER.size + mlen)


def bundle_array(data: bytes, manifest: dict[str, Any], blob: int, name: str,
                 dtype: str) -> np.ndarray:
    """A copy of array `name` of validated bundle bytes (`blob` from :func:`read_manifest`),
    with the shape its manifest entry gives."""
    a = manifest["arrays"][name]
    start = blob + int(a["offset"])
    flat = np.frombuffer(
        data, dtype=dtype, count=int(a["nbytes"]) // np.dtype(dtype).itemsize, offset=start
    )
    return flat.reshape([int(s) for s in a["shape"]]).copy()
