"""Scripted demonstrators of the manipulation skills: grasp, press, grasp_light.

An expert end-effector trajectory in the object frame (``eef - object``, in metres), with a
seeded variation of the start and of the path. A demonstration of one skill execution is a
list of **segments**, one :class:`a2l.lfd.Demonstration` per stretch of constant high-level
states: the segment's ``states`` are those it was given under, and a change of the gripper
state between two consecutive segments is the gripper action done in between
(:func:`segment_actions`). The teleoperation recorder (:mod:`a2l.lfd.teleop`) writes the
same format.

=============  ===================================================================  ============
skill          segments                                                             actions
=============  ===================================================================  ============
grasp          reach: start -> above the block -> down to the grasp point            close
               (gripper open); lift: straight up by :data:`LIFT` (gripper closed)
press          press: start -> above the button -> down on it                       -
grasp_light    light off: the grasp's segments with ``light: off`` added;            close / -
               light on: start -> ``RETREAT`` (away from the block), then wait
=============  ===================================================================  ============

Frames: every segment is expressed relative to the object's position at the start of the
segment (``frame="object"``). During the lift the block moves with the hand, so the lift is
the end-effector's rise above where the block was when the fingers closed; at run time
``eef - block`` stays at the grasp point and the lift's DS keeps pointing up.

:func:`replay` plays a demonstration in a PyBullet scene (the effect it should produce is
what the tests check).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.errors import A2LValueError
from a2l.lfd.demonstration import Demonstration
from a2l.rollout.effect_tests import RETREAT
from a2l.rollout.protocol import ArmSceneProtocol

__all__ = [
    "ABOVE",
    "GRASP_POINT",
    "LIFT",
    "PRESS_POINT",
    "RETREAT",
    "SKILL_OBJECTS",
    "demo_start",
    "demonstrate",
    "grasp_demonstration",
    "grasp_light_demonstration",
    "press_demonstration",
    "replay",
    "segment_actions",
]

#: End-effector point relative to the block's centre when the fingers close (m).
GRASP_POINT: NDArray[np.float64] = np.array([0.0, 0.0, -0.01])
#: End-effector point relative to the button cap's centre at the end of a press (m).
PRESS_POINT: NDArray[np.float64] = np.array([0.0, 0.0, -0.012])
#: Nominal height of the approach point above the grasp/press point (m).
ABOVE = 0.10
#: Rise of the lift segment (m); the ``grasped`` effect needs 5 cm.
LIFT = 0.10
#: The object each skill acts on, as the scene names it.
SKILL_OBJECTS: dict[str, str] = {"grasp": "block", "press": "button", "grasp_light": "block"}

_SPACING = 0.01     # distance between samples (m)
_SPEED = 0.10       # nominal end-effector speed of the demonstrator (m/s)
_WAIT = 1.0         # how long the light-on demonstration waits at the retreat point (s)


def demo_start(rng: np.random.Generator) -> NDArray[np.float64]:
    """A start relative to the object: above it, a little in front or beside."""
    return np.array([rng.uniform(-0.10, 0.06), rng.uniform(-0.10, 0.10),
                     rng.uniform(0.14, 0.22)])


def _bezier(p0: NDArray[np.float64], p1: NDArray[np.float64], p2: NDArray[np.float64],
            p3: NDArray[np.float64], spacing: float) -> NDArray[np.float64]:
    """A cubic Bezier curve sampled about `spacing` apart, shape (n, 3), from p0 to p3."""
    s = np.linspace(0.0, 1.0, 400)[:, None]
    curve = ((1 - s) ** 3 * p0 + 3 * (1 - s) ** 2 * s * p1 + 3 * (1 - s) * s ** 2 * p2
             + s ** 3 * p3)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
    n = max(2, int(np.ceil(arc[-1] / spacing)) + 1)
    target = np.linspace(0.0, arc[-1], n)
    return np.column_stack([np.interp(target, arc, curve[:, k]) for k in range(3)])


def _line(a: NDArray[np.float64], b: NDArray[np.float64], spacing: float) -> NDArray[np.float64]:
    n = max(2, int(np.ceil(np.linalg.norm(b - a) / spacing)) + 1)
    return a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)


def _timed(points: NDArray[np.float64], speed: float, t0: float = 0.0
           ) -> NDArray[np.float64]:
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    return t0 + np.concatenate([[0.0], np.cumsum(np.maximum(seg, 1e-4) / speed)])


def _from_above(rng: np.random.Generator, goal: NDArray[np.float64], start: ArrayLike | None
                ) -> NDArray[np.float64]:
    """start -> a curved path to a point above `goal` -> straight down onto `goal`."""
    p0 = demo_start(rng) if start is None else np.asarray(start, dtype=float).reshape(3)
    above = goal + np.array([rng.normal(0, 0.004), rng.normal(0, 0.004),
                             ABOVE + rng.uniform(-0.02, 0.02)])
    # the curve leaves the start upward-ish and arrives above the goal vertically
    c1 = p0 + np.array([0, 0, 0.03]) + rng.normal(0, 0.02, 3)
    c2 = above + np.array([0, 0, 0.04 + rng.uniform(0, 0.03)])
    approach = _bezier(p0, c1, c2, above, _SPACING)
    descent = _line(above, goal, _SPACING)
    return np.vstack([approach, descent[1:]])


def grasp_demonstration(seed: int, start: ArrayLike | None = None,
                        states: dict[str, str] | None = None) -> list[Demonstration]:
    """One scripted grasp: approach from above, close the gripper, lift.

    Parameters
    ----------
    seed : int
        Seeds the start (unless given), the approach path and the speed.
    start : array_like, shape (3,), optional
        Start of the end-effector relative to the block (m).
    states : dict, optional
        Extra high-level states every segment was given under (``{"light": "off"}``).

    Returns
    -------
    list of Demonstration
        ``[reach, lift]``: reach (N, 3) under ``gripper: open`` ending at
        :data:`GRASP_POINT`; lift (M, 3) under ``gripper: closed`` from the grasp point
        straight up by :data:`LIFT`. The gripper closes in between.
    """
    rng = np.random.default_rng(seed)
    speed = _SPEED * rng.uniform(0.8, 1.2)
    reach = _from_above(rng, GRASP_POINT, start)
    lift = _line(GRASP_POINT, GRASP_POINT + np.array([0.0, 0.0, LIFT]), _SPACING)
    extra = dict(states or {})
    t_reach = _timed(reach, speed)
    return [Demonstration(reach, t_reach, "object", {**extra, "gripper": "open"}),
            Demonstration(lift, _timed(lift, speed / 2), "object",
                          {**extra, "gripper": "closed"})]


def press_demonstration(seed: int, start: ArrayLike | None = None) -> list[Demonstration]:
    """One scripted press: approach from above the button, go down on it.

    Returns
    -------
    list of Demonstration
        ``[press]`` (N, 3) ending at :data:`PRESS_POINT` below the cap's centre (the cap
        goes down past the trigger depth and the light toggles); valid under any state
        (``states={}``).
    """
    rng = np.random.default_rng(seed)
    speed = _SPEED * rng.uniform(0.8, 1.2)
    path = _from_above(rng, PRESS_POINT, start)
    return [Demonstration(path, _timed(path, speed), "object", {})]


def grasp_light_demonstration(seed: int, light: str, start: ArrayLike | None = None
                              ) -> list[Demonstration]:
    """The light-dependent grasp: the block next to a "hot stove".

    Parameters
    ----------
    seed : int
        Seeds the start, the path and the speed.
    light : {"off", "on"}
        Off: the grasp (:func:`grasp_demonstration`) with ``light: off`` in every segment's
        states. On: move away from the block (up first, then back) to
        :data:`a2l.rollout.effect_tests.RETREAT` and
        wait there ``1 s`` (the last samples repeat the retreat point), one segment under
        ``light: on``; half the starts are the grasp's, half a point on a grasp's approach
        (the light came on mid-grasp), down to the grasp point itself.
    start : array_like, shape (3,), optional
        Start relative to the block (m).
    """
    if light == "off":
        return grasp_demonstration(seed, start, states={"light": "off"})
    if light != "on":
        raise A2LValueError(f"light must be 'off' or 'on', got {light!r}")
    rng = np.random.default_rng(seed)
    speed = _SPEED * rng.uniform(0.8, 1.2)
    if start is not None:
        p0 = np.asarray(start, dtype=float).reshape(3)
    elif rng.uniform() < 0.5:
        p0 = demo_start(rng)
    else:  # the light came on during a grasp: from a point of a grasp's approach
        reach = _from_above(rng, GRASP_POINT, None)
        p0 = reach[rng.integers(len(reach) // 3, len(reach))]
    goal = RETREAT + rng.normal(0, 0.005, 3)
    # up first (off the block), then back to the retreat point
    c1 = p0 + np.array([0.0, 0.0, 0.10]) + rng.normal(0, 0.005, 3)
    c2 = goal + np.array([0.03, 0.0, 0.0]) + rng.normal(0, 0.01, 3)
    path = _bezier(p0, c1, c2, goal, _SPACING)
    times = _timed(path, speed)
    n_wait = 5
    wait_t = times[-1] + np.linspace(_WAIT / n_wait, _WAIT, n_wait)
    positions = np.vstack([path, np.repeat(path[-1:], n_wait, axis=0)])
    return [Demonstration(positions, np.concatenate([times, wait_t]), "object",
                          {"light": "on"})]


def demonstrate(skill: str, n: int, seed: int = 0) -> list[list[Demonstration]]:
    """`n` scripted demonstrations of a skill, seeds ``seed``, ``seed + 1``, ...

    For ``grasp_light`` the light alternates (off, on, off, ...): the skill is demonstrated
    under both states.

    Returns
    -------
    list of list of Demonstration
        One list of segments per demonstration.
    """
    if skill not in SKILL_OBJECTS:
        raise A2LValueError(f"unknown manipulation skill '{skill}'; choose one of "
                            f"{sorted(SKILL_OBJECTS)}")
    if n < 1:
        raise A2LValueError(f"n must be >= 1, got {n}")
    out = []
    for i in range(n):
        s = seed + i
        if skill == "grasp":
            out.append(grasp_demonstration(s))
        elif skill == "press":
            out.append(press_demonstration(s))
        else:
            out.append(grasp_light_demonstration(s, "off" if i % 2 == 0 else "on"))
    return out


def segment_actions(segments: Sequence[Demonstration]) -> list[str | None]:
    """The gripper action at the end of each segment of one demonstration.

    Returns
    -------
    list of (str or None)
        ``"close"`` / ``"open"`` where the next segment's ``gripper`` state differs, else
        ``None`` (always ``None`` for the last segment).
    """
    out: list[str | None] = []
    for a, b in zip(segments, list(segments[1:]) + [None], strict=True):
        ga, gb = a.states.get("gripper"), (b.states.get("gripper") if b else None)
        out.append(None if b is None or ga == gb or gb is None else
                   ("close" if gb == "closed" else "open"))
    return out


def replay(scene: ArmSceneProtocol, segments: Sequence[Demonstration], obj: str,
           spacing: float = 0.02, on_segment: Callable[[int], None] | None = None) -> bool:
    """Play a demonstration in a PyBullet scene, from where it starts.

    The end-effector is reset to the first sample (relative to `obj`) and the scene's
    high-level states set to the first segment's (the light on for a light-on
    demonstration); the episode starts there. The end-effector then follows each
    segment's samples about `spacing` apart (straight moves through the C++ IK), relative
    to the object's true position at the segment's start; between segments the gripper
    does what :func:`segment_actions` says.

    Parameters
    ----------
    scene : a2l.sim.bullet.BulletScene
        Reset here, with the end-effector at the demonstration's start; the episode
        (``observe_effect(since="episode")``) starts there.
    segments : sequence of Demonstration
        One demonstration (3-D, ``frame="object"``).
    obj : str
        The object the frame is attached to.
    spacing : float
        Largest move between two followed samples (m).
    on_segment : callable, optional
        Called with the segment index before it is followed (e.g. to toggle the light).

    Returns
    -------
    bool
        Every move was carried out.
    """
    if not segments or any(s.dim != 3 or s.frame != "object" for s in segments):
        raise A2LValueError("replay needs 3-D segments in the 'object' frame")
    objects = scene.ground_truth()["objects"]
    if obj not in objects:
        raise A2LValueError(f"replay: no object '{obj}' in scene '{scene.name}'")
    start = segments[0].positions[0]
    scene.reset(eef=np.asarray(objects[obj]) + start)
    # a reset may draw the objects anew (object_jitter): correct the start
    here = np.asarray(scene.ground_truth()["objects"][obj], dtype=float) + start
    ok = True
    if np.linalg.norm(here - scene.eef_position()) > 1e-3:
        ok = bool(scene.move_by(here - scene.eef_position()))
    # the high-level states the demonstration was given under (those the scene has)
    for name, value in segments[0].states.items():
        now = scene.ground_truth()["states"]
        if name in now and now[name] != value:
            if name == "gripper":
                scene.close_gripper() if value == "closed" else scene.open_gripper()
            else:
                scene.perturb("toggle", state=name)
    scene.start_episode()
    actions = segment_actions(segments)
    for k, seg in enumerate(segments):
        if on_segment is not None:
            on_segment(k)
        origin = np.asarray(scene.ground_truth()["objects"][obj], dtype=float)
        last = seg.positions[0]
        n = len(seg.positions)
        for i in range(1, n):
            point = seg.positions[i]
            if np.linalg.norm(point - last) < spacing and i < n - 1:
                continue
            target = origin + point
            disp = target - scene.eef_position()
            if np.linalg.norm(disp) > 1e-3:
                ok = bool(scene.move_by(disp)) and ok
            last = point
        if actions[k] == "close":
            scene.close_gripper()
        elif actions[k] == "open":
            scene.open_gripper()
    return ok

