"""Skill bundles: writing and reading the one-file format of ``docs/bundle_format.md``.

Writing builds the header, the JSON manifest and the arrays, has the C++ loader validate the
bytes, then writes them atomically (temporary file in the same directory, then
:func:`os.replace`). Reading hands the bytes to the same C++ loader
(:func:`a2l._core.load_bundle_from_memory`), so there is a single validator of the format,
then decodes the manifest and the arrays into a :class:`~a2l.skills.spec.SkillSpec`.
"""

from __future__ import annotations

import json
import os
import struct
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from a2l import _core
from a2l.atomic import atomic_write_bytes
from a2l.errors import A2LFileNotFoundError, BundleError
from a2l.skills.spec import BUNDLE_SCHEMA_VERSION, VARIABLE_KINDS, SkillSpec, VariableSpec

__all__ = ["BUNDLE_MAGIC", "bundle_bytes", "load_bundle", "save_bundle"]

#: The 8 bytes every bundle starts with.
BUNDLE_MAGIC = b"A2LBNDL\x00"
_HEADER = struct.Struct("<8sIIII")  # magic, version, manifest length, manifest CRC, reserved


def _ceil8(n: int) -> int:
    return (n + 7) // 8 * 8


def _created_by() -> str:
    return f"a2l {_core.__version__}"


def _variable_json(v: VariableSpec, i: int) -> dict[str, Any]:
    if v.kind not in VARIABLE_KINDS:
        raise BundleError(f"variables[{i}] ('{v.name}').kind: unknown kind '{v.kind}'")
    if v.kind in ("effect", "high_level") and len(v.values) != v.n_bins:
        raise BundleError(
            f"variables[{i}] ('{v.name}').values: {len(v.values)} values for n_bins={v.n_bins}"
        )
    if v.kind == "distance" and (v.low is None or v.high is None):
        raise BundleError(f"variables[{i}] ('{v.name}'): a distance variable needs low and high")
    return v.to_json()


def bundle_bytes(spec: SkillSpec) -> bytes:
    """The bytes of the bundle of `spec` (validated by the C++ loader).

    Parameters
    ----------
    spec : SkillSpec
        ``posterior`` of shape (*bins, n_moves) and ``argmax`` of shape (*bins,), in the
        axis order of ``spec.variables``.

    Returns
    -------
    bytes
        Header, manifest, padding and arrays (``docs/bundle_format.md``).

    Raises
    ------
    a2l.BundleError
        The spec does not make a valid bundle (the message names the field or check).
    """
    posterior = np.asarray(spec.posterior, dtype="<f8", order="C")
    argmax = np.asarray(spec.argmax, dtype="<i4", order="C")
    directions = np.asarray(spec.directions)
    if directions.ndim != 2 or directions.shape[1:] != (3,):
        raise BundleError(
            f"movements.directions: shape must be (n_moves, 3), got {directions.shape}"
        )
    labels = list(spec.labels) or [f"m{i}" for i in range(len(directions))]
    post_bytes = posterior.tobytes(order="C")
    amax_bytes = argmax.tobytes(order="C")
    amax_offset = _ceil8(len(post_bytes))
    manifest: dict[str, Any] = {
        "schema_version": BUNDLE_SCHEMA_VERSION,
        "kind": "skill",
        "name": spec.name,
        "created_by": _created_by(),
        "robot": None
        if spec.robot is None
        else {k: str(spec.robot[k]) for k in ("name", "urdf_sha256", "base_link", "tip_link")},
        "target": "move",
        "variables": [_variable_json(v, i) for i, v in enumerate(spec.variables)],
        "movements": {
            "step": float(spec.step),
            "directions": [[int(x) for x in row] for row in directions],
            "labels": [str(label) for label in labels],
        },
        "execution": {
            "step_cap": int(spec.step_cap),
            "smoothing": bool(spec.smoothing),
            "uniform_tolerance": float(spec.uniform_tolerance),
        },
        "arrays": {
            "posterior": {
                "dtype": "float64",
                "shape": [int(s) for s in posterior.shape],
                "offset": 0,
                "nbytes": len(post_bytes),
                "crc32": zlib.crc32(post_bytes),
            },
            "argmax": {
                "dtype": "int32",
                "shape": [int(s) for s in argmax.shape],
                "offset": amax_offset,
                "nbytes": len(amax_bytes),
                "crc32": zlib.crc32(amax_bytes),
            },
        },
        "extra": spec.extra,
    }
    try:
        text = json.dumps(manifest, allow_nan=False, ensure_ascii=False).encode("utf-8")
    except (TypeError, ValueError) as exc:
        raise BundleError(f"manifest: cannot be written as JSON ({exc})") from exc
    header = _HEADER.pack(BUNDLE_MAGIC, BUNDLE_SCHEMA_VERSION, len(text), zlib.crc32(text), 0)
    head = header + text
    blob_pad = b"\x00" * (_ceil8(len(head)) - len(head))
    arr_pad = b"\x00" * (amax_offset - len(post_bytes))
    data = head + blob_pad + post_bytes + arr_pad + amax_bytes
    _core.load_bundle_from_memory(data, f"<bundle of skill '{spec.name}'>")  # the validator
    return data


