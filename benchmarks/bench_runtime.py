"""Skill runtime: C++ step(), table lookup, a whole control tick with differential IK, and
a2l-run's closed loop in the virtual and Bullet scenes, on push skills learned here."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

from a2l.framework.parts import SkillConfig
from a2l.robot import robots_dir
from a2l.skills import (
    Discretizer,
    MovementRepertoire,
    compile_policy,
    learn_network,
    make_skill_spec,
    push_dataset,
    save_bundle,
)

TITLE = "Skill runtime (C++ step, control tick with differential IK, a2l-run closed loop)"
RADIUS = 0.19  # start circle of the data and the runs (see tests/python/test_runtime_a2l_run.py)
EPISODES = 16


def _bin_dir() -> Path:
    return Path(os.environ.get("A2L_BENCH_BIN", "build/cpp"))


def _a2l_run() -> str:
    local = _bin_dir() / "a2l-run"
    if local.is_file():
        return str(local)
    return shutil.which("a2l-run") or str(Path(sys.executable).parent / "a2l-run")


def _bundles(tmp: Path) -> dict[str, tuple[Path, str]]:
    """Learned push skills: the planar one a2l-run runs, the same with the push framework's
    step rules (clearance, alignment, revisits: what its exported skills run with), and a
    3-D one (26 movements)."""
    out = {}
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    net = learn_network(disc.discretize(push_dataset(5000, seed=0, radius=RADIUS)), "hc-k2")
    spec = make_skill_spec(compile_policy(net, "move", disc.evidence), disc, name="push")
    out["planar"] = (save_bundle(spec, tmp / "planar.a2lb"), _describe(spec))
    rules = SkillConfig()  # the framework's defaults
    ruled = replace(spec, clearance=rules.clearance, clearance_ratio=rules.clearance_ratio,
                    align=rules.align, avoid_revisits=rules.avoid_revisits)
    out["planar, rules"] = (
        save_bundle(ruled, tmp / "planar_rules.a2lb"),
        f"the planar skill with the push framework's step rules (clearance {rules.clearance} m, "
        f"bar {rules.clearance_ratio}, alignment {rules.align} m, revisit rule)")
    disc3 = Discretizer()
    net3 = learn_network(disc3.discretize(push_dataset(5000, seed=1, radius=RADIUS)), "hand-coded")
    spec3 = make_skill_spec(compile_policy(net3, "move", disc3.evidence), disc3, name="push3d")
    out["3-D"] = (save_bundle(spec3, tmp / "push3d.a2lb"), _describe(spec3))
    return out


def _describe(spec) -> str:
    axes = " x ".join(f"{v.name} {v.n_bins}" for v in spec.variables)
    return f"{axes} -> {spec.posterior.shape[-1]} movements ({spec.argmax.size} rows)"


def _bench(bundle: Path, pattern: str) -> dict[str, dict]:
    out = subprocess.run(
        [
            str(_bin_dir() / "bench_skill"),
            str(bundle),
            str(robots_dir()),
            "--benchmark_format=json",
            f"--benchmark_filter={pattern}",
        ],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return {b["name"].split("/")[0].removeprefix("BM_"): b for b in json.loads(out)["benchmarks"]}


def _run(bundle: Path, *args: str, episodes: int = EPISODES, circle: bool = True) -> dict:
    """a2l-run's summary; starts on the data's circle (`--starts circle`), or a2l-run's
    default random starts (seed 0) when `circle` is false."""
    starts = ["--starts", "circle", "--radius", str(RADIUS)] if circle else []
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        subprocess.run(
            [
                _a2l_run(),
                str(bundle),
                "--episodes",
                str(episodes),
                *starts,
                "--quiet",
                "--summary",
                f.name,
                *args,
            ],
            capture_output=True,
            text=True,
            check=True,
            env=dict(os.environ, A2L_ROBOTS_DIR=str(robots_dir())),
        )
        return json.loads(Path(f.name).read_text())


def _manipulation_bundles(tmp: Path) -> dict[str, Path]:
    """grasp and press learned from scripted demonstrations (a2l.lfd: the compiled table and
    one DS phase per behaviour)."""
    from a2l.lfd.library import learn_recipe

    return {name: learn_recipe(name, tmp).bundle for name in ("grasp", "press")}


def skill_kinds(episodes: int = 64) -> str:
    """a2l-run steps per second per skill kind (push, grasp, press) and mode (table, ds)."""
    rows = []
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        bundles = {"push": _bundles(tmp)["planar"][0], **_manipulation_bundles(tmp)}
        for kind, bundle in bundles.items():
            for mode in ("table", "ds") if kind != "push" else ("table",):
                for robot in ((), ("--no-robot",)):
                    s = _run(bundle, "--mode", mode, *robot, episodes=episodes,
                             circle=kind == "push")
                    st = s["step_time"]
                    rows.append(
                        f"| {kind} | {mode} | {'Baxter IK' if not robot else 'none'} | "
                        f"{s['success']}/{s['episodes']} | {s['skill_steps']:,} | "
                        f"{s['steps_per_s']:,.0f} | {st['p50_us']:.2f} / {st['p99.9_us']:.2f} us |"
                    )
    return "\n".join([
        f"`a2l-run` per skill kind and mode (`--mode table`: the compiled table's `step()`; "
        f"`--mode ds`: the DS phases' `step_ds()`), virtual scene (push; grasp and press "
        f"semantics, docs/virtual_scene.md), as fast as possible, {episodes} episodes per "
        "effect; push: the planar skill above from its data's circle; grasp and press: learned "
        "from scripted demonstrations (`a2l.lfd.library.learn_recipe`, seed 0: the table and "
        "one DS phase per behaviour), random starts 0.02-0.10 m beside and 0.15 m above the "
        "object (seed 0). Steps/s include the scene and, with the robot, every control tick "
        "of differential IK.",
        "",
        "| skill | mode | robot | success | skill steps | skill steps/s | `step` p50 / p99.9 |",
        "|---|---|---|---|---|---|---|",
        *rows,
    ])


def _ns(b: dict) -> float:
    return b["real_time"] * {"ns": 1.0, "us": 1e3, "ms": 1e6}[b["time_unit"]]


def run() -> str:
    with tempfile.TemporaryDirectory() as d:
        bundles = _bundles(Path(d))
        planar = bundles["planar"][0]
        micro = {
            name: _bench(path, "table_lookup|discretize|step")
            for name, (path, _) in bundles.items()
        }
        rest = _bench(planar, "clock|executor|control|move|load")
        runs = {
            "virtual, Baxter IK": _run(planar, "--scene", "virtual"),
            "virtual, no robot": _run(planar, "--scene", "virtual", "--no-robot"),
            "bullet, Baxter IK": _run(planar, "--scene", "bullet"),
            "bullet, no robot": _run(planar, "--scene", "bullet", "--no-robot"),
            "virtual, Baxter IK, random starts": _run(planar, "--scene", "virtual", circle=False),
        }
        realtime = _run(
            planar, "--scene", "virtual", "--rate", "1000", "--effect", "far,left", episodes=2
        )

    lines = [
        "Skills learned here from synthetic push babbling (`push_dataset`, start circle "
        f"{RADIUS} m): **planar** = hill-climbing + K2, {bundles['planar'][1]}; "
        f"**planar, rules** = {bundles['planar, rules'][1]}; **3-D** = "
        f"hand-coded structure, {bundles['3-D'][1]}. Google Benchmark (`bench_skill`): mean "
        "per call over contexts on a 0.25 m disc around the box (most of them known); the "
        "*latency* rows time every call of 10^6 with `steady_clock` (its own cost, "
        f"p50 {rest['clock_latency']['p50_ns']:.0f} ns, is included).",
        "",
        "| C++ call | skill | mean | p50 | p99 | p99.9 | target |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, m in micro.items():
        lines.append(
            f"| table lookup (bins -> argmax) | {name} | {_ns(m['table_lookup']):.1f} ns | | | | |"
        )
        lines.append(
            f"| discretize (context -> bins) | {name} | {_ns(m['discretize']):.0f} ns | | | | |"
        )
        lat = m["step_latency"]
        lines.append(
            f"| `step()` context -> movement | {name} | {_ns(m['step']):.0f} ns | "
            f"{lat['p50_ns']:.0f} ns | {lat['p99_ns']:.0f} ns | {lat['p999_ns']:.0f} ns | "
            "median <= 2 us, p99.9 <= 10 us |"
        )
        lat = m["step_smoothing_latency"]
        lines.append(
            f"| `step()` with neighbour smoothing | {name} | {_ns(m['step_smoothing']):.0f} ns | "
            f"{lat['p50_ns']:.0f} ns | {lat['p99_ns']:.0f} ns | {lat['p999_ns']:.0f} ns | |"
        )
    t, lt = rest["executor_tick"], rest["executor_tick_latency"]
    lines.append(
        f"| executor tick (Baxter FK + Jacobian, 6x6 DLS IK, limit checks) | planar | "
        f"{_ns(t):.0f} ns | {lt['p50_ns']:.0f} ns | {lt['p99_ns']:.0f} ns | "
        f"{lt['p999_ns']:.0f} ns | |"
    )
    t, lt = rest["control_tick"], rest["control_tick_latency"]
    lines.append(
        f"| whole control tick: `step()` + new target + first joint command | planar | "
        f"{_ns(t):.0f} ns | {lt['p50_ns']:.0f} ns | {lt['p99_ns']:.0f} ns | "
        f"{lt['p999_ns']:.0f} ns | median <= 10 us, p99.9 <= 30 us |"
    )
    lines.append(f"| virtual scene `move` | | {_ns(rest['virtual_move']):.1f} ns | | | | |")
    if "bullet_move" in rest:
        lines.append(
            f"| Bullet scene `move` (5 cm at 0.25 m/s, 1/240 s steps, settling) | | "
            f"{_ns(rest['bullet_move']) / 1e3:.0f} us | | | | |"
        )
    lines.append(
        f"| load + validate the bundle ({rest['load_bundle']['bytes'] / 1024:.0f} KiB) | planar |"
        f" {_ns(rest['load_bundle']) / 1e3:.0f} us | | | | |"
    )
    per_step = [s["control_ticks"] / s["skill_steps"] for s in runs.values()
                if s["control_ticks"] and s["skill_steps"]]
    span = (f"{min(per_step):.0f}" if per_step and f"{min(per_step):.0f}" == f"{max(per_step):.0f}"
            else f"{min(per_step, default=0):.0f} to {max(per_step, default=0):.0f}")
    ticks_per_step = (f"{span} control ticks per skill step in the robot runs below"
                      if per_step else "no robot run")
    lines += [
        "",
        f"`a2l-run` closed loop, as fast as possible, {EPISODES} start points x 4 effects, "
        "planar skill. With the robot every movement (5 cm) is executed as joint commands at "
        f"1 kHz and 0.25 m/s ({ticks_per_step}); times measured inside a2l-run around each "
        "call. Starts: the rows without a note start on the circle of "
        f"radius {RADIUS} m the synthetic data was drawn on (`--starts circle --radius "
        f"{RADIUS}`, not turned: seed 0); *random starts* = a2l-run's default, `--starts "
        "random` with seed 0 (angle uniform, distance uniform in [0.10, 0.25] m), positions "
        "the data's circle does not hold.",
        "",
        "| scene | starts | success | skill steps/s | control ticks/s | `step()` p50 / p99.9 | "
        "control tick p50 / p99.9 |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, s in runs.items():
        st, tt = s["step_time"], s["tick_time"]
        tick = f"{tt['p50_us']:.2f} / {tt['p99.9_us']:.2f} us" if tt["n"] else "-"
        ticks = f"{s['control_ticks'] / s['elapsed_s']:,.0f}" if s["control_ticks"] else "-"
        lines.append(
            f"| {name} | {s['starts']['description']} | {s['success']}/{s['episodes']} | "
            f"{s['steps_per_s']:,.0f} | {ticks} | "
            f"{st['p50_us']:.2f} / {st['p99.9_us']:.2f} us | {tick} |"
        )
    st, tt, lt = realtime["step_time"], realtime["tick_time"], realtime["wakeup_lateness"]
    lines += [
        "",
        "At Baxter's rate (`--rate 1000`: one joint command per 1 ms, `sleep_until` on a "
        "stock kernel, shared machine; 2 start points on the data's circle x 2 effects): "
        f"{realtime['control_ticks']:,} ticks in {realtime['elapsed_s']:.2f} s, success "
        f"{realtime['success']}/{realtime['episodes']}; control tick p50 {tt['p50_us']:.2f} us, "
        f"p99.9 {tt['p99.9_us']:.2f} us; `step()` p50 {st['p50_us']:.2f} us (slower than "
        "flat out: caches go cold while the thread sleeps); wake-up lateness p50 "
        f"{lt['p50_us']:.0f} us, p99 {lt['p99_us']:.0f} us, p99.9 {lt['p99.9_us']:.0f} us: "
        "the OS scheduler, not the runtime, limits the real-time behaviour here (an RT kernel "
        "and SCHED_FIFO would be needed on the robot).",
    ]
    robot_runs = {k: v for k, v in runs.items() if v["tick_time"]["n"]}
    share = max(v["tick_time"]["p50_us"] for v in robot_runs.values()) / 1000.0
    worst = max(v["tick_time"]["max_us"] for v in robot_runs.values())
    lines += [
        "",
        f"Baxter's control period is 1,000 us: a median control tick uses {share:.2%} of it "
        f"(the slower median of the two robot runs above). The largest control tick of those "
        f"runs took {worst:,.0f} us: preemption on this shared 2-core machine, not the code "
        "(the step and tick allocate nothing and take no lock: `make test`'s NoAlloc tests).",
    ]
    lines += ["", skill_kinds()]
    return "\n".join(lines)
