"""``a2l experiment push --acquisition noveb``: NovEB's interactions on the Baxter scene
become iteration 0's dataset in the common format; the virtual scene (no camera) is refused
with a clear error."""

from __future__ import annotations

from pathlib import Path

import pytest

from a2l.acquisition import interaction_rows
from a2l.data.schema import EEF_COLUMNS, MOVE_COLUMNS, OBJECT_COLUMNS
from a2l.framework import FrameworkConfig
from a2l.framework.noveb_rollouts import noveb_acquire
from a2l.parallel import Executor
from a2l.rollout.env import scene_env


def test_noveb_interactions_are_dataset_rows_cut_where_the_object_moved(
        monkeypatch: pytest.MonkeyPatch) -> None:
    cfg = FrameworkConfig(
        scene="bullet", seed=0, discretization={"n_effects": 4}, starts={"n_starts": 4}
    )
    scene = scene_env(cfg).scene        # the scene the tasks of this thread play in
    executed = []
    orig = type(scene).execute
    monkeypatch.setattr(type(scene), "execute",
                        lambda self, d: executed.append(d) or orig(self, d))
    with Executor(workers=1) as ex:
        rollouts, noveb, movements = noveb_acquire(cfg, ex, evaluations=8, generation_size=4)
    assert noveb.told == 8 and noveb.generation == 2
    # the count (iteration 0's "acquire" movements with --acquisition noveb) is what the
    # scene executed
    assert movements == len(executed) > 8
    assert rollouts, "no NovEB trajectory moved the box (at push height, most do)"
    disc = cfg.discretization.discretizer()
    for r in rollouts:
        assert r.moved and r.stop == "moved"
        assert len(r.eef) == len(r.obj) == len(r.moves) + 1
        # the object had not moved before the last step, and moved at it
        assert int(disc.effects.discretize(r.obj[-1] - r.obj[0])[0]) == r.effect
        if len(r.moves) > 1:
            assert int(disc.effects.discretize(r.obj[-2] - r.obj[0])[0]) == -1
    frame = interaction_rows(rollouts, disc)
    assert len(frame) == sum(len(r.moves) for r in rollouts)
    assert not frame[[*EEF_COLUMNS, *OBJECT_COLUMNS, *MOVE_COLUMNS]].isna().any().any()
    assert len(disc.discretize(frame)) == len(frame)


def test_noveb_acquisition_needs_a_camera(tmp_path: Path) -> None:
    from a2l.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["experiment", "push", "--scene", "virtual", "--acquisition", "noveb",
              "--out", str(tmp_path / "x")])
    assert exc.value.code == 2
    with Executor(workers=1) as ex, pytest.raises(ValueError, match="camera"):
        noveb_acquire(FrameworkConfig(scene="virtual"), ex, evaluations=2)
