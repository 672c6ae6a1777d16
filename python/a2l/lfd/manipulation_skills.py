"""The manipulation skills in the LfD pipeline: grasp, press and the light-dependent grasp.

The scripted demonstrations (:mod:`a2l.lfd.manipulation`) are cut into **phases**, one per
set of high-level states a segment was given under; each phase becomes a behaviour of the
pipeline (:func:`a2l.lfd.skill.learn_skill`: vector field -> dataset -> network -> compiled
table -> bundle, the babbling path's learning) with its own rows (:func:`phase_rows`):

========================  ===========================  ==================  ============
skill / phase             states (``when``)            ends with (action)  precise at
========================  ===========================  ==================  ============
grasp: reach              gripper open                 ``close``           grasp point
grasp: lift               gripper closed               -                   grasp point
press: press              any                          -                   press point
grasp_light: reach, lift  light off, gripper as above  as grasp            grasp point
grasp_light: retreat      light on                     ``stay`` (wait)     retreat pose
========================  ===========================  ==================  ============

Each phase is also a **DS phase** of the bundle (:mod:`a2l.skills.phases`): the mean DS of
its segments, applying under its states, with its end action (tolerance
:data:`PHASE_TOLERANCE`); ``run_skill(mode="ds")`` runs them through the C++ ``step_ds``.

Why not the push skills' dataset and configuration (measured: ``docs/experiments/lfd.md``):
a grasp must end within about 1 cm of the grasp point (the block is 3 cm wide, the open
fingers 4.8 cm apart). With the push default (5 cm movements, 3 distance bins over
[0.05, 0.20] m, no inclination) the table cannot tell "above the block" from "beside it"
and every grasp failed. Here: 2 cm movements, 12 distance bins over [0, 0.24] m (2 cm
each, and the retreat pose, 20 cm away, inside the range instead of in the saturated last
bin), 8 orientations, 16 inclinations, the chapter-6 neighbour smoothing; the grid around
the demonstrations is sampled every ``resolution`` and, within :data:`FINE_RADIUS` of where
precision matters, every :data:`FINE_RESOLUTION`; every context variable is a fixed parent
of the movement (hill-climbing with K2 otherwise drops ``distance -> move``, and the table
then never knows when to close).

Effect tests (:mod:`a2l.rollout.effect_tests`): ``grasped`` (the block >= 5 cm up in the
closed gripper) and ``pressed`` are the scene's; ``grasp_light`` wants ``grasped`` with the
light off and ``away`` with it on (:data:`EFFECT_BY_LIGHT`, in the recipe's ``extra``;
:func:`a2l.rollout.effect_tests.light_test`): the end-effector at the retreat pose
(:data:`a2l.rollout.effect_tests.RETREAT`, within 4 cm) without having moved the block
(:func:`a2l.rollout.effect_tests.away_test`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from scipy.spatial import cKDTree

from a2l.lfd.config import LfDConfig
from a2l.lfd.dataset import dataset_frame
from a2l.lfd.demonstration import Demonstration
from a2l.lfd.manipulation import (
    GRASP_POINT,
    PRESS_POINT,
    SKILL_OBJECTS,
    demo_start,
    demonstrate,
)
from a2l.lfd.recipes import SkillRecipe, register_skill
from a2l.lfd.skill import Behaviour
from a2l.rollout.effect_tests import RETREAT
from a2l.rollout.protocol import SceneProtocol
from a2l.skills import (
    Discretizer,
    HighLevelState,
    InclinationBins,
    MovementRepertoire,
    OrientationBins,
)
from a2l.skills.spec import VariableSpec

__all__ = ["CONFIG", "EFFECT_BY_LIGHT", "FINE_RADIUS", "FINE_RESOLUTION", "N_INCLINATION",
           "NamedEffects", "Phase", "manipulation_discretizer", "phase_rows",
           "skill_phases"]

#: The configuration of the manipulation skills (see the module docstring for why).
CONFIG = LfDConfig(resolution=0.01, tube=0.06, smoothing=True, n_demos=8, maps=60,
                   path_length=0.8, discretization={"step": 0.02, "n_orient": 8, "n_dist": 12,
                                                    "dist_low": 0.0, "dist_high": 0.24})
#: Inclination sections of the manipulation skills' context.
N_INCLINATION = 16
#: Grid spacing (m) near the place where a phase must be precise.
FINE_RESOLUTION = 0.003
#: Radius (m) of the fine grid around that place.
FINE_RADIUS = 0.04
#: Tolerance (m) of each DS phase's target (:mod:`a2l.skills.phases`): the reach closes
#: within 5 mm of the grasp point; the lift's target moves with the block in the hand, it is
#: never reached (the effect test ends the run).
PHASE_TOLERANCE = {"reach": 0.005, "lift": 0.01, "press": 0.005, "retreat": 0.01}
#: Grid points this close (m) to the end of a phase take its end action.
ACTION_RADIUS = {"close": 0.015, "stay": 0.02}


@dataclass(frozen=True)
class NamedEffects:
    """An effect variable whose values are names (``grasped``, ``pressed``), not push
    directions: the rows carry the effect's name (the ``effect`` column).

    Duck-types :class:`a2l.skills.EffectDiscretizer` for :class:`a2l.skills.Discretizer`.
    """

    values: tuple[str, ...] = ("grasped",)
    name: str = "effect"
    n_effects: int = 1
    threshold: float = 0.0
    ratio: float = 1.0

    def discretize(self, displacement: np.ndarray) -> np.ndarray:
        raise ValueError(f"effect {list(self.values)}: rows must name their effect (column "
                         "'effect'); a displacement does not say it")

    def spec(self) -> Any:
        return VariableSpec(self.name, "effect", len(self.values), values=self.values)


@dataclass(frozen=True)
class Phase:
    """One phase of a manipulation skill: the segments demonstrated under one set of states.

    Attributes
    ----------
    name : str
    when : dict of str to str
        The high-level states the phase applies under (``{}``: any).
    segments : list of Demonstration
        The phase's segments of every demonstration (object frame, 3-D).
    end_action : str or None
        The action taken at the phase's end (``"close"``, ``"stay"``) or None.
    focus : ndarray, shape (3,)
        Where the phase must be precise (object frame): the fine grid's centre.
    """

    name: str
    when: dict[str, str]
    segments: list[Demonstration]
    end_action: str | None
    focus: np.ndarray

    @property
    def target(self) -> np.ndarray:
        """Mean end of the segments (3,): the phase's target in the object frame."""
        return np.mean([s.positions[-1] for s in self.segments], axis=0)


