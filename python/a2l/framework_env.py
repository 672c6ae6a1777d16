"""What the framework needs from a scene and from a skill, over the real components.

- :class:`SceneEnv` wraps an :mod:`a2l.sim` scene (``virtual``: the C++ kinematic push model;
  ``baxter``: the PyBullet push scene with the C++ IK): start the end-effector at an offset
  from the object's home, execute discrete movements, read positions.
- :class:`CppSkillRunner` runs a skill bundle through the C++ step of :mod:`a2l._core`
  (the same step ``a2l-run`` executes): there is no Python implementation of a step.
"""

from __future__ import annotations

import os
import threading
from typing import Any, ClassVar

import numpy as np

from a2l import _core

__all__ = ["CppSkillRunner", "SceneEnv", "make_env"]

#: Framework scene name -> a2l.sim scene name.
SCENES = {"virtual": "virtual", "baxter": "push"}


class SceneEnv:
    """A scene seen as the framework's rollout environment.

    Parameters
    ----------
    scene : a2l.sim.Scene
        A push-like scene with one movable object.
    source : {"ground_truth", "perceived"}
        Where object positions come from (the camera, or the simulator's truth).
    """

    def __init__(self, scene: Any, source: str | None = None) -> None:
        self.scene = scene
        self.source = source
        self.obj_name = scene.primary_object
        truth = scene.ground_truth()["objects"]
        if self.obj_name not in truth:
            raise ValueError(f"scene {scene.name!r} has no object {self.obj_name!r}")
        self.home = np.asarray(truth[self.obj_name], dtype=float)

    def begin(self, offset: np.ndarray) -> None:
        """Object at its home, end-effector at ``home + offset`` (same height as the object)."""
        self.scene.reset(eef=self.home + np.asarray(offset, dtype=float),
                         objects={self.obj_name: self.home[:2].copy()})

    def execute(self, direction: tuple[int, int, int]) -> bool:
        """One discrete movement; False if it could not be carried out."""
        return bool(self.scene.execute(direction))

    def eef(self) -> np.ndarray:
        """End-effector position, shape (3,)."""
        return np.asarray(self.scene.eef_position(), dtype=float)

    def object(self) -> np.ndarray:
        """Object position, shape (3,) (NaN if not seen)."""
        obs = (self.scene.perceive() if self.source == "perceived"
               else self.scene.ground_truth())
        pos = obs["objects"].get(self.obj_name)
        return np.full(3, np.nan) if pos is None else np.asarray(pos, dtype=float)

    def close(self) -> None:
        """Release the scene."""
        self.scene.close()


def make_env(scene: str, seed: int = 0, step: float = 0.05, source: str | None = None,
             **config: Any) -> SceneEnv:
    """The rollout environment of a framework scene name (``virtual`` or ``baxter``)."""
    from a2l.sim import make_scene

    if scene not in SCENES:
        raise ValueError(f"unknown scene {scene!r}; choose one of {sorted(SCENES)}")
    # Rollouts place the object themselves: a random jitter on reset would make a rollout
    # depend on how many resets its process made before (and so on the worker count).
    config.setdefault("object_jitter", 0.0)
    return SceneEnv(make_scene(SCENES[scene], seed=seed, step=step, **config), source)


class CppSkillRunner:
    """A skill bundle run step by step through the C++ runtime.

    Parameters
    ----------
    bundle : str
        Path of the skill bundle.
    """

    #: Runners per thread (a runner's SkillState is mutable: a Dask worker runs tasks in
    #: several threads), keyed by the bundle's path, size and modification time.
    _local: ClassVar[threading.local] = threading.local()

    def __init__(self, bundle: str) -> None:
        self.bundle = bundle
        self.skill = _core.load_bundle(bundle)
        self.state = _core.SkillState(self.skill)
        self.labels = list(self.skill.movements.labels)

    @classmethod
    def cached(cls, bundle: str) -> CppSkillRunner:
        """One runner per bundle per thread (loading validates the whole file).

        A file rewritten at the same path (a new run in the same directory, on a long-lived
        Dask worker) is loaded again.
        """
        cache: dict[tuple[str, int, int], CppSkillRunner] = \
            cls._local.__dict__.setdefault("runners", {})
        st = os.stat(bundle)
        key = (bundle, st.st_size, st.st_mtime_ns)
        runner = cache.get(key)
        if runner is None:
            if len(cache) > 8:
                cache.clear()
            runner = cache[key] = cls(bundle)
        return runner

    def reset(self) -> None:
        """Start a new run."""
        self.state.reset()

    def step_with_probability(self, eef: np.ndarray, obj: np.ndarray, effect: int
                              ) -> tuple[int | None, str, float]:
        """One C++ step.

        Returns
        -------
        (movement or None, status name, probability)
            None with the stop status (``step_cap``, ``unknown_context``...).
        """
        ctx = self.skill.context(np.asarray(eef, float), np.asarray(obj, float), int(effect))
        out = _core.step(self.skill, self.state, ctx)
        if out.status != _core.Status.ok:
            return None, _core.status_name(out.status), 0.0
        return int(out.movement), "ok", float(out.probability)

    def step(self, eef: np.ndarray, obj: np.ndarray, effect: int) -> tuple[int | None, str]:
        """One C++ step: (movement index or None, status name)."""
        move, status, _ = self.step_with_probability(eef, obj, effect)
        return move, status
