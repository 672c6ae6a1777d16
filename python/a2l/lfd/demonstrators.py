"""Scripted push demonstrators: an expert end-effector trajectory in the object frame.

A push demonstration for effect ``e`` (the object should move along the unit vector ``d_e``
of the table plane: ``far`` = +x, ``close`` = -x, ``left`` = +y, ``right`` = -y) is expressed
relative to the object (``x = eef - object``, the object at the origin, the target):

1. a start ``s`` at a seeded distance ``r0 in [r_low, r_high]`` and a seeded angle within
   ``± spread`` of the *approach side* ``u = -d_e`` (the side the end-effector pushes from);
2. an arc around the object from ``s`` to the pre-push point ``p = pre_push * u`` (plus a
   seeded lateral offset of at most ``path_noise``): the angle and the radius change linearly,
   the radius never below ``pre_push``, so the arc never touches the object; a seeded bump of
   at most ``path_noise`` on the radius varies the path;
3. the straight line from ``p`` through the object's (initial) centre to ``-depth * u``: the
   push itself. The frame is the object's pose at the start of the demonstration; while the
   expert pushes, the object moves ahead of the end-effector, which in the start frame ends
   ``depth`` beyond the object's initial centre. The DS's target is this end point, relative
   to the object: during execution the attractor follows the object, so it stays ahead of the
   end-effector and the push goes on along ``-u`` (a target at the object's centre would make
   every nearby start converge radially onto it, pushing the object sideways).

Samples are equally spaced along the path (constant speed ``speed``), the height is constant
(``z``: 0 is the object centre's height), so a push demonstration is planar in 3-D.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from a2l.lfd.demonstration import Demonstration
from a2l.skills.effects import AXIS_EFFECTS, EFFECT_DIRECTIONS

__all__ = ["PUSH_DIRECTIONS", "PushDemonstrator", "push_start"]

#: Direction (x, y) the object moves for each axis push effect, in the table plane (the C++
#: core's, :data:`a2l.skills.effects.EFFECT_DIRECTIONS`).
PUSH_DIRECTIONS: dict[str, tuple[float, float]] = {e: EFFECT_DIRECTIONS[e] for e in AXIS_EFFECTS}


def push_start(effect: str, rng: np.random.Generator, r_low: float = 0.14,
               r_high: float = 0.20, spread_deg: float = 60.0, z: float = 0.0) -> np.ndarray:
    """A seeded end-effector start (3,) in the object frame for a push `effect`.

    Distance uniform in ``[r_low, r_high]``, angle uniform within ``± spread_deg`` of the
    approach side (opposite the push direction); the same distribution the demonstrator and
    the skill trials (:func:`a2l.lfd.library.reset_for_trial`) draw from.
    """
    if effect not in PUSH_DIRECTIONS:
        raise ValueError(f"unknown push effect {effect!r}; known: {sorted(PUSH_DIRECTIONS)}")
    if not 0 < r_low <= r_high:
        raise ValueError(f"need 0 < r_low <= r_high, got {r_low}, {r_high}")
    ux, uy = (-v for v in PUSH_DIRECTIONS[effect])
    theta = math.atan2(uy, ux) + math.radians(rng.uniform(-spread_deg, spread_deg))
    r = rng.uniform(r_low, r_high)
    return np.array([r * math.cos(theta), r * math.sin(theta), z])


@dataclass(frozen=True)
class PushDemonstrator:
    """The scripted expert of one push effect (see the module docstring).

    Parameters
    ----------
    effect : {"far", "close", "left", "right"}
        The push effect demonstrated.
    r_low, r_high : float
        Range of the start's distance to the object (m).
    spread_deg : float
        The start's angle is within ± this of the approach side (degrees).
    pre_push : float
        Distance from the object of the point the push starts from (m); larger than the
        object's half-diagonal plus the end-effector's radius.
    path_noise : float
        Largest seeded offset of the pre-push point and of the arc's radius (m).
    depth : float
        How far beyond the object's initial centre the push ends (m), along the push.
    speed : float
        Demonstration speed (m/s); with the path length it gives the duration.
    n_points : int
        Samples per demonstration.
    z : float
        Height of the path relative to the object centre (m).
    """

    effect: str
    r_low: float = 0.14
    r_high: float = 0.20
    spread_deg: float = 60.0
    pre_push: float = 0.08
    path_noise: float = 0.01
    depth: float = 0.10
    approach_shape: str = "merge"
    merge: float = 0.10
    speed: float = 0.1
    n_points: int = 60
    z: float = 0.0

    def __post_init__(self) -> None:
        if self.effect not in PUSH_DIRECTIONS:
            raise ValueError(f"unknown push effect {self.effect!r}; known: "
                             f"{sorted(PUSH_DIRECTIONS)}")
        if not 0 < self.pre_push and 0 < self.r_low <= self.r_high:
            raise ValueError(f"need 0 < pre_push and 0 < r_low <= r_high, got {self.pre_push}, "
                             f"{self.r_low}, {self.r_high}")
        if not 0 <= self.path_noise < self.pre_push / 2:
            raise ValueError(f"path_noise must be in [0, pre_push / 2), got {self.path_noise}")
        if self.approach_shape not in ("arc", "line", "merge"):
            raise ValueError(f"approach_shape must be 'arc' or 'line', got "
                             f"{self.approach_shape!r}")
        if not self.depth >= 0:
            raise ValueError(f"depth must be >= 0, got {self.depth}")
        if self.n_points < 10:
            raise ValueError(f"n_points must be >= 10, got {self.n_points}")
        if not self.speed > 0:
            raise ValueError(f"speed must be > 0, got {self.speed}")

    @property
    def approach(self) -> np.ndarray:
        """Unit vector (2,) from the object to the side the push comes from."""
        return -np.asarray(PUSH_DIRECTIONS[self.effect])

    def start(self, rng: np.random.Generator) -> np.ndarray:
        """A seeded start (3,) in the object frame (:func:`push_start`)."""
        return push_start(self.effect, rng, self.r_low, self.r_high, self.spread_deg, self.z)

    def path(self, seed: int) -> np.ndarray:
        """The expert path (n_points, 3) in the object frame, from a seeded start to
        ``-depth * u``, equally spaced along its length."""
        rng = np.random.default_rng(np.random.SeedSequence([int(seed), 0x70757368]))
        s = self.start(rng)
        u = self.approach
        lateral = np.array([-u[1], u[0]]) * rng.uniform(-self.path_noise, self.path_noise)
        p = self.pre_push * u + lateral
        bump = rng.uniform(-self.path_noise, self.path_noise)
        th0, th1 = math.atan2(s[1], s[0]), math.atan2(p[1], p[0])
        dth = (th1 - th0 + math.pi) % (2 * math.pi) - math.pi
        r0, r1 = float(np.hypot(s[0], s[1])), float(np.hypot(p[0], p[1]))
        t = np.linspace(0.0, 1.0, 200)
        if self.approach_shape == "arc":
            r = r0 + (r1 - r0) * t + bump * np.sin(np.pi * t)
            r = np.maximum(r, min(r1, self.pre_push))
            arc = np.column_stack([r * np.cos(th0 + dth * t), r * np.sin(th0 + dth * t)])
        elif self.approach_shape == "merge":
            c = p + self.merge * u
            arc = ((1 - t)[:, None] ** 2 * s[None, :2] + (2 * (1 - t) * t)[:, None] * c[None, :]
                   + (t * t)[:, None] * p[None, :])
        else:
            normal = np.array([-(p - s[:2])[1], (p - s[:2])[0]])
            normal /= max(float(np.linalg.norm(normal)), 1e-12)
            arc = (s[:2][None, :] + t[:, None] * (p - s[:2])[None, :]
                   + bump * np.sin(np.pi * t)[:, None] * normal[None, :])
        end = -self.depth * u
        line = np.linspace(0.0, 1.0, 100)[1:, None] * (end - p)[None, :] + p[None, :]
        xy = np.vstack([arc, line])
        seg = np.linalg.norm(np.diff(xy, axis=0), axis=1)
        keep = np.concatenate([[True], seg > 1e-12])
        xy = xy[keep]
        s_cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
        q = np.linspace(0.0, s_cum[-1], self.n_points)
        out = np.column_stack([np.interp(q, s_cum, xy[:, 0]), np.interp(q, s_cum, xy[:, 1]),
                               np.full(self.n_points, self.z)])
        out[-1, :2] = end
        return out

    def demonstrate(self, seed: int, states: dict[str, str] | None = None) -> Demonstration:
        """One demonstration (frame ``"object"``) from `seed`.

        Parameters
        ----------
        seed : int
            Seeds the start, the pre-push offset and the arc's bump.
        states : dict of str to str, optional
            High-level states the demonstration is given under.
        """
        pos = self.path(seed)
        length = float(np.sum(np.linalg.norm(np.diff(pos, axis=0), axis=1)))
        times = np.linspace(0.0, length / self.speed, len(pos))
        return Demonstration(pos, times, "object", dict(states or {}))

    def demonstrations(self, n: int, seed: int = 0,
                       states: dict[str, str] | None = None) -> list[Demonstration]:
        """`n` demonstrations from seeds ``seed, seed + 1, ...``."""
        if n < 1:
            raise ValueError(f"n must be >= 1, got {n}")
        return [self.demonstrate(seed + i, states) for i in range(n)]