def skill_phases(skill: str, demos: Sequence[Sequence[Demonstration]]) -> list[Phase]:
    """The phases of `skill` from its demonstrations (lists of segments).

    Segments are grouped by their states; the group's name, end action and focus follow
    from the states: gripper open -> ``reach`` (ends with ``close`` at the grasp point; for
    ``press``: ``press``, no action), gripper closed -> ``lift``, light on -> ``retreat``
    (ends with ``stay`` at the retreat pose).
    """
    groups: dict[tuple[tuple[str, str], ...], list[Demonstration]] = {}
    for demo in demos:
        for seg in demo:
            groups.setdefault(tuple(sorted(seg.states.items())), []).append(seg)
    out = []
    for key, segs in groups.items():
        when = dict(key)
        if when.get("light") == "on":
            out.append(Phase("retreat", when, segs, "stay", RETREAT.copy()))
        elif skill == "press":
            out.append(Phase("press", when, segs, None, PRESS_POINT.copy()))
        elif when.get("gripper") == "closed":
            out.append(Phase("lift", when, segs, None, GRASP_POINT.copy()))
        else:
            out.append(Phase("reach", when, segs, "close", GRASP_POINT.copy()))
    return out


def _ball(radius: float, spacing: float, n_orient: int, n_incl: int) -> np.ndarray:
    """Points (M, 3) within `radius` of the object sampled in its context coordinates: every
    `spacing` in distance, three orientations per orientation section and three angles per
    inclination section, so every bin near the object has rows (a Cartesian grid leaves
    the thin sections near the vertical empty, where the C++ step then meets an unknown
    context)."""
    r = np.arange(spacing / 2, radius, spacing)
    w = 2 * np.pi / n_orient
    theta = (-np.pi + w * np.arange(n_orient))[:, None] + w * np.array([-1 / 3, 0.0, 1 / 3])
    phi = (np.pi / n_incl) * (np.arange(n_incl)[:, None] + np.array([1 / 6, 1 / 2, 5 / 6]))
    rr, tt, pp = np.meshgrid(r, theta.ravel(), phi.ravel(), indexing="ij")
    return np.column_stack([(rr * np.sin(pp) * np.cos(tt)).ravel(),
                            (rr * np.sin(pp) * np.sin(tt)).ravel(), (rr * np.cos(pp)).ravel()])


