"""Collision-free transit (C++ OMPL + Bullet) checked densely in PyBullet, and its limits."""

from __future__ import annotations

import numpy as np
import pytest

import a2l
from a2l import _core
from a2l.robot import BAXTER_ARMS, pybullet_urdf
from a2l.sim import make_scene
from a2l.sim._pybullet import p

# The project's set-up installs Bullet and OMPL: a build without them is a failure, not a skip.
assert _core.transit_available(), "a2l._core built without Bullet/OMPL (make setup installs them)"

from a2l.planning.transit import ArmTransit, execute_transit  # noqa: E402

DOWN = np.diag([-1.0, 1.0, -1.0])


def _pose(xyz) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = DOWN
    t[:3, 3] = xyz
    return t


@pytest.fixture(scope="module")
def world():
    scene = make_scene("press", seed=0)
    transit = ArmTransit("baxter", "right")
    transit.sync(scene)
    yield scene, transit
    scene.close()


class DenseChecker:
    """Collisions of the right arm in PyBullet: against the scene's bodies (in the scene's
    own client) and against the rest of the robot (a second client with self-collision)."""

    def __init__(self, scene, transit: ArmTransit) -> None:
        self.scene, self.transit = scene, transit
        self.c = scene.client
        self.bodies = [b for b in (p.getBodyUniqueId(i, physicsClientId=self.c)
                                   for i in range(p.getNumBodies(physicsClientId=self.c)))
                       if b != scene.robot]
        self.selfc = p.connect(p.DIRECT)
        self.robot = p.loadURDF(str(pybullet_urdf()), useFixedBase=True,
                                flags=p.URDF_USE_SELF_COLLISION, physicsClientId=self.selfc)
        self.names = {-1: "base"}
        index = {}
        for j in range(p.getNumJoints(self.robot, physicsClientId=self.selfc)):
            info = p.getJointInfo(self.robot, j, physicsClientId=self.selfc)
            self.names[j] = info[12].decode()
            index[info[1].decode()] = j
        for name, q in scene.other_joint_positions().items():
            p.resetJointState(self.robot, index[name], q, physicsClientId=self.selfc)
        self.arm_self = [index[n] for n in transit.joint_names]
        self.allowed = {tuple(sorted(pair)) for pair in transit.planner.allowed_pairs}
        self.moving = set(transit.planner.moving_links)

    def collisions(self, q) -> list[tuple[str, str]]:
        out = []
        for j, v in zip(self.scene.arm_joints, q, strict=True):
            p.resetJointState(self.scene.robot, j, v, physicsClientId=self.c)
        for b in self.bodies:
            for pt in p.getClosestPoints(self.scene.robot, b, 0.0, physicsClientId=self.c):
                if pt[8] < 0 and self.names.get(pt[3]) in self.moving:
                    out.append((self.names[pt[3]], f"body{b}"))
        for j, v in zip(self.arm_self, q, strict=True):
            p.resetJointState(self.robot, j, v, physicsClientId=self.selfc)
        p.performCollisionDetection(physicsClientId=self.selfc)
        for pt in p.getContactPoints(self.robot, self.robot, physicsClientId=self.selfc):
            a, b = self.names[pt[3]], self.names[pt[4]]
            if pt[8] < 0 and (a in self.moving or b in self.moving) and \
                    tuple(sorted((a, b))) not in self.allowed:
                out.append((a, b))
        return out

    def close(self) -> None:
        p.disconnect(self.selfc)


def _ik(scene, xyz) -> np.ndarray:
    q, rep = scene.kinematics.ik_report(_pose(xyz), np.asarray(BAXTER_ARMS["right"][2]))
    assert rep.status == a2l.Status.ok
    return q


def _dense(kin, positions: np.ndarray, step: float = 0.005) -> list[np.ndarray]:
    """Configurations along the trajectory with <= `step` m of end-effector travel and
    <= 0.01 rad of joint travel between consecutive ones."""
    out = [positions[0]]
    for a, b in zip(positions[:-1], positions[1:], strict=True):
        ea, eb = kin.fk(a)[:3, 3], kin.fk(b)[:3, 3]
        n = max(1, int(np.ceil(max(np.linalg.norm(eb - ea) / step,
                                   np.max(np.abs(b - a)) / 0.01))))
        # the end-effector may travel further between a and b than the chord: refine
        for k in range(1, n + 1):
            out.append(a + (b - a) * k / n)
    return out


