"""Perception error of the push scene's camera over random box positions on the table.

Places the box at 200 random spots (seeded), compares the OpenCV + depth estimate with
PyBullet's ground truth, prints the median and maximum error and writes a figure (a map
of the error over the table and its histogram).

Usage: ``python examples/perception_error.py [--n 200] [--seed 0]
[--out docs/perception_error.png]``
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from a2l.sim import make_scene  # noqa: E402
from a2l.sim.perception import perception_errors  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=200, help="random box positions")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs"
                                             / "perception_error.png"))
    args = parser.parse_args()
    with make_scene("push", seed=args.seed) as scene:
        positions, errors = perception_errors(scene, args.n, seed=args.seed)
        cfg = scene.config
        res = f"{cfg.camera_width}x{cfg.camera_height}"
    seen = ~np.isnan(errors).any(axis=1)
    err_mm = np.linalg.norm(errors[seen], axis=1) * 1000
    print(f"{seen.sum()}/{args.n} positions seen; error median {np.median(err_mm):.2f} mm, "
          f"p95 {np.percentile(err_mm, 95):.2f} mm, max {err_mm.max():.2f} mm")
    fig, (ax_map, ax_hist) = plt.subplots(1, 2, figsize=(10, 4.2),
                                          gridspec_kw={"width_ratios": [1.3, 1]})
    (cx, cy), (sx, sy) = cfg.table_center, cfg.table_size
    ax_map.add_patch(plt.Rectangle((cy - sy / 2, cx - sx / 2), sy, sx, fill=False, color="0.5"))
    sc = ax_map.scatter(positions[seen, 1], positions[seen, 0], c=err_mm, cmap="viridis", s=18)
    ax_map.quiver(positions[seen, 1], positions[seen, 0], errors[seen, 1], errors[seen, 0],
                  angles="xy", scale_units="xy", scale=0.05, width=0.003, color="k")
    ax_map.set_xlabel("y (m, robot's left)")
    ax_map.set_ylabel("x (m, forward)")
    ax_map.invert_xaxis()
    ax_map.set_aspect("equal")
    ax_map.set_title("box positions (arrows: planar error x20)")
    fig.colorbar(sc, ax=ax_map, label="error (mm)")
    ax_hist.hist(err_mm, bins=30, color="tab:blue")
    ax_hist.axvline(np.median(err_mm), color="k", ls="--",
                    label=f"median {np.median(err_mm):.2f} mm")
    ax_hist.axvline(err_mm.max(), color="tab:red", ls=":", label=f"max {err_mm.max():.2f} mm")
    ax_hist.set_xlabel("||perceived - true|| (mm)")
    ax_hist.set_ylabel("positions")
    ax_hist.legend()
    ax_hist.set_title(f"{seen.sum()} positions, {res} RGB-D camera")
    fig.suptitle("a2l.sim perception error (push scene, OpenCV segmentation + depth)")
    fig.tight_layout()
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
