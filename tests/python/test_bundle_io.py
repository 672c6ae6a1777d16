"""Skill bundles in Python: atomic writing, round trips, and corrupted files -> BundleError.

The bytes are validated by the C++ loader (one validator); these tests check that every
corruption of docs/bundle_format.md surfaces in Python as a clear a2l.BundleError.
"""

from __future__ import annotations

import json
import re
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

import a2l
from a2l import BundleError, _core
from a2l.errors import A2LFileNotFoundError
from a2l.skills import BUNDLE_SCHEMA_VERSION, SkillSpec, VariableSpec, load_bundle, save_bundle
from a2l.skills.bundle import BUNDLE_MAGIC, bundle_bytes

PLANAR = np.array(
    [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [1, 1, 0], [1, -1, 0], [-1, 1, 0], [-1, -1, 0]]
)


def make_spec(seed: int = 0, robot: bool = True) -> SkillSpec:
    """A random skill: effect(4) x distance(3) x orientation(8) x light(2) -> 8 movements."""
    rng = np.random.default_rng(seed)
    shape = (4, 3, 8, 2)
    post = rng.random((*shape, 8)) ** 3 + 1e-3
    post /= post.sum(axis=-1, keepdims=True)
    uniform = rng.random(shape) < 0.25
    post[uniform] = 1.0 / 8
    argmax = np.where(uniform, -1, post.argmax(axis=-1)).astype(np.int32)
    return SkillSpec(
        name="push",
        variables=[
            VariableSpec("effect", "effect", 4, values=("left", "right", "close", "far")),
            VariableSpec("distance", "distance", 3, low=0.05, high=0.20),
            VariableSpec("orientation", "orientation", 8),
            VariableSpec("light", "high_level", 2, values=("off", "on")),
        ],
        directions=PLANAR.copy(),
        posterior=post,
        argmax=argmax,
        labels=["+x", "-x", "+y", "-y", "+x+y", "+x-y", "-x+y", "-x-y"],
        step_cap=9,
        smoothing=True,
        robot={
            "name": "baxter",
            "urdf_sha256": "ab" * 32,
            "base_link": "base",
            "tip_link": "right_gripper",
        }
        if robot
        else None,
        extra={"note": "test", "n": [1, 2]},
    )


def header(data: bytes) -> tuple[bytes, int, int, int, int]:
    return struct.unpack_from("<8sIIII", data, 0)


def rewrite_manifest(data: bytes, edit) -> bytes:
    """Apply `edit` to the manifest, keep the arrays, fix the manifest length and CRC."""
    _, version, mlen, _, _ = header(data)
    manifest = json.loads(data[24 : 24 + mlen])
    blob = (24 + mlen + 7) // 8 * 8
    arrays = data[blob:]
    edit(manifest)
    text = json.dumps(manifest).encode()
    head = struct.pack("<8sIIII", BUNDLE_MAGIC, version, len(text), zlib.crc32(text), 0) + text
    return head + b"\0" * (-len(head) % 8) + arrays


def test_bundle_round_trip(tmp_path: Path) -> None:
    spec = make_spec()
    path = save_bundle(spec, tmp_path / "push.a2lb")
    back = load_bundle(path)
    assert back.name == "push"
    assert back.variables == spec.variables
    np.testing.assert_array_equal(back.posterior, spec.posterior)
    np.testing.assert_array_equal(back.argmax, spec.argmax)
    np.testing.assert_array_equal(back.directions, spec.directions)
    assert back.posterior.dtype == np.float64 and back.argmax.dtype == np.int32
    assert back.labels == spec.labels
    assert (back.step, back.step_cap, back.smoothing) == (0.05, 9, True)
    assert back.uniform_tolerance == spec.uniform_tolerance
    assert back.robot == spec.robot
    assert back.extra == spec.extra
    # The same file in the C++ runtime.
    skill = _core.load_bundle(path)
    assert skill.name == "push" and skill.n_moves == 8 and skill.step_cap == 9
    assert skill.robot == spec.robot
    np.testing.assert_array_equal(skill.table.posterior(), spec.posterior)
    np.testing.assert_array_equal(skill.table.argmax(), spec.argmax)


