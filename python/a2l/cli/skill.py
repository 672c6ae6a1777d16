"""``a2l skill show``, ``learn`` and ``run``: a user's own skills, from a demonstrations file
to a bundle run in a scene.

``show`` prints what a bundle holds (kind, variables and their bins, movements, effects, DS
phases, robot, checksums); ``learn`` learns a skill from a demonstrations file such as
``a2l demo-record`` writes (the LfD pipeline, :func:`a2l.lfd.skill.learn_skill`); ``run``
runs a bundle in closed loop in a scene (:func:`a2l.rollout.run.run_skill`) and prints the
outcome and the trace summary. ``learn --robot`` records the robot the skill is learned for;
``run`` builds a PyBullet scene on the robot the bundle was learned for (``--robot`` names
another, or a robot file; the scene refuses a bundle of another robot).
"""

from __future__ import annotations

import hashlib
import json
import struct
from collections import Counter
from pathlib import Path
from typing import Any

from jsonargparse import Namespace
from jsonargparse.typing import NonNegativeInt, PositiveInt

from a2l.cli.args import UsageError, check_record
from a2l.cli.lfd import lfd_config
from a2l.cli.parser import Parser, add_config_fields, add_config_option
from a2l.errors import BundleError
from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.skills.bundle_format import BundleView

#: Scenes ``a2l skill run`` can build (:func:`a2l.sim.make_scene`).
SCENES = ("virtual", "push", "grasp", "grasp_light", "press")


def bundle_summary(path: Path) -> dict[str, Any]:
    """What the bundle at `path` holds, as a JSON-able dict (validated by the C++ loader).

    Raises
    ------
    UsageError
        Not a file, or not a valid bundle (the loader's message).
    """
    # imported here: parsing and --help do not load this command's stack
    from a2l.skills.bundle import load_bundle
    from a2l.skills.ds_bundle import load_ds_bundle
    from a2l.skills.phases import load_ds_phases

    if not path.is_file():
        raise UsageError("BUNDLE", f"'{path}' is not a file")
    data = path.read_bytes()
    out: dict[str, Any] = {"path": str(path), "bytes": len(data),
                           "sha256": hashlib.sha256(data).hexdigest()}
    try:
        kind = BundleView.parse(data).manifest.get("kind")
        if kind == "ds":
            _, meta = load_ds_bundle(path)
            return {**out, "kind": "ds", "metadata": meta}
        spec = load_bundle(path)
        phases = load_ds_phases(path)
    except (BundleError, ValueError, KeyError, struct.error) as exc:
        raise UsageError("BUNDLE", f"'{path}' is not a valid bundle: {exc}") from None
    effects = [v.values for v in spec.variables if v.kind == "effect"]
    return {
        **out, "kind": "skill", "name": spec.name,
        "variables": [{"name": v.name, "kind": v.kind, "bins": v.n_bins,
                       **({"range": [v.low, v.high]} if v.low is not None else {}),
                       **({"edges": list(v.edges)} if v.edges else {}),
                       **({"values": list(v.values)} if v.values else {})}
                      for v in spec.variables],
        "movements": {"step": spec.step, "labels": list(spec.labels),
                      "actions": list(spec.actions)},
        "effects": list(effects[0]) if effects else [],
        "table_cells": int(spec.argmax.size),
        "uniform_cells": int((spec.argmax < 0).sum()),
        "step_cap": spec.step_cap, "smoothing": spec.smoothing,
        "ds_phases": [{"name": p.name, "when": dict(p.when), "end_action": p.end_action,
                       "tolerance": p.tolerance} for p in phases],
        "robot": spec.robot,
        "scene": spec.scene_settings,
    }


