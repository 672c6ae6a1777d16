"""The diffeomorphic DS of a skill: fitted in Python, evaluated by the C++ core.

:class:`DiffeoDS` wraps :class:`a2l._core.DiffeoDS` (forward and inverse maps, Jacobian,
velocity, rollout: C++, fixed-size Eigen, no allocation per call) and adds the fit
(:mod:`a2l.lfd.fit`) and the skill-bundle file (``docs/bundle_format.md``, section ``ds``).
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from a2l import _core
from a2l.lfd.demonstration import Demonstration
from a2l.lfd.fit import fit_diffeo, mean_demonstration, speed_gain
from a2l.skills.ds_bundle import DSArrays, load_ds_bundle, save_ds_bundle

__all__ = ["DiffeoDS"]

Trajectory = np.ndarray | Demonstration


class DiffeoDS:
    """The globally stable DS ``xdot = speed J_Phi(y) (target - y)``, ``y = Phi^-1(x)``.

    Build it with :meth:`fit`, :meth:`from_maps` or :meth:`load`. Its maps compose to
    ``Phi`` (direction ``"to_demo"``, the paper's construction) or to ``Phi^-1``
    (``"to_line"``: fitted from the demonstration onto the line; the velocity is then
    ``-speed J_C(x)^-1 (C(x) - target)``, explicit, no scalar solves). Either way
    :meth:`forward` is ``Phi`` (line space -> demonstration) and :meth:`inverse` its inverse.

    Parameters
    ----------
    core : a2l._core.DiffeoDS
        The validated C++ object.
    metadata : dict, optional
        How it was made (fit parameters, residual, frame, states); saved in the bundle.
    """

    def __init__(self, core: Any, metadata: dict[str, Any] | None = None) -> None:
        self._core = core
        self.metadata: dict[str, Any] = dict(metadata or {})

    # --- construction -----------------------------------------------------------------------
    @classmethod
    def from_maps(cls, target: np.ndarray, centers: np.ndarray, vectors: np.ndarray,
                  rhos: np.ndarray, speed: float = 1.0,
                  metadata: dict[str, Any] | None = None,
                  direction: str = "to_demo") -> DiffeoDS:
        """A DS from its maps (original units, application order).

        Parameters
        ----------
        target : array (d,), d in {2, 3}
        centers, vectors : arrays (K, d)
        rhos : array (K,)
        speed : float > 0
        metadata : dict, optional
        direction : {"to_demo", "to_line"}
            Whether the composed maps are ``Phi`` or ``Phi^-1``.

        Raises
        ------
        ValueError
            Naming the first map that is non-finite, has ``rho < 0`` or breaks
            ``rho ||v|| < sqrt(e/2)``, or the argument of the wrong shape (the C++
            validator, the same one the bundle loader uses).
        """
        arrays = [np.asarray(a, dtype=float) for a in (target, centers, vectors, rhos)]
        return cls(_core.DiffeoDS(*arrays, float(speed), direction=str(direction)), metadata)

    @classmethod
    def fit(cls, trajectory: Trajectory | Sequence[Trajectory], K: int = 150,
            beta: float | np.ndarray = 0.5, mu: float | np.ndarray = 0.9,
            duration: float | None = None,
            regularisation: float = 1e-4, direction: str = "to_demo") -> DiffeoDS:
        """Fit a DS to one demonstration, or to the time-aligned mean of several.

        Parameters
        ----------
        trajectory : array (N, d), Demonstration, or a sequence of them
            The demonstration(s); the target is the (mean) last point. Several are
            resampled on their own normalised time and averaged point by point
            (:func:`a2l.lfd.fit.mean_demonstration`).
        K, beta, mu : int, float or array, float or array
            Maps, correction fraction and safety factor, constant or per map
            (:func:`a2l.lfd.fit.fit_diffeo`, :func:`a2l.lfd.fit.schedule`).
        duration : float, optional
            Demonstration duration (s) the reproduction should last; default: the
            Demonstrations' mean duration, or 1 s for bare arrays. Sets the speed gain
            (:func:`a2l.lfd.fit.speed_gain`).
        regularisation : float
            Weight of ``rho^2`` in the width search.
        direction : {"to_demo", "to_line", "auto"}
            Fit the maps from the line onto the demonstration (default, the paper's), the
            other way (explicit velocity queries), or ``"auto"`` (both fitted, the one with the
            smaller mean error kept; :func:`a2l.lfd.fit.fit_diffeo`). The fitted DS's
            ``direction`` says which.
        """
        items = (list(trajectory) if isinstance(trajectory, (list, tuple))
                 else [trajectory])
        if not items:
            raise ValueError("no demonstration given")
        arrays = [it.positions if isinstance(it, Demonstration) else np.asarray(it, float)
                  for it in items]
        if duration is None:
            durs = [it.duration for it in items if isinstance(it, Demonstration)]
            duration = float(np.mean(durs)) if durs else 1.0
        ref = arrays[0] if len(arrays) == 1 else mean_demonstration(arrays)
        t0 = time.perf_counter()
        res = fit_diffeo(ref, K=K, beta=beta, mu=mu, regularisation=regularisation,
                         direction=direction)
        fit_ms = (time.perf_counter() - t0) * 1e3
        meta = {"K": K, "beta": np.asarray(beta).tolist(), "mu": np.asarray(mu).tolist(),
                "regularisation": regularisation,
                "duration": duration, "n_demonstrations": len(arrays),
                "max_error": res.max_error, "mean_error": res.mean_error,
                "direction_alternative": res.alternative, "fit_ms": fit_ms}
        first = items[0]
        if isinstance(first, Demonstration):
            meta.update(frame=first.frame, states=first.states)
        return cls.from_maps(res.target, res.centers, res.vectors, res.rhos,
                             speed_gain(duration), meta, direction=res.direction)

    # --- files --------------------------------------------------------------------------------
    def save(self, path: str | os.PathLike[str], name: str = "ds") -> Path:
        """Write a skill bundle (kind ``"ds"``) holding this DS and its metadata, atomically."""
        arrays = DSArrays(self.target, self.centers, self.vectors, self.rhos, self.speed,
                          self.direction)
        return save_ds_bundle(path, arrays, name=name, metadata=self.metadata)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> DiffeoDS:
        """Read a DS from a skill bundle through the C++ loader.

        Raises
        ------
        a2l.BundleError
            A malformed bundle or a map breaking the bound (named by its index).
        """
        core, meta = load_ds_bundle(path)
        return cls(core, meta)

    # --- evaluation (C++) ---------------------------------------------------------------------
    def velocity(self, x: np.ndarray) -> np.ndarray:
        """DS velocity at x (d,) or (M, d) -> same shape."""
        return self._core.velocity(np.asarray(x, dtype=float))

    def forward(self, x: np.ndarray) -> np.ndarray:
        """``Phi(x)``: line space -> demonstration space; (d,) or (M, d) -> same shape."""
        return self._core.forward(np.asarray(x, dtype=float))

    def inverse(self, y: np.ndarray) -> np.ndarray:
        """``Phi^{-1}(y)``; (d,) or (M, d) -> same shape."""
        return self._core.inverse(np.asarray(y, dtype=float))

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """``dPhi/dx``: (d,) -> (d, d); (M, d) -> (M, d, d)."""
        return self._core.jacobian(np.asarray(x, dtype=float))

    def rollout(self, x0: np.ndarray, dt: float, steps: int,
                method: str = "rk4") -> np.ndarray:
        """States at times ``0, dt, ..., (steps-1) dt`` from `x0` (d,), shape (steps, d).

        `method` is ``"rk4"`` (default), ``"euler"`` (what a controller applying the
        velocity each tick does) or ``"exact"`` (the flow mapped through Phi).
        """
        return self._core.rollout(np.asarray(x0, dtype=float), float(dt), int(steps), method)

    def arrival(self, starts: np.ndarray, dt: float, max_steps: int,
                tolerance: float) -> tuple[np.ndarray, np.ndarray]:
        """Explicit Euler from every start until it is within `tolerance` of the target.

        The states are those of ``rollout(x0, dt, steps, "euler")`` (the C++ velocity, the
        same update ``x + dt * f(x)``: what a controller applying the field at period `dt`
        does), all starts advanced together; a start stops at its first state within
        `tolerance` of the target (the runtime's convergence test) or after `max_steps`.

        Parameters
        ----------
        starts : array (M, d)
        dt : float > 0
        max_steps : int >= 0
        tolerance : float >= 0

        Returns
        -------
        steps : array (M,) of int
            Steps taken (`max_steps` where the start did not arrive).
        distance : array (M,)
            Distance of the last state to the target; arrived iff ``distance <= tolerance``.
        """
        x = np.array(starts, dtype=float, ndmin=2)
        if x.ndim != 2 or x.shape[1] != self.dim:
            raise ValueError(f"starts must have shape (M, {self.dim}), got {x.shape}")
        if not (np.isfinite(dt) and dt > 0 and max_steps >= 0 and tolerance >= 0):
            raise ValueError("arrival needs dt > 0, max_steps >= 0 and tolerance >= 0, got "
                             f"{dt}, {max_steps}, {tolerance}")
        target = self.target
        dist = np.linalg.norm(x - target, axis=1)
        steps = np.full(len(x), int(max_steps))
        steps[dist <= tolerance] = 0
        active = np.flatnonzero(dist > tolerance)
        for k in range(1, int(max_steps) + 1):
            if active.size == 0:
                break
            x[active] = x[active] + dt * self._core.velocity(x[active])
            dist[active] = np.linalg.norm(x[active] - target, axis=1)
            done = dist[active] <= tolerance
            steps[active[done]] = k
            active = active[~done]
        return steps, dist

    # --- parameters ---------------------------------------------------------------------------
    @property
    def target(self) -> np.ndarray:
        """The attractor (d,)."""
        return np.asarray(self._core.target)

    @property
    def n_maps(self) -> int:
        """Number of elementary maps K."""
        return int(self._core.n_maps)

    @property
    def dim(self) -> int:
        """Dimension d (2 or 3)."""
        return int(self._core.dim)

    @property
    def speed(self) -> float:
        """Gain of the line-space system."""
        return float(self._core.speed)

    @property
    def direction(self) -> str:
        """``"to_demo"`` (the maps compose to Phi) or ``"to_line"`` (to Phi^-1)."""
        return str(self._core.direction)

    @property
    def centers(self) -> np.ndarray:
        """Map centers (K, d)."""
        return np.asarray(self._core.centers)

    @property
    def vectors(self) -> np.ndarray:
        """Map displacements (K, d)."""
        return np.asarray(self._core.vectors)

    @property
    def rhos(self) -> np.ndarray:
        """Map inverse widths (K,)."""
        return np.asarray(self._core.rhos)

    @property
    def core(self) -> Any:
        """The underlying :class:`a2l._core.DiffeoDS`."""
        return self._core

    def __repr__(self) -> str:
        return (f"DiffeoDS(dim={self.dim}, n_maps={self.n_maps}, speed={self.speed:.4g}, "
                f"direction={self.direction!r})")
