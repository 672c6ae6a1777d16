"""``--record FILE.rrd`` of every experiment: a short run of each writes its recording and
it is read back (Rerun's dataframe API) with the entities a person would look at: a sweep's
seeds and a study's cells as groups of validation rollouts, the held-out rollouts, the
demonstrated skills' trials, the tasks' plan steps, the babbling trajectories, the LASA
demonstrations and DS paths."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

rr = pytest.importorskip("rerun", reason="the ros extra (rerun-sdk) is not installed")
pytest.importorskip("datafusion", reason="rerun-sdk[catalog] is not installed")

from a2l.cli import main  # noqa: E402
from a2l.rollout.recording import read_recording  # noqa: E402

#: The short push configuration of the framework's tests (virtual scene, one iteration).
SHORT = ["--scene", "virtual", "--effects", "4", "--starts", "2", "--iterations", "1",
         "--quiet"]


def rollouts_under(cols: dict[str, list], group: str) -> set[int]:
    """The rollout indices a recording holds under `group` (``""``: at the top)."""
    pre = f"/{group}/rollout/" if group else "/rollout/"
    return {int(c[len(pre):].split("/")[0]) for c in cols if c.startswith(pre)}


def summaries(cols: dict[str, list], prefix: str) -> list[str]:
    return [v[0] for v in cols.get(f"{prefix}/summary:TextLog:text", []) if v]


@pytest.fixture(scope="module")
def sweep(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``a2l experiment sweep --seeds 0-1 --record``: two short push runs."""
    out = tmp_path_factory.mktemp("sweep")
    assert main(["experiment", "sweep", *SHORT, "--seeds", "0-1", "--out", str(out / "run"),
                 "--record", str(out / "sweep.rrd")]) == 0
    return out


def test_sweep_records_every_seeds_final_validation(sweep: Path) -> None:
    from a2l.experiments.push import final_validation

    cols = read_recording(sweep / "sweep.rrd")
    for seed in (0, 1):
        frame, _ = final_validation(sweep / "run" / f"seed_{seed:03d}")
        assert rollouts_under(cols, f"seed/{seed}") == set(range(len(frame)))
        last = frame.iloc[-1]
        pre = f"/seed/{seed}/rollout/{len(frame) - 1}"
        points = [v for v in cols[f"{pre}/world/eef:Points3D:positions"] if v]
        eef = np.asarray(last.eef).reshape(-1, 3)
        assert len(points) == len(eef)
        np.testing.assert_allclose(np.asarray(points[-1]).reshape(3), eef[-1], atol=1e-6)
        assert summaries(cols, pre)[0].endswith(f": {last.outcome} ({last.stop})")
    assert rollouts_under(cols, "") == set()  # nothing outside the seeds' groups


def test_heldout_records_the_heldout_rollouts(sweep: Path, tmp_path: Path) -> None:
    out = tmp_path / "again"
    assert main(["experiment", "heldout", str(sweep / "run" / "seed_000"), "--out", str(out),
                 "--quiet", "--record", str(tmp_path / "held.rrd")]) == 0
    held = pd.read_parquet(out / "heldout.parquet")
    cols = read_recording(tmp_path / "held.rrd")
    assert rollouts_under(cols, "") == set(range(len(held))) and len(held) > 0
    for i, row in enumerate(held.itertuples()):
        moves = [v[0] for v in cols[f"/rollout/{i}/movement_index:Scalars:scalars"] if v]
        assert moves == [*map(float, row.moves), -1.0]  # every movement, then the end


def test_discretization_records_every_cell(tmp_path: Path) -> None:
    from a2l.experiments.discretization import run_discretization_study
    from a2l.framework import FrameworkConfig

    base = FrameworkConfig(
        scene="virtual", max_iterations=1, discretization={"n_effects": 4}, starts={"n_starts": 2}
    )
    res = run_discretization_study(tmp_path / "study", base, orientations=(8,),
                                   distances=(3, 4), quiet=True,
                                   record=tmp_path / "study.rrd")
    cols = read_recording(tmp_path / "study.rrd")
    for cell in ("o8-d3", "o8-d4"):
        assert rollouts_under(cols, cell), cell
    assert len(res["rows"]) == 2


def test_every_experiment_takes_record_and_records_nothing_by_default() -> None:
    from a2l.cli import build_parser, parse

    _, commands = build_parser()
    experiments = sorted(p[1] for p in commands if p[0] == "experiment")
    assert len(experiments) == 12, experiments  # push, sweep, tasks, lasa, panda-gym ...
    for name in experiments:
        options = {o for a in commands[("experiment", name)][0]._actions
                   for o in a.option_strings}
        assert "--record" in options, name
    _, ns, _ = parse(["experiment", "sweep"])
    assert ns.record is None


