"""K2Score against an independent computation of the K2 formula."""

from __future__ import annotations

import itertools
import math
from collections import Counter

import numpy as np
import pandas as pd
import pytest
from pgmpy.causal_discovery import ExpertKnowledge, HillClimbSearch
from pgmpy.structure_score import K2

from a2l.skills import K2Score


def k2_formula(df: pd.DataFrame, child: str, parents: list[str], states: dict) -> float:
    """K2 = sum over ALL q parent configurations j of
    lgamma(r) - lgamma(N_j + r) + sum_k lgamma(N_jk + 1), with plain Python counting."""
    r = len(states[child])
    n_jk = Counter(zip(*(df[p] for p in parents), df[child], strict=True))
    total = 0.0
    for config in itertools.product(*(states[p] for p in parents)):
        counts = [n_jk.get((*config, k), 0) for k in states[child]]
        total += math.lgamma(r) - math.lgamma(sum(counts) + r)
        total += sum(math.lgamma(c + 1) for c in counts)
    return total


def _random_data(n: int, cards: dict[str, int], seed: int) -> tuple[pd.DataFrame, dict]:
    rng = np.random.default_rng(seed)
    df = pd.DataFrame({v: rng.integers(0, c, n) for v, c in cards.items()})
    # make the child depend on two parents so the score is not that of pure noise
    df["x"] = (df["x"] + df["p0"] * (df["p1"] % 2)) % cards["x"]
    return df, {v: list(range(c)) for v, c in cards.items()}


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_k2_equals_the_formula_with_unseen_parent_configurations(seed: int) -> None:
    cards = {"x": 4, "p0": 4, "p1": 5, "p2": 3, "p3": 6, "p4": 4}
    df, states = _random_data(1000, cards, seed)
    parents = ["p0", "p1", "p2", "p3", "p4"]
    q = math.prod(cards[p] for p in parents)
    observed = len(df[parents].drop_duplicates())
    assert observed < 1000 < q  # most of the 1,440 configurations are missing
    ours = K2Score(df, state_names=states).local_score("x", tuple(parents))
    assert ours == pytest.approx(k2_formula(df, "x", parents, states), rel=1e-12, abs=1e-9)


def test_k2_every_parent_set_and_order() -> None:
    cards = {"x": 3, "p0": 2, "p1": 7, "p2": 3, "p3": 2, "p4": 5}
    df, states = _random_data(300, cards, 7)
    score = K2Score(df, state_names=states)
    names = ["p0", "p1", "p2", "p3", "p4"]
    for k in range(0, 4):
        for parents in itertools.combinations(names, k):
            expected = k2_formula(df, "x", list(parents), states)
            for perm in itertools.permutations(parents):
                assert score.local_score("x", perm) == pytest.approx(expected, rel=1e-12, abs=1e-9)


def test_k2_counts_declared_but_unobserved_states() -> None:
    df = pd.DataFrame({"x": [0, 1, 1, 0, 1], "p": ["a", "a", "b", "b", "b"]})
    states = {"x": [0, 1, 2], "p": ["a", "b", "c"]}  # x = 2 and p = "c" never occur
    expected = k2_formula(df, "x", ["p"], states)
    assert K2Score(df, state_names=states).local_score("x", ("p",)) == pytest.approx(expected)
    cat = df.assign(x=pd.Categorical(df["x"], categories=[0, 1, 2]))
    cat["p"] = pd.Categorical(df["p"], categories=["a", "b", "c"])
    assert K2Score(cat).local_score("x", ("p",)) == pytest.approx(expected)


def test_k2_agrees_with_pgmpy_when_every_configuration_is_observed() -> None:
    cards = {"x": 3, "p0": 2, "p1": 3, "p2": 2, "p3": 2, "p4": 2}
    df, states = _random_data(5000, cards, 3)
    parents = ("p0", "p1", "p2")
    assert len(df[list(parents)].drop_duplicates()) == 12
    ours = K2Score(df, state_names=states).local_score("x", parents)
    assert ours == pytest.approx(K2(df, state_names=states).local_score("x", parents), rel=1e-12)


def test_k2_rejects_bad_data() -> None:
    df = pd.DataFrame({"x": [0, 1, None], "p": [0, 1, 1]})
    with pytest.raises(ValueError, match="'x' has missing value"):
        K2Score(df)
    df = pd.DataFrame({"x": [0, 1, 3], "p": [0, 1, 1]})
    with pytest.raises(ValueError, match="'x' has .*not in its states: \\['3'\\]"):
        K2Score(df, state_names={"x": [0, 1, 2]})


def test_k2score_drives_pgmpy_hill_climbing() -> None:
    rng = np.random.default_rng(11)
    n = 5000
    a = rng.integers(0, 3, n)
    b = rng.integers(0, 4, n)
    noise = rng.random(n) < 0.2
    c = np.where(noise, rng.integers(0, 3, n), (a + b) % 3)  # c depends on a and b jointly
    df = pd.DataFrame({"a": a, "b": b, "c": c, "d": rng.integers(0, 2, n)})
    forbid = [("c", "a"), ("c", "b"), ("a", "b"), ("b", "a")]
    hc = HillClimbSearch(
        scoring_method=K2Score(df),
        expert_knowledge=ExpertKnowledge(forbidden_edges=forbid),
        return_type="dag",
        show_progress=False,
    )
    dag = hc.fit(df).causal_graph_
    assert set(dag.edges()) == {("a", "c"), ("b", "c")}
