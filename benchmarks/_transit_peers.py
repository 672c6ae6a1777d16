"""Transit against the peers: a2l, mplib and pybullet-planning on the same Baxter pairs.

The method, fixed before any result was seen:

- Scene: the ``task`` scene (table, block, button with its cap, lamp, box, floor), every
  object the axis-aligned box :meth:`obstacle_boxes` gives; Baxter's right arm moves, the rest
  of the robot stays at the scene's pose.
- Pairs: gripper-down configurations 3-25 cm above a point within 12 cm of an object (IK from
  randomised seeds), collision-free for a2l (2 cm padding) and for the common checker. The
  first ``N_ORDINARY`` pairs as they come ("ordinary"); then up to ``N_HARD`` pairs whose
  straight joint-space line collides under the common checker ("hard"), among at most
  ``HARD_DRAWS`` pairs drawn for them (shortened after the first full runs: such lines are
  rare, ~0.1-0.3 % of pairs, and drawing 20 did not end in an hour on the shared machine).
- Each planner: 2 s time limit, its defaults otherwise, one process for all its calls, the
  planner built once (set-up not timed). Time: wall time of the planning call; also its CPU
  time (the calling thread's), which load on a shared machine inflates far less.
- Common checker: PyBullet (not the code of any planner), Baxter's URDF with its meshes as
  PyBullet's convex hulls, the boxes unpadded; every returned path interpolated every
  0.005 rad (largest joint step) and each state tested for penetration (contact distance < 0)
  between an arm link and a box or another robot link, except parent/child links and the
  pairs already in contact at the neutral pose.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

SEED = 0
N_ORDINARY = 60
N_HARD = 20
HARD_DRAWS = 1500  # pairs drawn at most to find the N_HARD hard ones
TIME_LIMIT = 2.0
DENSE_STEP = 0.005  # rad: largest joint step between checked states of a returned path
HERE = Path(__file__).resolve().parent


@dataclass
class Outcome:
    """One planner on one pair."""

    ok: bool
    time_ms: float
    cpu_ms: float = float("nan")  # CPU time of the calling thread
    length: float = float("nan")  # rad, joint-space polyline
    colliding: bool = False  # the dense check found a penetrating state
    status: str = ""


@dataclass
class Problem:
    """What every planner is given."""

    urdf: str
    arm_joints: list[str]
    other_joints: dict[str, float]
    boxes: list[tuple[str, list[float], list[float]]]
    neutral: np.ndarray
    ordinary: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)
    hard: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)

    @property
    def pairs(self) -> list[tuple[np.ndarray, np.ndarray]]:
        return self.ordinary + self.hard


class DenseChecker:
    """The common checker: PyBullet, exact boxes, every 0.005 rad along a path."""

    def __init__(self, pb: Problem) -> None:
        import pybullet as p

        self.p = p
        self.cid = p.connect(p.DIRECT)
        self.robot = p.loadURDF(pb.urdf, useFixedBase=True, physicsClientId=self.cid,
                                flags=p.URDF_USE_SELF_COLLISION)
        c = self.cid
        names = {p.getJointInfo(self.robot, j, physicsClientId=c)[1].decode(): j
                 for j in range(p.getNumJoints(self.robot, physicsClientId=c))}
        self.joints = [names[n] for n in pb.arm_joints]
        for n, v in pb.other_joints.items():
            p.resetJointState(self.robot, names[n], v, physicsClientId=c)
        self.boxes = []
        for _, centre, half in pb.boxes:
            shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=c)
            self.boxes.append(p.createMultiBody(0, shape, basePosition=centre,
                                                physicsClientId=c))
        self.moving = self._moving_links()
        self.allowed = {frozenset((a, b)) for a, b in self._self_contacts(pb.neutral)}
        self.states = 0

    def _moving_links(self) -> set[int]:
        p, c = self.p, self.cid
        moving: set[int] = set()
        for link in range(p.getNumJoints(self.robot, physicsClientId=c)):
            j = link
            while j >= 0:
                if j in self.joints:
                    moving.add(link)
                    break
                j = p.getJointInfo(self.robot, j, physicsClientId=c)[16]
        return moving

    def _set(self, q: np.ndarray) -> None:
        for j, v in zip(self.joints, q, strict=True):
            self.p.resetJointState(self.robot, j, float(v), physicsClientId=self.cid)

    def _self_contacts(self, q: np.ndarray) -> list[tuple[int, int]]:
        self._set(q)
        self.p.performCollisionDetection(physicsClientId=self.cid)
        return [(cp[3], cp[4]) for cp in self.p.getContactPoints(
            self.robot, self.robot, physicsClientId=self.cid) if cp[8] < 0]

    def collides(self, q: np.ndarray) -> bool:
        """True if the arm at `q` (7,) penetrates a box or a robot link it may not touch."""
        p, c = self.p, self.cid
        self.states += 1
        self._set(q)
        p.performCollisionDetection(physicsClientId=c)
        for cp in p.getContactPoints(self.robot, physicsClientId=c):
            if cp[8] >= 0:
                continue
            if cp[2] != self.robot:  # a box
                if cp[3] in self.moving:
                    return True
                continue
            a, b = cp[3], cp[4]
            if (a in self.moving or b in self.moving) and frozenset((a, b)) not in self.allowed:
                return True
        return False

    def path_collides(self, waypoints: np.ndarray) -> bool:
        """True if a state of the polyline `waypoints` (m, 7), every DENSE_STEP, collides."""
        w = np.asarray(waypoints, dtype=float)
        if self.collides(w[0]):
            return True
        for a, b in zip(w[:-1], w[1:], strict=True):
            k = max(1, int(np.ceil(np.max(np.abs(b - a)) / DENSE_STEP)))
            for s in np.arange(1, k + 1) / k:
                if self.collides(a + s * (b - a)):
                    return True
        return False

    def close(self) -> None:
        self.p.disconnect(physicsClientId=self.cid)


def path_length(waypoints: np.ndarray) -> float:
    """Summed joint-space length (rad) of a polyline (m, n)."""
    w = np.asarray(waypoints, dtype=float)
    return float(np.sum(np.linalg.norm(np.diff(w, axis=0), axis=1))) if len(w) > 1 else 0.0


def make_problem() -> Problem:
    """The scene, the arm and the pairs (seeded: SEED)."""
    import a2l
    from a2l.planning.transit import ArmTransit
    from a2l.robot import arm_spec, pybullet_urdf
    from a2l.sim import make_scene

    rng = np.random.default_rng(SEED)
    spec = arm_spec("baxter", "right")
    transit = ArmTransit("baxter", "right")
    with make_scene("task", seed=SEED) as scene:
        transit.sync(scene)
        boxes = [(n, [float(x) for x in c], [float(x) for x in h])
                 for n, c, h in scene.obstacle_boxes()]
        pb = Problem(str(pybullet_urdf(spec.urdf)), list(transit.joint_names),
                     scene.other_joint_positions(), boxes,
                     np.asarray(scene.neutral_joint_positions, dtype=float))
        objects = [(c, h) for n, c, h in boxes if n not in ("floor", "table")]
        kin, neutral = scene.kinematics, pb.neutral
        checker = DenseChecker(pb)

        def config() -> np.ndarray:
            while True:
                c, h = objects[int(rng.integers(len(objects)))]
                xy = np.asarray(c[:2]) + rng.uniform(-0.12, 0.12, 2)
                z = c[2] + h[2] + rng.uniform(0.03, 0.25)
                seed_q = neutral + rng.normal(0.0, 0.4, neutral.shape)
                q, rep = kin.ik_report(scene.gripper_down_pose((xy[0], xy[1], z)), seed_q)
                if (rep.status == a2l.Status.ok and not transit.in_collision(q)
                        and not checker.collides(q)):
                    return np.asarray(q, dtype=float)

        cache = _pairs_cache(pb)
        if not _load_pairs(pb, cache, transit, checker):
            while len(pb.ordinary) < N_ORDINARY:
                pb.ordinary.append((config(), config()))
            for _ in range(HARD_DRAWS):
                a, b = config(), config()
                if checker.path_collides(np.stack([a, b])):
                    pb.hard.append((a, b))
                if len(pb.hard) == N_HARD:
                    break
            _save_pairs(pb, cache)
        checker.close()
    return pb


def _pairs_cache(pb: Problem) -> Path:
    """The file the pairs of `pb`'s scene are kept in (drawing them takes minutes): named by a
    hash of what they are drawn from (seed, counts, URDF, joints, boxes, the source of
    make_problem and of the common checker)."""
    import hashlib
    import inspect

    h = hashlib.sha256(Path(pb.urdf).read_bytes())
    h.update((inspect.getsource(make_problem) + inspect.getsource(DenseChecker)).encode())
    h.update(json.dumps([SEED, N_ORDINARY, N_HARD, HARD_DRAWS, pb.arm_joints, pb.other_joints,
                         pb.boxes, pb.neutral.tolist()], sort_keys=True).encode())
    return HERE.parent / "build" / "bench-cache" / f"transit-pairs-{h.hexdigest()[:16]}.npz"


def _load_pairs(pb: Problem, path: Path, transit: Any, checker: DenseChecker) -> bool:
    """Fill `pb`'s pairs from `path` if it holds pairs that still meet the method (every
    configuration free for a2l and for the common checker, every hard pair's straight line
    colliding); False if not (then they are drawn again)."""
    if not path.is_file():
        return False
    with np.load(path) as f:
        ordinary, hard = f["ordinary"], f["hard"]
    if ordinary.shape != (N_ORDINARY, 2, len(pb.arm_joints)) or len(hard) > N_HARD:
        return False
    configs = np.concatenate([ordinary, hard]).reshape(-1, len(pb.arm_joints))
    if any(transit.in_collision(q) or checker.collides(q) for q in configs):
        return False
    if not all(checker.path_collides(pair) for pair in hard):
        return False
    pb.ordinary = [(a, b) for a, b in ordinary]
    pb.hard = [(a, b) for a, b in hard]
    return True


def _save_pairs(pb: Problem, path: Path) -> None:
    import io

    from a2l.atomic import atomic_write_bytes

    buf = io.BytesIO()
    n = len(pb.arm_joints)
    np.savez(buf, ordinary=np.array(pb.ordinary).reshape(-1, 2, n),
             hard=np.array(pb.hard).reshape(-1, 2, n))
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(path, buf.getvalue())


def run_a2l(pb: Problem, pairwise: bool = True,
            **options: object) -> list[tuple[np.ndarray | None, Outcome]]:
    """a2l's ArmTransit (its defaults; `pairwise`: its collision checks pair by pair or by
    Bullet's world pass; `options` set fields of its TransitOptions)."""
    from a2l.planning.transit import ArmTransit

    transit = ArmTransit("baxter", "right", time_limit=TIME_LIMIT)
    transit.planner.set_pairwise(pairwise)
    for k, v in options.items():
        setattr(transit.options, k, v)
    transit.set_robot_joints(pb.other_joints)
    transit.set_obstacles([(n, c, h) for n, c, h in pb.boxes])
    out = []
    for i, (a, b) in enumerate(pb.pairs):
        t, c = time.perf_counter(), time.thread_time()
        r = transit.plan(a, b, seed=SEED + i)
        ms, cpu = (time.perf_counter() - t) * 1000, (time.thread_time() - c) * 1000
        out.append((r.waypoints if r.ok else None, Outcome(r.ok, ms, cpu, status=r.status)))
    return out