def test_transit_is_collision_free_in_pybullet_and_within_limits(world) -> None:
    scene, transit = world
    kin = scene.kinematics
    checker = DenseChecker(scene, transit)
    try:
        # from the right of the box to between the box and the button, 4 cm above the
        # table: the straight joint path goes through the box
        cfg = scene.config
        z = cfg.table_z + 0.04
        start_xyz = (cfg.box_position[0], cfg.box_position[1] - 0.12, z)
        goal_xyz = (cfg.box_position[0], (cfg.box_position[1] + cfg.button_position[1]) / 2, z)
        q0, q1 = _ik(scene, start_xyz), _ik(scene, goal_xyz)
        assert not checker.collisions(q0) and not checker.collisions(q1)
        straight = [q0 + (q1 - q0) * a for a in np.linspace(0, 1, 11)]
        assert any(transit.in_collision(q) for q in straight)
        assert any(checker.collisions(q) for q in straight)  # the checker sees collisions
        vmax = transit.velocity_limits()
        amax = transit.options.acceleration
        for seed in range(3):
            plan = transit.plan(q0, q1, seed=seed)
            assert plan.ok, plan.message
            np.testing.assert_allclose(plan.positions[0], q0, atol=1e-9)
            np.testing.assert_allclose(plan.positions[-1], q1, atol=1e-9)
            # limits: the reported derivatives and the sampled positions themselves
            assert np.all(np.abs(plan.velocities) <= vmax * (1 + 1e-9))
            assert np.all(np.abs(plan.accelerations) <= amax * (1 + 1e-9))
            dt = np.diff(plan.times)
            fd = np.diff(plan.positions, axis=0) / dt[:, None]
            assert np.all(np.abs(fd) <= vmax * (1 + 1e-6))
            dense = _dense(kin, plan.positions)
            eef = np.array([kin.fk(q)[:3, 3] for q in dense])
            assert np.max(np.linalg.norm(np.diff(eef, axis=0), axis=1)) <= 0.01
            hits = [(i, c) for i, q in enumerate(dense) if (c := checker.collisions(q))]
            assert not hits, f"seed {seed}: {len(hits)} of {len(dense)} in collision: {hits[:3]}"
    finally:
        checker.close()


def test_execute_transit_in_pybullet(world) -> None:
    scene, transit = world
    cfg = scene.config
    scene.reset()
    q0 = scene.joint_positions()
    q1 = _ik(scene, (cfg.box_position[0] - 0.05, cfg.box_position[1] - 0.15,
                     cfg.table_z + 0.1))
    before = scene.ground_truth()["objects"]
    plan = transit.plan(q0, q1)
    assert plan.ok, plan.message
    err = execute_transit(scene, plan)
    assert err < 0.02
    np.testing.assert_allclose(scene.joint_positions(), q1, atol=0.02)
    for name, pos in scene.ground_truth()["objects"].items():  # the transit disturbed nothing
        assert np.linalg.norm(np.subtract(pos, before[name])) < 1e-3
    # an object left out of the obstacles: the gripper may then stand where it is
    box = next(b for b in scene.obstacle_boxes() if b[0] == "box")
    q_in_box = _ik(scene, box[1])
    assert transit.in_collision(q_in_box)
    free = ArmTransit("baxter", "right")
    free.sync(scene, ignore=("box",))
    assert not free.in_collision(q_in_box)
    with pytest.raises(a2l.A2LValueError, match="increasing times"):
        scene.follow_joint_trajectory(plan.times, plan.positions[:, :3])
    failed = transit.plan(q0, np.full(7, 9.0))
    assert failed.status == "goal_out_of_limits"
    with pytest.raises(a2l.A2LValueError, match="no trajectory"):
        execute_transit(scene, failed)


def test_goal_in_collision_and_no_path_are_reported(world) -> None:
    scene, transit = world
    cfg = scene.config
    q0 = _ik(scene, (0.7, -0.5, cfg.table_z + 0.15))
    # a goal with the gripper inside the table
    q_bad = _ik(scene, (0.7, -0.5, cfg.table_z - 0.05))
    r = transit.plan(q0, q_bad, time_limit=1.0)
    assert r.status == "goal_in_collision" and "table" in r.message
    assert r.planning_time < 1.0
    # a wall the arm cannot pass: full height, radial from 10 cm off the shoulder's s0 axis,
    # between a start and a goal on either side; the lower shoulder link reaches further
    # than 10 cm from the axis, so s0 cannot turn past the wall (and it has no way round:
    # its limits span less than a turn)
    wall = ArmTransit("baxter", "right", time_limit=1.0)
    wall.set_robot_joints(scene.other_joint_positions())
    axis = wall.planner.link_pose(wall.neutral, "right_upper_shoulder")[:3, 3]
    phi = np.radians(-68.0)
    d = np.array([np.cos(phi), np.sin(phi), 0.0])
    rot = np.array([[d[0], -d[1], 0.0], [d[1], d[0], 0.0], [0.0, 0.0, 1.0]])
    centre = axis + d * 1.1
    centre[2] = 0.5
    wall.planner.set_obstacles([_core.CollisionBox("wall", centre, np.array([1.0, 0.01, 1.5]),
                                                   rot)], 0.0)
    q_start, q_goal = np.zeros(7), np.zeros(7)
    q_start[0], q_goal[0] = -1.2, 0.4
    assert not wall.in_collision(q_start) and not wall.in_collision(q_goal)
    r = wall.plan(q_start, q_goal)
    assert r.status == "no_path" and "time limit" in r.message
    assert r.planning_time < 1.0 + 0.5
    wall.planner.set_obstacles([], 0.0)  # without the wall, a path
    assert wall.plan(q_start, q_goal).ok


