"""Compiling a Bayesian network into a policy table: P(move | evidence) for every evidence
combination, with its argmax.

The table is built from the CPDs directly, not by one inference query per combination:

1. keep the ancestors of ``{target} ∪ evidence`` (other variables are barren: they sum to 1);
2. in the moral graph of what is kept, walk from the target through non-evidence ("hidden")
   variables: the evidence variables reached are exactly those not d-separated from the
   target by the rest of the evidence (the Markov blanket when nothing is hidden); they are
   the table's axes, the others do not change the posterior;
3. multiply the CPDs that touch the target or a reached hidden variable with one
   ``numpy.einsum`` per slice (summing the hidden variables out), then normalise over the
   target. Slices are fixed values of the leading axes, as few as keep each slice's working
   memory under ``memory_budget``.
"""

from __future__ import annotations

import itertools
import math
import string
from collections.abc import Hashable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from pgmpy.models import DiscreteBayesianNetwork

__all__ = ["PolicyTable", "compile_policy", "relevant_evidence"]

#: Probabilities within this of the maximum count as tied (the lowest index wins).
TIE_TOLERANCE = 1e-12


@dataclass
class PolicyTable:
    """A compiled action generator: the posterior over the target for every evidence
    combination.

    Attributes
    ----------
    target : str
        The inferred variable (``"move"``).
    target_states : list
        Its states, in the order of the last axis of :attr:`values`.
    variables : list of str
        The evidence variables that matter, in axis order.
    states : dict of str to list
        Each evidence variable's states, in index order.
    values : ndarray of float64, shape ``(*n_states, n_target_states)``
        P(target | evidence); every row sums to 1.
    argmax_indices : ndarray of int32, shape ``(*n_states,)``
        Index of the most probable target state (lowest on ties within 1e-12), or -1 where
        the row is uniform within :attr:`uniform_tolerance`.
    ignored : list of str
        Evidence variables that were asked for but do not change the posterior.
    uniform_tolerance : float
        A row whose entries all lie within this of 1/n_target_states is uniform.
    """

    target: str
    target_states: list
    variables: list[str]
    states: dict[str, list]
    values: np.ndarray
    argmax_indices: np.ndarray
    ignored: list[str] = field(default_factory=list)
    uniform_tolerance: float = 1e-9

    def __post_init__(self) -> None:
        shape = tuple(len(self.states[v]) for v in self.variables)
        if self.values.shape != (*shape, len(self.target_states)):
            raise ValueError(
                f"values has shape {self.values.shape}, "
                f"expected {(*shape, len(self.target_states))}"
            )
        if self.argmax_indices.shape != shape:
            raise ValueError(
                f"argmax_indices has shape {self.argmax_indices.shape}, expected {shape}"
            )
        self._lut = {v: {s: i for i, s in enumerate(self.states[v])} for v in self.variables}

    @property
    def shape(self) -> tuple[int, ...]:
        """Number of states of each evidence variable (the table's shape without the target)."""
        return tuple(self.argmax_indices.shape)

    @property
    def max_probability(self) -> np.ndarray:
        """Probability of the argmax, ndarray of float64, shape ``(*n_states,)``."""
        return self.values.max(axis=-1)

    def index(self, evidence: Mapping[str, Hashable]) -> tuple[int, ...]:
        """Axis indices of an evidence assignment.

        Parameters
        ----------
        evidence : mapping of str to state
            A state for every variable of :attr:`variables`; the :attr:`ignored` ones may
            be given too and are ignored.

        Raises
        ------
        ValueError
            A variable is missing, unknown, or its state is not one of its states.
        """
        extra = set(evidence) - set(self.variables) - set(self.ignored)
        if extra:
            raise ValueError(
                f"unknown evidence variable(s) {sorted(extra)}; the table takes {self.variables}"
            )
        idx = []
        for v in self.variables:
            if v not in evidence:
                raise ValueError(
                    f"evidence is missing variable {v!r}; the table takes {self.variables}"
                )
            s = evidence[v]
            i = self._lut[v].get(s)
            if i is None:
                raise ValueError(f"{v!r} has no state {s!r}; its states are {self.states[v]}")
            idx.append(i)
        return tuple(idx)

    def posterior(self, evidence: Mapping[str, Hashable]) -> dict[Hashable, float]:
        """P(target | evidence) as ``{target state: probability}``."""
        row = self.values[self.index(evidence)]
        return {s: float(p) for s, p in zip(self.target_states, row, strict=True)}

    def argmax(self, evidence: Mapping[str, Hashable]) -> Hashable | None:
        """The most probable target state, or None where the posterior is uniform (the
        network knows nothing about this context)."""
        i = int(self.argmax_indices[self.index(evidence)])
        return None if i < 0 else self.target_states[i]

    def probability(self, evidence: Mapping[str, Hashable]) -> float:
        """Probability of the most probable target state."""
        return float(self.values[self.index(evidence)].max())


