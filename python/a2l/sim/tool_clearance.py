"""How far above its tool point an arm's hand comes down: what caps the height of the boxes
its scenes push (:meth:`a2l.sim.SceneConfig.layout`).

The pushes move the tool point at the height of the box's centre. Above the tool point sits
the hand (the Panda's: 3.4 cm above its fingertips' centre, 21 cm wide); a box taller than
twice that reaches into it, and the hand clips its top while going round it (on the Panda, 68
of 128 held-out pushes of a tuning run moved the box the wrong way, the hand touching it 10 cm
off the tool point). The clearance is measured in PyBullet at the neutral pose: the lowest
point, above the tool point, of the links the wrist moves, less the gripper's fingers (they
push) and the links that hold the tool point (a pusher rod).
"""

from __future__ import annotations

from typing import Any

from a2l.sim._pybullet import p

__all__ = ["BOX_MARGIN", "tool_clearance"]

#: Room (m) kept between a box's top and the hand above a tool point at the box's mid-height.
BOX_MARGIN = 0.01


def tool_clearance(scene: Any) -> float:
    """Height (m) above the tool point, at the neutral pose, of the lowest point of the links
    the last joint of the chain moves, the gripper's fingers and the links around the tool
    point left out (module docstring); ``inf`` when no such link has a collision shape.

    Parameters
    ----------
    scene : a2l.sim.bullet.BulletScene
        A scene whose robot is built (:meth:`~a2l.sim.bullet.build.BuildMixin._build_robot`);
        its arm is left at the neutral pose.
    """
    c, robot = scene._client, scene._robot
    for j, q in zip(scene._arm, scene._neutral_q, strict=True):
        p.resetJointState(robot, j, float(q), physicsClientId=c)
    tool = scene.kinematics.fk(scene._neutral_q)[:3, 3]
    wrist = scene._moved_by({scene._arm[-1]})
    low = float("inf")
    for link in sorted(wrist - scene._finger_links):
        if not p.getCollisionShapeData(robot, link, physicsClientId=c):
            continue
        lo, hi = p.getAABB(robot, link, physicsClientId=c)
        if all(lo[i] - 1e-3 <= tool[i] <= hi[i] + 1e-3 for i in range(3)):
            continue  # it holds the tool point: a rod, a fixed jaw
        low = min(low, lo[2] - float(tool[2]))
    return low