def run_pybullet_planning(pb: Problem) -> list[tuple[np.ndarray | None, Outcome]]:
    """pybullet-planning's plan_joint_motion (BiRRT + smoothing) with its defaults."""
    import pybullet as p
    import pybullet_planning as pp

    np.random.seed(SEED)  # noqa: NPY002 (pybullet-planning samples from numpy's global state)
    import random

    random.seed(SEED)
    checker = DenseChecker(pb)  # a world of its own: robot and boxes as the checker sees them
    pp.set_client(checker.cid)
    robot, joints = checker.robot, checker.joints
    disabled = {tuple(sorted(pair)) for pair in checker.allowed if len(pair) == 2}
    disabled |= {(b, a) for a, b in disabled}
    out = []
    for a, b in pb.pairs:
        for j, v in zip(joints, a, strict=True):
            p.resetJointState(robot, j, float(v), physicsClientId=checker.cid)
        t, c = time.perf_counter(), time.thread_time()
        path = pp.plan_joint_motion(robot, joints, list(b), obstacles=checker.boxes,
                                    self_collisions=True, disabled_collisions=disabled,
                                    max_time=TIME_LIMIT)
        ms, cpu = (time.perf_counter() - t) * 1000, (time.thread_time() - c) * 1000
        ok = path is not None
        out.append((np.asarray(path) if ok else None,
                    Outcome(ok, ms, cpu, status="ok" if ok else "no_path")))
    checker.close()
    pp.set_client(0)
    return out


