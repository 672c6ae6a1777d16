"""The trajectory encoding shared by NovEB and its baselines: a genotype of ``3·k`` numbers
in [0, 1] is ``k`` waypoints in a box of the workspace over the table, followed with the
discrete movements of the world's movement layer.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.rollout.protocol import ArmSceneProtocol
from a2l.skills.repertoire import default_directions

__all__ = ["RETURN_REST_S", "WaypointEncoding", "follow_waypoints", "play_and_look"]

#: Seconds of physics between putting the arm back at the start and the image after: a box
#: the arm leaned on or pushed is at rest within 0.2 s (measured: moved < 2 mm after 0.15 s
#: over 14 pushes).
RETURN_REST_S = 0.2


@dataclass(frozen=True)
class WaypointEncoding:
    """``n_waypoints`` points in the box ``[low, high]`` of the workspace.

    Attributes
    ----------
    low, high : tuple of 3 float
        Corners (x, y, z) of the box (m).
    n_waypoints : int
        Points per trajectory.
    """

    low: tuple[float, float, float]
    high: tuple[float, float, float]
    n_waypoints: int = 3

    def __post_init__(self) -> None:
        if self.n_waypoints < 1:
            raise ValueError(f"n_waypoints must be >= 1, got {self.n_waypoints}")
        if len(self.low) != 3 or len(self.high) != 3 or not all(
                lo <= hi for lo, hi in zip(self.low, self.high, strict=True)):
            raise ValueError(f"low and high are 3 numbers each, low <= high, got {self.low}, "
                             f"{self.high}")

    @property
    def n_genes(self) -> int:
        """Length of a genotype."""
        return 3 * self.n_waypoints

    def decode(self, genotype: ArrayLike) -> NDArray[np.float64]:
        """The waypoints of `genotype` (``n_genes`` numbers in [0, 1]), shape (k, 3)."""
        g = np.asarray(genotype, dtype=float)
        if g.shape != (self.n_genes,) or not np.all(np.isfinite(g)):
            raise ValueError(f"a genotype is {self.n_genes} finite numbers, got shape "
                             f"{g.shape}")
        if np.any(g < 0) or np.any(g > 1):
            raise ValueError(f"genes must be in [0, 1], got {g.min():.3g}..{g.max():.3g}")
        lo, hi = np.asarray(self.low), np.asarray(self.high)
        return lo + g.reshape(-1, 3) * (hi - lo)


def follow_waypoints(execute: Callable[[tuple[int, int, int]], bool],
                     position: Callable[[], NDArray[np.float64]],
                     directions: NDArray[np.int_], step: float, start: ArrayLike,
                     points: NDArray[np.float64], max_moves: int) -> tuple[list[int], bool]:
    """Head for each point in turn with the movement closest to the way there.

    A point is passed when the nominal position (`start` plus the movements carried out)
    comes within 0.7 steps of it; a movement the world cannot carry out abandons the
    current point for the next one, from where the end-effector is then (`position`).
    Planning on the nominal position keeps the trajectory a function of its points alone
    while every movement is carried out (a physics scene ends a movement a few 1e-8 m off
    its target).

    Parameters
    ----------
    execute : callable
        ``execute(direction) -> carried out``: one discrete movement in the world.
    position : callable
        ``position() -> (3,)``: where the end-effector is.
    directions : ndarray of int, shape (n, 3)
        The movement repertoire (sign vectors).
    step : float
        Movement length (m).
    start : array_like, shape (3,)
        Where the end-effector starts.
    points : ndarray, shape (k, 3)
        The waypoints.
    max_moves : int
        Most movements tried.

    Returns
    -------
    moves : list of int
        Indices (into `directions`) of the movements carried out, in order.
    all_carried_out : bool
        No movement failed.
    """
    unit = directions.astype(float)
    unit /= np.linalg.norm(unit, axis=1, keepdims=True)
    at = np.asarray(start, dtype=float).copy()
    reach = 0.7 * step
    done: list[int] = []
    tries = 0
    clean = True
    for point in np.atleast_2d(points):
        while tries < max_moves:
            d = point - at
            if np.linalg.norm(d) < reach:
                break
            move = int(np.argmax(unit @ d))
            tries += 1
            if not execute(tuple(int(s) for s in directions[move])):
                at = np.asarray(position(), dtype=float).copy()
                clean = False
                break
            at = at + step * unit[move]
            done.append(move)
    return done, clean


def play_and_look(scene: ArmSceneProtocol, start: ArrayLike, points: NDArray[np.float64],
                  max_moves: int, image_size: int = 32,
                  observe: Callable[[], None] | None = None,
                  on_reset: Callable[[], None] | None = None,
                  rest: float = RETURN_REST_S
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64], list[int]]:
    """Play a waypoint trajectory in `scene`, put the arm back at `start`, and look.

    The end-effector starts at `start` (the objects where the scene resets them) and
    follows `points` (:func:`follow_waypoints`, all 26 directions) with physical movements.
    The arm is then put back at `start` kinematically (``scene.place_arm``: joint states
    set, as the next reset would) and the physics runs `rest` seconds with the arm held
    there, so that what the arm leaned on falls back and what it pushed comes to rest;
    the image then differs from the one before only where the world changed. Only the
    scene's ``reset``, ``execute``, ``eef_position`` (proprioception), ``place_arm``,
    ``settle`` and ``render`` (the main camera) are called.

    The way back is not a movement: retracing it physically doubled an evaluation's
    physics, and the only thing it could add to the outcome is a second push on the way
    back; the outcome is that of the trajectory played.

    Parameters
    ----------
    scene : a2l.sim.Scene
        A PyBullet scene (with a camera).
    start : array_like, shape (3,)
        Start and end of the trajectory.
    points : ndarray, shape (k, 3)
        Waypoints.
    max_moves : int
        Most movements.
    image_size : int
        Side of the descriptor's downsampled image.
    observe : callable, optional
        Called after each movement carried out (by an experimenter who records more).
    on_reset : callable, optional
        Called once after the reset, before the first movement (the same experimenter).
    rest : float
        Seconds of physics after the arm is put back, before the image (s).

    Returns
    -------
    descriptor : ndarray, shape (image_size ** 2,)
        Grey image after minus image before, downsampled (:func:`image_descriptor`).
    path : ndarray, shape (m + 1, 3)
        End-effector positions at the start and after each movement tried.
    out : list of int
        Indices into :func:`a2l.skills.repertoire.default_directions` (the 26 directions in
        the C++ core's order) of the movements carried out.
    """
    from a2l.acquisition.images import image_descriptor

    start = np.asarray(start, dtype=float)
    scene.reset(eef=start)
    if on_reset is not None:
        on_reset()
    before = scene.render(0)[0]
    path = [scene.eef_position()]

    def execute(d: tuple[int, int, int]) -> bool:
        ok = bool(scene.execute(d))
        path.append(scene.eef_position())
        if ok and observe is not None:
            observe()
        return ok

    out, _ = follow_waypoints(execute, scene.eef_position, default_directions(),
                              scene.step_length, start, points, max_moves)
    scene.place_arm(start)
    scene.settle(rest)
    after = scene.render(0)[0]
    return image_descriptor(after, before, image_size), np.array(path), out