def _print_summary(s: dict[str, Any]) -> None:
    print(f"{s['path']}: {s['kind']} bundle, {s['bytes']} bytes, sha256 {s['sha256']}")
    if s["kind"] == "ds":
        print(f"  metadata: {json.dumps(s['metadata'])}")
        return
    print(f"  name: {s['name']}; step cap {s['step_cap']}; smoothing "
          f"{'on' if s['smoothing'] else 'off'}")
    print("  variables:")
    for v in s["variables"]:
        detail = ("edges " + ", ".join(f"{x:g}" for x in v["edges"]) if "edges" in v
                  else f"{v['range'][0]:g}..{v['range'][1]:g}" if "range" in v
                  else ", ".join(v.get("values", [])))
        print(f"    {v['name']} ({v['kind']}): {v['bins']} bins {detail}".rstrip())
    mv = s["movements"]
    print(f"  movements: {len(mv['labels'])} directions of {mv['step']:g} m "
          f"({', '.join(mv['labels'])})" + (f" + actions {', '.join(mv['actions'])}"
                                           if mv["actions"] else ""))
    print(f"  effects: {', '.join(s['effects']) or '-'}")
    print(f"  table: {s['table_cells']} cells, {s['uniform_cells']} uniform")
    print("  DS phases: " + ("; ".join(
        f"{p['name']} when {p['when'] or 'always'} -> {p['end_action'] or '-'}"
        for p in s["ds_phases"]) or "none"))
    print("  scene settings it was learned with: " + (", ".join(
        f"{k} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in s["scene"].items())
        or "none"))
    robot = s["robot"]
    print("  robot: " + ("none" if robot is None else
                         f"{robot['name']} ({robot['base_link']} -> {robot['tip_link']}, "
                         f"URDF sha256 {robot['urdf_sha256']})"))


def _cmd_show(ns: Namespace) -> int:
    summary = bundle_summary(Path(ns.bundle))
    if ns.json:
        print(json.dumps(summary, indent=2))
    else:
        _print_summary(summary)
    return 0


def _cmd_learn(ns: Namespace) -> int:
    # imported here: parsing does not load the fit and pgmpy
    from a2l.lfd.dataset import skill_discretizer
    from a2l.lfd.demonstration import load_demonstrations
    from a2l.lfd.skill import Behaviour, learn_skill

    demos_path, out = Path(ns.demos), Path(ns.out)
    if not demos_path.is_file():
        raise UsageError("--demos", f"'{demos_path}' is not a file")
    if out.suffix != ".a2lb":
        raise UsageError("--out", f"'{out}': a bundle file ends in .a2lb")
    robot = _robot_record(ns.robot)
    cfg = lfd_config(ns) or DEFAULT
    effects = skill_discretizer(cfg, planar=ns.planar, n_effects=ns.n_effects).effects.values
    if ns.effect not in effects:
        raise UsageError("--effect", f"unknown effect {ns.effect!r}; valid: "
                         f"{', '.join(effects)}")
    try:
        demos = load_demonstrations(demos_path)
    except ValueError as exc:
        raise UsageError("--demos", str(exc)) from None
    bad = [i for i, d in enumerate(demos) if d.frame != "object" or d.dim != 3]
    if not demos or bad:
        raise UsageError("--demos", f"need 3-D demonstrations in the object frame; "
                         f"{'none' if not demos else f'demonstration(s) {bad} are not'}")
    out.parent.mkdir(parents=True, exist_ok=True)
    name = ns.name or out.stem
    learned = learn_skill(name, [Behaviour(list(demos), ns.effect, phase=name)], out,
                          cfg, planar=ns.planar, n_effects=ns.n_effects, robot=robot)
    print(f"learned {learned.name!r} from {len(demos)} demonstration(s): {learned.rows} rows, "
          f"{sum(learned.timings.values()):.1f} s; bundle {learned.bundle}")
    return 0


def _robot_record(robot: str | None) -> dict[str, str] | None:
    from a2l.errors import A2LError
    from a2l.lfd.library import robot_record

    try:
        return robot_record(robot)
    except A2LError as exc:
        raise UsageError("--robot", str(exc)) from None


def _scene_robot(scene: str, given: str | None, learned_for: dict[str, Any] | None
                 ) -> dict[str, str]:
    """The ``robot`` setting of `scene` (none for the virtual scene): `given`, else the
    robot the bundle was learned for (a built-in one), else the scene's own (Baxter). A
    robot the bundle was not learned for is a usage error."""
    from a2l.errors import A2LError
    from a2l.robot import BUILTIN_ROBOTS
    from a2l.sim import settings_for

    if not settings_for(scene, {"robot": None}):  # a scene with a robot
        if given is not None:
            raise UsageError("--robot", f"the {scene} scene has no robot")
        return {}
    if given is None and learned_for is not None:
        given = str(learned_for["name"])
        if given not in BUILTIN_ROBOTS:
            raise UsageError("--robot", f"the bundle was learned for robot {given!r}, not a "
                             "built-in one: give its robot file")
    if given is None:
        return {}
    from a2l.robot import robot_entry

    try:
        robot_entry(given).check_learned_for(learned_for, "the bundle")
    except A2LError as exc:
        raise UsageError("--robot", str(exc)) from None
    return {"robot": given}


def _run_settings(ns: Namespace, summary: dict[str, Any]) -> dict[str, Any]:
    """The scene settings of ``skill run``: those the skill was learned with that the scene
    has, the gripper's turn (``--gripper-yaw``), the robot (:func:`_scene_robot`)."""
    from a2l.sim import settings_for

    extra = settings_for(ns.scene, summary["scene"])
    if ns.gripper_yaw is not None:
        turn = settings_for(ns.scene, {"gripper_yaw": ns.gripper_yaw})
        if not turn and ns.gripper_yaw:
            raise UsageError("--gripper-yaw", f"the {ns.scene} scene has no gripper to turn")
        extra.update(turn)
    elif "gripper_yaw" in extra:
        print(f"gripper turned {extra['gripper_yaw']:g} degrees, as the skill was learned "
              "(--gripper-yaw overrides)")
    extra.update(_scene_robot(ns.scene, ns.robot, summary["robot"]))
    return extra


def _cmd_run(ns: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    import numpy as np

    from a2l.lfd.library import SKILLS, reset_for_trial
    from a2l.rollout.run import run_skill
    from a2l.sim import make_scene

    summary = bundle_summary(Path(ns.bundle))
    if summary["kind"] != "skill":
        raise UsageError("BUNDLE", f"'{ns.bundle}' is a DS bundle; run a skill bundle")
    if summary["effects"] and ns.effect not in summary["effects"]:
        raise UsageError("--effect", f"unknown effect {ns.effect!r}; the bundle's: "
                         f"{', '.join(summary['effects'])}")
    if ns.mode == "ds" and not summary["ds_phases"]:
        raise UsageError("--mode", "the bundle has no DS phase; use --mode table")
    from a2l.rollout.recording import scene_frame

    if ns.record is not None:
        check_record(Path(ns.record))
    frames: list[dict[str, Any]] = []
    with make_scene(ns.scene, seed=ns.seed, step=summary["movements"]["step"],
                    context_source="ground_truth", **_run_settings(ns, summary)) as scene:
        recipe = SKILLS.get(summary["name"])
        name = None
        if recipe is not None and recipe.object_name in scene.object_names:
            # a skill of the library (by its name): the start the experiments draw for a
            # trial of it, from --seed, and the object it acts on
            start = reset_for_trial(scene, summary["name"], ns.seed)["start"]
            name = recipe.object_name
            print(f"start: the end-effector {np.linalg.norm(start) * 100:.1f} cm from the "
                  f"{name} (a trial start of skill {summary['name']!r}, seed {ns.seed})")
        if ns.record is not None:
            frames.append(scene_frame(scene))
        run = run_skill(scene, ns.bundle, ns.effect, mode=ns.mode, max_steps=ns.max_steps,
                        on_step=(lambda k, st: frames.append(scene_frame(scene)))
                        if ns.record is not None else None, object_name=name)
        name = name or ("box" if "box" in scene.object_names else scene.primary_object)
    if ns.record is not None:
        _record(Path(ns.record), run, ns.bundle, name, frames)
    statuses = Counter(run.statuses)
    print(f"{'success' if run.success else 'failure'}: stop {run.stop}, "
          f"{run.movements} movement(s) in {len(run.steps)} step(s), "
          f"{run.wall:.2f} s")
    print("trace: " + ", ".join(f"{k} {v}" for k, v in statuses.items()))
    return 0 if run.success else 1


def _record(path: Path, run: Any, bundle: str, name: str, frames: list[dict[str, Any]]
            ) -> None:
    from a2l.rollout.recording import RerunRecorder, record_run
    from a2l.skills.runner import CppSkillRunner

    rec = RerunRecorder(path, name="a2l skill run")
    record_run(rec, run, CppSkillRunner(bundle).skill, object_name=name, frames=frames)
    print(f"recording: {rec.close()} (a2l view {path})")


def _show_parser() -> Parser:
    p = Parser(prog="a2l skill show", description="Print what a skill or DS bundle holds: "
               "kind, variables and their bins, movements, effects, DS phases, robot, "
               "checksums (validated by the C++ loader).")
    p.add_argument("bundle", metavar="BUNDLE", help="the .a2lb file")
    p.add_argument("--json", action="store_true", help="print it as JSON")
    return p


def _learn_parser() -> Parser:
    p = Parser(prog="a2l skill learn", description="Learn a skill from a demonstrations "
               "file (.csv or .parquet, e.g. from a2l demo-record): one DS per "
               "demonstration, the vector-field dataset, the network, the compiled table, "
               "and the bundle with the mean DS. Every LfDConfig field is an option "
               "--lfd.<field>.")
    p.add_argument("--demos", metavar="FILE", required=True, help="demonstrations file")
    p.add_argument("--out", metavar="BUNDLE", required=True, help="bundle to write (.a2lb)")
    p.add_argument("--effect", required=True, help="the effect the demonstrations produce")
    p.add_argument("--name", default=None, help="the skill's name (default: --out's stem)")
    p.add_argument("--planar", type=bool, default=True,
                   help="8 planar movements (default) or 26 in 3-D (false)")
    p.add_argument("--n_effects", type=int, choices=(4, 8), default=4,
                   help="push effects of the effect variable (default 4)")
    p.add_argument("--robot", default=None, metavar="NAME|FILE",
                   help="the robot the skill is learned for, which the bundle records and "
                   "the scenes of another robot refuse (default: none, it runs on any arm)")
    add_config_fields(p, LfDConfig, nested_key="lfd")
    return p


def _run_parser() -> Parser:
    p = Parser(prog="a2l skill run", description="Run a skill bundle in closed loop in a "
               "scene (the context skill, or its DS alone) and print the outcome and the "
               "trace summary; exit code 1 when the effect is not produced.")
    p.add_argument("bundle", metavar="BUNDLE", help="the skill bundle (.a2lb)")
    p.add_argument("--effect", required=True, help="the wanted effect")
    p.add_argument("--mode", choices=("table", "ds"), default="table",
                   help="the context skill (table, default) or the DS alone")
    p.add_argument("--scene", choices=SCENES, default="virtual",
                   help="the scene (default virtual)")
    p.add_argument("--seed", type=NonNegativeInt, default=0, help="scene seed (default 0)")
    p.add_argument("--robot", default=None, metavar="NAME|FILE",
                   help="the robot of a PyBullet scene: a built-in name or a robot file "
                   "(default: the robot the bundle was learned for, else Baxter)")
    p.add_argument("--max-steps", type=PositiveInt | None, default=None, metavar="N",
                   help="most steps (default: the bundle's step cap)")
    p.add_argument("--gripper-yaw", type=float | None, default=None, metavar="DEG",
                   help="turn of the gripper about the vertical (degrees; default: "
                   "the bundle's setting, which the sideways pushes push_right/push_left "
                   "learn as 90, else 0: fingers closing along y)")
    p.add_argument("--record", default=None, metavar="FILE.rrd",
                   help="write a Rerun recording of the run (a2l view FILE.rrd): links, "
                   "objects, end-effector path, camera, context bins, movements, effect")
    return p


def add_skill_parsers(sub: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """The ``skill`` subcommand: ``show``, ``learn``, ``run``."""
    skill = Parser(prog="a2l skill", description="inspect, learn and run skill bundles")
    sub.add_subcommand("skill", skill, help="inspect, learn and run skill bundles")
    cmds = skill.add_subcommands(metavar="ACTION")
    for name, parser, handler, help_ in (
            ("show", _show_parser(), _cmd_show, "what a bundle holds"),
            ("learn", _learn_parser(), _cmd_learn, "learn a skill from a demonstrations file"),
            ("run", _run_parser(), _cmd_run, "run a bundle in a scene")):
        add_config_option(parser)
        cmds.add_subcommand(name, parser, help=help_)
        commands[("skill", name)] = (parser, handler)