def mplib_python() -> str | None:
    """The Python of mplib's environment (``$A2L_MPLIB_PYTHON``), or None."""
    py = os.environ.get("A2L_MPLIB_PYTHON", "")
    return py if py and Path(py).is_file() else None


def _mplib_urdf(urdf: str, tmp: str) -> str:
    """A copy of `urdf` whose mesh paths are relative to `tmp` (mplib joins absolute mesh
    paths to the URDF's directory)."""
    text = Path(urdf).read_text()
    text = re.sub(r'filename="(/[^"]+)"',
                  lambda m: f'filename="{os.path.relpath(m.group(1), tmp)}"', text)
    out = Path(tmp) / "baxter.urdf"
    out.write_text(text)
    return str(out)


def run_mplib(pb: Problem) -> tuple[list[tuple[np.ndarray | None, Outcome]], str]:
    """mplib's OMPL planner, in its own environment (a child process). Returns the outcomes
    and mplib's version."""
    py = mplib_python()
    if py is None:
        raise RuntimeError("no mplib environment: set A2L_MPLIB_PYTHON (make bench does)")
    with tempfile.TemporaryDirectory() as tmp:
        problem = {
            "urdf": _mplib_urdf(pb.urdf, tmp), "move_group": "right_gripper",
            "arm_joints": pb.arm_joints, "other_joints": pb.other_joints, "boxes": pb.boxes,
            "pairs": [[a.tolist(), b.tolist()] for a, b in pb.pairs],
            "time_limit": TIME_LIMIT, "neutral": pb.neutral.tolist(),
        }
        src, dst = Path(tmp) / "problem.json", Path(tmp) / "result.json"
        src.write_text(json.dumps(problem))
        subprocess.run([py, str(HERE / "_mplib_child.py"), str(src), str(dst)], check=True,
                       cwd=tmp, stdout=subprocess.DEVNULL)
        res = json.loads(dst.read_text())
    out = [(np.asarray(r["waypoints"]) if r["ok"] else None,
            Outcome(r["ok"], r["time_s"] * 1000, r.get("cpu_s", float("nan")) * 1000,
                    status=r["status"]))
           for r in res["results"]]
    return out, res["version"]


