"""The ``virtual`` scene: the fast "virtual setup", a kinematic push model without
physics, robot or camera.

The model is the C++ :class:`a2l._core.VirtualScene` (docs/virtual_scene.md); this module
only gives it the :class:`~a2l.sim.scene.Scene` interface (effects, perturbations, context).
There is no Python implementation of the push model.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l import _core
from a2l.errors import A2LError, A2LValueError
from a2l.sim.movement import MoveResult
from a2l.sim.observation import Observation
from a2l.sim.scene import Scene
from a2l.sim.virtual_config import VirtualConfig

__all__ = ["VirtualScene"]

_FAR = 1.0e3  # where a removed box goes: out of reach of any movement


class VirtualScene(Scene):
    """An end-effector point and a box on a table plane (config:
    :class:`a2l.sim.VirtualConfig`).

    Every movement is carried out (there are no joints, no limits); the box moves when the
    end-effector enters it. ``perceive()`` returns the true state: the virtual setup has
    no camera.
    """

    name = "virtual"
    primary_object = "box"
    config: VirtualConfig

    def __init__(self, config: VirtualConfig, seed: int = 0) -> None:
        super().__init__(config, seed)
        if not hasattr(_core, "VirtualScene"):
            raise A2LError("this build of a2l._core has no VirtualScene: rebuild a2l "
                           "(make setup)")
        cfg = config
        self._model: Any = _core.VirtualScene(
            half_size=np.asarray(cfg.box_half_size, dtype=float), table_z=cfg.table_z,
            eef_radius=cfg.eef_radius)
        self.reset()

    def _box_home(self, xy: ArrayLike) -> NDArray[np.float64]:
        x, y = np.asarray(xy, dtype=float).reshape(2)
        return np.array([x, y, self.config.table_z + self.config.box_half_size[2]])

    def reset(self, eef: ArrayLike | None = None,
              objects: dict[str, ArrayLike] | None = None) -> None:
        cfg = self.config
        placed = dict(objects or {})
        for name in placed:
            if name != "box":
                raise A2LValueError(f"reset: unknown object '{name}'; this scene has ['box']")
        xy = np.asarray(placed.get("box", cfg.box_position), dtype=float).reshape(2)
        if cfg.object_jitter > 0:
            xy = xy + self._rng.uniform(-cfg.object_jitter, cfg.object_jitter, 2)
        e = np.asarray(cfg.eef_position if eef is None else eef, dtype=float).reshape(3)
        if not np.all(np.isfinite(e)):
            raise A2LValueError(f"reset: eef must be finite, got {eef!r}")
        self._model.reset(e, self._box_home(xy))
        self._removed = set()
        self._hold = 0
        self._episode_start = self._snapshot()
        self._step_start = self._episode_start

    def eef_position(self) -> NDArray[np.float64]:
        return np.asarray(self._model.eef_position, dtype=float).copy()

    def _object_names(self) -> list[str]:
        return ["box"]

    def _ground_truth(self) -> Observation:
        objs = {}
        if "box" not in self._removed:
            b = np.asarray(self._model.object_position, dtype=float)
            objs["box"] = (float(b[0]), float(b[1]), float(b[2]))
        return Observation(objs, {}, self.eef_position(), False)

    def _perceive(self) -> Observation:
        return self._ground_truth()

    def _move(self, displacement: NDArray[np.float64]) -> MoveResult:
        start = self.eef_position()
        self._model.move(np.asarray(displacement, dtype=float))
        return MoveResult(True, "ok", "", start + displacement, self.eef_position())

    def _idle(self) -> None:
        pass

    def _place(self, name: str, xyz: NDArray[np.float64]) -> None:
        self._model.reset(self.eef_position(), np.asarray(xyz, dtype=float))

    def _toggle(self, state: str) -> None:  # pragma: no cover - the scene has no states
        raise A2LValueError(f"the virtual scene has no high-level state '{state}'")

    def _park(self, name: str) -> None:
        self._model.reset(self.eef_position(),
                          np.array([_FAR, _FAR, self.config.table_z + _FAR]))
