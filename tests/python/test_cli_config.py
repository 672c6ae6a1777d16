"""The ``a2l`` command made from the configurations: every field of every part of
FrameworkConfig is an option of ``a2l experiment push`` (``--part.field``, and a key of
``--config FILE``), names are checked before any run directory is made (a name of the flat
configuration of earlier versions with its name now), and the command a run records
reproduces its configuration."""

from __future__ import annotations

import dataclasses
import json
import shlex
import time
from pathlib import Path

import pytest

from a2l.cli import main, parse
from a2l.cli.parser import config_from
from a2l.experiments.lasa import LasaConfig
from a2l.framework import FrameworkConfig
from a2l.framework.config import field_paths
from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.rundir import command_line


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    return capsys.readouterr().err


def test_push_help_lists_every_framework_config_field(
        capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as info:
        main(["experiment", "push", "--help"])
    assert info.value.code == 0
    text = capsys.readouterr().out
    missing = [p for p in field_paths(FrameworkConfig) if f"--{p} " not in text]
    assert missing == [] and len(field_paths(FrameworkConfig)) == 58
    # each with its description from its part's docstring
    assert "Push effects of the effect variable." in text
    assert "context variables also fixed as" in text
    assert "Held-out start positions (0: no held-out evaluation)" in text


@pytest.mark.parametrize("command", ["push", "discretization", "sweep"])
def test_every_field_is_an_option(command: str) -> None:
    skip = {"seed"} if command == "sweep" else set()
    cfg = FrameworkConfig(scene="bullet", scene_config={"gui": False},
                          discretization={"n_effects": 8, "n_offset": 3, "step": 0.04},
                          learning={"fixed_parents": ("distance", "orientation"),
                                    "structure": "hand-coded"},
                          directed={"try_cap": 7}, babbling={"erase_loops": True})
    argv = shlex.split(command_line(["experiment", command, "--out", "x"], cfg, skip=skip))
    path, ns, _ = parse(argv)
    assert path == ("experiment", command)
    assert config_from(ns, FrameworkConfig) == (
        cfg.with_(seed=0) if skip else cfg)


def test_a_misspelt_option_is_refused_with_the_valid_names(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    t0 = time.perf_counter()
    err = _refused(["experiment", "push", "--learning.fixed_parnts", '["distance"]', "--out",
                    str(out)], capsys)
    assert "unrecognized arguments: --learning.fixed_parnts" in err
    assert "did you mean --learning.fixed_parents" in err
    assert all(f"--{p}" in err for p in field_paths(FrameworkConfig))
    # a misspelt part too
    err = _refused(["experiment", "push", "--discretisation.n_orient", "24"], capsys)
    assert "did you mean --discretization.n_orient" in err
    assert not out.exists()
    print(f"refused in {time.perf_counter() - t0:.2f} s")


def test_an_option_of_the_flat_form_is_read_as_its_name_now(
        capsys: pytest.CaptureFixture[str]) -> None:
    """The commands earlier runs recorded (``--n_effects 4``) still run, with a warning."""
    _, ns, _ = parse(["experiment", "push", "--n_orient", "24", "--heldout-starts", "0"])
    assert config_from(ns, FrameworkConfig) == FrameworkConfig(
        discretization={"n_orient": 24}, heldout={"n_starts": 0})
    err = capsys.readouterr().err
    assert "warning: --n_orient is renamed; read as --discretization.n_orient" in err
    assert "warning: --heldout-starts is renamed; read as --heldout.n_starts" in err
    _, ns, _ = parse(["experiment", "sweep", "--seeds", "0", "--directed_per_pair=7"])
    assert config_from(ns, FrameworkConfig).directed.per_pair == 7


def test_a_list_option_takes_what_a_user_types() -> None:
    for value in ("distance,orientation", "distance, orientation", "[distance,orientation]",
                  '["distance", "orientation"]'):
        _, ns, _ = parse(["experiment", "push", "--learning.fixed_parents", value])
        assert config_from(ns, FrameworkConfig).learning.fixed_parents == (
            "distance", "orientation"), value
    _, ns, _ = parse(["experiment", "push", "--learning.fixed_parents=distance"])
    assert config_from(ns, FrameworkConfig).learning.fixed_parents == ("distance",)


def test_a_list_of_numbers_takes_what_a_user_types(capsys: pytest.CaptureFixture[str]) -> None:
    for value in ("0.07,0.10,0.15", "0.07, 0.1, 0.15", "[0.07,0.10,0.15]", "[0.07, 0.1, 0.15]"):
        _, ns, _ = parse(["experiment", "push", "--discretization.dist_edges", value])
        d = config_from(ns, FrameworkConfig).discretization
        assert d.dist_edges == (0.07, 0.10, 0.15), value
        assert d.discretizer().distance.n_bins == 4
    _, ns, _ = parse(["experiment", "push", "--discretization.dist_edges=0.1"])
    assert config_from(ns, FrameworkConfig).discretization.dist_edges == (0.1,)
    _, ns, _ = parse(["experiment", "push", "--discretization.dist_edges", "[]"])
    assert config_from(ns, FrameworkConfig).discretization.dist_edges == ()
    err = _refused(["experiment", "push", "--discretization.dist_edges", "0.1,0.07"], capsys)
    assert "argument --discretization.dist_edges: must be a list of at most 1023 bin edges" in err
    err = _refused(["experiment", "push", "--discretization.dist_edges", "0.1,near"], capsys)
    assert "argument --discretization.dist_edges:" in err
    # the command a run records parses back to its edges
    cfg = FrameworkConfig(discretization={"dist_edges": (0.07, 0.1)})
    command = command_line(["experiment", "push", "--out", "x"], cfg)
    assert config_from(parse(shlex.split(command))[1], FrameworkConfig) == cfg


def test_a_misspelt_variable_is_refused_before_any_run_directory(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    err = _refused(["experiment", "push", "--learning.fixed_parents", "distance,orientaton",
                    "--out", str(out)], capsys)
    assert ("argument --learning.fixed_parents: ['orientaton'] not context variables; they "
            "are ['distance', 'orientation']") in err
    assert not out.exists()
    # the same check for a sweep, and for a variable that only some configurations have
    err = _refused(["experiment", "sweep", "--seeds", "0-1", "--learning.fixed_parents",
                    '["offset_x"]', "--out", str(out)], capsys)
    assert "['offset_x'] not context variables" in err
    assert not out.exists()
    path, ns, _ = parse(["experiment", "push", "--discretization.n_offset", "3",
                         "--learning.fixed_parents", "offset_x"])
    assert config_from(ns, FrameworkConfig).learning.fixed_parents == ("offset_x",)


def test_config_file_sets_options_and_its_keys_are_checked(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    good = tmp_path / "good.yaml"
    good.write_text("discretization:\n  n_effects: 8\nlearning:\n  fixed_parents: [distance, "
                    "orientation]\nworkers: 2\n")
    _, ns, _ = parse(["experiment", "push", "--config", str(good), "--seed", "3"])
    assert config_from(ns, FrameworkConfig) == FrameworkConfig(
        seed=3, discretization={"n_effects": 8},
        learning={"fixed_parents": ("distance", "orientation")})
    assert ns.workers == 2
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"discretization": {"n_effects": 8}, "learning": {
        "fixed_parnts": []}}))
    out = tmp_path / "run"
    err = _refused(["experiment", "push", "--config", str(bad), "--out", str(out)], capsys)
    assert "unknown key(s) ['learning.fixed_parnts']" in err
    assert "learning.fixed_parents" in err
    assert not out.exists()


def test_a_config_file_of_the_flat_form_names_each_renamed_field(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    old = tmp_path / "old.json"
    old.write_text(json.dumps({"scene": "virtual", "n_effects": 8, "heldout_starts": 4}))
    err = _refused(["experiment", "push", "--config", str(old)], capsys)
    assert ("holds the flat form of an earlier version; renamed: n_effects is now "
            "discretization.n_effects, heldout_starts is now heldout.n_starts") in err


def test_earlier_option_names_still_work_and_are_named_in_messages(
        capsys: pytest.CaptureFixture[str]) -> None:
    _, ns, _ = parse(["experiment", "push", "--effects", "8", "--iterations", "3",
                      "--starts", "4", "--heldout.n-starts", "0"])
    assert config_from(ns, FrameworkConfig) == FrameworkConfig(
        max_iterations=3, discretization={"n_effects": 8}, starts={"n_starts": 4},
        heldout={"n_starts": 0})
    assert "argument --effects: must be 4 or 8" in _refused(
        ["experiment", "push", "--effects", "5"], capsys)


def test_recorded_push_command_reproduces_the_configuration(tmp_path: Path) -> None:
    """What run_push_experiment writes: the parse of its command is its configuration."""
    cfg = FrameworkConfig(seed=4, starts={"n_starts": 2}, learning={"fixed_parents": ()},
                          directed={"per_pair": 20, "waypoint_aim": 0.06, "try_cap": None})
    command = command_line(["a2l", "experiment", "push", "--out", tmp_path / "r"], cfg)
    assert "--directed.per_pair 20" in command and "--learning.fixed_parents '[]'" in command
    path, ns, _ = parse(shlex.split(command)[1:])
    assert config_from(ns, FrameworkConfig) == FrameworkConfig.from_dict(
        json.loads(json.dumps(cfg.to_dict()))) == cfg
    assert ns.out == str(tmp_path / "r")


def test_lasa_and_lfd_configurations_are_options() -> None:
    lasa = LasaConfig(K=40, beta=0.5, n_starts=40, direction="to_line")
    _, ns, _ = parse(shlex.split(command_line(["experiment", "lasa", "--out", "x"], lasa)))
    assert config_from(ns, LasaConfig) == lasa
    _, ns, _ = parse(["experiment", "lfd-skills", "--out", "x", "--lfd.discretization.step",
                      "0.03",
                      "--lfd.n_demos", "4"])
    assert config_from(ns.lfd, LfDConfig) == DEFAULT.with_(
        {"discretization.step": 0.03, "n_demos": 4})


def test_an_lfd_value_out_of_its_domain_names_the_option(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    err = _refused(["experiment", "lfd-skills", "--out", str(out),
                    "--lfd.discretization.step", "-1"], capsys)
    assert "argument --lfd.discretization.step: must be a positive length" in err
    assert not out.exists()


def test_prefixed_commands_parse_back() -> None:
    """The commands babbling and perturbations record (``--world.*``, ``--lfd.*``)."""
    from a2l.experiments.babbling_world import WorldConfig

    world = WorldConfig(n_waypoints=4, start=(0.4, -0.2, 0.2), time_step=1 / 120, seed=3)
    command = command_line(["experiment", "babbling", "--method", "noveb", "--seed", 3],
                           world, skip=("scene", "seed"), prefix="world.")
    _, ns, _ = parse(shlex.split(command))
    assert dataclasses.replace(config_from(ns.world, WorldConfig), seed=ns.seed) == world
    lfd = DEFAULT.with_({"maps": 20, "discretization.step": 0.03})
    command = command_line(["experiment", "perturbations", "--out", "x"], lfd, prefix="lfd.")
    _, ns, _ = parse(shlex.split(command))
    assert config_from(ns.lfd, LfDConfig) == lfd


@pytest.mark.parametrize("command", [["demo"], ["demo-record"], ["experiment", "tasks"],
                                     ["experiment", "babbling-compare"], ["skill", "run"]])
def test_every_command_reads_a_config_file(command: list[str], tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("no_such_option: 1\n")
    err = _refused([*command, "--config", str(bad)], capsys)
    assert "unknown key(s) ['no_such_option']" in err and "valid keys:" in err


def test_lfd_skills_records_a_command_that_reproduces_its_configuration(tmp_path: Path) -> None:
    from a2l.experiments.lfd_skills import run_lfd_skills

    cfg = dataclasses.replace(DEFAULT, n_demos=3, maps=10)
    run_lfd_skills(tmp_path / "r", ["push_right"], trials=1, scene="virtual", cfg=cfg,
                   quiet=True)
    config = json.loads((tmp_path / "r" / "config.json").read_text())
    assert config["configs"] == {"push_right": cfg.to_json()}
    path, ns, _ = parse(shlex.split(config["command"])[1:])
    assert path == ("experiment", "lfd-skills") and config_from(ns.lfd, LfDConfig) == cfg
    assert (ns.skills, ns.trials, ns.seed, ns.scene, ns.mode) == (
        "push_right", 1, 1040, "virtual", "table")


def test_a_preset_sets_its_fields_in_place_and_later_options_override_it(
        capsys: pytest.CaptureFixture[str]) -> None:
    from a2l.framework.config import PRESETS

    fresh = ["--validation.starts", "fresh", "--discretization.n_dist", "5",
             "--discretization.dist_edges", "0.1"]
    _, ns, _ = parse(["experiment", "push", *fresh, "--preset", "thesis"])
    cfg = config_from(ns, FrameworkConfig)
    assert cfg == FrameworkConfig.preset("thesis")  # the preset, after them, wins
    assert cfg.with_(PRESETS["thesis"]) == cfg
    _, ns, _ = parse(["experiment", "sweep", "--seeds", "0", "--preset=thesis", *fresh])
    cfg = config_from(ns, FrameworkConfig)
    assert cfg.validation.starts == "fresh" and cfg.discretization.n_dist == 5
    assert cfg.discretization.dist_edges == (0.1,)
    assert cfg.skill.step_cap == 12 and cfg.starts.radius == 0.2
    err = _refused(["experiment", "push", "--preset", "thesys"], capsys)
    assert "--preset: unknown 'thesys'; choose thesis" in err
    with pytest.raises(ValueError, match="preset: unknown 'x'; choose 'thesis'"):
        FrameworkConfig.preset("x")
