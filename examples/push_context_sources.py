"""A push run's final skill from its held-out starts, the context read from the camera and
from the simulator's ground truth, side by side.

The skill (``RUN/skills/push.a2lb``) runs from each of the run's held-out starts for each
effect (``FrameworkConfig.heldout_offsets``, the same starts for both sources), in closed
loop through the C++ step, as the push experiment's held-out evaluation does; only
``context_source`` differs. Each rollout is judged twice: as the loop saw it (the effect
the source read) and by the simulator's truth (the object's true displacement classified
by the same effect classifier). Prints one Markdown row per source.

Usage: ``python examples/push_context_sources.py RUN [--sources perceived,ground_truth]
[--bundle PATH]`` (another bundle of the run, e.g. an iteration's, than the final one)
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

import numpy as np

from a2l.framework import FrameworkConfig
from a2l.framework.scoring import FALSE_POSITIVE, SUCCESS, score_of
from a2l.framework.validation import ValidationTask, heldout_task
from a2l.progress import progress_bar
from a2l.rollout.env import scene_env


def evaluate(cfg: FrameworkConfig, bundle: Path, quiet: bool = False) -> dict[str, object]:
    """Held-out rollouts of `bundle` under `cfg`; the outcomes as seen and as true."""
    disc = cfg.discretization.discretizer()
    names = disc.effects.values
    env = scene_env(cfg)
    seen, true = [], []
    n_effects = cfg.discretization.n_effects
    pairs = [(s, e) for s in range(cfg.heldout.n_starts) for e in range(n_effects)]
    with progress_bar(f"held-out ({cfg.context_source})", len(pairs), quiet) as bar:
        for k, (s, e) in enumerate(pairs):
            r = heldout_task(ValidationTask(cfg, str(bundle), s, e))
            moved = np.asarray(env.scene.ground_truth()["objects"][env.obj_name]) - env.home
            effect = disc.effects.classify(moved)
            t = replace(r, outcome=(SUCCESS if effect == e else FALSE_POSITIVE if effect >= 0
                                    else "fail"))
            seen.append(r)
            true.append(t)
            if bar is not None:
                bar(k + 1)

    def rates(rs: list) -> dict[str, float]:
        return {names[e]: float(np.mean([r.outcome == SUCCESS for r in rs if r.wanted == e]))
                for e in range(n_effects)}

    return {
        "source": cfg.context_source,
        "seen_rate": float(np.mean([r.outcome == SUCCESS for r in seen])),
        "true_rate": float(np.mean([r.outcome == SUCCESS for r in true])),
        "true_per_effect": rates(true),
        "true_false_positives": sum(r.outcome == FALSE_POSITIVE for r in true),
        "seen_score": score_of(seen, n_effects, cfg.heldout.n_starts),
        "true_score": score_of(true, n_effects, cfg.heldout.n_starts),
        "disagree": sum(a.outcome != b.outcome for a, b in zip(seen, true, strict=True)),
        "stops": {k: sum(r.stop == k for r in seen) for k in sorted({r.stop for r in seen})},
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a push experiment's run directory")
    parser.add_argument("--sources", default="perceived,ground_truth")
    parser.add_argument("--bundle", type=Path, default=None,
                        help="the skill to run (default RUN/skills/push.a2lb)")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args()
    config = json.loads((args.run / "config.json").read_text())
    base = FrameworkConfig.from_dict(config["framework"])
    bundle = args.bundle or args.run / "skills" / "push.a2lb"
    print(f"run {args.run}, skill {bundle} (trained with context {base.context_source}, "
          f"seed {base.seed}), "
          f"{base.heldout.n_starts} held-out starts x {base.discretization.n_effects} effects")
    print("| context at run time | success rate (truth) | per effect (truth) | false positives "
          "(truth) | score (truth) | success rate as the loop saw it | rollouts judged "
          "differently | stops |")
    print("|---|---|---|---|---|---|---|---|")
    for src in args.sources.split(","):
        cfg = base.with_(context_source=src, scene_config={
            k: v for k, v in base.scene_config.items() if k not in ("source", "context_source")})
        m = evaluate(cfg, bundle, args.quiet)
        per = ", ".join(f"{k} {v:.0%}" for k, v in m["true_per_effect"].items())
        label = "camera" if src == "perceived" else "ground truth"
        print(f"| {label} | {m['true_rate']:.1%} | {per} | {m['true_false_positives']} | "
              f"{m['true_score']:.1f} | {m['seen_rate']:.1%} | {m['disagree']} | "
              f"{', '.join(f'{k} {v}' for k, v in m['stops'].items())} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
