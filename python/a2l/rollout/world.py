"""An :mod:`a2l.sim` scene as the world of a closed loop (:class:`SceneWorld`,
:func:`a2l.rollout.loop.closed_loop`): it observes one object and the high-level states,
carries out a skill's commands and adds up the object displacement they produced.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from a2l.rollout.loop import Decision
from a2l.rollout.protocol import SceneProtocol

__all__ = ["SceneWorld", "observe"]


def observe(scene: SceneProtocol, source: str | None = None) -> dict[str, dict[str, Any]]:
    """The scene's perceived or true objects and states (default: its ``context_source``)."""
    src = source or getattr(scene.config, "context_source", "ground_truth")
    return scene.perceive() if src == "perceived" else scene.ground_truth()


class SceneWorld:
    """A scene seen by a skill acting on one object.

    Parameters
    ----------
    scene : SceneProtocol
    name : str
        The object the skill acts on.
    source : {"perceived", "ground_truth"}, optional
        Where object positions and states come from (default: the scene's config).
    states_fn : callable ``scene -> dict``, optional
        The high-level states a step sees (default: the observed ones).
    displacements : bool
        Whether a command that is an array is a displacement (a DS step,
        :meth:`~a2l.sim.Scene.execute_displacement`) rather than a direction.

    Attributes
    ----------
    produced : ndarray, shape (3,)
        The true object displacement the carried out commands produced, summed over them
        (a perturbation between two steps is not counted).
    """

    def __init__(self, scene: SceneProtocol, name: str, source: str | None = None,
                 states_fn: Callable[[Any], dict[str, str]] | None = None,
                 displacements: bool = False) -> None:
        self.scene = scene
        self.name = name
        self.source = source
        self.states_fn = states_fn
        self.displacements = displacements
        self.produced = np.zeros(3)

    def look(self) -> tuple[NDArray[np.float64], dict[str, str]]:
        """The object (NaN when not seen) and the high-level states."""
        obs = observe(self.scene, self.source)
        pos = obs["objects"].get(self.name)
        obj = np.full(3, np.nan) if pos is None else np.asarray(pos, dtype=float)
        states = dict(self.states_fn(self.scene)) if self.states_fn else dict(obs["states"])
        return obj, states

    def truth(self) -> NDArray[np.float64]:
        """The object's true position, shape (3,)."""
        return np.asarray(self.scene.ground_truth()["objects"][self.name], dtype=float)

    def observe(self) -> tuple[NDArray[np.float64], NDArray[np.float64], dict[str, str]]:
        """``(eef, obj, states)``: the object and states first, then the end-effector."""
        obj, states = self.look()
        return np.asarray(self.scene.eef_position(), dtype=float), obj, states

    def act(self, decision: Decision) -> str:
        """Carry out a direction or an action (:meth:`~a2l.sim.Scene.execute`) or a DS
        displacement; the scene's move status."""
        command = decision.command
        before = self.truth()
        if not self.displacements or isinstance(command, str):
            res = self.scene.execute(command)
        else:
            res = self.scene.execute_displacement(command)
        self.produced += self.truth() - before
        return str(res.status)
