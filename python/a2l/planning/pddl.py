"""PDDL from a skill repertoire: one operator per skill, a problem from a perceived state.

A :class:`Skill` is a planning operator written the way a skill is learned: the high-level
states it was learned under and what it needs become its preconditions, its effect
predicates its effects. :func:`domain_pddl` turns a repertoire (a list of skills) into a
STRIPS domain with types; :func:`problem_pddl` turns a perceived state (object regions,
high-level states, what the gripper holds) and a goal given as PDDL text into a problem.
Both are plain text a user can read, edit and rerun with any PDDL planner.

Literals are PDDL text, e.g. ``"(at ?o ?from)"``, ``"(light-on)"``; a delete effect is
``"(not (at ?o ?from))"``. Variables must be parameters of the skill; a predicate has the
same arity everywhere. High-level states are 0-ary predicates ``<state>-<value>``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from a2l.errors import A2LValueError

__all__ = [
    "Literal",
    "PerceivedState",
    "Skill",
    "domain_pddl",
    "parse_literal",
    "problem_pddl",
    "state_literal",
]

_NAME = re.compile(r"^[a-z][a-z0-9_-]*$")
_TYPES = ("region", "movable", "pressable")


@dataclass(frozen=True)
class Literal:
    """A parsed literal: predicate, arguments (variables ``?x`` or object names), sign."""

    predicate: str
    args: tuple[str, ...] = ()
    negated: bool = False

    def text(self) -> str:
        """The literal as PDDL text."""
        atom = "(" + " ".join((self.predicate, *self.args)) + ")"
        return f"(not {atom})" if self.negated else atom


def parse_literal(text: str) -> Literal:
    """Parse ``"(p a ?b)"`` or ``"(not (p a ?b))"``.

    Raises
    ------
    a2l.A2LValueError
        The text is not one literal with a valid predicate name.
    """
    tokens = text.replace("(", " ( ").replace(")", " ) ").split()
    negated = False
    if tokens[:2] == ["(", "not"] and tokens[-1:] == [")"]:
        negated, tokens = True, tokens[2:-1]
    if len(tokens) < 3 or tokens[0] != "(" or tokens[-1] != ")" or "(" in tokens[1:] or \
            ")" in tokens[1:-1]:
        raise A2LValueError(f"literal {text!r}: expected '(predicate args...)' or "
                            "'(not (predicate args...))'")
    pred, args = tokens[1].lower(), tuple(t.lower() for t in tokens[2:-1])
    if not _NAME.match(pred):
        raise A2LValueError(f"literal {text!r}: bad predicate name {pred!r}")
    return Literal(pred, args, negated)


def state_literal(state: str, value: str) -> str:
    """The 0-ary predicate of a high-level state value, e.g. ``("light", "on")`` ->
    ``"(light-on)"``."""
    return f"({state}-{value})".lower()


@dataclass(frozen=True)
class Skill:
    """One skill of the repertoire as a planning operator.

    Attributes
    ----------
    name : str
        Operator name (lower case, letters, digits, ``-``, ``_``), e.g. ``"push-left"``.
    parameters : tuple of (str, str)
        ``("?o", "movable")``, ... : variable and type (``region``, ``movable``, ``pressable``).
    learned_under : tuple of str
        Literals of the high-level states the skill was learned under, e.g.
        ``("(gripper-closed)",)``: preconditions.
    needs : tuple of str
        Further preconditions: where the object is, ``(hand-empty)`` to grasp, ...
    effects : tuple of str
        Effect literals (add, or ``(not ...)`` to delete).
    kind : str
        What executes it (``"push"``, ``"grasp"``, ``"place"``, ``"press"``, ``"gripper"``);
        the executor maps a plan step to a learned skill through ``kind`` and ``effect``.
    effect : str
        The effect the skill was learned for (METHOD's vocabulary: ``left``, ``grasped``...).
    """

    name: str
    parameters: tuple[tuple[str, str], ...]
    learned_under: tuple[str, ...] = ()
    needs: tuple[str, ...] = ()
    effects: tuple[str, ...] = ()
    kind: str = ""
    effect: str = ""
    _parsed: tuple[tuple[Literal, ...], tuple[Literal, ...]] = field(
        init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not _NAME.match(self.name):
            raise A2LValueError(f"skill name {self.name!r}: use lower-case letters, digits, "
                                "'-' and '_', starting with a letter")
        variables = set()
        for var, typ in self.parameters:
            if not var.startswith("?") or not _NAME.match(var[1:]):
                raise A2LValueError(f"skill {self.name}: bad parameter {var!r}")
            if typ not in _TYPES:
                raise A2LValueError(f"skill {self.name}: parameter {var} has type {typ!r}, "
                                    f"expected one of {_TYPES}")
            variables.add(var)
        pre = tuple(parse_literal(t) for t in (*self.learned_under, *self.needs))
        eff = tuple(parse_literal(t) for t in self.effects)
        if not eff:
            raise A2LValueError(f"skill {self.name}: no effect")
        for lit in pre:
            if lit.negated:
                raise A2LValueError(f"skill {self.name}: negative precondition {lit.text()} "
                                    "(STRIPS: use a positive state predicate instead)")
        for lit in (*pre, *eff):
            for a in lit.args:
                if a.startswith("?") and a not in variables:
                    raise A2LValueError(f"skill {self.name}: {lit.text()} uses {a}, which is "
                                        f"not a parameter ({sorted(variables)})")
        object.__setattr__(self, "_parsed", (pre, eff))

    @property
    def preconditions(self) -> tuple[Literal, ...]:
        """Parsed preconditions (learned_under, then needs)."""
        return self._parsed[0]

    @property
    def effect_literals(self) -> tuple[Literal, ...]:
        """Parsed effects."""
        return self._parsed[1]

    def pddl(self) -> str:
        """The ``(:action ...)`` block."""
        params = " ".join(f"{v} - {t}" for v, t in self.parameters)
        pre = _unique(lit.text() for lit in self.preconditions)
        eff = _unique(lit.text() for lit in self.effect_literals)
        return (f"  (:action {self.name}\n    :parameters ({params})\n"
                f"    :precondition (and {' '.join(pre)})\n"
                f"    :effect (and {' '.join(eff)}))")


def _unique(items: Iterable[str]) -> list[str]:
    return list(dict.fromkeys(items))


def _signatures(skills: Sequence[Skill]) -> dict[str, tuple[str, ...]]:
    """Predicate -> argument types, checked for one arity and one type per position."""
    sig: dict[str, tuple[str, ...]] = {}
    for s in skills:
        types = dict(s.parameters)
        for lit in (*s.preconditions, *s.effect_literals):
            t = tuple(types.get(a, "object") for a in lit.args)
            old = sig.get(lit.predicate)
            if old is None:
                sig[lit.predicate] = t
            elif len(old) != len(t):
                raise A2LValueError(f"predicate {lit.predicate} has {len(old)} arguments in one "
                                    f"skill and {len(t)} in {s.name}")
            elif old != t:  # different types at one position: widen to object
                sig[lit.predicate] = tuple(a if a == b else "object" for a, b in zip(old, t,
                                                                                   strict=True))
    return sig


def domain_pddl(skills: Sequence[Skill], name: str = "a2l") -> str:
    """The PDDL domain of a repertoire: types, predicates inferred from the skills, and one
    action per skill.

    Raises
    ------
    a2l.A2LValueError
        Empty repertoire, two skills with one name, a predicate used with two arities.
    """
    if not skills:
        raise A2LValueError("domain_pddl: the repertoire is empty")
    names = [s.name for s in skills]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise A2LValueError(f"domain_pddl: skills named more than once: {sorted(dup)}")
    sig = _signatures(skills)
    preds = "\n".join(
        "    (" + " ".join([p, *(f"?a{i} - {t}" for i, t in enumerate(types))]) + ")"
        for p, types in sorted(sig.items()))
    actions = "\n".join(s.pddl() for s in skills)
    return (f"(define (domain {name})\n  (:requirements :strips :typing)\n"
            f"  (:types {' '.join(_TYPES)} - object)\n  (:predicates\n{preds})\n"
            f"{actions}\n)\n")


@dataclass(frozen=True)
class PerceivedState:
    """What the robot perceives, in the planner's words.

    Attributes
    ----------
    regions : tuple of str
        Table regions (PDDL objects of type ``region``).
    movables : dict of str to str or None
        Movable object -> its region, or None while held.
    buttons : tuple of str
        Buttons (type ``pressable``).
    states : dict of str to str
        High-level states, e.g. ``{"light": "on", "gripper": "open"}``.
    holding : str or None
        The object in the gripper.
    static : tuple of str
        Facts that never change (region neighbourhood, e.g. ``"(left-of mid-left mid-centre)"``).
    """

    regions: tuple[str, ...]
    movables: Mapping[str, str | None]
    buttons: tuple[str, ...] = ()
    states: Mapping[str, str] = field(default_factory=dict)
    holding: str | None = None
    static: tuple[str, ...] = ()

    def facts(self) -> list[str]:
        """The initial facts."""
        out = [f"(at {o} {r})" for o, r in self.movables.items() if r is not None]
        out.append(f"(holding {self.holding})" if self.holding else "(hand-empty)")
        out += [state_literal(k, v) for k, v in sorted(self.states.items())]
        out += list(self.static)
        return _unique(out)


def _check_goal(goal: str, known: set[str], predicates: Mapping[str, int]) -> None:
    depth = 0
    for ch in goal:
        depth += {"(": 1, ")": -1}.get(ch, 0)
        if depth < 0:
            break
    if depth != 0 or "(" not in goal:
        raise A2LValueError(f"goal {goal!r}: unbalanced parentheses or not PDDL")
    for m in re.finditer(r"\(\s*([^\s()]+)([^()]*)\)", goal.lower()):
        pred, args = m.group(1), m.group(2).split()
        if pred not in predicates:
            raise A2LValueError(f"goal {goal!r}: unknown predicate {pred!r}; the domain has "
                                f"{sorted(predicates)}")
        if len(args) != predicates[pred]:
            raise A2LValueError(f"goal {goal!r}: {pred} takes {predicates[pred]} arguments, "
                                f"got {len(args)}")
        for a in args:
            if a not in known:
                raise A2LValueError(f"goal {goal!r}: unknown object {a!r}; the problem has "
                                    f"{sorted(known)}")


def problem_pddl(skills: Sequence[Skill], state: PerceivedState, goal: str,
                 name: str = "task", domain: str = "a2l") -> str:
    """The PDDL problem of reaching `goal` from `state`.

    Parameters
    ----------
    skills : sequence of Skill
        The repertoire (its predicates check the goal).
    state : PerceivedState
        The initial state.
    goal : str
        PDDL goal text: one atom or ``(and ...)`` of atoms, e.g.
        ``"(and (at block far-right) (light-off))"``.

    Raises
    ------
    a2l.A2LValueError
        The goal names an unknown predicate or object, or has the wrong arity.
    """
    sig = _signatures(skills)
    arity = {p: len(t) for p, t in sig.items()}
    objs = {"region": state.regions, "movable": tuple(state.movables),
            "pressable": state.buttons}
    known = {o for group in objs.values() for o in group}
    clash = sorted(known & (set(_TYPES) | set(arity) | {"object"}))
    if clash:
        raise A2LValueError(f"object names {clash} are also type or predicate names: rename them")
    for fact in state.facts():
        lit = parse_literal(fact)
        if lit.predicate not in arity:
            continue  # a fact no skill mentions is harmless: keep the problem readable
        for a in lit.args:
            if a not in known:
                raise A2LValueError(f"state fact {fact}: unknown object {a!r}")
    _check_goal(goal, known, arity)
    decl = "\n".join(f"    {' '.join(names)} - {t}" for t, names in objs.items() if names)
    init = "\n".join(f"    {f}" for f in state.facts()
                     if parse_literal(f).predicate in arity)
    goal_text = goal.strip().lower()
    return (f"(define (problem {name})\n  (:domain {domain})\n  (:objects\n{decl})\n"
            f"  (:init\n{init})\n  (:goal {goal_text})\n)\n")
