"""compile_policy against pgmpy's VariableElimination on every evidence combination."""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import pytest
from pgmpy.factors.discrete import TabularCPD
from pgmpy.inference import VariableElimination
from pgmpy.models import DiscreteBayesianNetwork

from a2l.skills import (
    Discretizer,
    HighLevelState,
    InclinationBins,
    MovementRepertoire,
    OrientationBins,
    PolicyTable,
    compile_policy,
    known_structure_dataset,
    learn_network,
    push_dataset,
)
from a2l.skills.compile import TIE_TOLERANCE


def _ve_argmax(p: np.ndarray, tol: float) -> int:
    if np.all(np.abs(p - 1 / p.size) <= tol):
        return -1
    return int(np.flatnonzero(p >= p.max() - TIE_TOLERANCE)[0])


def assert_matches_variable_elimination(
    net: DiscreteBayesianNetwork, table: PolicyTable, evidence: list[str]
) -> int:
    """Every combination of every evidence variable (the ignored ones too) → VE posterior."""
    ve = VariableElimination(net)
    states = {v: list(net.get_cpds(v).state_names[v]) for v in evidence}
    n = 0
    for combo in itertools.product(*(states[v] for v in evidence)):
        ev = dict(zip(evidence, combo, strict=True))
        q = ve.query([table.target], evidence=ev, show_progress=False)
        order = [q.state_names[table.target].index(s) for s in table.target_states]
        p_ve = np.asarray(q.values, dtype=np.float64)[order]
        mine = table.posterior(ev)
        p_mine = np.array([mine[s] for s in table.target_states])
        np.testing.assert_allclose(p_mine, p_ve, rtol=0, atol=1e-9)
        a_ve = _ve_argmax(p_ve, table.uniform_tolerance)
        a_mine = int(table.argmax_indices[table.index(ev)])
        if a_mine != a_ve:  # only a tie within 1e-9 may break differently
            assert a_mine >= 0 and a_ve >= 0 and abs(p_ve[a_mine] - p_ve[a_ve]) < 1e-9
        assert table.argmax(ev) == (None if a_mine < 0 else table.target_states[a_mine])
        n += 1
    return n


def test_learned_push_network_matches_variable_elimination() -> None:
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    data = disc.discretize(push_dataset(1500, seed=3))
    net = learn_network(data, "hc-k2")
    table = compile_policy(net, "move", disc.evidence)
    assert set(table.variables) == set(net.get_parents("move"))
    assert set(table.variables) | set(table.ignored) == set(disc.evidence)
    assert (table.argmax_indices == -1).any() and (table.argmax_indices >= 0).any()
    n = assert_matches_variable_elimination(net, table, table.variables)
    assert n == np.prod(table.shape) >= 48


def test_markov_blanket_with_children_matches_variable_elimination() -> None:
    # move -> effect <- light: with the constraint off, move has a child and a co-parent
    disc = Discretizer(
        orientation=OrientationBins(8),
        inclination=InclinationBins(2),
        movements=MovementRepertoire(planar=True),
        high_level=(HighLevelState("light", ("off", "on")),),
    )
    df, _ = known_structure_dataset(30_000, seed=1, discretizer=disc, move_parents=("orientation",))
    rng = np.random.default_rng(1)
    m = df["move"].cat.codes.to_numpy()
    light = df["light"].cat.codes.to_numpy()
    eff = np.where(rng.random(len(df)) < 0.8, (m + light) % 4, rng.integers(0, 4, len(df)))
    df["effect"] = pd.Categorical.from_codes(eff, categories=df["effect"].cat.categories)
    net = learn_network(df, "hc-k2", target_has_no_children=False)
    blanket = set(net.get_markov_blanket("move"))
    assert net.get_children("move"), "the test needs move to have a child"
    table = compile_policy(net, "move", disc.evidence)
    assert set(table.variables) == blanket
    assert table.variables == [v for v in disc.evidence if v in blanket]  # caller's axis order
    assert_matches_variable_elimination(net, table, disc.evidence)