def save_bundle(spec: SkillSpec, path: str | os.PathLike[str]) -> Path:
    """Write a skill bundle atomically.

    Parameters
    ----------
    spec : SkillSpec
        The skill (see :class:`~a2l.skills.spec.SkillSpec` for the array shapes).
    path : str or PathLike
        Destination file (missing parent directories are created).

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    a2l.BundleError
        The spec does not make a valid bundle; nothing is written.
    """
    data = bundle_bytes(spec)
    return atomic_write_bytes(path, data)


def load_bundle(path: str | os.PathLike[str]) -> SkillSpec:
    """Read and validate a skill bundle.

    The bytes are validated by the C++ loader (every check of ``docs/bundle_format.md``),
    then decoded.

    Parameters
    ----------
    path : str or PathLike
        The bundle file.

    Returns
    -------
    SkillSpec
        ``posterior`` float64 of shape (*bins, n_moves), ``argmax`` int32 of shape (*bins,),
        ``directions`` int64 of shape (n_moves, 3).

    Raises
    ------
    a2l.BundleError
        Malformed, corrupted or of another schema version; the message names the field or
        the check.
    a2l.A2LFileNotFoundError
        The file does not exist or cannot be read.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise A2LFileNotFoundError(f"skill bundle '{path}': cannot read ({exc})") from exc
    _core.load_bundle_from_memory(data, str(path))  # raises BundleError naming the check
    (_, _, mlen, _, _) = _HEADER.unpack_from(data, 0)
    manifest = json.loads(data[_HEADER.size : _HEADER.size + mlen].decode("utf-8"))
    blob = _ceil8(_HEADER.size + mlen)

    def array(name: str, dtype: str) -> np.ndarray:
        a = manifest["arrays"][name]
        start = blob + int(a["offset"])
        flat = np.frombuffer(
            data, dtype=dtype, count=int(a["nbytes"]) // np.dtype(dtype).itemsize, offset=start
        )
        return flat.reshape([int(s) for s in a["shape"]]).copy()

    variables = []
    for v in manifest["variables"]:
        values = tuple(v.get("values", ()))
        variables.append(
            VariableSpec(
                name=v["name"],
                kind=v["kind"],
                n_bins=len(values) if v["kind"] in ("effect", "high_level") else int(v["n_bins"]),
                low=float(v["low"]) if v["kind"] == "distance" else None,
                high=float(v["high"]) if v["kind"] == "distance" else None,
                values=values,
            )
        )
    mv, ex = manifest["movements"], manifest["execution"]
    extra = manifest.get("extra")
    return SkillSpec(
        name=manifest["name"],
        variables=variables,
        directions=np.asarray(mv["directions"], dtype=np.int64).reshape(-1, 3),
        posterior=array("posterior", "<f8").astype(np.float64),
        argmax=array("argmax", "<i4").astype(np.int32),
        step=float(mv["step"]),
        labels=[str(x) for x in mv["labels"]],
        step_cap=int(ex["step_cap"]),
        smoothing=bool(ex["smoothing"]),
        uniform_tolerance=float(ex["uniform_tolerance"]),
        robot=None if manifest["robot"] is None else dict(manifest["robot"]),
        extra=dict(extra) if isinstance(extra, dict) else {},
    )