@pytest.mark.parametrize("command", [
    ["experiment", "sweep", "--seeds", "0"], ["experiment", "discretization"],
    ["experiment", "heldout", "."], ["experiment", "lfd-skills"],
    ["experiment", "babbling", "--method", "random"],
    ["experiment", "babbling-compare"], ["experiment", "parametrization"],
    ["experiment", "lasa"], ["experiment", "tasks"]])
def test_a_recording_not_ending_in_rrd_is_a_usage_error(command: list[str], tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]
                                                       ) -> None:
    with pytest.raises(SystemExit) as info:
        main([*command, "--out", str(tmp_path / "out"), "--record", str(tmp_path / "x.txt")])
    assert info.value.code == 2
    assert "a Rerun recording ends in .rrd" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_lfd_skills_records_every_trial_of_every_skill(tmp_path: Path) -> None:
    import dataclasses

    from a2l.experiments.lfd_skills import run_lfd_skills
    from a2l.lfd.config import DEFAULT

    cfg = dataclasses.replace(DEFAULT, n_demos=3, maps=10)
    run_lfd_skills(tmp_path / "r", ["push_right"], trials=2, scene="virtual", cfg=cfg,
                   quiet=True, context_source="ground_truth", record=tmp_path / "lfd.rrd")
    trials = pd.read_csv(tmp_path / "r" / "trials.csv")
    cols = read_recording(tmp_path / "lfd.rrd")
    assert rollouts_under(cols, "push_right") == {0, 1}
    for i, t in enumerate(trials.itertuples()):
        pre = f"/push_right/rollout/{i}"
        assert summaries(cols, pre) == [
            f"push_right seed {t.seed}: {'success' if t.success else 'failure'} ({t.stop})"]
        moves = [v for v in cols[f"{pre}/movement_index:Scalars:scalars"] if v]
        assert len(moves) - 1 == t.movements  # a row per step, the last one the stop
        assert f"{pre}/world/objects/box:Boxes3D:centers" in cols
        assert f"{pre}/bins/distance:Scalars:scalars" in cols


def test_babbling_and_the_comparison_record_every_evaluation(tmp_path: Path) -> None:
    """``babbling --record``: an evaluation a rollout, its path the one played, the box at
    its home first and where the experimenter found it last; ``babbling-compare --record``
    the same per run, under ``<method>-s<seed>``."""
    run = tmp_path / "cmp" / "random-s1"
    common = ["--evaluations", "4", "--generation-size", "2", "--scene", "push", "--quiet"]
    assert main(["experiment", "babbling", "--method", "random", "--seed", "1", *common,
                 "--out", str(run), "--record", str(tmp_path / "bab.rrd")]) == 0
    evals = pd.read_parquet(run / "evaluations.parquet")
    with np.load(run / "paths.npz") as z:
        paths = [z[k] for k in z.files]
    cols = read_recording(tmp_path / "bab.rrd")
    assert rollouts_under(cols, "") == set(range(4))
    for i, (row, path) in enumerate(zip(evals.itertuples(), paths, strict=True)):
        pre = f"/rollout/{i}"
        points = [v for v in cols[f"{pre}/world/eef:Points3D:positions"] if v]
        np.testing.assert_allclose(np.asarray(points).reshape(-1, 3), path, atol=1e-6)
        boxes = [np.asarray(v).reshape(3) for v in cols[f"{pre}/world/objects/box:Boxes3D:centers"]
                 if v]
        np.testing.assert_allclose(boxes[-1][:2], [row.x_box, row.y_box], atol=1e-6)
        assert summaries(cols, pre)[0].startswith(f"evaluation {i} (generation ")
    assert main(["experiment", "babbling-compare", "--methods", "random", "--seeds", "1",
                 "--first-seed", "1", *common, "--out", str(tmp_path / "cmp"),
                 "--record", str(tmp_path / "cmp.rrd")]) == 0  # the run above, reused
    again = read_recording(tmp_path / "cmp.rrd")
    assert rollouts_under(again, "random-s1") == set(range(4))
    assert again["/random-s1/rollout/3/world/eef:Points3D:positions"] == \
        cols["/rollout/3/world/eef:Points3D:positions"]