def _grid(phase: Phase, resolution: float, tube: float, n_orient: int
          ) -> tuple[np.ndarray, np.ndarray]:
    """Points near the phase's segments (coarse), near its focus (fine) and around the
    object in context coordinates (:func:`_ball`: finely within :data:`FINE_RADIUS`, then
    every `resolution` as far as the segments go), and the index of the nearest segment of
    each (points farther than `tube` from every segment are dropped)."""
    paths = [s.positions for s in phase.segments]
    allp = np.vstack(paths)
    labels = np.concatenate([np.full(len(p), i) for i, p in enumerate(paths)])
    lo, hi = allp.min(axis=0) - tube, allp.max(axis=0) + tube
    axes = [lo[k] + resolution * np.arange(int(np.floor((hi[k] - lo[k]) / resolution)) + 1)
            for k in range(3)]
    coarse = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    r = FINE_RESOLUTION * np.arange(-int(FINE_RADIUS / FINE_RESOLUTION),
                                    int(FINE_RADIUS / FINE_RESOLUTION) + 1)
    fine = np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3)
    fine = fine[np.linalg.norm(fine, axis=1) <= FINE_RADIUS] + phase.focus
    reach = float(np.max(np.linalg.norm(allp, axis=1))) + tube
    grid = np.vstack([coarse, fine,
                      _ball(FINE_RADIUS, FINE_RESOLUTION, n_orient, N_INCLINATION),
                      _ball(reach, resolution, n_orient, N_INCLINATION)])
    dist, idx = cKDTree(allp).query(grid)
    keep = dist <= tube
    return grid[keep], labels[idx[keep]].astype(np.int64)