def validate(pb: Problem, runs: dict[str, list[tuple[np.ndarray | None, Outcome]]]) -> None:
    """Dense-check every returned path with the common checker; fill length and colliding.
    A path that does not start at the pair's start or end at its goal counts as colliding."""
    checker = DenseChecker(pb)
    for results in runs.values():
        for (a, b), (w, o) in zip(pb.pairs, results, strict=True):
            if w is None or not o.ok:
                continue
            ends = np.allclose(w[0], a, atol=1e-6) and np.allclose(w[-1], b, atol=1e-6)
            o.length = path_length(w)
            o.colliding = not ends or checker.path_collides(w)
    checker.close()


def _row(name: str, outs: list[Outcome], ref: dict[str, float] | None) -> str:
    t = np.array([o.time_ms for o in outs])
    ok = [o for o in outs if o.ok]
    med, p95 = float(np.median(t)), float(np.percentile(t, 95))
    length = float(np.median([o.length for o in ok])) if ok else float("nan")
    coll = sum(o.colliding for o in ok)
    ratio = (f"{med / ref['med']:.2f} / {p95 / ref['p95']:.2f}" if ref else "1 / 1")
    cpu = np.array([o.cpu_ms for o in outs])
    return (f"| {name} | {len(ok)}/{len(outs)} | {med:.1f} | {p95:.1f} | {ratio} | "
            f"{np.median(cpu):.1f} / {np.percentile(cpu, 95):.1f} | {length:.2f} | {coll} |")


