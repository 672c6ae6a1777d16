"""learn_network: structure recovery, constraints, Bayesian parameters."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from pgmpy.models import DiscreteBayesianNetwork

from a2l.skills import (
    Discretizer,
    HighLevelState,
    compile_policy,
    known_structure_dataset,
    learn_network,
    learn_structure,
)


def test_hill_climbing_recovers_the_parents_of_move_at_1e5_rows() -> None:
    disc = Discretizer(high_level=(HighLevelState("light", ("off", "on")),))
    for seed, parents in ((0, ("effect", "orientation", "distance")), (1, ("effect", "light"))):
        df, truth = known_structure_dataset(
            100_000, seed=seed, discretizer=disc, move_parents=parents
        )
        net = learn_network(df, "hc-k2", target_has_no_children=True)
        assert set(net.get_parents("move")) == set(truth.parents["move"]) == set(parents)
        assert list(net.get_children("move")) == []
        # the other variables are independent in the truth: no edge among them either
        assert set(net.edges()) == {(p, "move") for p in parents}


def test_move_gets_children_without_the_constraint() -> None:
    # With the constraint off, nothing stops the search from orienting edges out of move:
    # on data where move is a parent of the effect, it does.
    df, _ = known_structure_dataset(20_000, seed=2, move_parents=("orientation",))
    rng = np.random.default_rng(0)
    codes = df["move"].cat.codes.to_numpy() % 4
    noisy = np.where(rng.random(len(df)) < 0.9, codes, rng.integers(0, 4, len(df)))
    df["effect"] = pd.Categorical.from_codes(noisy, categories=df["effect"].cat.categories)
    free = learn_structure(df, target_has_no_children=False)
    assert set(free.get_parents("move")) | set(free.get_children("move")) >= {"effect"}
    constrained = learn_structure(df)
    assert list(constrained.get_children("move")) == []
    assert "effect" in constrained.get_parents("move")


def test_constraints_black_white_fixed_indegree() -> None:
    df, _ = known_structure_dataset(20_000, seed=3)
    dag = learn_structure(df, black_list=[("orientation", "move")])
    assert "orientation" not in dag.get_parents("move")
    dag = learn_structure(df, max_indegree=1)
    assert all(len(dag.get_parents(v)) <= 1 for v in dag.nodes())
    dag = learn_structure(df, white_list=[("effect", "move"), ("distance", "move")])
    assert set(dag.edges()) <= {("effect", "move"), ("distance", "move")}
    dag = learn_structure(df, fixed_parents=["inclination"])
    assert "inclination" in dag.get_parents("move")
    with pytest.raises(ValueError, match="both required and forbidden"):
        learn_structure(df, fixed_parents=["inclination"], black_list=[("inclination", "move")])
    with pytest.raises(ValueError, match=r"fixed_parents: \['speed'\] not dataset columns"):
        learn_structure(df, fixed_parents=["speed"])
    with pytest.raises(ValueError, match="'speed'"):
        learn_structure(df, black_list=[("speed", "move")])


def test_hand_coded_structure() -> None:
    df, _ = known_structure_dataset(2_000, seed=4)
    net = learn_network(df, "hand-coded")
    assert isinstance(net, DiscreteBayesianNetwork)
    assert set(net.get_parents("move")) == {"effect", "distance", "orientation", "inclination"}
    assert len(net.edges()) == 4
    net.check_model()


def test_unseen_evidence_gives_a_uniform_posterior() -> None:
    # 200 rows cannot cover the 4 x 3 x 16 x 8 = 1,536 parent configurations of the
    # hand-coded structure: BDeu must give those it never saw a uniform distribution.
    df, _ = known_structure_dataset(200, seed=5)
    net = learn_network(df, "hand-coded", equivalent_sample_size=5)
    cpd = net.get_cpds("move")
    assert list(cpd.state_names["move"]) == list(df["move"].cat.categories)
    table = compile_policy(net, "move", ["effect", "distance", "orientation", "inclination"])
    seen = {(table.states["effect"].index(e), *rest) for e, *rest in df[table.variables].to_numpy()}
    for idx in np.ndindex(*table.shape):
        row = table.values[idx]
        if idx in seen:
            assert table.argmax_indices[idx] >= 0
            assert row.max() > 1 / 26 + 1e-3
        else:
            np.testing.assert_allclose(row, 1 / 26, atol=1e-12)
            assert table.argmax_indices[idx] == -1
    assert 0 < len(seen) < np.prod(table.shape)


def test_learn_network_errors_name_the_problem() -> None:
    df, _ = known_structure_dataset(500, seed=6)
    with pytest.raises(ValueError, match="structure must be one of"):
        learn_network(df, "pc")
    with pytest.raises(ValueError, match="no constraints"):
        learn_network(df, "hand-coded", max_indegree=2)
    with pytest.raises(ValueError, match="unknown constraint.*max_parents"):
        learn_network(df, "hc-k2", max_parents=2)
    with pytest.raises(ValueError, match="no column 'move'"):
        learn_network(df.drop(columns=["move"]))
    with pytest.raises(ValueError, match="empty"):
        learn_network(df.iloc[:0])
    states = {"distance": [0, 1]}  # the data has distance 2 as well
    with pytest.raises(ValueError, match="'distance'.*not in its states.*2"):
        learn_network(df, "hand-coded", state_names=states)
    with pytest.raises(ValueError, match="'distance'.*not in its states"):
        learn_network(df, "hc-k2", state_names=states)
