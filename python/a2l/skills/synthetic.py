"""Synthetic datasets for tests and benchmarks.

- :func:`push_dataset`: random babbling around a box in the virtual scene of
  ``docs/virtual_scene.md`` (the C++ ``VirtualScene``, the one the runtime uses). It follows
  the acquisition (docs/method.md): start points on a circle around the object, up to `max_steps`
  random movements, keep a trajectory only if it moved the box, label every step with the
  observed effect.
- :func:`known_structure_dataset`: samples of a discrete network whose structure is known
  (the parents of ``move`` are given), for testing structure recovery.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from a2l._core import VirtualScene
from a2l.skills.discretizer import Discretizer
from a2l.skills.repertoire import MovementRepertoire

__all__ = ["KnownStructure", "known_structure_dataset", "push_dataset"]


#: The columns of :func:`push_dataset`'s table, in order.
_COLUMNS = ["episode", "step", "eef_x", "eef_y", "eef_z", "obj_x", "obj_y", "obj_z",
            "move_dx", "move_dy", "move_dz", "effect_dx", "effect_dy", "effect_dz"]


def _steps_to_contact(scene: VirtualScene, plan: list[int],
                      disp_list: list[tuple[float, ...]]) -> int:
    """Carry out the movements of `plan` until one pushes the box; return how many were
    carried out (the pushing one included), or 0 when none pushed."""
    for k, m in enumerate(plan, start=1):
        if scene.move(disp_list[m]):
            return k
    return 0


def push_dataset(
    n_trajectories: int,
    *,
    seed: int = 0,
    movements: MovementRepertoire | None = None,
    radius: float = 0.2,
    n_starts: int = 16,
    max_steps: int = 7,
    object_position: tuple[float, float, float] = (0.7, 0.0, 0.04),
    half_size: tuple[float, float, float] = (0.035, 0.0425, 0.04),
    eef_radius: float = 0.01,
    min_displacement: float = 0.01,
    max_tries: int | None = None,
) -> pd.DataFrame:
    """Random push babbling in the virtual scene (``a2l._core.VirtualScene``).

    Parameters
    ----------
    n_trajectories : int
        Number of kept trajectories (those that moved the box).
    seed : int
        Seed of the random generator.
    movements : MovementRepertoire, optional
        The movements babbled with (default: the 8 planar directions, step 0.05 m).
    radius : float
        Radius of the circle of start points around the object (m).
    n_starts : int
        Number of start points, evenly on the circle, at the object's height.
    max_steps : int
        Most random movements per trajectory; a trajectory ends when the box moves.
    object_position : (3,) floats
        Box centre at every start (m).
    half_size : (3,) floats
        Box half-extents (m).
    eef_radius : float
        The end-effector's radius (m): contact when inside the box grown by it.
    min_displacement : float
        A trajectory is kept when it moved the box at least this far (m); the default is
        :class:`~a2l.skills.EffectDiscretizer`'s threshold, so every kept row has an effect.
    max_tries : int, optional
        Most trajectories tried (default 200 × `n_trajectories`).

    Returns
    -------
    pandas.DataFrame, shape (n_steps, 14)
        A raw dataset (:mod:`a2l.data.schema`): ``episode, step, eef_*, obj_*, move_d*,
        effect_d*`` where ``effect_d*`` is the box displacement of the trajectory.

    Raises
    ------
    RuntimeError
        Fewer than `n_trajectories` kept after `max_tries`.
    """
    if n_trajectories < 1:
        raise ValueError(f"n_trajectories must be >= 1, got {n_trajectories}")
    rng = np.random.default_rng(seed)
    moves = movements or MovementRepertoire(planar=True)
    disp = moves.displacement(np.arange(moves.n_moves))  # (n_moves, 3)
    obj0 = np.asarray(object_position, dtype=np.float64)
    angles = np.arange(n_starts) * 2 * np.pi / n_starts
    starts = obj0 + radius * np.stack([np.cos(angles), np.sin(angles), 0 * angles], axis=1)
    max_tries = max_tries or 200 * n_trajectories
    scene = VirtualScene(half_size=np.asarray(half_size, dtype=np.float64), eef_radius=eef_radius)

    # Draw trajectories in batches; run each in the scene until the box moves. Only the
    # kept ones are written out: before its last step the box has not moved, and the
    # end-effector positions are the same sequential sums the scene makes (eef += d).
    disp_list = [tuple(map(float, d)) for d in disp]
    obj0_list = tuple(map(float, obj0))
    start_list = [tuple(map(float, p)) for p in starts]
    blocks: list[np.ndarray] = []
    n_kept = 0
    tried = 0
    while n_kept < n_trajectories:
        if tried >= max_tries:
            raise RuntimeError(
                f"only {n_kept} of {n_trajectories} trajectories moved the box in {tried} tries"
            )
        batch = min(max(1024, 8 * (n_trajectories - n_kept)), max_tries - tried)
        tried += batch
        start_idx = rng.integers(0, n_starts, batch).tolist()
        plans = rng.integers(0, moves.n_moves, (batch, max_steps))
        for i, plan in enumerate(plans.tolist()):
            scene.reset(start_list[start_idx[i]], obj0_list)
            k = _steps_to_contact(scene, plan, disp_list)  # the last one pushed
            if k == 0:
                continue
            effect = np.asarray(scene.object_position) - obj0
            if np.hypot(effect[0], effect[1]) < min_displacement:
                continue
            d = disp[plans[i, :k]]
            eef = np.cumsum(np.vstack([starts[start_idx[i]], d[:-1]]), axis=0)
            blocks.append(
                np.hstack(
                    [
                        np.full((k, 1), n_kept),
                        np.arange(k)[:, None],
                        eef,
                        np.tile(obj0, (k, 1)),
                        d,
                        np.tile(effect, (k, 1)),
                    ]
                )
            )
            n_kept += 1
            if n_kept == n_trajectories:
                break
    df = pd.DataFrame(np.vstack(blocks), columns=_COLUMNS)
    return df.astype({"episode": np.int64, "step": np.int64})


@dataclass(frozen=True)
class KnownStructure:
    """A discrete network of known structure used to generate data.

    Attributes
    ----------
    parents : dict of str to tuple of str
        Parents of every variable (``move``'s are the ones to recover).
    cards : dict of str to int
        Number of states of every variable.
    cpts : dict of str to ndarray
        P(variable | parents), shape ``(*parent cards, card)``, in the order of `parents`.
    """

    parents: dict[str, tuple[str, ...]]
    cards: dict[str, int]
    cpts: dict[str, np.ndarray]


def known_structure_dataset(
    n_rows: int,
    *,
    seed: int = 0,
    discretizer: Discretizer | None = None,
    move_parents: tuple[str, ...] = ("effect", "orientation", "distance"),
    concentration: float = 0.3,
) -> tuple[pd.DataFrame, KnownStructure]:
    """Samples of a network where ``move`` has `move_parents` and nothing else depends on
    anything (the context variables are independent and uniform).

    Each row of P(move | parents) is drawn from a symmetric Dirichlet(`concentration`):
    small concentrations give peaked, learnable conditionals.

    Parameters
    ----------
    n_rows : int
        Number of samples.
    seed : int
        Seed of the CPTs and of the samples.
    discretizer : Discretizer, optional
        Gives the variables and their states (default: :class:`Discretizer` defaults, i.e.
        effect 4, distance 3, orientation 16, inclination 8, move 26).
    move_parents : tuple of str
        The true parents of ``move``.
    concentration : float
        Dirichlet concentration of the rows of P(move | parents).

    Returns
    -------
    df : pandas.DataFrame, shape (n_rows, n_variables)
        Categorical columns with every state as a category.
    truth : KnownStructure
    """
    disc = discretizer or Discretizer()
    states = disc.state_names()
    target = disc.movements.name
    unknown = [p for p in move_parents if p not in states or p == target]
    if unknown:
        raise ValueError(f"move_parents {unknown} are not evidence variables of the discretizer")
    rng = np.random.default_rng(seed)
    cards = {v: len(s) for v, s in states.items()}
    codes: dict[str, np.ndarray] = {}
    cpts: dict[str, np.ndarray] = {}
    parents: dict[str, tuple[str, ...]] = {}
    for v in states:
        if v == target:
            continue
        parents[v] = ()
        cpts[v] = np.full(cards[v], 1.0 / cards[v])
        codes[v] = rng.integers(0, cards[v], n_rows)
    pshape = tuple(cards[p] for p in move_parents)
    cpt = rng.dirichlet(np.full(cards[target], concentration), size=pshape)
    cpts[target] = cpt
    parents[target] = tuple(move_parents)
    rows = (
        cpt[tuple(codes[p] for p in move_parents)]
        if move_parents
        else np.broadcast_to(cpt, (n_rows, cards[target]))
    )
    u = rng.random(n_rows)[:, None]
    codes[target] = np.minimum((rows.cumsum(axis=1) < u).sum(axis=1), cards[target] - 1)
    df = pd.DataFrame(
        {v: pd.Categorical.from_codes(codes[v], categories=states[v]) for v in disc.variable_names}
    )
    return df, KnownStructure(parents=parents, cards=cards, cpts=cpts)