def table(pb: Problem, runs: dict[str, list[tuple[np.ndarray | None, Outcome]]],
          reference: str) -> str:
    """Markdown: per pair group, one row per planner; ratios against `reference`."""
    groups = {f"all {len(pb.pairs)} pairs": slice(0, len(pb.pairs)),
              f"{len(pb.ordinary)} ordinary pairs": slice(0, len(pb.ordinary)),
              f"{len(pb.hard)} hard pairs (straight line collides)":
                  slice(len(pb.ordinary), len(pb.pairs))}
    lines = ["| pairs | planner | success | median ms | p95 ms | median / p95 vs "
             f"{reference} | CPU ms median / p95 | path length rad (median) | "
             "paths colliding (dense check) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for gname, sl in groups.items():
        if sl.stop == sl.start:
            continue
        ref_t = np.array([o.time_ms for _, o in runs[reference][sl]])
        ref = {"med": float(np.median(ref_t)), "p95": float(np.percentile(ref_t, 95))}
        for name, results in runs.items():
            outs = [o for _, o in results[sl]]
            row = _row(name, outs, None if name == reference else ref)
            lines.append(f"| {gname} " + row)
    return "\n".join(lines)


def run_all(baselines: dict[str, dict[str, object]] | None = None) -> str:
    """Every planner on the pairs, validated; the Markdown of the comparison. `baselines`:
    extra a2l rows, name -> keyword arguments of :func:`run_a2l` (e.g. the settings before a
    change)."""
    import importlib.metadata as md

    t0, load0 = time.perf_counter(), os.getloadavg()[0]
    pb = make_problem()
    runs: dict[str, list[tuple[np.ndarray | None, Outcome]]] = {}
    runs["a2l"] = run_a2l(pb)
    for name, opts in (baselines or {}).items():
        runs[name] = run_a2l(pb, **opts)
    versions = [f"pybullet-planning {md.version('pybullet_planning')}"]
    runs["pybullet-planning"] = run_pybullet_planning(pb)
    if mplib_python():
        runs["mplib"], v = run_mplib(pb)
        versions.append(f"mplib {v} (own environment, numpy < 2)")
    else:
        versions.append("mplib not run (no A2L_MPLIB_PYTHON)")
    validate(pb, runs)
    load = os.getloadavg()[0]
    fails = {n: sorted({o.status for _, o in r if not o.ok}) for n, r in runs.items()}
    fails_txt = "; ".join(f"{n}: {', '.join(s)}" for n, s in fails.items() if s)
    return (
        "Baxter's right arm in the `task` scene (table, block, button and cap, lamp, box, "
        "floor as boxes), gripper-down start/goal pairs 3-25 cm above points within 12 cm "
        f"of the objects, seed {SEED}: {len(pb.ordinary)} pairs as drawn and the "
        f"{len(pb.hard)} pairs whose straight joint-space line collides found among "
        f"{HARD_DRAWS} more pairs drawn (at most {N_HARD} were sought). Each planner: 2 s "
        "limit, its own defaults, built once; time = wall time of the planning call, and "
        "the CPU time of the calling thread (a2l: `ArmTransit.plan`, "
        "time parameterisation included; mplib: the OMPL call `Planner.plan_qpos` makes, "
        "simplification included, TOPP not; pybullet-planning: `plan_joint_motion`, BiRRT + "
        "smoothing). Every returned path is then checked by one common checker (PyBullet, "
        f"boxes unpadded, a state every {DENSE_STEP} rad, penetration = collision; "
        "parent/child links and pairs in contact at the neutral pose ignored). Versions: "
        f"{', '.join(versions)}. Load average at the start: {load0:.1f}, at the end: "
        f"{load:.1f} (2 cores shared; wall times are inflated by it, CPU times much less); "
        f"the whole comparison took {time.perf_counter() - t0:.0f} s.\n\n"
        + table(pb, runs, "a2l")
        + (f"\n\nFailure statuses: {fails_txt}." if fails_txt else "")
    )


#: The a2l settings before the transit was made faster (from 81b1535 on), kept as baseline rows:
#: Bullet's world pass for every check, 20 rounds of 10 shortcut attempts without stopping,
#: every motion checked at 0.01 rad; then pairwise checks with shortcutting that stops
#: (81b1535), still at one resolution.
BEFORE = {"a2l before (world pass, 200 shortcuts, one resolution)":
          {"pairwise": False, "shortcut_rounds": 20, "shortcut_patience": 0,
           "coarse_resolution": 0.0},
          "a2l pairwise, one resolution (81b1535)": {"coarse_resolution": 0.0}}

if __name__ == "__main__":
    print(run_all(BEFORE))
    sys.exit(0)
