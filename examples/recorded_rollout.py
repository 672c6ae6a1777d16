"""A recorded push rollout as a person sees it: record one, read the recording back, draw it.

Learns ``push_far`` from its scripted demonstrations, runs it on held-out trial seed
``--seed`` of the PyBullet push scene with a Rerun recording (``--rrd``, what ``a2l skill run
--record`` writes; ``a2l view`` opens it), then reads the recording back with Rerun's
dataframe API (:func:`a2l.rollout.recording.read_recording`) and draws what it holds: the
camera at the first and last steps, the arm's link frames and the end-effector path seen
from above with the box at every step, and over the steps the effect (the box's
displacement), the chosen movement and the context bins. Everything drawn comes from the
recording, not from the run in memory.

Usage: ``python examples/recorded_rollout.py [--seed 1000] [--rrd push_far.rrd]
[--out docs/recorded_rollout.png]``
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from a2l.lfd.library import learn_recipe, make_skill_scene, reset_for_trial  # noqa: E402
from a2l.rollout.effect_tests import PUSH_DISTANCE  # noqa: E402
from a2l.rollout.recording import (  # noqa: E402
    RerunRecorder,
    read_recording,
    record_run,
    scene_frame,
)
from a2l.rollout.run import run_skill  # noqa: E402
from a2l.skills.runner import CppSkillRunner  # noqa: E402

#: Baxter's right arm, base to gripper: the links drawn as a chain.
ARM = ("right_arm_mount", "right_upper_shoulder", "right_lower_shoulder", "right_upper_elbow",
       "right_lower_elbow", "right_upper_forearm", "right_lower_forearm", "right_wrist",
       "right_gripper_base_link", "right_gripper")
PRE = "/rollout/0"


def record(seed: int, rrd: Path) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        bundle = learn_recipe("push_far", tmp).bundle
        frames = []
        with make_skill_scene("push_far", seed=seed) as scene:
            reset_for_trial(scene, "push_far", seed)
            frames.append(scene_frame(scene))
            run = run_skill(scene, bundle, "far",
                            on_step=lambda k, st: frames.append(scene_frame(scene)))
        rec = RerunRecorder(rrd, name="push_far")
        record_run(rec, run, CppSkillRunner(bundle).skill, object_name="box", frames=frames)
        rec.close()
    print(f"{'success' if run.success else 'failure'}: stop {run.stop}, {run.movements} "
          f"movements; recording {rrd}")


def _points(cols: dict, entity: str) -> np.ndarray:
    rows = cols[entity]
    return np.array([r[0] if r else [np.nan] * 3 for r in rows], dtype=float)


def _scalars(cols: dict, entity: str) -> np.ndarray:
    return np.array([r[0] if r else np.nan for r in cols[f"{entity}:Scalars:scalars"]])


def _image(cols: dict, row: int) -> np.ndarray:
    fmt = cols[f"{PRE}/camera:Image:format"][row][0]
    buf = np.asarray(cols[f"{PRE}/camera:Image:buffer"][row][0], dtype=np.uint8)
    return buf.reshape(fmt["height"], fmt["width"], -1)


def draw(rrd: Path, out: Path) -> None:
    cols = read_recording(rrd)
    steps = np.asarray(cols["step"])
    eef = _points(cols, f"{PRE}/world/eef:Points3D:positions")
    box = _points(cols, f"{PRE}/world/objects/box:Boxes3D:centers")
    fig = plt.figure(figsize=(12, 7.6))
    grid = fig.add_gridspec(3, 3, height_ratios=(1, 1, 1), width_ratios=(1, 1, 1.1))
    for j, (row, name) in enumerate(((0, "first step"), (len(steps) - 1, "last step"))):
        ax = fig.add_subplot(grid[0 if j == 0 else 1, 0])
        ax.imshow(_image(cols, row))
        ax.set_title(f"camera, {name}", fontsize=9)
        ax.axis("off")
    ax = fig.add_subplot(grid[:, 1])
    for row, style in ((0, ":"), (len(steps) - 1, "-")):
        chain = np.array([cols[f"{PRE}/world/robot/{n}:Transform3D:translation"][row][0]
                          for n in ARM])
        ax.plot(chain[:, 1], chain[:, 0], style, color="0.45", marker="o", ms=3,
                label=f"arm links, step {steps[row]}")
    ax.scatter(box[:, 1], box[:, 0], c=steps, cmap="viridis", marker="s", s=90, alpha=0.35,
               label="box centre (colour: step)", zorder=2)
    ax.plot(eef[:, 1], eef[:, 0], "-o", color="tab:orange", ms=3, label="end-effector path",
            zorder=3)
    ax.set_xlabel("← left    y (m)")
    ax.set_ylabel("x (m), forward ↑")
    ax.invert_xaxis()  # +y (the robot's left) on the left, as seen from above
    ax.xaxis.set_major_locator(plt.MaxNLocator(4))  # tick labels apart
    ax.set_aspect("equal")
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title("from above (world frame)", fontsize=9)
    ax = fig.add_subplot(grid[0, 2])
    for axis in "xy":
        ax.plot(steps, _scalars(cols, f"{PRE}/effect/{axis}"), "-o", ms=3,
                label=f"box moved along {axis}")
    ax.axhline(PUSH_DISTANCE, color="k", lw=0.8, ls="--", label="push distance")
    ax.set_ylabel("m")
    ax.legend(fontsize=7)
    ax.set_title("effect over the steps", fontsize=9)
    ax = fig.add_subplot(grid[1, 2], sharex=ax)
    texts = [t[0] if t else "" for t in cols[f"{PRE}/movement:TextLog:text"]]
    ax.step(steps, _scalars(cols, f"{PRE}/movement_index"), where="mid", color="tab:green")
    for s, t in zip(steps, texts, strict=True):
        ax.annotate(t.split(": ")[-1] if t.startswith("ok") else t.split(":")[0],
                    (s, _scalars(cols, f"{PRE}/movement_index")[s]), fontsize=6,
                    rotation=60, xytext=(0, 4), textcoords="offset points")
    ax.set_ylabel("movement index")
    ax.set_title("chosen movement (label), stop status", fontsize=9, pad=14)
    ax = fig.add_subplot(grid[2, 2], sharex=ax)
    for name in ("distance", "orientation"):
        ax.step(steps, _scalars(cols, f"{PRE}/bins/{name}"), where="mid", label=name)
    ax.set_xlabel("step")
    ax.set_ylabel("bin")
    ax.legend(fontsize=7)
    ax.set_title("context bins", fontsize=9)
    fig.suptitle(f"push_far, read back from {rrd.name} (Rerun dataframe API)", fontsize=11)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"figure {out}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1000, help="held-out trial seed")
    ap.add_argument("--rrd", type=Path, default=Path("push_far.rrd"))
    ap.add_argument("--out", type=Path, default=Path("docs/recorded_rollout.png"))
    args = ap.parse_args()
    record(args.seed, args.rrd)
    draw(args.rrd, args.out)


if __name__ == "__main__":
    main()
