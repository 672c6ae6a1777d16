"""Vector field -> dataset: the rows a demonstrated skill's Bayesian network is learned from.

Chapter 6 of the thesis (docs/method.md): points are sampled on a grid around the demonstrations,
in the object frame (``x = eef - object``); at each point the DS velocity becomes the nearest
movement of the repertoire and the point becomes context bins, through the **same**
:class:`a2l.skills.Discretizer` the babbling path uses (:func:`skill_discretizer` builds it
from :class:`a2l.skills.discretization.DiscretizationConfig`, the configuration both paths
share); the demonstration's high-level states and the demonstrated effect are added as
columns. The result is a raw interaction dataset
(:mod:`a2l.data.schema`, one row per grid point, the object at the origin), so that the
discretization, the learning and the compilation are the babbling path's own
(:func:`a2l.lfd.skill.learn_skill`).

Which DS gives a point its velocity: each demonstration has its own DS
(:func:`a2l.lfd.skill.fit_fields`); a grid point takes the velocity of the DS of the
demonstration nearest to it, or, with ``blend = sigma > 0``, the sum of every DS's unit
velocity weighted by ``exp(-d_i^2 / (2 sigma^2))`` (``d_i``: the point's distance to
demonstration i), so that where demonstrations from both sides cross, their sideways parts
cancel. Points farther than ``tube`` from every demonstration are not
sampled (the DS far from every demonstration is a straight line to the object, which a push
cannot follow: these contexts stay unknown, and the skill says so instead of guessing).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import pandas as pd
from scipy.spatial import cKDTree

from a2l.data.schema import EEF_COLUMNS, MOVE_COLUMNS, OBJECT_COLUMNS
from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.lfd.demonstration import Demonstration

__all__ = ["demo_distances", "grid_points", "skill_discretizer", "vector_field_rows"]


def skill_discretizer(cfg: LfDConfig = DEFAULT, high_level: Sequence[Any] = (),
                      planar: bool = True, n_effects: int = 4) -> Any:
    """The discretizer of a demonstrated skill: the babbling path's, from the same function.

    Parameters
    ----------
    cfg : LfDConfig
        Bins, range and movement step.
    high_level : sequence of a2l.skills.HighLevelState
        High-level states the table is conditioned on.
    planar : bool
        8 movements in the table plane (push) or 26 in 3-D.
    n_effects : {4, 8}
        Push effects of the effect variable.

    Returns
    -------
    a2l.skills.Discretizer
    """
    disc = cfg.skill_discretization(planar, n_effects).discretizer()
    return replace(disc, high_level=tuple(high_level)) if high_level else disc


def _dense(demo: Demonstration, spacing: float) -> np.ndarray:
    """The demonstration's positions (n, 3) resampled every `spacing` along its path."""
    pos = demo.positions
    if pos.shape[1] == 2:
        pos = np.column_stack([pos, np.zeros(len(pos))])
    length = float(demo.arc_length()[-1])
    n = max(2, int(np.ceil(length / spacing)) + 1)
    d = Demonstration(pos, demo.times, demo.frame, demo.states)
    return d.resample(n, by="arclength").positions if length > 0 else pos


def _until_closest(demo: Demonstration) -> Demonstration:
    """The demonstration up to its sample nearest the object (the origin), included."""
    k = int(np.argmin(np.linalg.norm(demo.positions, axis=1)))
    if k >= len(demo.times) - 1:
        return demo
    k = max(k, 1)
    return Demonstration(demo.positions[: k + 1], demo.times[: k + 1], demo.frame, demo.states)