def phase_rows(phase: Phase, fields: Sequence[Any], effect: str, cfg: LfDConfig,
               episode0: int = 0) -> pd.DataFrame:
    """The raw dataset of one phase: a row per grid point (:mod:`a2l.data.schema`).

    Parameters
    ----------
    phase : Phase
    fields : sequence of a2l.lfd.DiffeoDS
        ``fields[i]`` is the DS of ``phase.segments[i]``; a point takes the velocity of the
        DS of the segment nearest to it.
    effect : str
        The skill's effect (the ``effect`` column).
    cfg : LfDConfig
        Grid spacing, tube and movement length.
    episode0 : int
        First episode id.

    Returns
    -------
    pandas.DataFrame, shape (M, n_columns)
        The object at the origin, the end-effector at the grid point, ``move_*`` the DS
        velocity scaled to one movement, ``action`` the phase's end action within
        :data:`ACTION_RADIUS` of its target (empty elsewhere), ``effect`` and one column
        per state of ``phase.when``.
    """
    if len(fields) != len(phase.segments):
        raise ValueError(f"{len(fields)} fields for {len(phase.segments)} segments")
    points, nearest = _grid(phase, cfg.resolution, cfg.tube,
                            cfg.discretization.n_orient)
    vel = np.zeros_like(points)
    for i, ds in enumerate(fields):
        sel = nearest == i
        if sel.any():
            vel[sel] = np.asarray(ds.velocity(points[sel]), dtype=float).reshape(-1, 3)
    speed = np.linalg.norm(vel, axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        move = np.where(speed > 1e-12, cfg.step * vel / speed, 0.0)
    action = np.full(len(points), "", dtype=object)
    if phase.end_action is not None:
        near = np.linalg.norm(points - phase.target, axis=1) <= ACTION_RADIUS[phase.end_action]
        action[near] = phase.end_action
    return dataset_frame(points, move, effect, dict(phase.when), episode0, action=action)


def manipulation_discretizer(skill: str, cfg: LfDConfig = CONFIG) -> Any:
    """The discretizer of a manipulation skill: of ``cfg.discretization``, distance
    (``n_dist`` over ``[dist_low, dist_high]``, or between ``dist_edges``), orientation
    (``n_orient``) and 26 directions of ``step`` plus its actions; inclination
    (:data:`N_INCLINATION`), its high-level states, its named effect."""
    states = _HIGH_LEVEL[skill]
    d = cfg.discretization
    return Discretizer(
        distance=d.distance_bins(),
        orientation=OrientationBins(d.n_orient), inclination=InclinationBins(N_INCLINATION),
        movements=MovementRepertoire(step=d.step, actions=_ACTIONS[skill]),
        effects=NamedEffects((_EFFECTS[skill],)),  # type: ignore[arg-type]
        high_level=tuple(HighLevelState(n, v) for n, v in states))


def _behaviours(skill: str) -> Any:
    def behaviours(cfg: LfDConfig, seed: int) -> list[Behaviour]:
        demos = demonstrate(skill, cfg.n_demos * (2 if skill == "grasp_light" else 1), seed)
        out = []
        for phase in skill_phases(skill, demos):
            def rows(fields: Any, _demos: Any, effect: str, c: LfDConfig,
                     _states: Any, episode0: int, phase: Phase = phase) -> pd.DataFrame:
                return phase_rows(phase, fields, effect, c, episode0)

            out.append(Behaviour(list(phase.segments), _EFFECTS[skill], dict(phase.when),
                                 rows=rows, phase=phase.name, end_action=phase.end_action,
                                 tolerance=PHASE_TOLERANCE[phase.name]))
        return out

    return behaviours


#: The manipulation skills' high-level states (name, values).
_HIGH_LEVEL: dict[str, tuple[tuple[str, tuple[str, ...]], ...]] = {
    "grasp": (("gripper", ("open", "closed")),),
    "press": (),
    "grasp_light": (("gripper", ("open", "closed")), ("light", ("off", "on"))),
}
_ACTIONS = {"grasp": ("close",), "press": (), "grasp_light": ("close", "stay")}
#: What ``grasp_light`` should do under each light value (the effect tested).
EFFECT_BY_LIGHT = {"off": "grasped", "on": "away"}
_EFFECTS = {"grasp": "grasped", "press": "pressed", "grasp_light": "grasped"}


def _setup(skill: str) -> Any:
    if skill != "grasp_light":
        return None

    def setup(scene: SceneProtocol, rng: np.random.Generator) -> None:
        # half the trials under each light state
        if rng.uniform() < 0.5:
            scene.perturb("toggle", state="light")
            scene.start_episode()

    return setup


_DESCRIPTIONS = {
    "grasp": "grasp the block: approach from above, close the gripper, lift (>= 5 cm)",
    "press": "press the button (the light toggles)",
    "grasp_light": "light off: grasp the block; light on (a hot stove): move away to the "
                   "retreat pose and wait",
}

def register() -> None:
    """Register the grasp, press and grasp_light recipes (their effect tests, ``away``
    included, are :data:`a2l.rollout.effect_tests.EFFECT_TESTS`')."""
    for skill in ("grasp", "press", "grasp_light"):
        register_skill(SkillRecipe(
            name=skill, scene=skill, effect=_EFFECTS[skill], object_name=SKILL_OBJECTS[skill],
            behaviours=_behaviours(skill), start=demo_start,
            high_level=tuple(HighLevelState(n, v) for n, v in _HIGH_LEVEL[skill]),
            planar=False, object_jitter=0.03, setup=_setup(skill),
            discretizer=lambda cfg, s=skill: manipulation_discretizer(s, cfg),
            description=_DESCRIPTIONS[skill], config=CONFIG, context_edges=True,
            extra={"effect_by_light": dict(EFFECT_BY_LIGHT)} if skill == "grasp_light"
            else {}))
