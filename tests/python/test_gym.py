"""Gymnasium both ways (``a2l.gym``, the extra ``a2l[gym]``): every registered a2l environment
passes Gymnasium's own checker; a Gymnasium environment without end-effector or object
access is refused by name; a short learning run inside panda-gym's ``PandaPush-v3`` counts
every ``env.step`` the environment itself counts, and its skill reaches goals from the
environment's own resets."""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from a2l.errors import A2LValueError
from a2l.gym import ENV_IDS, GymScene, GymSceneConfig, gym_scene

#: Every env.step a counted environment took, by instance (the environment's own count).
COUNTS: list[StepCount] = []


class StepCount(gymnasium.Wrapper):  # type: ignore[misc]
    """Counts the ``step`` calls that reach the environment, outside a2l's code."""

    def __init__(self, env: gymnasium.Env) -> None:
        super().__init__(env)
        self.steps = 0
        COUNTS.append(self)

    def step(self, action: Any) -> Any:
        self.steps += 1
        return self.env.step(action)


def _counted_push(**kwargs: Any) -> gymnasium.Env:
    from panda_gym.envs import PandaPushEnv

    return StepCount(PandaPushEnv(**kwargs))


if "a2l-test/CountedPandaPush-v0" not in gymnasium.registry:
    gymnasium.register("a2l-test/CountedPandaPush-v0", entry_point=_counted_push,
                       max_episode_steps=50)


@pytest.mark.parametrize("env_id", sorted(ENV_IDS))
def test_every_registered_a2l_environment_passes_gymnasiums_checker(env_id: str) -> None:
    env = gymnasium.make(env_id)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a checker's warning fails the test
            check_env(env.unwrapped)
        obs, info = env.reset(seed=3)
        assert set(obs) == {"observation", "achieved_goal", "desired_goal"}
        assert info["is_success"] == bool(
            np.linalg.norm(obs["achieved_goal"] - obs["desired_goal"]) < 0.05)
        batch = env.unwrapped.compute_reward(np.zeros((4, 3)), np.full((4, 3), 0.01), {})
        assert batch.shape == (4,) and np.all(batch == 0.0)
    finally:
        env.close()


def test_a_discrete_action_is_a_movement_of_the_repertoire() -> None:
    env = gymnasium.make("a2l/PushVirtual-v0")
    try:
        obs, _ = env.reset(seed=0)
        labels = env.unwrapped.labels
        obs2, *_ = env.step(labels.index("+y"))
        moved = obs2["observation"][:3] - obs["observation"][:3]
        assert moved[1] == pytest.approx(0.05, abs=1e-6) and abs(moved[0]) < 1e-6
    finally:
        env.close()


def test_an_environment_without_end_effector_or_object_is_refused_by_name() -> None:
    with pytest.raises(A2LValueError, match=r"'CartPole-v1' does not expose an "
                       r"end-effector .* nor an object"):
        gym_scene("CartPole-v1")
    with pytest.raises(A2LValueError, match=r"'PandaReach-v3' does not expose a body "
                       r"named 'object'"):
        gym_scene("PandaReach-v3")


def test_a_gym_scene_counts_steps_and_places_the_start() -> None:
    scene = gym_scene("a2l-test/CountedPandaPush-v0", seed=0)
    counter = COUNTS[-1]
    try:
        assert scene.env_steps == counter.steps == 0
        scene.reset(eef=np.array([-0.2, 0.0, 0.02]), objects={"object": (-0.05, 0.0)})
        assert np.linalg.norm(scene.eef_position() - [-0.2, 0.0, 0.02]) < 0.005
        for _ in range(5):
            scene.execute((1, 0, 0))
        assert scene.env_steps == counter.steps == 5
        assert scene.observe_effect(since="episode") == "far"  # the cube was pushed +x
        drive = GymScene(gymnasium.make("PandaPush-v3"), GymSceneConfig(placement="drive"))
        try:
            drive.reset(eef=np.array([-0.2, 0.1, 0.02]))
            assert drive.env_steps > 3 and drive.placements == 0
            assert np.linalg.norm(drive.eef_position() - [-0.2, 0.1, 0.02]) < 0.005
        finally:
            drive.close()
    finally:
        scene.close()