def _moral_neighbours(network: DiscreteBayesianNetwork, nodes: set[str]) -> dict[str, set[str]]:
    nb: dict[str, set[str]] = {n: set() for n in nodes}
    for n in nodes:
        scope = [n, *network.get_parents(n)]
        for a in scope:
            for b in scope:
                if a != b:
                    nb[a].add(b)
    return nb


def relevant_evidence(
    network: DiscreteBayesianNetwork, target: str, evidence: Sequence[str]
) -> tuple[list[str], set[str], set[str]]:
    """The evidence variables that matter for the posterior of `target`.

    Returns
    -------
    relevant : list of str
        Evidence variables not d-separated from `target` by the other evidence, in the
        order of `evidence` (the Markov blanket of `target` when every other variable is
        evidence).
    hidden : set of str
        Non-evidence variables that must be summed out.
    kept : set of str
        The ancestral set of ``{target} ∪ evidence``.
    """
    ev = set(evidence)
    kept = {target} | ev
    for v in list(kept):
        kept |= _ancestors(network, v)
    nb = _moral_neighbours(network, kept)
    hidden: set[str] = set()
    reached_ev: set[str] = set()
    frontier = [target]
    seen = {target}
    while frontier:
        v = frontier.pop()
        for u in nb[v]:
            if u in seen:
                continue
            seen.add(u)
            if u in ev:
                reached_ev.add(u)
            else:
                hidden.add(u)
                frontier.append(u)
    return [e for e in evidence if e in reached_ev], hidden, kept


def _ancestors(network: DiscreteBayesianNetwork, v: str) -> set[str]:
    out = {v}
    stack = [v]
    while stack:
        for p in network.get_parents(stack.pop()):
            if p not in out:
                out.add(p)
                stack.append(p)
    return out


