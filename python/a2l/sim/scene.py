"""The scene interface shared by the PyBullet scenes and the virtual scene.

The movement's validation and outcome (:func:`as_direction`, :class:`MoveResult`) live in
:mod:`a2l.sim.movement` (the repertoire's directions, order and labels in
:mod:`a2l.skills.repertoire`, read from the C++ core), observations and their effects in
:mod:`a2l.sim.observation`; both are re-exported here.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.errors import A2LValueError
from a2l.sim.context import Context, low_level_state
from a2l.sim.movement import MoveResult, as_direction
from a2l.sim.observation import Observation, observed_effect
from a2l.skills.spec import ACTIONS

__all__ = ["MoveResult", "Observation", "Scene", "as_direction"]

_PERTURB_PARAMS: dict[str, set[str]] = {
    "move_object": {"delta", "name"},
    "hold": {"steps"},
    "toggle": {"state"},
    "remove_object": {"name"},
}


class Scene(ABC):
    """A tabletop scene the robot acts in; see :func:`a2l.sim.make_scene`.

    Positions are in the world frame (Baxter's ``base`` frame: x forward, y left, z up),
    in metres; this is the table frame of every scene (the table top is ``z = table_z``).
    """

    #: Scene name (``"push"``, ...).
    name: str = ""
    #: Name of the object perturbations act on by default.
    primary_object: str = ""

    def __init__(self, config: Any, seed: int) -> None:
        self.config = config
        self.seed = int(seed)
        self._rng = np.random.default_rng(self.seed)
        self._step_start: dict[str, Observation] = {}
        self._episode_start: dict[str, Observation] = {}
        self._hold = 0
        self._removed: set[str] = set()

    # --- to implement ---------------------------------------------------------------
    @abstractmethod
    def reset(self, eef: ArrayLike | None = None,
              objects: dict[str, ArrayLike] | None = None) -> None:
        """Put the scene back in its initial state (a new draw of the object jitter).

        Parameters
        ----------
        eef : array_like, shape (3,), optional
            Start the end-effector here instead of at the neutral pose.
        objects : dict of str to (x, y), optional
            Place these objects here instead of their configured positions.
        """

    @abstractmethod
    def eef_position(self) -> NDArray[np.float64]:
        """End-effector point (3,) in the world frame."""

    @abstractmethod
    def _ground_truth(self) -> Observation: ...

    @abstractmethod
    def _perceive(self) -> Observation: ...

    @abstractmethod
    def _move(self, displacement: NDArray[np.float64]) -> MoveResult: ...

    @abstractmethod
    def _idle(self) -> None:
        """Let the time of one movement pass without moving the arm."""

    @abstractmethod
    def _place(self, name: str, xyz: NDArray[np.float64]) -> None:
        """Teleport object `name` to `xyz` (keeping its orientation), at rest."""

    @abstractmethod
    def _toggle(self, state: str) -> None: ...

    def _gripper(self, closed: bool) -> None:
        """Close (or open) the gripper and let the fingers move; scenes with a gripper
        override it."""
        raise A2LValueError(f"{type(self).__name__} has no gripper: the actions 'open' and "
                            "'close' cannot be carried out")

    @abstractmethod
    def _park(self, name: str) -> None:
        """Take object `name` out of the scene until the next reset."""

    def close(self) -> None:  # noqa: B027 - nothing to release by default
        """Release the scene's resources (idempotent)."""

    @property
    def state_names(self) -> tuple[str, ...]:
        """Names of the scene's high-level states."""
        return tuple(self.ground_truth()["states"])

    @property
    def object_names(self) -> tuple[str, ...]:
        """Names of the scene's objects (present or removed)."""
        return tuple(self._object_names())

    @abstractmethod
    def _object_names(self) -> list[str]: ...

    # --- public interface -------------------------------------------------------------
    @property
    def step_length(self) -> float:
        """Length of one discrete movement (m)."""
        return float(self.config.step)

    def execute(self, movement: ArrayLike | str) -> MoveResult:
        """Carry out one discrete movement of the end-effector, or an action.

        Parameters
        ----------
        movement : tuple of 3 int, or str
            Signs in {-1, 0, 1}, not all 0: the end-effector moves by ``step * d / ||d||``.
            Or an action of the repertoire (:data:`a2l.skills.spec.ACTIONS`): ``"open"`` /
            ``"close"`` the gripper (high-level state ``gripper``), ``"stay"`` (hold still for
            one movement's duration).

        Returns
        -------
        MoveResult
            True when carried out; otherwise ``status`` says why. A movement that cannot be
            carried out is never replaced by another one.

        Raises
        ------
        a2l.A2LValueError
            Not a movement nor an action, or open/close in a scene without a gripper.
        """
        if isinstance(movement, str):
            return self._execute_action(movement)
        d = as_direction(movement)
        return self._carry_out(self.step_length * d / np.linalg.norm(d))

    def _carry_out(self, disp: NDArray[np.float64]) -> MoveResult:
        """Record the step's start, then move by `disp` (or stay, held)."""
        self._step_start = self._snapshot()
        if self._hold > 0:
            self._hold -= 1
            here = self.eef_position()
            self._idle()
            return MoveResult(False, "held", f"end-effector held still ({self._hold} more "
                              "steps)", here + disp, self.eef_position())
        return self._move(disp)

    def _execute_action(self, action: str) -> MoveResult:
        if action not in ACTIONS:
            raise A2LValueError(f"unknown action {action!r}: an action is one of {ACTIONS}")
        self._step_start = self._snapshot()
        here = self.eef_position()
        if self._hold > 0:  # held: the arm and the gripper stay as they are
            self._hold -= 1
            self._idle()
            return MoveResult(False, "held", f"end-effector held still ({self._hold} more "
                              "steps)", here, self.eef_position())
        if action == "stay":
            self._idle()
        else:
            self._gripper(action == "close")
        return MoveResult(True, "ok", "", here, self.eef_position())

    def execute_displacement(self, displacement: ArrayLike) -> MoveResult:
        """Move the end-effector by an arbitrary displacement (a DS step), at most one
        movement's length.

        Parameters
        ----------
        displacement : array_like, shape (3,)
            Finite, ``0 < ||displacement|| <= step`` (m).

        Returns
        -------
        MoveResult
            As :meth:`execute` (a hold perturbation holds it too).
        """
        disp = np.asarray(displacement, dtype=float).reshape(-1)
        norm = float(np.linalg.norm(disp)) if disp.shape == (3,) else np.nan
        if not (np.isfinite(norm) and 0 < norm <= self.step_length * (1 + 1e-9)):
            raise A2LValueError(f"a displacement is 3 finite numbers of length in (0, "
                                f"{self.step_length}] m, got {displacement!r}")
        return self._carry_out(disp)

    def move_by(self, displacement: ArrayLike) -> MoveResult:
        """Move the end-effector by any displacement (m), of any length.

        :meth:`execute` moves by one discrete movement of the repertoire,
        :meth:`execute_displacement` by at most one movement's length; the demonstrators
        and the teleoperation recorder need any displacement. Same checks (workspace, IK,
        reach) and the same ``MoveResult``; the step's start is recorded so that
        ``observe_effect()`` covers this move. A hold perturbation does not hold it.

        Parameters
        ----------
        displacement : array_like, shape (3,)
            Finite (m).

        Raises
        ------
        a2l.A2LValueError
            Not 3 finite numbers.
        """
        d = np.asarray(displacement, dtype=float).reshape(3)
        if not np.all(np.isfinite(d)):
            raise A2LValueError(f"displacement must be 3 finite numbers, got {displacement!r}")
        self._step_start = self._snapshot()
        return self._move(d)

    def ground_truth(self) -> dict[str, dict[str, Any]]:
        """True object positions and high-level states.

        Returns
        -------
        dict
            ``{"objects": {name: (x, y, z)}, "states": {name: value}}``; a removed object
            is absent.
        """
        return self._ground_truth().as_dict()

    def perceive(self) -> dict[str, dict[str, Any]]:
        """Object positions and high-level states as the cameras see them.

        Same layout as :meth:`ground_truth`; an object no camera sees is absent. The
        main camera is rendered; a side camera only when the arm hides part of an object
        from it. States the camera cannot see (the gripper) come from the robot itself.
        """
        return self._perceive().as_dict()

    def _observe(self, source: str | None) -> Observation:
        src = self._source(source)
        return self._perceive() if src == "perceived" else self._ground_truth()

    def _source(self, source: str | None) -> str:
        src = source or getattr(self.config, "context_source", "ground_truth")
        if src not in ("perceived", "ground_truth"):
            raise A2LValueError(f"source must be 'perceived' or 'ground_truth', got {src!r}")
        return src

    def _snapshot(self) -> dict[str, Observation]:
        snap = {"ground_truth": self._ground_truth()}
        if self._source(None) == "perceived":
            snap["perceived"] = self._perceive()
        return snap

    def episode_start(self, source: str = "ground_truth") -> dict[str, dict[str, Any]]:
        """Object positions and high-level states at the start of the episode (the last
        :meth:`reset` or :meth:`start_episode`), as :meth:`ground_truth` lays them out.

        Parameters
        ----------
        source : {"ground_truth", "perceived"}
            ``"perceived"`` only when the scene's ``context_source`` is (it is recorded
            then only).

        Raises
        ------
        a2l.A2LValueError
            No such observation was recorded.
        """
        start = self._episode_start.get(self._source(source))
        if start is None:
            raise A2LValueError(f"no '{source}' observation was recorded at the start of the "
                                "episode; use source='ground_truth' or set context_source")
        return start.as_dict()

    def start_episode(self) -> None:
        """Start a new effect episode now, without resetting anything:
        ``observe_effect(since="episode")`` counts from the current state (a skill run in
        the middle of a task, or after a trial's set-up changed a state)."""
        self._episode_start = self._snapshot()

    def context(self, source: str | None = None) -> Context:
        """Read the context: low-level states of every object and the high-level states.

        Parameters
        ----------
        source : {"perceived", "ground_truth"}, optional
            Default: the config's ``context_source``.
        """
        obs = self._observe(source)
        eef = self.eef_position()
        objects = {n: low_level_state(eef, pos) for n, pos in obs.objects.items()}
        return Context(eef=eef, objects=objects, states=dict(obs.states),
                       source=self._source(source))

    def observe_effect(self, since: str = "step", source: str | None = None) -> str:
        """Name the effect between an earlier instant and now.

        Parameters
        ----------
        since : {"step", "episode"}
            From the start of the last :meth:`execute`, or from the last :meth:`reset`.
        source : {"perceived", "ground_truth"}, optional
            Default: the config's ``context_source``.

        Returns
        -------
        str
            ``"pressed"`` (the light toggled), ``"grasped"`` (an object lifted in the
            closed gripper), a push effect (``"far"``, ``"close_left"``, ... see
            :mod:`a2l.skills.effects`) or ``"none"``.
        """
        if since not in ("step", "episode"):
            raise A2LValueError(f"since must be 'step' or 'episode', got {since!r}")
        src = self._source(source)
        start = (self._step_start if since == "step" else self._episode_start).get(src)
        if start is None:
            raise A2LValueError(f"no '{src}' observation was recorded at the start of the "
                                f"{since}; use source='ground_truth' or set context_source")
        return self._effect(start, self._observe(src))

    def _effect(self, before: Observation, after: Observation) -> str:
        return observed_effect(before, after, list(self.movable_names), self.config)

    @property
    def movable_names(self) -> tuple[str, ...]:
        """Names of the objects a push can move (every object but the button)."""
        return tuple(n for n in self._object_names() if n != "button")

    def perturb(self, kind: str, **params: Any) -> None:
        """Perturb the scene between two steps.

        Parameters
        ----------
        kind : str
            ``"move_object"`` (``delta=(dx, dy)``, ``name=`` optional: teleport an object
            by delta on the table), ``"hold"`` (``steps=N``: the next N movements leave the
            end-effector where it is), ``"toggle"`` (``state=name``: flip a high-level
            state) or ``"remove_object"`` (``name=`` optional: the object leaves the scene
            until the next reset).
        """
        if kind not in _PERTURB_PARAMS:
            raise A2LValueError(f"unknown perturbation kind '{kind}'; choose one of "
                                f"{sorted(_PERTURB_PARAMS)}")
        for key in params:
            if key not in _PERTURB_PARAMS[kind]:
                raise A2LValueError(f"unknown parameter '{key}' for perturbation '{kind}'; "
                                    f"known: {sorted(_PERTURB_PARAMS[kind])}")
        if kind == "hold":
            steps = params.get("steps")
            if not isinstance(steps, (int, np.integer)) or isinstance(steps, bool) or steps < 0:
                raise A2LValueError(f"hold: 'steps' must be an integer >= 0, got {steps!r}")
            self._hold = int(steps)
            return
        if kind == "toggle":
            state = params.get("state")
            known = self.state_names
            if state not in known:
                raise A2LValueError(f"toggle: unknown high-level state '{state}'; this scene "
                                    f"has {sorted(known)}")
            self._toggle(str(state))
            return
        name = params.get("name") or self.primary_object
        if name not in self._object_names():
            raise A2LValueError(f"{kind}: unknown object '{name}'; this scene has "
                                f"{sorted(self._object_names())}")
        if name in self._removed:
            raise A2LValueError(f"{kind}: object '{name}' was removed")
        if kind == "remove_object":
            self._park(name)
            self._removed.add(name)
            return
        delta = params.get("delta")
        try:
            dxy = np.asarray(delta, dtype=float).reshape(2)
        except (TypeError, ValueError) as exc:
            raise A2LValueError(f"move_object: 'delta' must be (dx, dy), got {delta!r}") from exc
        if not np.all(np.isfinite(dxy)):
            raise A2LValueError(f"move_object: 'delta' must be finite, got {delta!r}")
        pos = np.asarray(self._ground_truth().objects[name], dtype=float)
        pos[:2] += dxy
        self._place(name, pos)

    def __enter__(self) -> Scene:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass
