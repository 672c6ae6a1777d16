"""Kinematics: FK, Jacobian and IK per call on Baxter's right arm, beside PyBullet's IK."""

from __future__ import annotations

import json
import os
import subprocess
import time
from pathlib import Path

import numpy as np
import pybullet as pb

import a2l
from a2l.robot import arm_spec, pybullet_urdf, robots_dir

TITLE = "Kinematics (Baxter right arm, base -> right_gripper)"
#: Installed versions stamped on the section (benchmarks/run.py).
PACKAGES = ("pybullet", "numpy")
#: Published IK figures quoted for reference (not measured here), with their source.
PUBLISHED_IK = {
    "text": "on the Baxter arm (7 DOF), Orocos KDL's joint-limited inverse-Jacobian solver "
            "solves 61.07 % at 2.21 ms on average, TRAC-IK (speed mode) 99.62 % at 0.43 ms "
            "(10,000 random reachable configurations, full pose at 1e-5, 5 ms timeout, seeded "
            "from the chain's nominal pose).",
    "source": "the TRAC-IK README, results table 'as of TRAC-IK tag v1.4.6' "
              "(bitbucket.org/traclabs/trac_ik; method in P. Beeson and B. Ames, "
              "'TRAC-IK: An Open-Source Library for Improved Solving of Generic Inverse "
              "Kinematics', IEEE-RAS Humanoids 2015)",
}
N_TARGETS = 1000


def _cpp_figures() -> dict[str, dict[str, float]]:
    """Run the Google Benchmark binary; per-call mean, p50, p99 in µs and IK success."""
    binary = Path(os.environ.get("A2L_BENCH_BIN", "build/cpp")) / "bench_kinematics"
    out = subprocess.run(
        [str(binary), str(robots_dir()), "--benchmark_format=json"],
        capture_output=True, text=True, check=True,
    ).stdout
    figures = {}
    for b in json.loads(out)["benchmarks"]:
        name = b["name"].split("/")[0].removeprefix("BM_")
        per_call_ns = b["real_time"] if name == "ik" else b["real_time"] / 16
        figures[name] = {
            "mean_us": per_call_ns / 1000.0,
            "p50_us": b["p50_us"],
            "p99_us": b["p99_us"],
            "success": b.get("success", float("nan")),
        }
    return figures


def _rotation_angle(r: np.ndarray) -> float:
    return float(np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0)))


def _python_ik_comparison() -> list[tuple[str, float, float, float, float]]:
    """Our IK (through the binding) and PyBullet's on the same targets, same process."""
    spec = arm_spec("baxter", "right")
    kin = a2l.Kinematics(spec.urdf, spec.base_link, spec.tip_link)
    rng = np.random.default_rng(0)
    targets = [kin.fk(rng.uniform(kin.lower, kin.upper)) for _ in range(N_TARGETS)]
    neutral = np.array(spec.neutral)

    client = pb.connect(pb.DIRECT)
    body = pb.loadURDF(str(pybullet_urdf()), useFixedBase=True, physicsClientId=client)
    index = {}
    movable = []
    for j in range(pb.getNumJoints(body, physicsClientId=client)):
        info = pb.getJointInfo(body, j, physicsClientId=client)
        index[info[12].decode()] = j
        if info[2] != pb.JOINT_FIXED:
            movable.append(info[1].decode())
    arm_columns = [movable.index(n) for n in kin.joint_names]
    tip = index[spec.tip_link]
    lower = [pb.getJointInfo(body, j, physicsClientId=client)[8] for j in range(
        pb.getNumJoints(body, physicsClientId=client))
        if pb.getJointInfo(body, j, physicsClientId=client)[2] != pb.JOINT_FIXED]
    upper = [pb.getJointInfo(body, j, physicsClientId=client)[9] for j in range(
        pb.getNumJoints(body, physicsClientId=client))
        if pb.getJointInfo(body, j, physicsClientId=client)[2] != pb.JOINT_FIXED]

    def pybullet_ik(t: np.ndarray, iterations: int, null_space: bool) -> np.ndarray:
        for name, v in zip(kin.joint_names, neutral, strict=True):
            pb.resetJointState(body, movable_index[name], v, physicsClientId=client)
        quat = _matrix_to_quat(t[:3, :3])
        extra = {}
        if null_space:  # PyBullet's only way to take the joint limits into account
            extra = {"lowerLimits": lower, "upperLimits": upper,
                     "jointRanges": list(np.subtract(upper, lower)),
                     "restPoses": [0.0] * len(movable)}
        sol = pb.calculateInverseKinematics(
            body, tip, t[:3, 3].tolist(), quat, maxNumIterations=iterations,
            residualThreshold=1e-5, physicsClientId=client, **extra)
        return np.array(sol)[arm_columns]

    movable_index = {pb.getJointInfo(body, j, physicsClientId=client)[1].decode(): j
                     for j in range(pb.getNumJoints(body, physicsClientId=client))}
    rows = []

    def run(name: str, solve) -> None:
        times, errors, ok = [], [], 0
        for t in targets:
            t0 = time.perf_counter()
            q = solve(t)
            times.append((time.perf_counter() - t0) * 1e6)
            reached = kin.fk(q)  # PyBullet may leave the limits: FK is defined anyway
            err = float(np.linalg.norm(reached[:3, 3] - t[:3, 3]))
            errors.append(err)
            if (err < 1e-4 and _rotation_angle(reached[:3, :3].T @ t[:3, :3]) < 1e-3
                    and kin.within_limits(q, 1e-9)):
                ok += 1
        a = np.array(times)
        rows.append((name, ok / len(targets), float(a.mean()), float(np.median(a)),
                     float(np.percentile(a, 99)), float(np.median(errors))))

    def ours(t: np.ndarray) -> np.ndarray:
        q, _ = kin.ik_report(t, neutral)
        return q

    run("a2l `Kinematics.ik` (C++ LM + restarts, via Python)", ours)
    run("PyBullet `calculateInverseKinematics`, 20 iterations",
        lambda t: pybullet_ik(t, 20, False))
    run("PyBullet `calculateInverseKinematics`, 200 iterations",
        lambda t: pybullet_ik(t, 200, False))
    run("PyBullet `calculateInverseKinematics`, 200 iterations, null space (limits)",
        lambda t: pybullet_ik(t, 200, True))
    pb.disconnect(client)
    return rows


def _matrix_to_quat(r: np.ndarray) -> list[float]:
    w = np.sqrt(max(0.0, 1.0 + r[0, 0] + r[1, 1] + r[2, 2])) / 2.0
    x = np.copysign(np.sqrt(max(0.0, 1.0 + r[0, 0] - r[1, 1] - r[2, 2])) / 2.0, r[2, 1] - r[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1.0 - r[0, 0] + r[1, 1] - r[2, 2])) / 2.0, r[0, 2] - r[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1.0 - r[0, 0] - r[1, 1] + r[2, 2])) / 2.0, r[1, 0] - r[0, 1])
    return [float(x), float(y), float(z), float(w)]


def run() -> str:
    cpp = _cpp_figures()
    lines = [
        "C++ (Google Benchmark, `benchmarks/cpp/bench_kinematics.cpp`); FK and Jacobian timed "
        "in batches of 16 calls, IK call by call on 1,000 random reachable poses (FK of random "
        "configurations within limits), seeded from a neutral pose.",
        "",
        "| call | mean (µs) | median (µs) | p99 (µs) | target | IK success |",
        "|---|---|---|---|---|---|",
    ]
    targets = {"fk": "≤ 0.5 µs", "jacobian": "", "ik": "≤ 200 µs mean, ≥ 99.5 %"}
    for name in ("fk", "jacobian", "ik"):
        f = cpp[name]
        success = f"{f['success']:.1%}" if name == "ik" else ""
        lines.append(f"| {name} | {f['mean_us']:.3f} | {f['p50_us']:.3f} | {f['p99_us']:.3f} | "
                     f"{targets[name]} | {success} |")
    rows = _python_ik_comparison()
    lines += [
        "",
        f"IK from Python on the same {N_TARGETS} targets, in one process (times include the "
        "Python call; success = position within 0.1 mm, orientation within 1 mrad, inside the "
        "joint limits):",
        "",
        "| solver | success | mean (µs) | median (µs) | p99 (µs) | mean time ÷ a2l's "
        "| median position error (mm) |",
        "|---|---|---|---|---|---|---|",
    ]
    ours_mean = rows[0][2]
    for name, ok, mean, med, p99, err in rows:
        lines.append(f"| {name} | {ok:.1%} | {mean:.1f} | {med:.1f} | {p99:.1f} | "
                     f"{mean / ours_mean:.2f} | {err * 1e3:.3f} |")
    lines += [
        "",
        f"For reference, published figures (other machine, other targets, not measured "
        f"here): {PUBLISHED_IK['text']} Source: {PUBLISHED_IK['source']}.",
    ]
    return "\n".join(lines)
