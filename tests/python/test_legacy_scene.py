"""The scene ``baxter`` of earlier runs (the PyBullet scenes with Baxter, before robots were
data) is read once where a scene name comes in, as scene ``bullet`` with robot Baxter: by
the framework's configuration (given, on the command line, or in an earlier run's
``config.json``) and by the experiments on demonstrated skills. The one mapping lives in
:data:`a2l.rollout.env.LEGACY_SCENES`; the string ``"baxter"`` is elsewhere in the package
only as a robot."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from a2l.cli import parse
from a2l.cli.push import framework_config
from a2l.errors import ConfigError
from a2l.experiments.lfd_skills import SCENES as LFD_SCENES
from a2l.experiments.lfd_skills import resolve_scene
from a2l.framework import FrameworkConfig
from a2l.framework.config import DIRECTED_TRY_CAP, FALLBACK, SCENES, TRAIN_FALLBACK
from a2l.rollout.env import ENV_SCENES, LEGACY_SCENES, ROBOT_SCENES, normalise_scene

PACKAGE = Path(__file__).resolve().parents[2] / "python" / "a2l"


def test_the_scene_baxter_is_bullet_on_baxter() -> None:
    """Given, with its default robot or Baxter named, it is the bullet scene on Baxter (the
    same configuration, so the same defaults); with another robot it is refused."""
    assert LEGACY_SCENES == {"baxter": ("bullet", "baxter")}
    cfg = FrameworkConfig(scene="baxter", seed=3, discretization={"n_effects": 4})
    assert (cfg.scene, cfg.robot) == ("bullet", "baxter")
    assert cfg == FrameworkConfig(scene="bullet", robot="baxter", seed=3,
                                  discretization={"n_effects": 4})
    assert FrameworkConfig(scene="baxter", robot="baxter").scene == "bullet"
    assert FrameworkConfig().with_(scene="baxter").scene == "bullet"
    with pytest.raises(ConfigError, match="scene 'baxter' is Baxter's; for robot 'panda' use "
                       "scene 'bullet'"):
        FrameworkConfig(scene="baxter", robot="panda")
    assert normalise_scene("virtual", "panda") == ("virtual", "panda")
    assert normalise_scene("bullet", "ur5") == ("bullet", "ur5")


def test_no_table_keeps_a_scene_by_its_earlier_name() -> None:
    """The per-scene defaults are keyed by today's scenes only: the earlier name takes those
    of the scene it names (``bullet``), as it did when it had its own, equal, values."""
    assert "baxter" not in ENV_SCENES and ROBOT_SCENES == ("bullet",)
    for table in (DIRECTED_TRY_CAP, FALLBACK, TRAIN_FALLBACK):
        assert set(table) == set(SCENES)
    assert not set(LEGACY_SCENES) & set(SCENES) and not set(LEGACY_SCENES) & set(LFD_SCENES)


def test_an_earlier_runs_config_json_reads_scene_baxter_as_bullet(tmp_path: Path) -> None:
    """``--resume`` reads the run's ``config.json`` with :meth:`FrameworkConfig.from_dict`:
    its scene ``baxter`` (composed or flat form) is scene bullet with robot Baxter."""
    # what such a run wrote: the scene's resolved defaults (then equal to bullet's) included
    old = {**FrameworkConfig(scene="bullet", seed=3, discretization={"n_effects": 4}
                             ).to_dict(), "scene": "baxter"}
    path = tmp_path / "config.json"
    path.write_text(json.dumps({"experiment": "push", "framework": old}))
    cfg = FrameworkConfig.from_dict(json.loads(path.read_text())["framework"])
    assert (cfg.scene, cfg.robot) == ("bullet", "baxter")
    assert cfg == FrameworkConfig(scene="bullet", seed=3, discretization={"n_effects": 4})
    with pytest.warns(FutureWarning):  # the flat form of earlier versions
        flat = FrameworkConfig.from_dict({"scene": "baxter", "n_effects": 4, "seed": 3})
    assert flat == cfg


@pytest.mark.parametrize("command", [
    # as docs/results/push-baxter.md records it (--n_effects: an earlier spelling)
    "experiment push --scene baxter --n_effects 4 --seed 1000 --quiet --out DIR --workers 2",
    "experiment push --scene baxter --discretization.n_effects 4 --max_iterations 1 --seed 3",
    "experiment push --scene bullet --robot baxter --discretization.n_effects 4 --seed 3",
])
def test_the_command_line_scene_baxter_is_bullet_on_baxter(command: str) -> None:
    _, ns, _ = parse(command.split())
    cfg = framework_config(ns)
    assert (cfg.scene, cfg.robot, cfg.discretization.n_effects) == ("bullet", "baxter", 4)


def test_the_lfd_experiments_read_scene_baxter_as_bullet_on_baxter() -> None:
    assert resolve_scene("baxter", "baxter") == resolve_scene(None, "baxter") == "bullet"
    with pytest.raises(ConfigError, match="--robot: scene 'baxter' is Baxter's"):
        resolve_scene("baxter", "panda")
    for command in ("lfd-skills", "parametrization"):
        _, ns, _ = parse(["experiment", command, "--scene", "baxter", "--out", "x"])
        assert resolve_scene(ns.scene, ns.robot) == "bullet"


@pytest.mark.parametrize("command", ["push", "lfd-skills"])
def test_help_names_bullet_and_baxter_as_its_earlier_name(
        command: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        parse(["experiment", command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "bullet" in text
    assert re.search(r"baxter, (the|their) earlier name", text), text


#: Where ``"baxter"`` may stand in the package, as a robot: the built-in robot entries and
#: the lookups of Baxter's URDF (every default names :data:`a2l.robot.DEFAULT_ROBOT`)...
ROBOT_FILES = ("robot/builtin_robots.py", "robot/robot_file.py", "robot/descriptions.py")
#: ... and the one place the scene name stands: the mapping of the earlier scene names.
LEGACY_HOME = ("rollout/env.py", "LEGACY_SCENES: dict[str, tuple[str, str]] = {")


def _kind(rel: str, line: str) -> str | None:
    """Why `line` of package file `rel` may hold ``"baxter"``, or None."""
    if rel in ROBOT_FILES:
        return "robot entry"
    if (rel, line.strip()[:len(LEGACY_HOME[1])]) == LEGACY_HOME:
        return "legacy scene"
    return None


def test_the_package_names_baxter_only_as_a_robot_and_once_as_an_earlier_scene() -> None:
    """``grep -rn '"baxter"' python/a2l``: every hit is a built-in robot entry or the one
    mapping of the earlier scene name (:data:`a2l.rollout.env.LEGACY_SCENES`); a default
    robot is :data:`a2l.robot.DEFAULT_ROBOT`, the one home of the name."""
    from a2l.robot import DEFAULT_ROBOT

    hits: dict[str, list[str]] = {}
    for path in sorted(PACKAGE.rglob("*")):
        if not path.is_file() or path.suffix in (".so", ".pyd", ".pyc"):
            continue
        rel = path.relative_to(PACKAGE).as_posix()
        for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            if '"baxter"' in line:
                hits.setdefault(str(_kind(rel, line)), []).append(f"{rel}:{n}: {line.strip()}")
    assert "None" not in hits, "\n".join(hits["None"])
    assert len(hits["legacy scene"]) == 1 and hits["robot entry"]
    assert DEFAULT_ROBOT == "baxter"


def test_a_sweep_of_scene_baxter_continues_with_the_same_command(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """An earlier sweep's ``config.json`` names scene ``baxter``: the same configuration,
    read today as scene bullet on Baxter, continues it (it goes on to run its seed);
    other seeds are refused."""
    import a2l.experiments.sweep as sweep
    from a2l.rundir import write_json

    class Ran(Exception):
        pass

    def run(*args: object, **kwargs: object) -> None:
        raise Ran

    cfg = FrameworkConfig(scene="baxter", discretization={"n_effects": 4})
    write_json(tmp_path / "config.json", {
        "experiment": "sweep", "framework": {**cfg.to_dict(), "scene": "baxter"},
        "overrides": {}, "seeds": [1]})
    monkeypatch.setattr(sweep, "run_push_experiment", run)
    with pytest.raises(ValueError, match="another configuration"):
        sweep.run_seed_sweep(cfg, [2], out=tmp_path, quiet=True)
    with pytest.raises(Ran):
        sweep.run_seed_sweep(cfg, [1], out=tmp_path, quiet=True)
