"""Deep RL beside a2l on panda-gym's PandaPush-v3: TQC + HER with rl-baselines3-zoo's panda
hyperparameters, and ``a2l experiment panda-gym``, judged by the same evaluation (the
environment's own episodes from evaluation seed 1502, its ``is_success``, its 50 steps).

The seeds are those of a2l's published run (learning seeds 1002 and 1003, evaluation seed
1502; docs/gym.md): the a2l side is that run made again on this commit, the RL side learns
with the same seeds.

The RL side is resumable: each seed's run (``<dir>/tqc-<seed>/``) saves its model and its
replay buffer every :data:`CHUNK` env steps (a folder ``ckpt-<steps>/``, complete before
``progress.json`` names it: a run stopped while saving resumes from the one before) and, at every
budget reached, the model of that budget and its evaluation (``results.json``); a second call
continues from the last chunk saved (the episode under way is cut there, as SB3 does when it
loads a HER buffer: resumed training is not bitwise the one uninterrupted). The seeds run side
by side, one process each (one torch thread each); the CPU seconds of training are kept
beside the wall seconds, so that a run that shared its cores still reports its cost. The a2l
side is one ``a2l experiment panda-gym`` run per seed (``<dir>/a2l-<seed>/``, kept). The
extra ``a2l[rl]`` (torch on the CPU, stable-baselines3, sb3-contrib); never part of
``make test``.

Cost: one env step with the zoo's networks (3 x 512, two critics of 25 quantiles, batches of
2,048) takes 0.6-0.7 s of one core here (December 2026): 50,000 steps are about 9 hours of CPU
a seed, 100,000 about 18.

Standalone: ``python benchmarks/bench_rl.py [--budgets 10000,25000] [--seeds 1002,1003]
[--episodes 500] [--dir build/bench-rl]`` prints the section's Markdown; ``--worker SEED``
trains one seed only (what the section starts per seed).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

TITLE = "Deep RL beside a2l on panda-gym's PandaPush-v3 (TQC + HER, the same evaluation)"
PACKAGES = ("torch", "stable-baselines3", "sb3-contrib", "gymnasium", "panda-gym")

ENV_ID = "PandaPush-v3"
#: rl-baselines3-zoo's ``her-defaults`` of ``PandaPush-v1`` (hyperparams/tqc.yml), with its
#: ``env_wrapper`` (:func:`make_env`); the buffer holds every transition of the largest budget
#: (the zoo's 1e6 never fills before).
ZOO: dict[str, Any] = {
    "batch_size": 2048, "gamma": 0.95, "learning_rate": 1e-3, "tau": 0.05,
    "policy_kwargs": {"net_arch": [512, 512, 512], "n_critics": 2},
    "replay_buffer_kwargs": {"goal_selection_strategy": "future", "n_sampled_goal": 4},
}
BUDGETS = (10_000, 25_000, 50_000, 100_000)
SEEDS = (1002, 1003)
EVAL_SEED = 1502
#: Env steps between two saves of a run (model and replay buffer).
CHUNK = 1_000
EPISODES = 500
DIR = Path(__file__).resolve().parents[1] / "build" / "bench-rl"
#: The published figure, with its source.
PUBLISHED = ("TQC + HER on panda-gym v1's PandaPush after 1 M steps: mean sparse reward "
             "-6.4 +- 6.4 over 3,000 episodes, nearly every episode solved (source: "
             "rl-baselines3-zoo's benchmark table, row tqc PandaPush-v1: -6.405, 6.400, 1M, "
             "3000 episodes)")


def _write(path: Path, data: Any) -> None:
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=2))
    os.replace(tmp, path)


def make_env() -> Any:
    """``PandaPush-v3`` in the zoo's wrapper: the time left in the episode as one more
    feature of the observation (sb3-contrib's ``TimeFeatureWrapper``)."""
    import gymnasium
    import panda_gym  # noqa: F401 - registers the environment
    from sb3_contrib.common.wrappers import TimeFeatureWrapper

    return TimeFeatureWrapper(gymnasium.make(ENV_ID))


def evaluate_policy(model: Any, seeds: list[int]) -> dict[str, float]:
    """Success of `model`'s deterministic policy on the episodes reset with `seeds`, the
    median steps of an episode, and the evaluation's wall time."""
    import numpy as np

    env = make_env()
    t0, wins, steps = time.perf_counter(), 0, []
    for s in seeds:
        obs, info = env.reset(seed=s)
        done, n = False, 0
        while not done:
            action, _ = model.predict(obs, deterministic=True)
            obs, _r, term, trunc, info = env.step(action)
            done, n = term or trunc, n + 1
        wins += bool(info["is_success"])
        steps.append(n)
    env.close()
    return {"success": wins / len(seeds), "steps_per_episode": float(np.median(steps)),
            "eval_s": time.perf_counter() - t0}


def _load_or_start(d: Path, env: Any, seed: int, buffer_size: int) -> tuple[Any, dict]:
    """The run's model where it stopped (its last chunk) and its progress, or a new one."""
    from sb3_contrib import TQC
    from stable_baselines3 import HerReplayBuffer

    state = d / "progress.json"
    progress = json.loads(state.read_text()) if state.is_file() else {}
    if progress.get("checkpoint"):
        ckpt = d / progress["checkpoint"]
        model = TQC.load(ckpt / "model.zip", env=env, device="cpu")
        model.load_replay_buffer(ckpt / "replay.pkl")  # cuts the episode under way
        return model, progress
    model = TQC("MultiInputPolicy", env, buffer_size=buffer_size, seed=seed,
                replay_buffer_class=HerReplayBuffer, device="cpu", verbose=0, **ZOO)
    return model, {"env_steps": 0, "train_s": 0.0, "train_cpu_s": 0.0}


def _save_checkpoint(model: Any, d: Path) -> str:
    """Save `model` and its replay buffer into a new folder of `d`, whole before it is named
    (a run stopped while saving keeps its previous checkpoint); the folder's name."""
    name = f"ckpt-{int(model.num_timesteps)}"
    tmp = d / f"{name}.tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir()
    model.save(tmp / "model.zip")
    model.save_replay_buffer(tmp / "replay.pkl")
    shutil.rmtree(d / name, ignore_errors=True)
    os.replace(tmp, d / name)
    return name


def _drop_checkpoints(d: Path, keep: str) -> None:
    """Remove the checkpoints of `d` other than `keep` (the one ``progress.json`` names)."""
    for old in d.glob("ckpt-*"):
        if old.name != keep:
            shutil.rmtree(old, ignore_errors=True)


def train_seed(seed: int, budgets: tuple[int, ...], directory: Path, episodes: int) -> None:
    """TQC + HER for `seed` up to each budget, continuing from the last chunk saved."""
    import torch

    from a2l.experiments.panda_gym_eval import episode_seeds

    torch.set_num_threads(1)
    d = directory / f"tqc-{seed}"
    d.mkdir(parents=True, exist_ok=True)
    path = d / "results.json"
    results = json.loads(path.read_text()) if path.is_file() else {}
    if all(str(b) in results for b in budgets):
        return
    env = make_env()
    model, progress = _load_or_start(d, env, seed, max(budgets))
    seeds = episode_seeds(EVAL_SEED, episodes)
    for b in budgets:
        if str(b) in results:
            continue
        while model.num_timesteps < b:
            t0, c0 = time.perf_counter(), time.process_time()
            model.learn(min(CHUNK, b - model.num_timesteps), reset_num_timesteps=False)
            progress = {"env_steps": int(model.num_timesteps),
                        "train_s": progress["train_s"] + time.perf_counter() - t0,
                        "train_cpu_s": progress["train_cpu_s"] + time.process_time() - c0}
            progress["checkpoint"] = _save_checkpoint(model, d)
            _write(d / "progress.json", progress)
            _drop_checkpoints(d, keep=progress["checkpoint"])
        model.save(d / f"model_{b}.zip")
        results[str(b)] = {**progress, "episodes": episodes, **evaluate_policy(model, seeds)}
        _write(path, results)
        print(f"[bench rl] seed {seed}: {b:,} steps, success {results[str(b)]['success']:.1%}"
              f" ({progress['train_cpu_s']:.0f} s of CPU in training)", flush=True)


def a2l_runs(seeds: tuple[int, ...], directory: Path, episodes: int) -> dict[int, Any]:
    """``a2l experiment panda-gym`` per seed (kept: a finished run is read back)."""
    from a2l.experiments.panda_gym import PandaGymConfig, run_panda_gym

    out = {}
    for s in seeds:
        d = directory / f"a2l-{s}"
        if not (d / "metrics.json").is_file():
            run_panda_gym(PandaGymConfig(seed=s, eval_seed=EVAL_SEED, eval_episodes=episodes),
                          out=d, quiet=True)
        out[s] = json.loads((d / "metrics.json").read_text())
    return out


def plot(a2l: dict[int, Any], rl: dict[int, Any], path: Path) -> None:
    """Both curves on one plot: success against env steps, a2l's and RL's per seed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for s, m in a2l.items():
        ax.plot([p["env_steps"] for p in m["learning_curve"]],
                [100 * p["success"] for p in m["learning_curve"]], "o-", label=f"a2l, seed {s}")
    for s, r in rl.items():
        pts = sorted((v["env_steps"], 100 * v["success"]) for v in r.values())
        if pts:
            ax.plot(*zip(*pts, strict=True), "s--", label=f"TQC + HER, seed {s}")
    ax.axhline(90, color="grey", linestyle=":")
    ax.set_xscale("log")
    ax.set_xlabel("env steps of learning")
    ax.set_ylabel(f"success on {ENV_ID} (%)")
    ax.set_ylim(0, 100)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _steps_to(points: list[tuple[int, float]], target: float) -> int | None:
    return next((n for n, s in sorted(points) if s >= target), None)


def markdown(a2l: dict[int, Any], rl: dict[int, Any], figure: str | None) -> str:
    """The section: a2l's and RL's success per seed and budget, wall times, the ratio."""
    lines = [f"Evaluation: {EPISODES} episodes of `{ENV_ID}` reset from evaluation seed "
             f"{EVAL_SEED} (a2l: `a2l experiment panda-gym`, its curve on the first 100; RL: "
             "the deterministic policy), the environment's `is_success` and 50-step limit. "
             f"RL: TQC + HER with rl-baselines3-zoo's hyperparameters ({json.dumps(ZOO)}); "
             f"for scale, {PUBLISHED}.", "",
             "RL's learning CPU seconds are its process's (it may have shared its core); a2l's "
             "run comes after the RL runs, on cores of its own.", "",
             "| side | seed | env steps | success | episodes | learning wall (s) "
             "| learning CPU (s) |",
             "|---|---|---|---|---|---|---|"]
    for s, m in a2l.items():
        lines.append(f"| a2l | {s} | {m['env_steps_learning']:,} | {m['success_rate']:.1%} | "
                     f"{m['eval_episodes']} | {m['wall_s']['learning']:.0f} | – |")
    for s, r in rl.items():
        for b in sorted(r, key=int):
            v = r[b]
            lines.append(f"| TQC + HER | {s} | {v['env_steps']:,} | {v['success']:.1%} | "
                         f"{v['episodes']} | {v['train_s']:.0f} | {v['train_cpu_s']:.0f} |")
    for s in a2l:
        a = _steps_to([(p["env_steps"], p["success"]) for p in a2l[s]["learning_curve"]], 0.9)
        r = _steps_to([(v["env_steps"], v["success"]) for v in rl.get(s, {}).values()], 0.9)
        lines.append("")
        lines.append(f"Seed {s}: env steps to 90 % (a2l: on its curve's 100 episodes): a2l "
                     + (f"{a:,}" if a else "not reached") + ", RL "
                     + (f"{r:,}" if r else "not reached within the budgets run")
                     + (f" (ratio {r / a:.1f})" if a and r else "") + ".")
    if figure:
        lines += ["", f"![a2l and TQC + HER on {ENV_ID}]({figure})"]
    return "\n".join(lines) + "\n"


def run(budgets: tuple[int, ...] = BUDGETS, seeds: tuple[int, ...] = SEEDS,
        episodes: int = EPISODES, directory: Path = DIR) -> str:
    """The section: the RL seeds side by side (resumed where they stopped), then a2l."""
    directory.mkdir(parents=True, exist_ok=True)
    procs = [subprocess.Popen([sys.executable, __file__, "--worker", str(s), "--budgets",
                               ",".join(map(str, budgets)), "--episodes", str(episodes),
                               "--dir", str(directory)]) for s in seeds]
    if any(p.wait() for p in procs):
        raise RuntimeError("a TQC + HER run failed (its output is above)")
    rl = {s: json.loads((directory / f"tqc-{s}" / "results.json").read_text()) for s in seeds}
    a2l = a2l_runs(seeds, directory, episodes)
    fig = Path(__file__).resolve().parent / "sections" / "rl.png"
    fig.parent.mkdir(exist_ok=True)
    plot(a2l, rl, fig)
    return markdown(a2l, rl, "benchmarks/sections/rl.png")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--budgets", default=",".join(map(str, BUDGETS)))
    p.add_argument("--seeds", default=",".join(map(str, SEEDS)))
    p.add_argument("--episodes", type=int, default=EPISODES)
    p.add_argument("--dir", default=str(DIR))
    p.add_argument("--worker", type=int, default=None, help=argparse.SUPPRESS)
    a = p.parse_args()
    budgets = tuple(int(b) for b in a.budgets.split(","))
    if a.worker is not None:
        train_seed(a.worker, budgets, Path(a.dir), a.episodes)
        return
    print(run(budgets, tuple(int(s) for s in a.seeds.split(",")), a.episodes, Path(a.dir)))


if __name__ == "__main__":
    main()