def compile_policy(
    network: DiscreteBayesianNetwork,
    target: str = "move",
    evidence: Sequence[str] | None = None,
    *,
    uniform_tolerance: float = 1e-9,
    memory_budget: int = 256 * 2**20,
) -> PolicyTable:
    """Compile the posterior over `target` for every combination of the evidence that matters.

    Parameters
    ----------
    network : pgmpy.models.DiscreteBayesianNetwork
        A fitted network (every variable has a CPD).
    target : str
        The inferred variable.
    evidence : sequence of str, optional
        The evidence variables, in the desired axis order; default: every other variable
        in the network's node order. Those that do not change the posterior are dropped
        (listed in :attr:`PolicyTable.ignored`).
    uniform_tolerance : float
        Rows within this of uniform get argmax -1.
    memory_budget : int
        Most bytes of working memory for one slice of the computation (the finished table
        itself, ``prod(shape) · (n_target · 8 + 4)`` bytes, is not counted).

    Returns
    -------
    PolicyTable

    Raises
    ------
    ValueError
        Unknown target or evidence variable, target among the evidence, a missing CPD,
        inconsistent state names, or a single slice that cannot fit in `memory_budget`.
    """
    evidence = _checked_evidence(network, target, evidence, memory_budget)
    relevant, hidden, kept = relevant_evidence(network, target, evidence)
    states, operands = _factors(network, kept, {target} | hidden)
    axes = [*relevant, target]
    if len(axes) + len(hidden) > 52:
        raise ValueError(f"too many variables for one einsum: {len(axes) + len(hidden)} > 52")
    card = {v: len(states[v]) for v in [*axes, *hidden]}
    out = _posteriors(operands, relevant, target, hidden, card, memory_budget)
    n_t = card[target]
    total = out.sum(axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        out /= total
    out[~np.isfinite(out).all(axis=-1)] = 1.0 / n_t  # evidence of probability 0: no information
    uniform = np.all(np.abs(out - 1.0 / n_t) <= uniform_tolerance, axis=-1)
    best = np.argmax(out >= out.max(axis=-1, keepdims=True) - TIE_TOLERANCE, axis=-1)
    argmax = np.where(uniform, -1, best).astype(np.int32)
    return PolicyTable(
        target=target,
        target_states=list(states[target]),
        variables=relevant,
        states={v: list(states[v]) for v in relevant},
        values=out,
        argmax_indices=argmax,
        ignored=[e for e in evidence if e not in relevant],
        uniform_tolerance=uniform_tolerance,
    )


def _checked_evidence(network: DiscreteBayesianNetwork, target: str,
                      evidence: Sequence[str] | None, memory_budget: int) -> list[str]:
    """The evidence variables (default: every variable but `target`, in node order), after
    checking them, the target and the memory budget."""
    nodes = set(network.nodes())
    if target not in nodes:
        raise ValueError(f"target {target!r} is not a variable of the network")
    if evidence is None:
        evidence = [str(v) for v in network.nodes() if v != target]
    evidence = list(evidence)
    unknown = [e for e in evidence if e not in nodes]
    if unknown:
        raise ValueError(f"evidence variable(s) {unknown} are not in the network")
    if target in evidence:
        raise ValueError(f"the target {target!r} cannot be evidence")
    if len(set(evidence)) != len(evidence):
        raise ValueError(f"evidence variables repeat: {evidence}")
    if not memory_budget > 0:
        raise ValueError(f"memory_budget must be positive, got {memory_budget}")
    return evidence


def _factors(network: DiscreteBayesianNetwork, kept: set[str], active: set[str]
             ) -> tuple[dict[str, list], list[tuple[np.ndarray, list[str]]]]:
    """The state names of every variable of the CPDs of `kept`, and the CPDs that touch an
    `active` (target or hidden) variable as ``(values shaped by cardinality, scope)``."""
    states: dict[str, list] = {}
    operands: list[tuple[np.ndarray, list[str]]] = []
    for node in sorted(kept):
        cpd = network.get_cpds(node)
        if cpd is None:
            raise ValueError(f"variable {node!r} has no CPD: fit the network first")
        scope = list(cpd.variables)
        for v in scope:
            sn = list(cpd.state_names[v])
            if states.setdefault(v, sn) != sn:
                raise ValueError(f"CPDs disagree on the states of {v!r}")
        if active & set(scope):
            vals = np.asarray(cpd.values, dtype=np.float64).reshape(cpd.cardinality)
            operands.append((vals, scope))
    return states, operands


def _posteriors(operands: list[tuple[np.ndarray, list[str]]], relevant: list[str],
                target: str, hidden: set[str], card: dict[str, int],
                memory_budget: int) -> np.ndarray:
    """The unnormalised joint of every `relevant` combination and `target`, shape
    ``(*cards of relevant, card of target)``, summed over `hidden` by einsum, in slices
    over the leading relevant axes small enough for `memory_budget`."""
    axes = [*relevant, target]
    letter = dict(zip([*axes, *sorted(hidden)], string.ascii_letters, strict=False))
    shape = tuple(card[v] for v in relevant)
    out = np.empty((*shape, card[target]), dtype=np.float64)
    # Working memory of a slice: the full product over its indices (an upper bound on any
    # einsum intermediate) plus the operands' slices, in float64.
    full = math.prod(card[v] for v in [*axes, *hidden]) * 8 * 2
    n_fixed = 0
    while n_fixed < len(relevant) and full // max(1, math.prod(shape[:n_fixed])) > memory_budget:
        n_fixed += 1
    if full // max(1, math.prod(shape[:n_fixed])) > memory_budget:
        raise ValueError(
            f"one slice needs ~{full // max(1, math.prod(shape)):,} bytes, over memory_budget "
            f"{memory_budget:,}: too many hidden states ({sorted(hidden)})"
        )
    fixed = relevant[:n_fixed]
    out_sub = "".join(letter[v] for v in axes[n_fixed:])
    for combo in itertools.product(*(range(card[v]) for v in fixed)):
        at = dict(zip(fixed, combo, strict=True))
        ops: list[np.ndarray] = []
        subs: list[str] = []
        for vals, scope in operands:
            index = tuple(at.get(v, slice(None)) for v in scope)
            ops.append(vals[index])
            subs.append("".join(letter[v] for v in scope if v not in at))
        expr = ",".join(subs) + "->" + out_sub
        out[combo] = np.einsum(expr, *ops, optimize=len(ops) > 2)
    return out
