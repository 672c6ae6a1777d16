"""Learning the action generator's Bayesian network (structure and parameters).

Structure: hill-climbing with :class:`~a2l.skills.k2.K2Score` (``"hc-k2"``), or the
hand-coded baseline where every other variable is a parent of ``move`` (``"hand-coded"``).
Parameters: Bayesian estimation with a BDeu (or K2) Dirichlet prior, so that a parent
configuration never seen in the data gives a uniform conditional, not a crash or a zero.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Mapping, Sequence

import pandas as pd
from pgmpy.base import DAG
from pgmpy.causal_discovery import ExpertKnowledge, HillClimbSearch
from pgmpy.models import DiscreteBayesianNetwork
from pgmpy.parameter_estimator import DiscreteBayesianEstimator

from a2l.skills.k2 import K2Score
from a2l.skills.states import as_state_names, state_codes

__all__ = ["STRUCTURES", "hand_coded_structure", "learn_network", "learn_structure"]

#: Structure-learning methods of :func:`learn_network`.
STRUCTURES = ("hc-k2", "hand-coded")

Edge = tuple[str, str]


def hand_coded_structure(variables: Sequence[str], target: str = "move") -> DAG:
    """The baseline structure: every variable is a parent of `target`, no other edge.

    Parameters
    ----------
    variables : sequence of str
        All variables (including `target`).
    target : str
        The movement variable.

    Returns
    -------
    pgmpy.base.DAG
    """
    if target not in variables:
        raise ValueError(f"target {target!r} is not among the variables {list(variables)}")
    dag = DAG()
    dag.add_nodes_from(variables)
    dag.add_edges_from((v, target) for v in variables if v != target)
    return dag


def _check_edges(edges: Iterable[Edge], variables: Sequence[str], what: str) -> list[Edge]:
    out = []
    for e in edges:
        if len(e) != 2:
            raise ValueError(f"{what}: an edge is a (parent, child) pair, got {e!r}")
        for v in e:
            if v not in variables:
                raise ValueError(f"{what}: edge {tuple(e)} names {v!r}, not a dataset column")
        out.append((e[0], e[1]))
    return out


def learn_structure(
    df: pd.DataFrame,
    *,
    target: str = "move",
    target_has_no_children: bool = True,
    black_list: Iterable[Edge] = (),
    white_list: Iterable[Edge] = (),
    fixed_parents: Iterable[str] = (),
    max_indegree: int | None = None,
    state_names: Mapping[str, Sequence] | None = None,
    tabu_length: int = 100,
    epsilon: float = 1e-4,
    max_iter: int = 1_000_000,
) -> DAG:
    """Hill-climbing with the K2 score under structural constraints.

    Parameters
    ----------
    df : pandas.DataFrame, shape (n_rows, n_variables)
        Discrete dataset (e.g. from :meth:`a2l.skills.Discretizer.discretize`).
    target : str
        The movement variable.
    target_has_no_children : bool
        Forbid every edge out of `target` (the movement is inferred, it explains nothing).
    black_list : iterable of (str, str)
        Forbidden edges.
    white_list : iterable of (str, str)
        If not empty, the only edges the search may add (every other edge is forbidden).
    fixed_parents : iterable of str
        Variables that must be parents of `target` in the result (the configurations'
        ``fixed_parents``: :class:`a2l.framework.FrameworkConfig`, the LfD skills' effect and
        states).
    max_indegree : int or None
        Most parents a variable may have.
    state_names : mapping, optional
        States of each variable (see :class:`~a2l.skills.k2.K2Score`).
    tabu_length, epsilon, max_iter
        Passed to :class:`pgmpy.causal_discovery.HillClimbSearch`.

    Returns
    -------
    pgmpy.base.DAG
        The learned structure, over every column of `df`.
    """
    variables = [str(c) for c in df.columns]
    if target not in variables:
        raise ValueError(f"dataset has no column {target!r} (the target); it has {variables}")
    forbidden = set(_check_edges(black_list, variables, "black_list"))
    bad = [v for v in fixed_parents if v not in variables or v == target]
    if bad:
        raise ValueError(f"fixed_parents: {bad} not dataset columns other than the target "
                         f"{target!r}; they are {[v for v in variables if v != target]}")
    required = {(v, target) for v in fixed_parents}
    allowed = set(_check_edges(white_list, variables, "white_list"))
    if allowed:
        forbidden |= {(a, b) for a in variables for b in variables if a != b} - allowed - required
    if target_has_no_children:
        forbidden |= {(target, v) for v in variables if v != target}
    clash = forbidden & required
    if clash:
        raise ValueError(f"edges both required and forbidden: {sorted(clash)}")
    score = K2Score(df, state_names=state_names)
    search = HillClimbSearch(
        scoring_method=score,
        tabu_length=tabu_length,
        max_indegree=max_indegree,
        expert_knowledge=ExpertKnowledge(
            forbidden_edges=sorted(forbidden), required_edges=sorted(required)
        ),
        return_type="dag",
        epsilon=epsilon,
        max_iter=max_iter,
        show_progress=False,
    )
    search.fit(df)
    dag = DAG()
    dag.add_nodes_from(variables)
    dag.add_edges_from(search.causal_graph_.edges())
    return dag


def learn_network(
    df: pd.DataFrame,
    structure: str = "hc-k2",
    *,
    target: str = "move",
    state_names: Mapping[str, Sequence] | None = None,
    prior_type: str = "BDeu",
    equivalent_sample_size: float = 5.0,
    **constraints: object,
) -> DiscreteBayesianNetwork:
    """Learn a fitted Bayesian network (structure + parameters) from a discrete dataset.

    Parameters
    ----------
    df : pandas.DataFrame, shape (n_rows, n_variables)
        Discrete dataset; categorical columns keep their unseen categories as states.
    structure : {"hc-k2", "hand-coded"}
        Hill-climbing with :class:`~a2l.skills.k2.K2Score`, or every variable → `target`.
    target : str
        The movement variable.
    state_names : mapping of str to sequence, optional
        States of each variable, in index order; default: categories, else sorted values.
    prior_type : {"BDeu", "K2"}
        Dirichlet prior of the parameters (pgmpy's ``DiscreteBayesianEstimator``).
    equivalent_sample_size : float
        BDeu's equivalent sample size.
    **constraints
        For ``"hc-k2"``: the keyword arguments of :func:`learn_structure`
        (``target_has_no_children=True``, ``black_list``, ``white_list``, ``fixed_parents``,
        ``max_indegree``, ``tabu_length``, ``epsilon``, ``max_iter``).

    Returns
    -------
    pgmpy.models.DiscreteBayesianNetwork
        Fitted network whose CPDs list every state of :func:`state_names` (in that order).

    Raises
    ------
    ValueError
        Unknown `structure`, a constraint for the hand-coded structure, an unknown
        constraint, a missing target column, or an empty dataset.
    """
    if structure not in STRUCTURES:
        raise ValueError(f"structure must be one of {STRUCTURES}, got {structure!r}")
    if len(df) == 0:
        raise ValueError("dataset is empty: nothing to learn from")
    if target not in df.columns:
        raise ValueError(
            f"dataset has no column {target!r} (the target); it has {list(df.columns)}"
        )
    names = as_state_names(df, state_names)
    if structure == "hand-coded":
        if constraints:
            raise ValueError(
                f"the hand-coded structure takes no constraints, got {sorted(constraints)}"
            )
        dag = hand_coded_structure([str(c) for c in df.columns], target)
    else:
        known = {
            "target_has_no_children",
            "black_list",
            "white_list",
            "fixed_parents",
            "max_indegree",
            "tabu_length",
            "epsilon",
            "max_iter",
        }
        unknown = set(constraints) - known
        if unknown:
            raise ValueError(f"unknown constraint(s) {sorted(unknown)}; known: {sorted(known)}")
        dag = learn_structure(df, target=target, state_names=names, **constraints)  # type: ignore[arg-type]
    model = DiscreteBayesianNetwork(dag.edges())
    model.add_nodes_from(dag.nodes())
    data = pd.DataFrame(
        {
            c: pd.Categorical.from_codes(state_codes(df[c], names[c], str(c)), names[c])
            for c in df.columns
        }
    )
    estimator = DiscreteBayesianEstimator(
        state_names=names, prior_type=prior_type, equivalent_sample_size=equivalent_sample_size
    )
    pgmpy_logger = logging.getLogger("pgmpy")
    level = pgmpy_logger.level
    pgmpy_logger.setLevel(logging.WARNING)  # pgmpy logs its dtype inference at INFO
    try:
        model.fit(data, estimator=estimator)
    finally:
        pgmpy_logger.setLevel(level)
    return model