def grid_points(demos: Sequence[Demonstration], resolution: float, tube: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """Grid points around the demonstrations and the demonstration nearest to each.

    The grid spans the demonstrations' bounding box enlarged by `tube`, every `resolution`
    on each axis along which the demonstrations vary (an axis on which every demonstration
    stays at one value, such as the height of a planar push, keeps that value); a point is
    kept when it lies within `tube` of a demonstration up to the demonstration's sample
    nearest the object (a push demonstration goes on beyond the object's initial centre,
    where the end-effector can only be because the object moved ahead of it: the contexts
    there are the ones at the object's face).

    Parameters
    ----------
    demos : sequence of Demonstration
        In the object frame, 2-D or 3-D (2-D ones get z = 0).
    resolution, tube : float
        Grid spacing and largest distance to a demonstration (m).

    Returns
    -------
    points : ndarray, shape (M, 3)
        Positions in the object frame.
    nearest : ndarray of int64, shape (M,)
        Index in `demos` of the demonstration nearest to each point.
    """
    if not demos:
        raise ValueError("no demonstration to sample a grid around")
    if not (resolution > 0 and tube > 0):
        raise ValueError(f"resolution and tube must be > 0, got {resolution}, {tube}")
    paths = [_dense(_until_closest(d), resolution / 2) for d in demos]
    allp = np.vstack(paths)
    labels = np.concatenate([np.full(len(p), i) for i, p in enumerate(paths)])
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    axes = []
    for k in range(3):
        if hi[k] - lo[k] < 1e-9:
            axes.append(np.array([lo[k]]))
        else:
            a, b = lo[k] - tube, hi[k] + tube
            n = int(np.floor((b - a) / resolution + 1e-9)) + 1
            axes.append(a + resolution * np.arange(n))
    if np.prod([len(a) for a in axes]) > 5_000_000:
        raise ValueError(f"the grid would hold {np.prod([len(a) for a in axes]):,} points: "
                         f"raise the resolution ({resolution} m)")
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    dist, idx = cKDTree(allp).query(grid)
    keep = dist <= tube
    return grid[keep], labels[idx[keep]].astype(np.int64)


def demo_distances(points: np.ndarray, demos: Sequence[Demonstration],
                   resolution: float) -> np.ndarray:
    """Distance (M, n_demos) from each point (M, 3) to each demonstration (up to its sample
    nearest the object, as :func:`grid_points` samples)."""
    out = np.empty((len(points), len(demos)))
    for i, d in enumerate(demos):
        out[:, i] = cKDTree(_dense(_until_closest(d), resolution / 2)).query(points)[0]
    return out


def _velocity(ds: Any, points: np.ndarray) -> np.ndarray:
    """DS velocity (M, 3) at `points` (M, 3) (a 2-D DS sees x, y; its z velocity is 0)."""
    out = np.zeros_like(points)
    x = points if ds.dim == 3 else points[:, :2]
    out[:, : ds.dim] = np.asarray(ds.velocity(x), dtype=float).reshape(-1, ds.dim)
    return out


def vector_field_rows(fields: Sequence[Any], demos: Sequence[Demonstration], effect: str,
                      cfg: LfDConfig = DEFAULT, states: dict[str, str] | None = None,
                      episode0: int = 0) -> pd.DataFrame:
    """The raw dataset of one demonstrated behaviour: a row per grid point.

    Parameters
    ----------
    fields : sequence of a2l.lfd.DiffeoDS
        ``fields[i]`` is the DS of ``demos[i]`` (3-D, object frame, target at the origin).
    demos : sequence of Demonstration
        The demonstrations, in the object frame.
    effect : str
        The demonstrated effect (the ``effect`` column).
    cfg : LfDConfig
        Grid resolution, tube and movement step.
    states : dict of str to str, optional
        High-level states the demonstrations were given under (one column each); default:
        the first demonstration's.
    episode0 : int
        First episode id (rows of several behaviours concatenated keep distinct ids).

    Returns
    -------
    pandas.DataFrame, shape (M, n_columns)
        Columns of :data:`a2l.data.schema.REQUIRED_COLUMNS` (object at the origin, the
        end-effector at the grid point, ``move_*`` the DS velocity scaled to one movement's
        length), ``effect`` and one column per high-level state. A point where the DS
        velocity is zero (the target itself) gets a zero move, which the discretizer drops.
    """
    if len(fields) != len(demos):
        raise ValueError(f"{len(fields)} fields for {len(demos)} demonstrations")
    points, nearest = grid_points(demos, cfg.resolution, cfg.tube)
    vel = np.zeros_like(points)
    if cfg.blend > 0:
        dist = demo_distances(points, demos, cfg.resolution)
        w = np.exp(-(dist**2 - dist.min(axis=1, keepdims=True) ** 2) / (2 * cfg.blend**2))
        for i, ds in enumerate(fields):
            v = _velocity(ds, points)
            n = np.linalg.norm(v, axis=1, keepdims=True)
            with np.errstate(invalid="ignore", divide="ignore"):
                vel += w[:, i : i + 1] * np.where(n > 1e-12, v / n, 0.0)
    else:
        for i, ds in enumerate(fields):
            sel = nearest == i
            if sel.any():
                vel[sel] = _velocity(ds, points[sel])
    speed = np.linalg.norm(vel, axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        move = np.where(speed > 1e-12, cfg.step * vel / speed, 0.0)
    states = dict(demos[0].states if states is None else states)
    return dataset_frame(points, move, effect, states, episode0)


def dataset_frame(points: np.ndarray, move: np.ndarray, effect: str,
                  states: dict[str, str], episode0: int = 0,
                  action: np.ndarray | None = None) -> pd.DataFrame:
    """Rows in the common dataset format, one per sampled point (the object at the origin).

    Parameters
    ----------
    points : np.ndarray, shape (n, 3)
        End-effector positions relative to the object (m).
    move : np.ndarray, shape (n, 3)
        The movement at each point (m).
    effect : str
        The effect every row produces.
    states : dict[str, str]
        High-level state values, the same for every row.
    episode0 : int
        Episode number of the first row (each row is its own one-step episode).
    action : np.ndarray of object, shape (n,), optional
        An action name (or None) per row: the dataset's ``action`` column.

    Returns
    -------
    pandas.DataFrame
        n rows: ``episode``, ``step``, eef, object and move columns, ``action`` if given,
        ``effect`` and one column per state.
    """
    n = len(points)
    data: dict[str, Any] = {"episode": episode0 + np.arange(n, dtype=np.int64),
                            "step": np.zeros(n, dtype=np.int64)}
    for k, c in enumerate(EEF_COLUMNS):
        data[c] = points[:, k]
    for c in OBJECT_COLUMNS:
        data[c] = np.zeros(n)
    for k, c in enumerate(MOVE_COLUMNS):
        data[c] = move[:, k]
    if action is not None:
        data["action"] = action
    data["effect"] = np.full(n, effect, dtype=object)
    for name, value in states.items():
        data[name] = np.full(n, value, dtype=object)
    return pd.DataFrame(data)
