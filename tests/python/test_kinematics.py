"""C++ kinematics (a2l.Kinematics) against PyBullet, IK success rates, and errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pybullet as pb
import pytest

import a2l
from a2l.robot import arm_spec, baxter_urdf, pybullet_urdf, robots_dir


def _quat_to_matrix(q: tuple[float, float, float, float]) -> np.ndarray:
    return np.array(pb.getMatrixFromQuaternion(q)).reshape(3, 3)


def _rotation_angle(r: np.ndarray) -> float:
    return float(np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0)))


@pytest.fixture(scope="module")
def bullet_baxter():
    """Baxter loaded in PyBullet (DIRECT) from the rewritten URDF copy."""
    client = pb.connect(pb.DIRECT)
    body = pb.loadURDF(str(pybullet_urdf()), useFixedBase=True, physicsClientId=client)
    joints = {}
    links = {}
    for j in range(pb.getNumJoints(body, physicsClientId=client)):
        info = pb.getJointInfo(body, j, physicsClientId=client)
        joints[info[1].decode()] = j
        links[info[12].decode()] = j
    yield client, body, joints, links
    pb.disconnect(client)


def _base_frame(client: int, body: int) -> tuple[np.ndarray, np.ndarray]:
    """World pose of the base link frame (PyBullet reports the base's centre of mass)."""
    com_pos, com_orn = pb.getBasePositionAndOrientation(body, physicsClientId=client)
    inertial = pb.getDynamicsInfo(body, -1, physicsClientId=client)[3:5]
    inv_pos, inv_orn = pb.invertTransform(inertial[0], inertial[1])
    pos, orn = pb.multiplyTransforms(com_pos, com_orn, inv_pos, inv_orn)
    return np.array(pos), _quat_to_matrix(orn)


def test_baxter_urdf_is_found_in_the_installed_package() -> None:
    path = baxter_urdf()
    assert path.is_file() and path.name == "baxter.urdf"
    assert robots_dir() in path.parents
    assert "package://" in path.read_text()


def test_pybullet_copy_has_absolute_existing_mesh_paths() -> None:
    text = pybullet_urdf().read_text()
    assert "package://" not in text
    meshes = [line.split('filename="')[1].split('"')[0] for line in text.splitlines()
              if 'filename="' in line]
    assert len(meshes) > 20
    assert all(Path(m).is_absolute() and Path(m).is_file() for m in meshes)


@pytest.mark.parametrize("arm", ["right", "left"])
def test_fk_matches_pybullet_link_frames(bullet_baxter, arm: str) -> None:
    client, body, joints, links = bullet_baxter
    spec = arm_spec("baxter", arm)
    kin = a2l.Kinematics(spec.urdf, spec.base_link, spec.tip_link)
    base_p, base_r = _base_frame(client, body)
    tip = links[spec.tip_link]
    rng = np.random.default_rng(7 if arm == "right" else 8)
    worst_p = worst_r = 0.0
    for _ in range(1000):
        q = rng.uniform(kin.lower, kin.upper)
        for name, value in zip(kin.joint_names, q, strict=True):
            pb.resetJointState(body, joints[name], value, physicsClientId=client)
        state = pb.getLinkState(body, tip, computeForwardKinematics=True, physicsClientId=client)
        world_p, world_r = np.array(state[4]), _quat_to_matrix(state[5])
        # Express PyBullet's link frame in the base frame.
        p = base_r.T @ (world_p - base_p)
        r = base_r.T @ world_r
        t = kin.fk(q)
        worst_p = max(worst_p, float(np.linalg.norm(t[:3, 3] - p)))
        worst_r = max(worst_r, _rotation_angle(t[:3, :3].T @ r))
    assert worst_p < 1e-6, f"{arm}: position error {worst_p:.3g} m"
    assert worst_r < 1e-6, f"{arm}: orientation error {worst_r:.3g} rad"


def _ik_success(kin: a2l.Kinematics, neutral: np.ndarray, seed: int, n: int = 1000) -> float:
    rng = np.random.default_rng(seed)
    ok = 0
    for i in range(n):
        target = kin.fk(rng.uniform(kin.lower, kin.upper))
        options = a2l.IkOptions()
        options.seed = i
        q, report = kin.ik_report(target, neutral, options)
        if report.status == a2l.Status.ok:
            ok += 1
            assert kin.within_limits(q), "IK solution outside the joint limits"
            reached = kin.fk(q)
            assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) < 1e-5
            assert _rotation_angle(reached[:3, :3].T @ target[:3, :3]) < 1e-5
    return ok / n


