"""The one learn -> compile -> bundle pipeline (:func:`a2l.skills.pipeline.learn_bundle`),
used by the framework and LfD (one pipeline for both): its bundle is byte for byte the one the steps
called one by one write, its metadata may depend on the rows kept, and an empty dataset is
refused naming the skill."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from a2l.skills import (
    Discretizer,
    MovementRepertoire,
    compile_policy,
    learn_network,
    load_bundle,
    make_skill_spec,
    push_dataset,
    save_bundle,
)
from a2l.skills.pipeline import learn_bundle


@pytest.mark.parametrize("structure", ["hc-k2", "hand-coded"])
def test_pipeline_writes_the_bundle_of_the_steps(tmp_path: Path, structure: str) -> None:
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    raw = push_dataset(600, seed=3)
    constraints = {"fixed_parents": ["effect"]} if structure == "hc-k2" else {}
    discrete = disc.discretize(raw)
    net = learn_network(discrete, structure, state_names=disc.state_names(), **constraints)
    spec = make_skill_spec(compile_policy(net, "move", disc.evidence), disc, name="push",
                           step_cap=9, smoothing=True, extra={"n": len(discrete)})
    steps = save_bundle(spec, tmp_path / "steps.a2lb")
    learned = learn_bundle(raw, disc, tmp_path / "pipeline.a2lb", name="push",
                           structure=structure, constraints=constraints, step_cap=9,
                           smoothing=True, extra=lambda rows: {"n": rows})
    assert learned.path.read_bytes() == steps.read_bytes()
    assert learned.rows == len(discrete) and load_bundle(learned.path).extra["n"] == len(discrete)
    assert set(learned.timings) == {"discretize", "learn", "compile", "save"}
    assert learned.table.target == "move" and learned.spec.name == "push"


def test_pipeline_refuses_an_empty_dataset(tmp_path: Path) -> None:
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    empty = push_dataset(50, seed=0).iloc[:0]
    assert isinstance(empty, pd.DataFrame)
    with pytest.raises(ValueError, match="skill 'push': the dataset has no usable row"):
        learn_bundle(empty, disc, tmp_path / "x.a2lb", name="push")
    assert not (tmp_path / "x.a2lb").exists()