def test_every_option_reaches_the_planner(world) -> None:
    """ArmTransit.plan passes every field of its options (a negative shortcut budget is
    refused by the C++ planner, so it must have arrived there)."""
    scene, transit = world
    q0 = _ik(scene, (0.7, -0.5, scene.config.table_z + 0.15))
    for field in ("shortcut_rounds", "shortcut_patience"):
        saved = getattr(transit.options, field)
        setattr(transit.options, field, -1)
        try:
            r = transit.plan(q0, q0)
        finally:
            setattr(transit.options, field, saved)
        assert r.status == "invalid_argument" and "shortcut" in r.message


def test_time_parameterize_limits() -> None:
    wp = np.array([[0.0, 0.0], [1.0, -0.5], [1.0, 0.5], [1.0, 0.5]])
    v, a = np.array([1.0, 0.5]), np.array([2.0, 1.0])
    r = _core.time_parameterize(wp, v, a, 0.001)
    assert np.all(np.abs(r.velocities) <= v + 1e-12)
    assert np.all(np.abs(r.accelerations) <= a + 1e-12)
    np.testing.assert_allclose(r.positions[-1], wp[-1])
    # the profile passes through every vertex at rest: the path stays on the polyline
    for w in wp:
        assert np.min(np.linalg.norm(r.positions - w, axis=1)) < 1e-3
    with pytest.raises(a2l.A2LValueError):
        _core.time_parameterize(wp, np.array([1.0, 0.0]), a, 0.01)


def test_transit_for_the_panda_in_the_task_scene() -> None:
    """A task scene built for the Panda plans its transits for the Panda's arm
    (ArmTransit.for_scene, what execute_task makes by default): around the block, which the
    straight joint path goes through, and the arm follows it in PyBullet without touching
    anything."""
    from a2l.planning.transit import transit_robot

    scene = make_scene("task", seed=0, robot="panda")
    try:
        transit = ArmTransit.for_scene(scene)
        assert transit.robot.name == "panda" and transit.spec.tip_link == "panda_hand_tcp"
        assert transit.joint_names == [f"panda_joint{i}" for i in range(1, 8)]
        transit.sync(scene)
        bx, by = scene.config.block_position
        z = scene.config.table_z + 0.04
        q0, q1 = (scene.kinematics.ik_report(scene.gripper_down_pose(np.array(p)),
                                             scene.neutral_joint_positions)[0]
                  for p in ((bx - 0.12, by, z), (bx + 0.12, by, z)))
        assert not transit.in_collision(q0) and not transit.in_collision(q1)
        assert any(transit.in_collision(q0 + (q1 - q0) * a) for a in np.linspace(0, 1, 11))
        scene.place_arm((bx - 0.12, by, z))
        before = scene.ground_truth()["objects"]
        plan = transit.plan(scene.joint_positions(), q1, seed=0)
        assert plan.ok, plan.message
        # (not every sample of the timed path is clear of the padded model: the planner
        # checks its path at its own resolution, and the path depends on the OMPL state
        # earlier plans of the process left; what holds is the physical check below)
        assert execute_transit(scene, plan) < 0.02
        np.testing.assert_allclose(scene.eef_position(), (bx + 0.12, by, z), atol=0.01)
        for name, pos in scene.ground_truth()["objects"].items():  # nothing disturbed
            assert np.linalg.norm(np.subtract(pos, before[name])) < 1e-3, name
    finally:
        scene.close()
    assert transit_robot("baxter", "left").name == "baxter-left"
    with pytest.raises(a2l.A2LValueError, match="unknown Baxter arm 'middle'"):
        ArmTransit("baxter", "middle")
