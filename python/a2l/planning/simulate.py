"""What a plan should do to the facts: STRIPS progression of a repertoire's skills.

The executor (``docs/planning.md``) compares the facts it perceives after each skill with
the facts predicted here: an effect not produced, or a world changed behind the robot's
back, shows up as a difference and triggers replanning.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from a2l.errors import A2LValueError
from a2l.planning.pddl import Literal, Skill, parse_literal
from a2l.planning.planners import PlanStep

__all__ = ["apply_step", "goal_literals", "simulate_plan", "unmet"]


def _ground(lit: Literal, binding: dict[str, str]) -> str:
    return "(" + " ".join((lit.predicate, *(binding.get(a, a) for a in lit.args))) + ")"


def apply_step(skills: Sequence[Skill], facts: Iterable[str], step: PlanStep) -> frozenset[str]:
    """The facts after `step` (its skill's add and delete effects).

    Raises
    ------
    a2l.A2LValueError
        Unknown skill, wrong number of arguments, or a precondition that does not hold
        (the message names it).
    """
    by_name = {s.name: s for s in skills}
    skill = by_name.get(step.name)
    if skill is None:
        raise A2LValueError(f"plan step {step}: no skill named {step.name!r}")
    if len(step.args) != len(skill.parameters):
        raise A2LValueError(f"plan step {step}: {skill.name} takes {len(skill.parameters)} "
                            "arguments")
    binding = {v: a.lower() for (v, _), a in zip(skill.parameters, step.args, strict=True)}
    now = {parse_literal(f).text() for f in facts}
    for lit in skill.preconditions:
        g = _ground(lit, binding)
        if g not in now:
            raise A2LValueError(f"plan step {step}: precondition {g} does not hold")
    for lit in skill.effect_literals:
        if lit.negated:
            now.discard(_ground(lit, binding))
    for lit in skill.effect_literals:
        if not lit.negated:
            now.add(_ground(lit, binding))
    return frozenset(now)


def simulate_plan(skills: Sequence[Skill], facts: Iterable[str],
                  plan: Sequence[PlanStep]) -> list[frozenset[str]]:
    """The facts before the plan and after each step, (len(plan) + 1) sets."""
    out = [frozenset(parse_literal(f).text() for f in facts)]
    for step in plan:
        out.append(apply_step(skills, out[-1], step))
    return out


def goal_literals(goal: str) -> list[str]:
    """The atoms of a conjunctive goal ``(and (p a) (q))`` or ``(p a)``."""
    text = goal.strip().lower()
    inner = text[1:-1].strip()
    if inner.startswith("and"):
        text = inner[3:]
    out, depth, start = [], 0, -1
    for i, ch in enumerate(text):
        if ch == "(":
            if depth == 0:
                start = i
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                out.append(parse_literal(text[start:i + 1]).text())
    return out


def unmet(goal: str, facts: Iterable[str]) -> list[str]:
    """Goal atoms that do not hold in `facts`."""
    now = {parse_literal(f).text() for f in facts}
    return [g for g in goal_literals(goal) if g not in now]
