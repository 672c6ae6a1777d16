"""The DS section of a bundle: written by Python (save_ds_bundle, bundle_bytes(spec, ds=...)),
read and validated by the C++ loader (_core.load_ds), which names a bad map's index."""

from __future__ import annotations

import json
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from a2l import BundleError, _core
from a2l.errors import A2LFileNotFoundError
from a2l.skills import SkillSpec, VariableSpec, load_bundle
from a2l.skills.bundle import BUNDLE_MAGIC, bundle_bytes
from a2l.skills.ds_bundle import DSArrays, ds_bundle_bytes, load_ds_bundle, save_ds_bundle

BOUND = float(np.sqrt(np.e / 2.0))


def make_spec(seed: int) -> SkillSpec:
    """A small skill: distance(3) -> 2 movements."""
    post = np.random.default_rng(seed).random((3, 2)) + 0.1
    post /= post.sum(axis=-1, keepdims=True)
    return SkillSpec(
        name="reach_and_push",
        variables=[VariableSpec("distance", "distance", 3, low=0.05, high=0.20)],
        directions=np.array([[1, 0, 0], [-1, 0, 0]]),
        posterior=post,
        argmax=post.argmax(axis=-1).astype(np.int32),
    )


def make_ds(seed: int = 0, d: int = 2, k: int = 25) -> DSArrays:
    rng = np.random.default_rng(seed)
    vectors = rng.normal(size=(k, d))
    return DSArrays(
        target=rng.uniform(-1.0, 1.0, d),
        centers=rng.uniform(-5.0, 5.0, (k, d)),
        vectors=vectors,
        rhos=rng.uniform(0.2, 0.9, k) * BOUND / np.linalg.norm(vectors, axis=1),
        speed=1.3,
    )


def patch_array(data: bytes, name: str, values: np.ndarray) -> bytes:
    """Replace array `name`'s bytes (same size) and repair its CRC and the manifest's."""
    _, version, mlen, _, _ = struct.unpack_from("<8sIIII", data, 0)
    manifest = json.loads(data[24 : 24 + mlen])
    blob = (24 + mlen + 7) // 8 * 8
    raw = np.ascontiguousarray(values, dtype="<f8").tobytes()
    a = manifest["arrays"][name]
    assert len(raw) == a["nbytes"]
    arrays = bytearray(data[blob:])
    arrays[a["offset"] : a["offset"] + len(raw)] = raw
    a["crc32"] = zlib.crc32(raw)
    text = json.dumps(manifest).encode()
    head = struct.pack("<8sIIII", BUNDLE_MAGIC, version, len(text), zlib.crc32(text), 0) + text
    return head + b"\0" * (-len(head) % 8) + bytes(arrays)


@pytest.mark.parametrize("d", [2, 3])
def test_ds_bundle_round_trip(tmp_path: Path, d: int) -> None:
    arrays = make_ds(1, d)
    path = save_ds_bundle(tmp_path / "reach.a2lb", arrays, name="reach", metadata={"K": 25})
    ds = _core.load_ds(path)
    assert (ds.dim, ds.n_maps, ds.speed) == (d, 25, 1.3)
    for field in ("target", "centers", "vectors", "rhos"):
        np.testing.assert_array_equal(getattr(ds, field), getattr(arrays, field))
    back, metadata = load_ds_bundle(path)
    assert metadata == {"K": 25} and back.n_maps == 25
    # the loaded DS evaluates as one built from the arrays
    direct = _core.DiffeoDS(arrays.target, arrays.centers, arrays.vectors, arrays.rhos, 1.3)
    x = np.random.default_rng(2).uniform(-6.0, 6.0, (50, d))
    np.testing.assert_array_equal(ds.velocity(x), direct.velocity(x))
    # a DS-only bundle is not a skill
    with pytest.raises(BundleError, match="kind: 'ds'"):
        load_bundle(path)


def test_skill_with_ds(tmp_path: Path) -> None:
    spec, arrays = make_spec(3), make_ds(4, 3, 7)
    path = tmp_path / "skill.a2lb"
    path.write_bytes(bundle_bytes(spec, ds=arrays))
    assert load_bundle(path).name == spec.name
    np.testing.assert_array_equal(_core.load_ds(path).rhos, arrays.rhos)
    plain = tmp_path / "plain.a2lb"
    plain.write_bytes(bundle_bytes(spec))
    with pytest.raises(BundleError, match="ds: missing"):
        _core.load_ds(plain)


