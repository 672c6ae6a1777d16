"""The robot's still links (pedestal, torso, head, the idle arm) are left out of the collision
tests with the static bodies (floor, table), and still collide with an object that moves."""

from __future__ import annotations

from a2l.sim import make_scene
from a2l.sim._pybullet import p


def test_still_links_skip_static_bodies_but_not_objects() -> None:
    with make_scene("push", seed=0, object_jitter=0.0, context_source="ground_truth") as s:
        c, r = s.client, s._robot
        floor, table, box = (s._bodies.ids[k] for k in ("floor", "table", "box"))
        s.settle(0.05)
        # the pedestal stands on the floor: before the filter, one contact at every step
        assert p.getContactPoints(r, floor, physicsClientId=c) == ()
        # the box dropped on the idle (left) arm's gripper collides with it
        left = s._link_index["l_gripper_l_finger_tip"]
        tip = p.getLinkState(r, left, physicsClientId=c)[0]
        p.resetBasePositionAndOrientation(box, (tip[0], tip[1], tip[2] + 0.06), (0, 0, 0, 1),
                                          physicsClientId=c)
        hit = False
        for _ in range(120):
            p.stepSimulation(physicsClientId=c)
            hit = hit or any(pt[3] not in s._finger_links
                             for pt in p.getContactPoints(r, box, physicsClientId=c))
        assert hit
        # the acting arm still collides with the table: pressed into it, it touches it
        s.reset()
        eef = s.eef_position()
        s.place_arm((eef[0], eef[1], s.config.table_z - 0.02))
        s.settle(0.05)
        assert p.getContactPoints(r, table, physicsClientId=c) != ()
