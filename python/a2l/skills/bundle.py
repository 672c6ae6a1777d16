"""Skill bundles: writing and reading the one-file format of ``docs/bundle_format.md``.

Writing builds the header, the JSON manifest and the arrays, has the C++ loader validate the
bytes, then writes them atomically (temporary file in the same directory, then
:func:`os.replace`). Reading hands the bytes to the same C++ loader
(:func:`a2l._core.load_bundle_from_memory`), so there is a single validator of the format,
then decodes the manifest and the arrays into a :class:`~a2l.skills.spec.SkillSpec`.

A bundle may also hold a diffeomorphic DS (section ``ds``): alone (kind ``"ds"``,
:func:`save_ds_bundle`) or beside a skill table (``bundle_bytes(spec, ds=...)``). Its maps are
validated by the same C++ loader (:func:`a2l._core.load_ds`), which names a bad map's index.
A skill bundle may hold DS phases (section ``ds_phases``, :mod:`a2l.skills.phases`).
"""

from __future__ import annotations

import json
import os
import struct
import zlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from a2l import _core
from a2l.atomic import atomic_write_bytes
from a2l.errors import A2LFileNotFoundError, BundleError
from a2l.skills.phases import DSPhase, ds_phases_section
from a2l.skills.spec import (
    BUNDLE_SCHEMA_VERSION,
    RANGED_KINDS,
    VARIABLE_KINDS,
    SkillSpec,
    VariableSpec,
)

__all__ = [
    "BUNDLE_MAGIC",
    "DSArrays",
    "bundle_bytes",
    "ds_bundle_bytes",
    "load_bundle",
    "load_ds_bundle",
    "save_bundle",
    "save_ds_bundle",
]

#: The 8 bytes every bundle starts with.
BUNDLE_MAGIC = b"A2LBNDL\x00"
_HEADER = struct.Struct("<8sIIII")  # magic, version, manifest length, manifest CRC, reserved


def _ceil8(n: int) -> int:
    return (n + 7) // 8 * 8


def _created_by() -> str:
    return f"a2l {_core.__version__}"


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


def _pack(manifest: dict[str, Any], arrays: list[tuple[str, np.ndarray]]) -> bytes:
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


def _variable_json(v: VariableSpec, i: int) -> dict[str, Any]:
    if v.kind not in VARIABLE_KINDS:
        raise BundleError(f"variables[{i}] ('{v.name}').kind: unknown kind '{v.kind}'")
    if v.kind in ("effect", "high_level") and len(v.values) != v.n_bins:
        raise BundleError(
            f"variables[{i}] ('{v.name}').values: {len(v.values)} values for n_bins={v.n_bins}"
        )
    if v.kind in RANGED_KINDS and (v.low is None or v.high is None):
        raise BundleError(f"variables[{i}] ('{v.name}'): a {v.kind} variable needs low and high")
    return v.to_json()


def bundle_bytes(
    spec: SkillSpec,
    ds: DSArrays | None = None,
    ds_phases: Sequence[DSPhase] | None = None,
    ds_states: Mapping[str, Sequence[str]] | None = None,
) -> bytes:
    """The bytes of the bundle of `spec` (validated by the C++ loader).

    Parameters
    ----------
    spec : SkillSpec
        ``posterior`` of shape (*bins, n_moves) and ``argmax`` of shape (*bins,), in the
        axis order of ``spec.variables``.
    ds : DSArrays, optional
        A diffeomorphic DS stored beside the table (section ``ds``).
    ds_phases : sequence of a2l.skills.phases.DSPhase, optional
        The DS phases (section ``ds_phases``), run by the C++ ``step_ds``.
    ds_states : mapping of str to sequence of str, optional
        Values of states the phases name that are not high-level variables of the table
        (``gripper`` defaults to ``("open", "closed")``).

    Returns
    -------
    bytes
        Header, manifest, padding and arrays (``docs/bundle_format.md``).

    Raises
    ------
    a2l.BundleError
        The spec does not make a valid bundle (the message names the field or check).
    """
    posterior = np.asarray(spec.posterior, dtype=np.float64)
    argmax = np.asarray(spec.argmax, dtype=np.int32)
    directions = np.asarray(spec.directions)
    if directions.ndim != 2 or directions.shape[1:] != (3,):
        raise BundleError(
            f"movements.directions: shape must be (n_moves, 3), got {directions.shape}"
        )
    labels = list(spec.labels) or [f"m{i}" for i in range(len(directions))]
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
            "actions": [str(a) for a in spec.actions],
        },
        "execution": {
            "step_cap": int(spec.step_cap),
            "smoothing": bool(spec.smoothing),
            "uniform_tolerance": float(spec.uniform_tolerance),
        },
        "extra": spec.extra,
    }
    arrays = [("posterior", posterior), ("argmax", argmax)]
    if ds is not None:
        manifest["ds"], ds_arrays = ds.section()
        arrays += ds_arrays
    if ds_phases:
        manifest["ds_phases"], phase_arrays = ds_phases_section(ds_phases, spec, ds_states)
        arrays += phase_arrays
    data = _pack(manifest, arrays)
    _core.load_bundle_from_memory(data, f"<bundle of skill '{spec.name}'>")  # the validator
    return data


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
        "created_by": _created_by(),
        "ds": entry,
        "extra": dict(metadata or {}),
    }
    data = _pack(manifest, arrays)
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
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise A2LFileNotFoundError(f"skill bundle '{path}': cannot read ({exc})") from exc
    ds = _core.load_ds_from_memory(data, str(path))
    (_, _, mlen, _, _) = _HEADER.unpack_from(data, 0)
    extra = json.loads(data[_HEADER.size : _HEADER.size + mlen].decode("utf-8")).get("extra")
    return ds, dict(extra) if isinstance(extra, dict) else {}


def save_bundle(
    spec: SkillSpec,
    path: str | os.PathLike[str],
    ds_phases: Sequence[DSPhase] | None = None,
    ds_states: Mapping[str, Sequence[str]] | None = None,
    ds: DSArrays | None = None,
) -> Path:
    """Write a skill bundle atomically.

    Parameters
    ----------
    spec : SkillSpec
        The skill (see :class:`~a2l.skills.spec.SkillSpec` for the array shapes).
    path : str or PathLike
        Destination file (missing parent directories are created).
    ds_phases : sequence of a2l.skills.phases.DSPhase, optional
        DS phases (section ``ds_phases``): what ``CppSkillRunner(path, mode="ds")`` runs.
    ds_states : mapping of str to sequence of str, optional
        Values of states the phases name that the table does not hold.
    ds : DSArrays, optional
        A single DS stored beside the table (section ``ds``).

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    a2l.BundleError
        The spec does not make a valid bundle; nothing is written.
    """
    data = bundle_bytes(spec, ds=ds, ds_phases=ds_phases, ds_states=ds_states)
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
        ``directions`` int64 of shape (n_directions, 3), ``actions`` the actions' names
        (n_moves = n_directions + len(actions)).

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
                low=float(v["low"]) if v["kind"] in RANGED_KINDS else None,
                high=float(v["high"]) if v["kind"] in RANGED_KINDS else None,
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
        actions=[str(x) for x in mv["actions"]],
    )
