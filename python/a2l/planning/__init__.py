"""Task planning with the learned skills: PDDL generation, planners, and collision-free
transit between skills (OMPL). See ``docs/planning.md``.

The transit planner is imported lazily (``a2l.planning.transit``): it needs PyBullet scenes
only to execute; the PDDL part needs no simulator.
"""

from __future__ import annotations

from a2l.planning.pddl import Literal, PerceivedState, Skill, domain_pddl, problem_pddl
from a2l.planning.planners import PLANNERS, PlanResult, PlanStep, solve, solve_files, write_task
from a2l.planning.repertoire import (
    DIRECTIONS,
    TableRegions,
    grasp_skill,
    gripper_skill,
    place_skill,
    press_skills,
    push_skill,
    tabletop_repertoire,
)
from a2l.planning.simulate import apply_step, goal_literals, simulate_plan, unmet

__all__ = [
    "DIRECTIONS",
    "PLANNERS",
    "Literal",
    "PerceivedState",
    "PlanResult",
    "PlanStep",
    "Skill",
    "TableRegions",
    "apply_step",
    "domain_pddl",
    "goal_literals",
    "grasp_skill",
    "gripper_skill",
    "place_skill",
    "press_skills",
    "problem_pddl",
    "push_skill",
    "simulate_plan",
    "solve",
    "solve_files",
    "tabletop_repertoire",
    "unmet",
    "write_task",
]