@pytest.mark.parametrize("arm", ["right", "left"])
def test_ik_succeeds_on_baxter(arm: str) -> None:
    spec = arm_spec("baxter", arm)
    kin = a2l.Kinematics(spec.urdf, spec.base_link, spec.tip_link)
    rate = _ik_success(kin, np.array(spec.neutral), seed=11)
    assert rate >= 0.995, f"Baxter {arm}: IK success {rate:.1%}"


def test_ik_succeeds_on_panda() -> None:
    spec = arm_spec("panda")
    kin = a2l.Kinematics(spec.urdf, spec.base_link, spec.tip_link)
    assert kin.n_joints == 7
    rate = _ik_success(kin, np.array(spec.neutral), seed=12)
    assert rate >= 0.995, f"Panda: IK success {rate:.1%}"


def test_ik_is_reproducible(baxter_right: a2l.Kinematics) -> None:
    target = baxter_right.fk(np.array([0.5, -0.3, 1.0, 1.2, -1.0, 0.8, 0.3]))
    far_seed = np.array(baxter_right.lower) * 0.9
    a = baxter_right.ik(target, far_seed)
    b = baxter_right.ik(target, far_seed)
    np.testing.assert_array_equal(a, b)


def test_jacobian_matches_finite_differences(baxter_right: a2l.Kinematics, rng) -> None:
    q = rng.uniform(baxter_right.lower, baxter_right.upper)
    jac = baxter_right.jacobian(q)
    assert jac.shape == (6, 7)
    h = 1e-6
    for c in range(7):
        dq = np.zeros(7)
        dq[c] = h
        dp = (baxter_right.fk(q + dq)[:3, 3] - baxter_right.fk(q - dq)[:3, 3]) / (2 * h)
        np.testing.assert_allclose(jac[:3, c], dp, atol=1e-7)


# --- errors -------------------------------------------------------------------------

def test_missing_urdf_names_the_file(tmp_path: Path) -> None:
    missing = tmp_path / "nope.urdf"
    with pytest.raises(FileNotFoundError, match="nope.urdf"):
        a2l.Kinematics(missing, "base", "tip")


def test_malformed_urdf_is_a_urdf_error(tmp_path: Path) -> None:
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'></robot")
    with pytest.raises(a2l.URDFError, match="bad.urdf"):
        a2l.Kinematics(bad, "a", "a")
    with pytest.raises(ValueError):  # URDFError is a ValueError too
        a2l.Kinematics(bad, "a", "a")


def test_unknown_link_names_the_link() -> None:
    with pytest.raises(a2l.UnknownLinkError, match="'right_hand_typo'"):
        a2l.Kinematics(baxter_urdf(), "base", "right_hand_typo")


def test_wrong_joint_vector_size_names_the_sizes(baxter_right: a2l.Kinematics) -> None:
    with pytest.raises(ValueError, match=r"shape \(7,\).*got shape \(3,\)"):
        baxter_right.fk(np.zeros(3))
    with pytest.raises(ValueError, match="NaN"):
        baxter_right.jacobian(np.full(7, np.nan))
    with pytest.raises(ValueError, match=r"\(4, 4\)"):
        baxter_right.ik(np.eye(3), np.zeros(7))


def test_unreachable_target_raises_ik_error(baxter_right: a2l.Kinematics) -> None:
    target = np.eye(4)
    target[:3, 3] = [3.0, 0.0, 0.0]
    options = a2l.IkOptions()
    options.max_attempts = 5
    with pytest.raises(a2l.IKError, match="no solution"):
        baxter_right.ik(target, np.zeros(7), options)
    q, report = baxter_right.ik_report(target, np.zeros(7), options)
    assert report.status == a2l.Status.unreachable and report.attempts == 5
    assert baxter_right.within_limits(q)
