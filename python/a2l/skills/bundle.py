"""Skill bundles: writing and reading the one-file format of ``docs/bundle_format.md``.

Writing builds the JSON manifest and the arrays, packs them
(:mod:`a2l.skills.bundle_format`), has the C++ loader validate the bytes, then writes them
atomically (temporary file in the same directory, then :func:`os.replace`). Reading goes
through the one reader, :func:`a2l.skills.bundle_format.read_bundle`: the same C++ loader
(:func:`a2l._core.load_bundle_from_memory`) validates the bytes, so there is a single
validator of the format, then the manifest and its arrays are decoded into a
:class:`~a2l.skills.spec.SkillSpec`.

A bundle may also hold a diffeomorphic DS (section ``ds``, :mod:`a2l.skills.ds_bundle`,
whose names are re-exported here): alone (kind ``"ds"``, :func:`save_ds_bundle`) or beside a
skill table (``bundle_bytes(spec, ds=...)``).
A skill bundle may hold DS phases (section ``ds_phases``, :mod:`a2l.skills.phases`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from a2l import _core
from a2l.atomic import atomic_write_bytes
from a2l.errors import BundleError
from a2l.skills.bundle_format import BUNDLE_MAGIC, created_by, pack_bundle, read_bundle
from a2l.skills.ds_bundle import DSArrays, ds_bundle_bytes, load_ds_bundle, save_ds_bundle
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


def _variable_json(v: VariableSpec, i: int) -> dict[str, Any]:
    if v.kind not in VARIABLE_KINDS:
        raise BundleError(f"variables[{i}] ('{v.name}').kind: unknown kind '{v.kind}'")
    if v.kind in ("effect", "high_level") and len(v.values) != v.n_bins:
        raise BundleError(
            f"variables[{i}] ('{v.name}').values: {len(v.values)} values for n_bins={v.n_bins}"
        )
    if v.kind in RANGED_KINDS and (v.low is None or v.high is None):
        raise BundleError(f"variables[{i}] ('{v.name}'): a {v.kind} variable needs low and high")
    if v.edges and v.kind != "distance":
        raise BundleError(f"variables[{i}] ('{v.name}').edges: only a distance variable may "
                          f"have edges, this is a {v.kind} variable")
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
        ``posterior`` of shape ``(*bins, n_moves)`` and ``argmax`` of shape ``(*bins,)``, in the
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
        "created_by": created_by(),
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
            "fallback": str(spec.fallback),
            # written when the rule is on: a bundle without it is the same bytes as before
            **({"clearance": float(spec.clearance)} if spec.clearance else {}),
            **({"clearance_ratio": float(spec.clearance_ratio)}
               if spec.clearance_ratio != _core.CLEARANCE_RATIO else {}),
            **({"align": float(spec.align)} if spec.align else {}),
            **({"avoid_revisits": True} if spec.avoid_revisits else {}),
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
    data = pack_bundle(manifest, arrays)
    _core.load_bundle_from_memory(data, f"<bundle of skill '{spec.name}'>")  # the validator
    return data


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
        ``posterior`` float64 of shape ``(*bins, n_moves)``, ``argmax`` int32 of shape ``(*bins,)``,
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
    view, _ = read_bundle(path, _core.load_bundle_from_memory)
    manifest = view.manifest
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
                edges=tuple(float(x) for x in v.get("edges", ())),
            )
        )
    mv, ex = manifest["movements"], manifest["execution"]
    return SkillSpec(
        name=manifest["name"],
        variables=variables,
        directions=np.asarray(mv["directions"], dtype=np.int64).reshape(-1, 3),
        posterior=view.array("posterior"),
        argmax=view.array("argmax"),
        step=float(mv["step"]),
        labels=[str(x) for x in mv["labels"]],
        step_cap=int(ex["step_cap"]),
        smoothing=bool(ex["smoothing"]),
        uniform_tolerance=float(ex["uniform_tolerance"]),
        fallback=str(ex.get("fallback", "none")),
        clearance=float(ex.get("clearance", 0.0)),
        clearance_ratio=float(ex.get("clearance_ratio", _core.CLEARANCE_RATIO)),
        align=float(ex.get("align", 0.0)),
        avoid_revisits=bool(ex.get("avoid_revisits", False)),
        robot=None if manifest["robot"] is None else dict(manifest["robot"]),
        extra=view.extra,
        actions=[str(x) for x in mv["actions"]],
    )