def test_bundle_layout_follows_the_format(tmp_path: Path) -> None:
    data = bundle_bytes(make_spec(robot=False))
    magic, version, mlen, crc, reserved = header(data)
    assert magic == b"A2LBNDL\x00" and version == BUNDLE_SCHEMA_VERSION == 4 and reserved == 0
    assert crc == zlib.crc32(data[24 : 24 + mlen])
    manifest = json.loads(data[24 : 24 + mlen])
    assert manifest["robot"] is None and manifest["kind"] == "skill"
    blob = (24 + mlen + 7) // 8 * 8
    ends = []
    for name, a in manifest["arrays"].items():
        assert a["offset"] % 8 == 0
        chunk = data[blob + a["offset"] : blob + a["offset"] + a["nbytes"]]
        assert zlib.crc32(chunk) == a["crc32"], name
        ends.append(blob + a["offset"] + a["nbytes"])
    assert max(ends) == len(data)


def test_bundle_write_is_atomic_and_refuses_invalid_specs(tmp_path: Path) -> None:
    path = tmp_path / "skill.a2lb"
    save_bundle(make_spec(1), path)
    before = path.read_bytes()
    bad = make_spec(2)
    bad.posterior = bad.posterior[..., :7]  # 7 movements for 8 directions
    with pytest.raises(BundleError, match=r"arrays\.posterior\.shape"):
        save_bundle(bad, path)
    assert path.read_bytes() == before  # untouched
    bad = make_spec(3)
    bad.posterior[0, 0, 0, 0] *= 2  # a row that does not sum to 1
    with pytest.raises(BundleError, match="sums to"):
        save_bundle(bad, path)
    bad = make_spec(4)
    bad.directions[2] = (0, 0, 0)
    with pytest.raises(BundleError, match=r"movements\.directions\[2\]"):
        save_bundle(bad, path)
    bad = make_spec(6)
    row = tuple(np.argwhere(bad.argmax >= 0)[0])
    bad.argmax[row] = -1  # "no information" on an informative row: the runtime would stop
    with pytest.raises(BundleError, match=r"arrays\.argmax\[\d+\]: -1 \(no information\)"):
        save_bundle(bad, path)
    bad = make_spec(6)
    row = tuple(np.argwhere(bad.argmax < 0)[0])
    bad.argmax[row] = 2  # a movement for a uniform row: a guess
    with pytest.raises(BundleError, match="for a uniform posterior row"):
        save_bundle(bad, path)
    save_bundle(make_spec(5), path)  # overwrite
    assert load_bundle(path).step_cap == 9
    assert sorted(p.name for p in tmp_path.iterdir()) == ["skill.a2lb"]  # no temporary left


@pytest.fixture
def good(tmp_path: Path) -> bytes:
    return bundle_bytes(make_spec(7))


def expect_bundle_error(tmp_path: Path, data: bytes, pattern: str) -> BundleError:
    path = tmp_path / "corrupt.a2lb"
    path.write_bytes(data)
    with pytest.raises(BundleError, match=pattern) as info:
        load_bundle(path)
    assert "corrupt.a2lb" in str(info.value)
    with pytest.raises(BundleError, match=pattern):
        _core.load_bundle(path)  # the same message from the C++ loader directly
    return info.value


def test_bundle_truncated(tmp_path: Path, good: bytes) -> None:
    expect_bundle_error(tmp_path, good[:0], "truncated")
    expect_bundle_error(tmp_path, good[:20], "truncated")
    expect_bundle_error(tmp_path, good[:300], "manifest length")
    expect_bundle_error(tmp_path, good[:-1], "outside the file")
    for n in np.linspace(1, len(good) - 1, 60).astype(int):
        expect_bundle_error(tmp_path, good[:n], ".")