def _random_network(seed: int) -> DiscreteBayesianNetwork:
    """A -> M <- H <- B, M -> C <- D, H -> F, E alone; cards 2..4."""
    rng = np.random.default_rng(seed)
    edges = [("A", "M"), ("H", "M"), ("B", "H"), ("M", "C"), ("D", "C"), ("H", "F")]
    net = DiscreteBayesianNetwork(edges)
    net.add_node("E")
    card = {"A": 3, "B": 2, "C": 3, "D": 2, "E": 2, "F": 3, "H": 4, "M": 4}
    for v in net.nodes():
        parents = sorted(net.get_parents(v))
        cols = int(np.prod([card[p] for p in parents]))
        values = rng.dirichlet(np.ones(card[v]), size=cols).T
        net.add_cpds(
            TabularCPD(
                v,
                card[v],
                values,
                evidence=parents or None,
                evidence_card=[card[p] for p in parents] or None,
                state_names={u: [f"{u}{i}" for i in range(card[u])] for u in [v, *parents]},
            )
        )
    net.check_model()
    return net


@pytest.mark.parametrize("seed", [0, 1])
def test_hidden_variables_are_summed_out(seed: int) -> None:
    net = _random_network(seed)
    evidence = ["E", "D", "C", "B", "A"]  # H hidden (summed out), F hidden and barren
    table = compile_policy(net, "M", evidence)
    assert table.variables == ["D", "C", "B", "A"]
    assert table.ignored == ["E"]
    assert_matches_variable_elimination(net, table, evidence)
    # H observed: B is then d-separated from M
    table_h = compile_policy(net, "M", ["A", "B", "C", "D", "H"])
    assert table_h.variables == ["A", "C", "D", "H"] and table_h.ignored == ["B"]
    assert_matches_variable_elimination(net, table_h, ["A", "B", "C", "D", "H"])


def test_memory_budget_slices_give_the_same_table(monkeypatch: pytest.MonkeyPatch) -> None:
    net = _random_network(2)
    evidence = ["A", "B", "C", "D"]  # cards 3, 2, 3, 2; M 4 and hidden H 4
    calls = []
    einsum = np.einsum
    monkeypatch.setattr(np, "einsum", lambda *a, **k: calls.append(1) or einsum(*a, **k))
    whole = compile_policy(net, "M", evidence)
    assert len(calls) == 1
    # working set 3*2*3*2*4*4 * 16 B = 9,216 B: slicing the first 4, 3, 2 axes fits
    for budget, n_slices in ((300, 36), (600, 18), (2000, 6)):
        calls.clear()
        sliced = compile_policy(net, "M", evidence, memory_budget=budget)
        assert len(calls) == n_slices
        np.testing.assert_array_equal(whole.argmax_indices, sliced.argmax_indices)
        np.testing.assert_allclose(whole.values, sliced.values, rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="memory_budget"):
        compile_policy(net, "M", evidence, memory_budget=16)


def test_rows_are_distributions() -> None:
    disc = Discretizer(movements=MovementRepertoire(planar=True))
    net = learn_network(disc.discretize(push_dataset(300, seed=4)), "hand-coded")
    table = compile_policy(net, "move", disc.evidence)
    assert table.values.dtype == np.float64 and table.argmax_indices.dtype == np.int32
    np.testing.assert_allclose(table.values.sum(axis=-1), 1.0, atol=1e-12)
    assert (table.values >= 0).all()
    best = table.argmax_indices
    np.testing.assert_array_equal(
        table.max_probability[best >= 0],
        np.take_along_axis(table.values, np.maximum(best, 0)[..., None], -1)[..., 0][best >= 0],
    )


def test_policy_table_errors_name_the_problem() -> None:
    net = _random_network(3)
    table = compile_policy(net, "M", ["A", "B", "C", "D", "E"])
    ev = {"A": "A0", "B": "B1", "C": "C2", "D": "D0"}
    assert sum(table.posterior(ev).values()) == pytest.approx(1.0)
    assert table.posterior({**ev, "E": "E1"}) == table.posterior(ev)  # E is ignored
    with pytest.raises(ValueError, match="missing variable 'D'"):
        table.posterior({k: v for k, v in ev.items() if k != "D"})
    with pytest.raises(ValueError, match="unknown evidence variable.*'Z'"):
        table.argmax({**ev, "Z": 1})
    with pytest.raises(ValueError, match="'A' has no state 'A7'"):
        table.argmax({**ev, "A": "A7"})
    with pytest.raises(ValueError, match="not a variable"):
        compile_policy(net, "Q")
    with pytest.raises(ValueError, match="cannot be evidence"):
        compile_policy(net, "M", ["A", "M"])
    with pytest.raises(ValueError, match=r"\['Z'\] are not in the network"):
        compile_policy(net, "M", ["A", "Z"])
