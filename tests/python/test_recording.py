"""Recordings: a push rollout recorded as a Rerun recording and read back with Rerun's
dataframe API (entities, rows per step, the effect over time); ``a2l view`` refuses bad
paths with a clear message (the viewer itself needs a display)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

rr = pytest.importorskip("rerun", reason="the ros extra (rerun-sdk) is not installed")
pytest.importorskip("datafusion", reason="rerun-sdk[catalog] is not installed")

from a2l.rollout.effect_tests import PUSH_DISTANCE  # noqa: E402


def scalar_column(cols: dict[str, list], entity: str) -> list[float | None]:
    return [None if v is None else float(v[0]) for v in cols[f"{entity}:Scalars:scalars"]]


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, object]:
    from a2l.lfd.library import learn_recipe, make_skill_scene, reset_for_trial
    from a2l.rollout.recording import RerunRecorder, record_run, scene_frame
    from a2l.rollout.run import run_skill
    from a2l.skills.runner import CppSkillRunner

    out = tmp_path_factory.mktemp("rec")
    bundle = learn_recipe("push_far", out).bundle
    frames = []
    with make_skill_scene("push_far", seed=1000) as scene:
        reset_for_trial(scene, "push_far", 1000)
        frames.append(scene_frame(scene))
        run = run_skill(scene, bundle, "far",
                        on_step=lambda k, st: frames.append(scene_frame(scene)))
    rec = RerunRecorder(out / "push.rrd")
    record_run(rec, run, CppSkillRunner(bundle).skill, object_name="box", frames=frames)
    return rec.close(), run, bundle


def test_a_recorded_push_reads_back_with_its_entities_and_counts(recorded) -> None:
    path, run, _ = recorded
    assert run.success  # the rollout recorded is a successful push far
    from a2l.rollout.recording import read_recording

    cols = read_recording(path)
    pre = "/rollout/0"
    for entity in ("world/eef:Points3D:positions", "world/eef_path:LineStrips3D:strips",
                   "world/objects/box:Boxes3D:centers", "world/target:Points3D:positions",
                   "world/robot/right_gripper:Transform3D:translation",
                   "camera:Image:buffer", "bins/distance:Scalars:scalars",
                   "bins/orientation:Scalars:scalars", "movement:TextLog:text",
                   "movement_index:Scalars:scalars", "effect/x:Scalars:scalars"):
        assert f"{pre}/{entity}" in cols, sorted(cols)
    steps = cols["step"]
    assert steps == list(range(len(run.steps)))  # one row per step
    # the chosen movements, step by step, as the run took them
    assert scalar_column(cols, f"{pre}/movement_index") == [float(s.movement)
                                                           for s in run.steps]
    texts = cols[f"{pre}/movement:TextLog:text"]
    assert texts[-1] == ["effect_produced: -"] and texts[0][0].startswith("ok: ")
    # the effect over time: from 0 to at least the push distance along x
    x = scalar_column(cols, f"{pre}/effect/x")
    assert x[0] == 0.0 and x[-1] >= PUSH_DISTANCE
    np.testing.assert_allclose(x[-1], run.obj[-1, 0] - run.obj[0, 0], atol=1e-9)
    # bins are the runtime's: a distance bin within the bundle's 4 bins at every step
    assert all(0 <= b < 4 for b in scalar_column(cols, f"{pre}/bins/distance"))
    assert sum(v is not None for v in cols[f"{pre}/camera:Image:buffer"]) == len(run.steps)


def test_framework_rollouts_are_recorded_one_per_rollout(recorded, tmp_path: Path) -> None:
    """What ``a2l experiment push --record`` writes: the validation rollouts, each its own
    entity tree, with its movements and how it ended."""
    from a2l.acquisition.interactions import Rollout
    from a2l.rollout.recording import RerunRecorder, read_recording, record_rollouts
    from a2l.skills.runner import CppSkillRunner

    skill = CppSkillRunner(recorded[2]).skill
    box = np.array([0.6, -0.2, -0.16])
    path0 = box + np.array([[-0.15, 0, 0.0], [-0.13, 0, 0.0], [-0.11, 0, 0.0]])
    rollouts = [Rollout(0, [0, 0], path0, np.array([box, box, box + [0.06, 0, 0]]),
                        effect=3, wanted=3, outcome="success", stop="moved"),
                Rollout(1, [2], path0[:2], np.array([box, box]), effect=-1, wanted=0,
                        outcome="fail", stop="step_cap")]
    rec = RerunRecorder(tmp_path / "validation.rrd")
    assert record_rollouts(rec, rollouts, skill) == 2
    cols = read_recording(rec.close())
    assert cols["step"] == [0, 1, 2]
    assert scalar_column(cols, "/rollout/0/movement_index") == [0.0, 0.0, -1.0]
    assert scalar_column(cols, "/rollout/1/movement_index")[:2] == [2.0, -1.0]
    assert scalar_column(cols, "/rollout/0/effect/x")[2] == pytest.approx(0.06)
    summaries = [v[0] for v in cols["/rollout/1/summary:TextLog:text"] if v]
    assert summaries == ["start 1, wanted left: fail (step_cap)"]
    assert [v[0] for v in cols["/rollout/0/movement:TextLog:text"]] == [
        "ok: +x", "ok: +x", "success: -"]


def test_skill_run_records_and_view_refuses_bad_paths(tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]
                                                      ) -> None:
    from a2l.cli import main

    (tmp_path / "junk.rrd").write_bytes(b"not a recording")
    (tmp_path / "run.mcap").write_bytes(b"")
    for argv, message in (
            (["view", str(tmp_path / "none.rrd")], "is not a file"),
            (["view", str(tmp_path / "junk.rrd")], "is not a Rerun recording"),
            (["view", str(tmp_path / "run.mcap")], "open it with Foxglove or ros2 bag"),
            (["view", str(tmp_path / "run.txt")], "a Rerun recording ends in .rrd"),
            (["skill", "run", str(tmp_path / "junk.rrd"), "--effect", "far", "--record",
              str(tmp_path / "x.rrd")], "is not a valid bundle"),
            (["experiment", "push", "--record", str(tmp_path / "push.txt")],
             "a Rerun recording ends in .rrd")):
        with pytest.raises(SystemExit) as info:
            main(argv)
        assert info.value.code == 2
        assert message in capsys.readouterr().err


def test_perturbation_trials_are_recorded_one_rollout_each(tmp_path: Path) -> None:
    """``a2l experiment perturbations --record``: every trial (skill, condition, mode, seed)
    is a rollout whose path is the trial's saved trajectory and whose summary says how it
    ended."""
    from a2l.experiments.perturbations import DEFAULT_SEED, run_perturbations
    from a2l.rollout.recording import read_recording

    run = tmp_path / "run"
    run_perturbations(run, ["push_far"], trials=1, seed=DEFAULT_SEED,
                      conditions=["none", "move_object"], quiet=True, plots=False,
                      context_source="ground_truth", record=tmp_path / "trials.rrd")
    trials = pd.read_csv(run / "trials.csv")
    saved = np.load(run / "trajectories.npz")
    cols = read_recording(tmp_path / "trials.rrd")
    assert len(trials) == 4  # 2 conditions x 2 modes x 1 seed
    for i, t in enumerate(trials.itertuples()):
        name = f"{t.skill}/{t.condition}/{t.mode}/{t.seed}"
        summaries = [v[0] for v in cols[f"/rollout/{i}/summary:TextLog:text"] if v]
        assert summaries == [f"{name}: {'success' if t.success else 'failure'} ({t.stop})"]
        eef = saved[f"{name}/eef"]
        points = [v for v in cols[f"/rollout/{i}/world/eef:Points3D:positions"] if v]
        assert len(points) == len(eef)
        np.testing.assert_allclose(np.asarray(points[-1]).reshape(3), eef[-1], atol=1e-6)