def test_writer_refuses_a_map_breaking_the_bound(tmp_path: Path) -> None:
    arrays = make_ds(5)
    rhos = arrays.rhos.copy()
    rhos[7] = 1.01 * BOUND / np.linalg.norm(arrays.vectors[7])
    bad = DSArrays(arrays.target, arrays.centers, arrays.vectors, rhos, arrays.speed)
    with pytest.raises(BundleError, match=r"map 7: rho \* \|\|v\|\|"):
        save_ds_bundle(tmp_path / "bad.a2lb", bad)
    assert not (tmp_path / "bad.a2lb").exists()
    with pytest.raises(ValueError, match="map 7"):
        _core.DiffeoDS(bad.target, bad.centers, bad.vectors, bad.rhos, 1.0)


def test_loader_refuses_bad_maps_by_index(tmp_path: Path) -> None:
    arrays = make_ds(6)
    good = ds_bundle_bytes(arrays)
    path = tmp_path / "corrupt.a2lb"
    rhos = arrays.rhos.copy()
    rhos[11] *= 10.0
    path.write_bytes(patch_array(good, "ds_rhos", rhos))
    with pytest.raises(BundleError, match=r"corrupt\.a2lb.*map 11: rho \* \|\|v\|\|"):
        _core.load_ds(path)
    centers = arrays.centers.copy()
    centers[3, 1] = np.nan
    path.write_bytes(patch_array(good, "ds_centers", centers))
    with pytest.raises(BundleError, match="map 3: center is not finite"):
        _core.load_ds(path)
    path.write_bytes(good[:-5])
    with pytest.raises(BundleError):
        _core.load_ds(path)
    with pytest.raises(A2LFileNotFoundError):
        _core.load_ds(tmp_path / "missing.a2lb")


def test_writer_refuses_wrong_shapes_and_values(tmp_path: Path) -> None:
    a = make_ds(7)
    with pytest.raises(BundleError, match=r"ds_centers: shape must be \(25, 2\)"):
        ds_bundle_bytes(DSArrays(a.target, a.centers[:, :1], a.vectors, a.rhos))
    with pytest.raises(BundleError, match=r"ds.target: shape must be"):
        ds_bundle_bytes(DSArrays(np.zeros(4), a.centers, a.vectors, a.rhos))
    with pytest.raises(BundleError, match="ds: target and speed must be finite"):
        ds_bundle_bytes(DSArrays(np.array([np.nan, 0.0]), a.centers, a.vectors, a.rhos))
    with pytest.raises(BundleError, match="ds.speed: must be > 0"):
        ds_bundle_bytes(DSArrays(a.target, a.centers, a.vectors, a.rhos, speed=-1.0))


def test_binding_shapes_and_non_finite_input() -> None:
    a = make_ds(8, 3, 10)
    ds = _core.DiffeoDS(a.target, a.centers, a.vectors, a.rhos, 2.0)
    assert ds.velocity(np.zeros(3)).shape == (3,)
    assert ds.forward(np.zeros((4, 3))).shape == (4, 3)
    assert ds.jacobian(np.zeros(3)).shape == (3, 3)
    assert ds.jacobian(np.zeros((5, 3))).shape == (5, 3, 3)
    assert ds.rollout(np.ones(3), 0.1, 7).shape == (7, 3)
    x = np.zeros((3, 3))
    x[2, 1] = np.inf
    with pytest.raises(ValueError, match=r"velocity: x\[2\] is not finite"):
        ds.velocity(x)
    with pytest.raises(ValueError, match="shape"):
        ds.inverse(np.zeros(2))
    with pytest.raises(ValueError, match="method"):
        ds.rollout(np.ones(3), 0.1, 3, method="midpoint")
    with pytest.raises(ValueError, match=r"centers must have shape \(10, 3\)"):
        _core.DiffeoDS(a.target, a.centers[:, :2], a.vectors, a.rhos)