@pytest.mark.slow
def test_a_short_learning_run_in_panda_push_counts_every_env_step(tmp_path: Path) -> None:
    from a2l.experiments.panda_gym import PandaGymConfig, run_panda_gym

    first = len(COUNTS)
    cfg = PandaGymConfig(seed=0, eval_episodes=3, curve_episodes=1, max_iterations=1)
    overrides = {"scene_config": {"env_id": "a2l-test/CountedPandaPush-v0",
                                  "placement": "teleport", "slow_radius": 0.06,
                                  "slow_scale": 0.5},
                 "starts.n_starts": 2, "validation.n_fresh": 1, "directed.per_pair": 2,
                 "directed.try_cap": 4, "extension.max_extensions": 4}
    m = run_panda_gym(cfg, out=tmp_path / "run", overrides=overrides, quiet=True,
                      record=tmp_path / "episodes.rrd")
    learning, curve_env, final_env = COUNTS[first:first + 3]
    # every env.step of learning, as the environment counted them, is in the metrics
    assert m["env_steps_run"] == learning.steps > 0
    state = json.loads(max((tmp_path / "run" / "checkpoints").glob("iter_*")).joinpath(
        "state.json").read_text())
    assert state["movements"][-1]["robot_movements_total"] == learning.steps
    assert m["learning_curve"][-1]["env_steps"] == learning.steps
    # the evaluation: the environment's own episodes, each at most its 50 steps
    episodes = (tmp_path / "run" / "episodes.csv").read_text().splitlines()[1:]
    steps = [int(line.split(",")[3]) for line in episodes]
    assert len(steps) == 3 and sum(steps) == final_env.steps and max(steps) <= 50
    assert curve_env.steps > 0
    assert 0.0 <= m["success_rate"] <= 1.0 and m["eval_episodes"] == 3
    for name in ("metrics.json", "report.md", "learning_curve.png", "skills/push.a2lb"):
        assert (tmp_path / "run" / name).is_file()
    from a2l.rollout.recording import read_recording

    logged = read_recording(tmp_path / "episodes.rrd")
    assert any("rollout/2/" in column for column in logged)  # the third episode


def test_the_goal_controller_descends_clear_of_the_cube_before_it_pushes() -> None:
    from a2l.rollout.approach import descent

    scene = gym_scene("PandaPush-v3", seed=0)
    try:
        # the cube right under the gripper: it must first move away, then go down
        scene.new_episode(seed=1)
        eef = scene.eef_position()
        scene.access.place_object("object", np.array([eef[0], eef[1], 0.02]))
        moves = []
        for _ in range(12):
            o = np.asarray(scene.ground_truth()["objects"]["object"])
            d = descent(scene.eef_position(), o, 0.05)
            if d is None:
                break
            moves.append(d)
            scene.execute_displacement(d)
        assert moves[0][2] == 0.0 and moves[-1][2] < 0.0  # away first, down last
        cube = np.asarray(scene.ground_truth()["objects"]["object"])
        assert scene.eef_position()[2] <= 0.04
        assert np.linalg.norm(cube[:2] - eef[:2]) < 0.005  # the cube was not touched
        assert np.hypot(*(scene.eef_position() - cube)[:2]) >= 0.05
    finally:
        scene.close()


def test_the_transit_goes_over_the_cube_to_the_face_it_pushes_next() -> None:
    from a2l.rollout.approach import Transit

    scene = gym_scene("PandaPush-v3", seed=0, slow_radius=0.06, slow_scale=0.5)
    transit = Transit()
    far = np.array([1.0, 0.0])
    try:
        # the gripper pressed against the cube's far face: to push it +x it must go round
        scene.reset(eef=np.array([0.04, 0.0, 0.02]), objects={"object": (0.0, 0.0)})
        cube = np.asarray(scene.ground_truth()["objects"]["object"])
        assert not transit.in_place(scene.eef_position(), cube, far)
        over, steps = [], 0
        while (move := transit.next(scene.eef_position(), cube, far, 0.05)) is not None:
            assert steps < transit.max_steps
            scene.move_by(move)
            steps += 1
            p = scene.eef_position()
            if np.hypot(*(p - cube)[:2]) < 0.025:  # over the cube's top
                over.append(p[2])
        moved = np.asarray(scene.ground_truth()["objects"]["object"]) - cube
        assert np.linalg.norm(moved[:2]) < 0.003  # over it, not through it
        assert over and min(over) > 2 * cube[2] + 0.01  # above its top (4 cm)
        assert np.linalg.norm(scene.eef_position() - transit.target(cube, far)) < 0.015
        assert transit.in_place(scene.eef_position(), cube, far)
        assert scene.env_steps == steps <= 10
    finally:
        scene.close()


def test_move_by_keeps_its_height_and_full_speed_in_the_air() -> None:
    scene = gym_scene("PandaPush-v3", seed=0, slow_radius=0.06, slow_scale=0.5)
    try:
        # over the cube in the air: not slowed (nothing to push there), z as given
        scene.reset(eef=np.array([-0.03, 0.0, 0.1]), objects={"object": (0.0, 0.0)})
        before = scene.eef_position()
        scene.move_by(np.array([0.05, 0.0, 0.0]))
        after = scene.eef_position()
        assert abs(after[2] - before[2]) < 0.01 and after[0] - before[0] > 0.02
        # away from it, a planar movement of the repertoire goes down to the work height;
        # move_by does not (the arm sags a few mm in one env.step)
        dropped = []
        for planar in (True, False):
            scene.reset(eef=np.array([-0.15, 0.0, 0.1]), objects={"object": (0.0, 0.0)})
            if planar:
                scene.execute((1, 0, 0))
            else:
                scene.move_by(np.array([0.05, 0.0, 0.0]))
            dropped.append(0.1 - scene.eef_position()[2])
        assert dropped[1] < 0.01 and dropped[0] > 2 * dropped[1]
        assert scene.env_steps == 3
    finally:
        scene.close()