def test_bundle_wrong_checksums(tmp_path: Path, good: bytes) -> None:
    b = bytearray(good)
    b[40] ^= 0x04
    expect_bundle_error(tmp_path, bytes(b), "manifest CRC-32")
    b = bytearray(good)
    b[-1] ^= 0x01
    expect_bundle_error(tmp_path, bytes(b), r"arrays\.argmax\.crc32")
    b = bytearray(good)
    b[-2000] ^= 0x01
    expect_bundle_error(tmp_path, bytes(b), r"arrays\.posterior\.crc32")


def test_bundle_wrong_version(tmp_path: Path, good: bytes) -> None:
    b = bytearray(good)
    # 1: before the DS section; 2: before the movement actions; 3: before ds.direction
    for other in (1, 2, 3, BUNDLE_SCHEMA_VERSION + 1):
        b[8:12] = struct.pack("<I", other)
        expect_bundle_error(tmp_path, bytes(b), f"schema version: the header says {other}")
    expect_bundle_error(
        tmp_path, rewrite_manifest(good, lambda m: m.update(schema_version=3)), "schema_version"
    )


def test_bundle_wrong_shapes_and_fields(tmp_path: Path, good: bytes) -> None:
    def shape(m):
        m["arrays"]["posterior"]["shape"] = [4, 3, 2, 8, 8]

    expect_bundle_error(tmp_path, rewrite_manifest(good, shape), r"arrays\.posterior\.shape")

    def bins(m):
        m["variables"][2]["n_bins"] = 16

    expect_bundle_error(tmp_path, rewrite_manifest(good, bins), r"arrays\.posterior\.shape")

    def missing(m):
        del m["movements"]["labels"]

    expect_bundle_error(tmp_path, rewrite_manifest(good, missing), r"movements\.labels: missing")

    def kind(m):
        m["variables"][1]["kind"] = "temperature"

    expect_bundle_error(tmp_path, rewrite_manifest(good, kind), r"variables\[1\]\.kind")

    def typed(m):
        m["execution"]["step_cap"] = 2.5

    expect_bundle_error(tmp_path, rewrite_manifest(good, typed), r"execution\.step_cap")


def test_bundle_random_bytes_and_bad_magic(tmp_path: Path, good: bytes) -> None:
    rng = np.random.default_rng(0)
    for i in range(200):
        data = rng.integers(0, 256, int(rng.integers(0, 3000)), dtype=np.uint8).tobytes()
        if i % 2:
            data = good[:24] + data  # a plausible header, random rest
        expect_bundle_error(tmp_path, data, ".")
    expect_bundle_error(tmp_path, b"PK\x03\x04" + good[4:], "magic")


def test_bundle_unknown_keys_are_ignored(tmp_path: Path, good: bytes) -> None:
    def future(m):
        m["new_section"] = {"anything": [1, 2, 3]}
        m["movements"]["new_field"] = True

    path = tmp_path / "future.a2lb"
    path.write_bytes(rewrite_manifest(good, future))
    assert load_bundle(path).name == "push"


def test_bundle_missing_file(tmp_path: Path) -> None:
    with pytest.raises(A2LFileNotFoundError):
        load_bundle(tmp_path / "nope.a2lb")
    with pytest.raises(A2LFileNotFoundError, match="nope.a2lb"):
        _core.load_bundle(tmp_path / "nope.a2lb")


def test_one_bundle_reader() -> None:
    """The package reads bundle bytes in one place, through the manifest
    (:func:`a2l.skills.bundle_format.read_bundle`); no other module parses the header."""
    root = Path(a2l.__file__).parent
    home = root / "skills" / "bundle_format.py"
    parsers = [p.relative_to(root).as_posix() for p in sorted(root.rglob("*.py"))
               if p != home and re.search(r"unpack_from|A2LBNDL|\[24 ?:",
                                          p.read_text(encoding="utf-8"))]
    assert parsers == []
