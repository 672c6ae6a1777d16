"""a2l's push scenes as goal-conditioned Gymnasium environments (:class:`PushEnv`),
registered on ``import a2l.gym`` (:data:`ENV_IDS`):

- ``a2l/Push-v0``, ``a2l/PushContinuous-v0``: the PyBullet push scene (Baxter by default;
  ``gymnasium.make("a2l/Push-v0", robot="panda")`` any robot of :mod:`a2l.robot`);
- ``a2l/PushVirtual-v0``, ``a2l/PushVirtualContinuous-v0``: the virtual scene (the C++
  kinematic push model, no physics).

As panda-gym's tasks: dict observations ``observation`` (end-effector, object, object
relative to the end-effector: 9 floats), ``achieved_goal`` (the object) and
``desired_goal`` (the goal); a sparse reward ``-1`` until the object is within
``distance_threshold`` of the goal (``compute_reward`` works on batches, for hindsight
relabelling); ``terminated`` when it is; 50 steps an episode. The action is a movement of
a2l's planar repertoire (``Discrete(8)``, the push skills' movements in the C++ core's
order) or, in the continuous variant, an end-effector displacement of at most one movement
(``Box(-1, 1, (3,))`` times the movement's length).
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from a2l.errors import A2LValueError, UnreachableError
from a2l.robot import DEFAULT_ROBOT
from a2l.sim import make_scene
from a2l.skills.repertoire import default_directions, direction_label

__all__ = ["ENV_IDS", "PushEnv", "register_envs"]

#: a2l's registered environments: id -> keyword arguments of :class:`PushEnv`.
ENV_IDS: dict[str, dict[str, Any]] = {
    "a2l/Push-v0": {"scene": "push"},
    "a2l/PushContinuous-v0": {"scene": "push", "action_type": "continuous"},
    "a2l/PushVirtual-v0": {"scene": "virtual"},
    "a2l/PushVirtualContinuous-v0": {"scene": "virtual", "action_type": "continuous"},
}
#: Steps of an episode (panda-gym's push: 50).
MAX_EPISODE_STEPS = 50
#: Draws of an end-effector start before a reset gives up on reaching one.
START_DRAWS = 20


class PushEnv(gymnasium.Env):  # type: ignore[misc]
    """An a2l push scene as a goal-conditioned Gymnasium environment.

    Parameters
    ----------
    scene : {"push", "virtual"}
        The PyBullet push scene or the virtual scene (:func:`a2l.sim.make_scene`).
    robot : str
        The PyBullet scene's robot (a built-in name or a robot file); ignored by the
        virtual scene.
    action_type : {"discrete", "continuous"}
        A movement of the planar repertoire, or a displacement.
    object_range, goal_range : float
        Sides of the squares around the scene's object position where a reset draws the
        object and the goal (m).
    start_r_low, start_r_high : float
        The end-effector starts at a uniform angle and a distance uniform in this range
        from the object (m), at its height.
    distance_threshold : float
        Success: the object within this of the goal (m).
    reward_type : {"sparse", "dense"}
        ``-1``/``0`` by success, or minus the distance.
    render_mode : {None, "rgb_array"}
        ``rgb_array``: the scene camera's frame (PyBullet scene only).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(self, scene: str = "push", robot: str = DEFAULT_ROBOT,
                 action_type: str = "discrete", object_range: float = 0.10,
                 goal_range: float = 0.20, start_r_low: float = 0.10,
                 start_r_high: float = 0.25, distance_threshold: float = 0.05,
                 reward_type: str = "sparse", render_mode: str | None = None) -> None:
        if scene not in ("push", "virtual"):
            raise A2LValueError(f"scene: {scene!r} is not 'push' or 'virtual'")
        if action_type not in ("discrete", "continuous"):
            raise A2LValueError(f"action_type: {action_type!r} is not 'discrete' or "
                                "'continuous'")
        if reward_type not in ("sparse", "dense"):
            raise A2LValueError(f"reward_type: {reward_type!r} is not 'sparse' or 'dense'")
        if render_mode not in (None, "rgb_array") or (render_mode and scene == "virtual"):
            raise A2LValueError(f"render_mode: {render_mode!r} is not available for scene "
                                f"{scene!r}")
        if scene == "virtual":
            self.metadata = {"render_modes": [], "render_fps": 5}
        kwargs: dict[str, Any] = {"robot": robot} if scene == "push" else {}
        self.scene = make_scene(scene, seed=0, context_source="ground_truth",
                                object_jitter=0.0, **kwargs)
        self.object_name = self.scene.primary_object
        self.home = np.asarray(self.scene.ground_truth()["objects"][self.object_name],
                               dtype=float)
        self.action_type, self.reward_type = action_type, reward_type
        self.object_range, self.goal_range = float(object_range), float(goal_range)
        self.start_r = (float(start_r_low), float(start_r_high))
        self.distance_threshold = float(distance_threshold)
        self.render_mode = render_mode
        self.directions = default_directions(planar=True)
        self.labels = tuple(direction_label(d) for d in self.directions)
        if action_type == "discrete":
            self.action_space = spaces.Discrete(len(self.directions))
        else:
            self.action_space = spaces.Box(-1.0, 1.0, shape=(3,), dtype=np.float32)
        box = spaces.Box(-10.0, 10.0, shape=(3,), dtype=np.float32)
        self.observation_space = spaces.Dict({
            "observation": spaces.Box(-10.0, 10.0, shape=(9,), dtype=np.float32),
            "achieved_goal": box, "desired_goal": box})
        self.goal = self.home.copy()

    # --- Gymnasium ----------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, NDArray[np.float32]], dict[str, Any]]:
        super().reset(seed=seed)
        rng = self.np_random
        obj = self.home.copy()
        obj[:2] += rng.uniform(-self.object_range / 2, self.object_range / 2, 2)
        self.goal = self.home.copy()
        self.goal[:2] += rng.uniform(-self.goal_range / 2, self.goal_range / 2, 2)
        for _ in range(START_DRAWS):
            a = rng.uniform(0.0, 2 * np.pi)
            r = rng.uniform(*self.start_r)
            eef = obj + np.array([r * np.cos(a), r * np.sin(a), 0.0])
            try:
                self.scene.reset(eef=eef, objects={self.object_name: obj[:2]})
                break
            except UnreachableError:
                continue
        else:
            raise UnreachableError(f"no reachable end-effector start around {obj} in "
                                   f"{START_DRAWS} draws")
        obs = self._obs()
        return obs, {"is_success": bool(self._success(obs["achieved_goal"]))}

    def step(self, action: Any) -> tuple[dict[str, NDArray[np.float32]], float, bool, bool,
                                         dict[str, Any]]:
        """One movement: a movement of the repertoire (discrete) or an end-effector
        displacement of at most one movement's length (continuous, `action` shape (3,)).

        Returns
        -------
        observation : dict
            ``observation`` (9,), ``achieved_goal`` (3,), ``desired_goal`` (3,).
        reward : float
            :meth:`compute_reward` of the new state.
        terminated : bool
            The object is within ``distance_threshold`` of the goal.
        truncated : bool
            Always False here (the ``TimeLimit`` wrapper truncates).
        info : dict
            ``is_success`` and ``move_status`` (the movement's status).
        """
        if self.action_type == "discrete":
            res = self.scene.execute(tuple(int(s) for s in self.directions[int(action)]))
        else:
            step = self.scene.step_length
            disp = np.clip(np.asarray(action, dtype=float).reshape(3), -1.0, 1.0) * step
            norm = float(np.linalg.norm(disp))
            if norm < 1e-9:
                res = self.scene.execute("stay")
            else:
                res = self.scene.execute_displacement(disp * min(1.0, step / norm))
        obs = self._obs()
        success = bool(self._success(obs["achieved_goal"]))
        info = {"is_success": success, "move_status": str(res.status)}
        reward = float(self.compute_reward(obs["achieved_goal"], obs["desired_goal"], info))
        return obs, reward, success, False, info

    def compute_reward(self, achieved_goal: NDArray[np.floating],
                       desired_goal: NDArray[np.floating], info: Any) -> NDArray[np.float32]:
        """The reward of `achieved_goal` against `desired_goal`, shapes (..., 3) (batches
        for hindsight relabelling): ``-(d > threshold)`` (sparse) or ``-d`` (dense)."""
        d = np.linalg.norm(np.asarray(achieved_goal) - np.asarray(desired_goal), axis=-1)
        if self.reward_type == "sparse":
            return -(d > self.distance_threshold).astype(np.float32)
        return -d.astype(np.float32)

    def render(self) -> NDArray[np.uint8] | None:
        """The scene camera's RGB frame (H, W, 3) with ``render_mode="rgb_array"``."""
        if self.render_mode != "rgb_array":
            return None
        return np.asarray(self.scene.render(0)[0], dtype=np.uint8).copy()  # type: ignore[attr-defined]

    def close(self) -> None:
        scene = self.__dict__.pop("scene", None)
        if scene is not None:
            scene.close()

    # --- helpers ------------------------------------------------------------------------
    def _success(self, achieved: NDArray[np.floating]) -> bool:
        return bool(np.linalg.norm(np.asarray(achieved) - self.goal) < self.distance_threshold)

    def _obs(self) -> dict[str, NDArray[np.float32]]:
        eef = np.asarray(self.scene.eef_position(), dtype=float)
        obj = np.asarray(self.scene.ground_truth()["objects"][self.object_name], dtype=float)
        return {"observation": np.concatenate([eef, obj, obj - eef]).astype(np.float32),
                "achieved_goal": obj.astype(np.float32),
                "desired_goal": self.goal.astype(np.float32)}


def register_envs() -> tuple[str, ...]:
    """Register :data:`ENV_IDS` with Gymnasium (again: nothing changes); returns the ids."""
    for env_id, kwargs in ENV_IDS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point="a2l.gym.envs:PushEnv", kwargs=kwargs,
                               max_episode_steps=MAX_EPISODE_STEPS)
    return tuple(ENV_IDS)
