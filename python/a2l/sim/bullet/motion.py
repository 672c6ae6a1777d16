"""Moving the arm and the gripper of a PyBullet scene: straight lines of the end-effector
through the C++ IK, joint trajectories, settling, the gripper."""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

import a2l
from a2l.errors import A2LValueError, UnreachableError
from a2l.robot.gripper import gripper_down
from a2l.sim._pybullet import p
from a2l.sim.movement import MoveResult

__all__ = ["MotionMixin"]

#: Shortest settling at the end of a movement (s): 5 physics steps at 240 Hz.
_SETTLE_MIN_S = 5.0 / 240.0


class MotionMixin:
    """Moves the robot of a :class:`~a2l.sim.bullet.BulletScene` (one of its bases)."""

    _client: int
    _robot: int
    _tick: int
    _targets: dict[int, float]
    _effort: list[float]
    _arm: list[int]
    _fingers: list[int]
    _finger_open: tuple[float, ...]
    _finger_closed: tuple[float, ...]
    _tool_down: NDArray[np.float64]
    _vmax: NDArray[np.float64]
    _neutral_q: NDArray[np.float64]
    _states: dict[str, str]
    _perceived_cache: Any
    kinematics: a2l.Kinematics
    config: Any

    # --- low level ----------------------------------------------------------------
    def _arm_q(self) -> NDArray[np.float64]:
        states = p.getJointStates(self._robot, self._arm, physicsClientId=self._client)
        return np.array([s[0] for s in states])

    def eef_position(self) -> NDArray[np.float64]:
        return self.kinematics.fk(self._arm_q())[:3, 3].copy()

    def joint_positions(self) -> NDArray[np.float64]:
        """Joint positions (7,) of the acting arm, base to tip."""
        return self._arm_q()

    def _command(self) -> None:
        idx = list(self._targets)
        p.setJointMotorControlArray(
            self._robot, idx, p.POSITION_CONTROL,
            targetPositions=[self._targets[j] for j in idx],
            forces=self._effort, positionGains=[self.config.position_gain] * len(idx),
            physicsClientId=self._client)

    def _sim_step(self) -> None:
        p.stepSimulation(physicsClientId=self._client)
        self._tick += 1
        self._after_sim_step()
        if self.config.gui:
            time.sleep(self.config.time_step)

    def _after_sim_step(self) -> None:
        """Hook run after every physics step (the press scene watches its button)."""

    def _set_arm_targets(self, q: NDArray[np.float64]) -> None:
        for j, v in zip(self._arm, q, strict=True):
            self._targets[j] = float(v)

    def _set_fingers(self, closed: bool) -> None:
        """Gripper joint targets: closed or open (nothing for an arm without a gripper)."""
        for j, q in zip(self._fingers, self._finger_closed if closed else self._finger_open,
                        strict=True):
            self._targets[j] = q

    @property
    def neutral_joint_positions(self) -> NDArray[np.float64]:
        """Joint positions (7,) of the acting arm at the neutral pose (a copy)."""
        return np.array(self._neutral_q, dtype=float)

    def gripper_down_pose(self, xyz: ArrayLike) -> NDArray[np.float64]:
        """Homogeneous pose (4, 4) of the end-effector at `xyz` (3,) with the gripper pointing
        down (the robot's ``tool_down``), turned by the config's ``gripper_yaw``
        (:func:`gripper_down`): the target every movement and transit asks the IK for."""
        t = np.eye(4)
        t[:3, :3] = gripper_down(getattr(self.config, "gripper_yaw", 0.0), self._tool_down)
        t[:3, 3] = np.asarray(xyz, dtype=float)
        return t

    def _ik_down(self, xyz: ArrayLike, what: str) -> NDArray[np.float64]:
        """Joint positions (7,) that put the end-effector at `xyz` with the gripper pointing
        down, by the C++ IK from the neutral pose (the same solution every time), or an
        A2LValueError that starts with `what` (:class:`~a2l.errors.UnreachableError` when
        the IK finds no such pose)."""
        target = np.asarray(xyz, dtype=float).reshape(3)
        if not np.all(np.isfinite(target)):
            raise A2LValueError(f"{what}: eef must be 3 finite numbers, got {xyz!r}")
        q, rep = self.kinematics.ik_report(self.gripper_down_pose(target), self._neutral_q)
        if rep.status != a2l.Status.ok:
            raise UnreachableError(f"{what}: eef {tuple(np.round(target, 4))} is unreachable "
                                f"with the gripper pointing down "
                                f"({a2l._core.status_name(rep.status)})")
        return np.asarray(q, dtype=float)

    def place_arm(self, eef: ArrayLike) -> None:
        """Put the acting arm, at rest, where the end-effector is at `eef` with the gripper
        pointing down, as :meth:`reset` places it, without touching anything else: a
        kinematic placement (joint states set, no physics step), not a movement. The
        objects stay as they are; let the physics run (:meth:`settle`) for them to react.

        Raises
        ------
        a2l.A2LValueError
            `eef` is not 3 finite numbers or is out of reach; the world is then unchanged.
        """
        q = self._ik_down(eef, "place_arm")
        self._set_arm_targets(q)
        for j, v in zip(self._arm, q, strict=True):
            p.resetJointState(self._robot, j, v, 0.0, physicsClientId=self._client)
        self._command()
        self._tick += 1
        self._perceived_cache = None

    def _move(self, disp: NDArray[np.float64]) -> MoveResult:
        cfg = self.config
        start = self.eef_position()
        target = start + disp
        lo = np.array(cfg.workspace_min) + np.array([0, 0, cfg.table_z])
        hi = np.array(cfg.workspace_max) + np.array([0, 0, cfg.table_z])
        if np.any(target < lo) or np.any(target > hi):
            axis = "xyz"[int(np.argmax((target < lo) | (target > hi)))]
            return MoveResult(False, "workspace_limit",
                              f"target {tuple(np.round(target, 3))} leaves the workspace along "
                              f"{axis} ([{tuple(np.round(lo, 3))}, {tuple(np.round(hi, 3))}])",
                              target, start)
        plan = self._plan_path(start, disp)
        if isinstance(plan, MoveResult):
            return plan
        self._follow_path(plan, float(np.linalg.norm(disp)))
        self._settle_at(target)
        reached = self.eef_position()
        err = float(np.linalg.norm(reached - target))
        if err > cfg.reach_tolerance:
            return MoveResult(False, "blocked", f"the end-effector stopped {err:.3f} m short "
                              f"of its target {tuple(np.round(target, 3))}", target, reached)
        return MoveResult(True, "ok", "", target, reached)

    # The three phases of a movement, timed apart by benchmarks/bench_sim.py.
    def _plan_path(self, start: NDArray[np.float64], disp: NDArray[np.float64]
                   ) -> list[NDArray[np.float64]] | MoveResult:
        """Joint positions (7,) of the straight line's waypoints, by the C++ IK, or why the
        line cannot be followed (a MoveResult)."""
        cfg = self.config
        target = start + disp
        n = max(1, math.ceil(np.linalg.norm(disp) / cfg.waypoint_spacing - 1e-9))
        q = self._arm_q()
        plan = []
        for i in range(1, n + 1):
            wp = start + disp * (i / n)
            qi, rep = self.kinematics.ik_report(self.gripper_down_pose(wp), q)
            if rep.status != a2l.Status.ok:
                status = a2l._core.status_name(rep.status)
                return MoveResult(False, "unreachable" if status != "joint_limit" else status,
                                  f"IK found no solution within the joint limits for waypoint "
                                  f"{i}/{n} at {tuple(np.round(wp, 3))} ({status}; error "
                                  f"{rep.position_error:.4f} m, {rep.orientation_error:.4f} rad)",
                                  target, start)
            jump = float(np.max(np.abs(qi - q)))
            if jump > cfg.max_joint_jump:
                return MoveResult(False, "unreachable",
                                  f"the IK solution for waypoint {i}/{n} at "
                                  f"{tuple(np.round(wp, 3))} is {jump:.2f} rad away in joint "
                                  f"space (> max_joint_jump {cfg.max_joint_jump}): the arm "
                                  "would swing around", target, start)
            plan.append(qi)
            q = qi
        return plan

    def _follow_path(self, plan: list[NDArray[np.float64]], length: float) -> None:
        """Send the waypoints one after the other, each held for the time the nominal speed
        gives it (longer where a joint would exceed its URDF velocity limit)."""
        cfg = self.config
        steps_per_wp = max(1, round(length / len(plan) / cfg.speed / cfg.time_step))
        q = self._arm_q()
        for qi in plan:
            need = float(np.max(np.abs(qi - q) / self._vmax)) / cfg.time_step
            self._set_arm_targets(qi)
            self._command()
            for _ in range(max(steps_per_wp, math.ceil(need))):
                self._sim_step()
            q = qi

    def _settle_at(self, target: NDArray[np.float64]) -> None:
        """Step until the end-effector is within 2 mm of `target` (at least 1/48 s: 5 steps
        at the default 240 Hz; at most 0.3 s)."""
        ts = self.config.time_step
        settle_min = max(1, math.ceil(_SETTLE_MIN_S / ts - 1e-9))
        settle_max = max(settle_min, round(0.3 / ts))
        for i in range(settle_max):
            self._sim_step()
            if i >= settle_min - 1 and np.linalg.norm(self.eef_position() - target) < 0.002:
                break

    def _idle(self) -> None:
        cfg = self.config
        n = max(1, round(cfg.step / cfg.speed / cfg.time_step))
        for _ in range(n):
            self._sim_step()

    def settle(self, seconds: float = 0.2) -> None:
        """Let the physics run for `seconds` with the current joint targets."""
        for _ in range(max(1, round(seconds / self.config.time_step))):
            self._sim_step()

    def open_gripper(self) -> None:
        """Open the gripper and let the fingers move (0.4 s)."""
        self._states["gripper"] = "open"
        self._set_fingers(False)
        self._command()
        self.settle(0.4)

    def _gripper(self, closed: bool) -> None:
        if closed:
            self.close_gripper()
        else:
            self.open_gripper()

    def close_gripper(self) -> None:
        """Close the gripper and let the fingers move (0.4 s); an object between the finger
        tips is squeezed with the fingers' effort limit."""
        self._states["gripper"] = "closed"
        self._set_fingers(True)
        self._command()
        self.settle(0.4)

    def follow_joint_trajectory(self, times: ArrayLike, positions: ArrayLike) -> float:
        """Track a joint trajectory of the acting arm with position targets, one per physics
        step (linear interpolation between samples), then let the arm settle (<= 0.3 s).

        Parameters
        ----------
        times : array_like, shape (k,)
            Increasing sample times (s), from 0.
        positions : array_like, shape (k, 7)
            Joint positions of the arm at `times`.

        Returns
        -------
        float
            Largest joint error (rad) to the last sample at the end.
        """
        t = np.asarray(times, dtype=float).reshape(-1)
        q = np.asarray(positions, dtype=float)
        if q.ndim != 2 or q.shape != (t.size, len(self._arm)) or t.size == 0 or \
                np.any(np.diff(t) < 0) or not np.all(np.isfinite(q)):
            raise A2LValueError(f"follow_joint_trajectory: need increasing times (k,) and "
                                f"finite positions (k, {len(self._arm)}), got {t.shape} and "
                                f"{q.shape}")
        dt = self.config.time_step
        for k in range(1, max(1, math.ceil(t[-1] / dt)) + 1):
            tk = min(k * dt, t[-1])
            self._set_arm_targets(np.array([np.interp(tk, t, q[:, i])
                                            for i in range(q.shape[1])]))
            self._command()
            self._sim_step()
        for _ in range(round(0.3 / dt)):
            if np.max(np.abs(self._arm_q() - q[-1])) < 2e-3:
                break
            self._sim_step()
        self._perceived_cache = None
        return float(np.max(np.abs(self._arm_q() - q[-1])))