def test_parametrization_records_every_cells_trials(tmp_path: Path) -> None:
    from a2l.experiments.parametrization import run_parametrization

    run_parametrization(tmp_path / "p", ["push_far"],
                        {"resolution": (0.02,), "step": (0.05,), "n_orient": (8, 16),
                         "n_dist": (3,), "smoothing": (False,)},
                        trials=2, scene="virtual", quiet=True, record=tmp_path / "p.rrd")
    cells = pd.read_csv(tmp_path / "p" / "cells.csv")
    cols = read_recording(tmp_path / "p.rrd")
    for c in cells.itertuples():
        group = f"push_far/cell{c.cell:03d}"
        assert rollouts_under(cols, group) == {0, 1}
        lines = [summaries(cols, f"/{group}/rollout/{i}")[0] for i in (0, 1)]
        assert [line.split(":")[0] for line in lines] == ["push_far seed 500",
                                                         "push_far seed 501"]
        assert sum(" success " in f" {line} " for line in lines) / 2 == c.success_rate


def test_lasa_records_the_demonstrations_and_the_ds_paths(tmp_path: Path) -> None:
    """``lasa --record``: per shape and demonstration, the demonstration and the DS from its
    start, traced in the plane over the demonstration's time, ending where each ends."""
    from a2l.experiments.lasa_methods import load_lasa_shape

    assert main(["experiment", "lasa", "--out", str(tmp_path / "lasa"), "--shapes", "Line",
                 "--K", "40", "--mu", "0.6", "--starts", "40", "--tune", "false",
                 "--query_points", "20", "--quiet", "--record", str(tmp_path / "l.rrd")]) == 0
    demos, durations = load_lasa_shape("Line")
    cols = read_recording(tmp_path / "l.rrd")
    times = read_recording(tmp_path / "l.rrd", index="time")["time"]
    assert rollouts_under(cols, "Line") == set(range(len(demos)))
    assert max(times).total_seconds() == pytest.approx(max(durations), abs=1e-6)
    target = None
    for i, demo in enumerate(demos):
        pre = f"/Line/rollout/{i}/plane"
        points = [np.asarray(v).reshape(2) for v in cols[f"{pre}/demo:Points2D:positions"]
                  if v]
        assert 50 <= len(points) <= 100  # resampled, at most 100 per path
        np.testing.assert_allclose(points[0], demo[0])
        np.testing.assert_allclose(points[-1], demo[-1])
        ds = [np.asarray(v).reshape(2) for v in cols[f"{pre}/ds:Points2D:positions"] if v]
        np.testing.assert_allclose(ds[0], demo[0], atol=1e-9)  # the DS from its start
        target = [v for v in cols[f"{pre}/target:Points2D:positions"] if v][0]
        # the DS ends nearer the target than it started
        t = np.asarray(target).reshape(2)
        assert np.linalg.norm(ds[-1] - t) < 0.2 * np.linalg.norm(ds[0] - t)
        assert f"{pre}/demo_path:LineStrips2D:strips" in cols


def test_tasks_records_every_trials_executed_steps(tmp_path: Path) -> None:
    """``tasks --record``: a trial a rollout, a row per executed plan step labelled with the
    step and how it ended, the block where it ended as the trial's row says."""
    from a2l.experiments.tasks import run_tasks

    run_tasks(tmp_path / "t", ["light-off-place-right"], trials=1, seed=7100,
              faults=(True,), quiet=True, plots=False, context_source="ground_truth",
              record=tmp_path / "t.rrd")
    row = pd.read_csv(tmp_path / "t" / "trials.csv").iloc[0]
    cols = read_recording(tmp_path / "t.rrd")
    pre = "/light-off-place-right/fault/rollout/0"
    assert rollouts_under(cols, "light-off-place-right/fault") == {0}
    texts = [v[0] for v in cols[f"{pre}/movement:TextLog:text"] if v]
    steps = row.stops.split(";")
    assert len(texts) == len(steps) + 1 and texts[-1] == "end: -"
    for text, stop in zip(texts, steps, strict=False):
        name, how = stop.split(":", 1)
        assert text.startswith(f"ok: ({name} ") and text.endswith(f" ({how})"), (text, stop)
    block = [v for v in cols[f"{pre}/world/objects/block:Boxes3D:centers"] if v][-1]
    np.testing.assert_allclose(np.asarray(block).reshape(3)[:2], [row.block_x, row.block_y],
                               atol=1e-6)
    note = summaries(cols, pre)[0]
    assert note.startswith("light-off-place-right seed 7100 with its fault: ")
    assert ("success" if row.success else "failure") in note
