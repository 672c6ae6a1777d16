"""Skills as planning operators, and the table's regions.

The constructors here write the operator of each kind of learned skill: the high-level
states it was learned under become preconditions, what it needs is added (an empty hand to
push, grasp or press; the object held to place), and its effect predicates are the effects.
How a skill bundle maps onto them is described in ``docs/planning.md``.

Directions follow ``docs/method.md``: ``left`` is +y, ``right`` -y, ``close`` -x (towards the
robot), ``far`` +x; the diagonals combine them (``close_left``...).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from a2l.errors import A2LValueError
from a2l.planning.pddl import Skill, state_literal
from a2l.skills.effects import EFFECT_DIRECTIONS

__all__ = [
    "DIRECTIONS",
    "TableRegions",
    "gripper_skill",
    "tabletop_repertoire",
    "grasp_skill",
    "place_skill",
    "press_skills",
    "push_skill",
]

#: Effect name -> unit step in (x, y) region indices (the effect's direction,
#: :data:`a2l.skills.effects.EFFECT_DIRECTIONS`).
DIRECTIONS: dict[str, tuple[int, int]] = {
    e: (int(x), int(y)) for e, (x, y) in EFFECT_DIRECTIONS.items()
}


def _under(learned_under: Mapping[str, str]) -> tuple[str, ...]:
    return tuple(state_literal(k, v) for k, v in sorted(learned_under.items()))


def _direction_predicate(effect: str) -> str:
    return f"{effect.replace('_', '-')}-of"


def push_skill(effect: str, learned_under: Mapping[str, str] | None = None) -> Skill:
    """Push a movable object one region in direction `effect`.

    ``push-<effect> ?o ?from ?to``: needs ``(at ?o ?from)``, ``(<effect>-of ?to ?from)`` and
    an empty hand; moves the object to ``?to``.
    """
    if effect not in DIRECTIONS:
        raise A2LValueError(f"push_skill: effect {effect!r} is not one of {sorted(DIRECTIONS)}")
    name = f"push-{effect.replace('_', '-')}"
    return Skill(name, (("?o", "movable"), ("?from", "region"), ("?to", "region")),
                 learned_under=_under(learned_under or {}),
                 needs=("(at ?o ?from)", f"({_direction_predicate(effect)} ?to ?from)",
                        "(hand-empty)"),
                 effects=("(at ?o ?to)", "(not (at ?o ?from))"), kind="push", effect=effect)


def grasp_skill(learned_under: Mapping[str, str] | None = None) -> Skill:
    """Grasp a movable object and lift it: needs an empty hand and an open gripper (added to
    `learned_under`); the object is held, the gripper closed."""
    under = {"gripper": "open", **(learned_under or {})}
    return Skill("grasp", (("?o", "movable"), ("?r", "region")),
                 learned_under=_under(under), needs=("(at ?o ?r)", "(hand-empty)"),
                 effects=("(holding ?o)", "(gripper-closed)", "(not (at ?o ?r))",
                          "(not (hand-empty))", "(not (gripper-open))"),
                 kind="grasp", effect="grasped")


def place_skill(learned_under: Mapping[str, str] | None = None) -> Skill:
    """Put the held object down in a region and open the gripper."""
    return Skill("place", (("?o", "movable"), ("?r", "region")),
                 learned_under=_under(learned_under or {}), needs=("(holding ?o)",),
                 effects=("(at ?o ?r)", "(hand-empty)", "(gripper-open)",
                          "(not (holding ?o))", "(not (gripper-closed))"),
                 kind="place", effect="placed")


def press_skills(state: str = "light", values: Sequence[str] = ("on", "off"),
                 learned_under: Mapping[str, str] | None = None) -> list[Skill]:
    """Press a button that toggles high-level state `state` between two `values`: one
    operator per direction (``press-<state>-<to>``), each needing the other value and an
    empty hand."""
    if len(values) != 2 or values[0] == values[1]:
        raise A2LValueError(f"press_skills: need two different values, got {values!r}")
    out = []
    for old, new in ((values[0], values[1]), (values[1], values[0])):
        out.append(Skill(f"press-{state}-{new}", (("?b", "pressable"),),
                         learned_under=_under(learned_under or {}),
                         needs=(state_literal(state, old), "(hand-empty)"),
                         effects=(state_literal(state, new), f"(not {state_literal(state, old)})"),
                         kind="press", effect="pressed"))
    return out


def gripper_skill(value: str) -> Skill:
    """Open or close the empty gripper (``open-gripper`` / ``close-gripper``): a primitive,
    not a learned skill, so that skills learned with the other gripper state can be chained."""
    other = {"open": "closed", "closed": "open"}.get(value)
    if other is None:
        raise A2LValueError(f"gripper_skill: value must be 'open' or 'closed', got {value!r}")
    verb = "open" if value == "open" else "close"
    return Skill(f"{verb}-gripper", (), needs=(state_literal("gripper", other), "(hand-empty)"),
                 effects=(state_literal("gripper", value),
                          f"(not {state_literal('gripper', other)})"),
                 kind="gripper", effect=value)


def tabletop_repertoire(pushes: Sequence[str] = ("left", "right", "close", "far"),
                        press_under: Mapping[str, str] | None = None) -> list[Skill]:
    """The tabletop repertoire: push in each direction of `pushes`, grasp, place, press the
    light's button (learned under `press_under`, by default with the gripper closed), and the
    gripper primitives."""
    skills = [push_skill(e) for e in pushes] + [grasp_skill(), place_skill()]
    under = {"gripper": "closed"} if press_under is None else press_under
    skills += press_skills("light", ("on", "off"), learned_under=under)
    return skills + [gripper_skill("open"), gripper_skill("closed")]


@dataclass(frozen=True)
class TableRegions:
    """The table top cut into ``nx`` x ``ny`` regions, the planner's places.

    Attributes
    ----------
    center : tuple of float
        (x, y) of the table's centre (m).
    size : tuple of float
        (x, y) extent of the table (m).
    nx, ny : int
        Regions along x (close -> far) and y (right -> left).
    """

    center: tuple[float, float]
    size: tuple[float, float]
    nx: int = 3
    ny: int = 3

    def __post_init__(self) -> None:
        if self.nx < 1 or self.ny < 1 or min(self.size) <= 0:
            raise A2LValueError(f"TableRegions: need nx, ny >= 1 and a positive size, got "
                                f"{self.nx}x{self.ny}, {self.size}")

    def name(self, i: int, j: int) -> str:
        """Name of region (i along x, j along y): ``close-right`` ... ``far-left`` on a 3x3
        grid, ``x<i>-y<j>`` otherwise."""
        xs = ("close", "mid", "far") if self.nx == 3 else None
        ys = ("right", "centre", "left") if self.ny == 3 else None
        return f"{xs[i] if xs else f'x{i}'}-{ys[j] if ys else f'y{j}'}"

    @property
    def names(self) -> tuple[str, ...]:
        """Every region's name."""
        return tuple(self.name(i, j) for i in range(self.nx) for j in range(self.ny))

    def index(self, xy: ArrayLike) -> tuple[int, int] | None:
        """(i, j) of the region holding point `xy` (2,), or None off the table."""
        p = np.asarray(xy, dtype=float).reshape(-1)[:2]
        lo = np.asarray(self.center) - np.asarray(self.size) / 2
        f = (p - lo) / np.asarray(self.size)
        if np.any(f < 0) or np.any(f > 1) or not np.all(np.isfinite(f)):
            return None
        return min(int(f[0] * self.nx), self.nx - 1), min(int(f[1] * self.ny), self.ny - 1)

    def region_of(self, xy: ArrayLike) -> str | None:
        """Name of the region holding `xy`, or None off the table."""
        ij = self.index(xy)
        return None if ij is None else self.name(*ij)

    def center_of(self, region: str) -> tuple[float, float]:
        """Centre (x, y) of region `region` (m)."""
        for i in range(self.nx):
            for j in range(self.ny):
                if self.name(i, j) == region:
                    lo = np.asarray(self.center) - np.asarray(self.size) / 2
                    c = lo + (np.array([i, j]) + 0.5) * np.asarray(self.size) / (self.nx, self.ny)
                    return float(c[0]), float(c[1])
        raise A2LValueError(f"unknown region {region!r}; the table has {self.names}")

    def neighbour_facts(self, effects: Sequence[str]) -> tuple[str, ...]:
        """Static facts ``(<effect>-of to from)`` for each direction in `effects`."""
        out = []
        for e in effects:
            di, dj = DIRECTIONS[e]
            for i in range(self.nx):
                for j in range(self.ny):
                    i2, j2 = i + di, j + dj
                    if 0 <= i2 < self.nx and 0 <= j2 < self.ny:
                        out.append(f"({_direction_predicate(e)} {self.name(i2, j2)} "
                                   f"{self.name(i, j)})")
        return tuple(out)
