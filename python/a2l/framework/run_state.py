"""What an A2L run carries from one iteration to the next (:class:`RunState`, also what a
checkpoint holds), and the robot movements an iteration records (:func:`movement_record`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from a2l.acquisition.interactions import Rollout, rollouts_from_table, rollouts_table
from a2l.framework.config import FrameworkConfig
from a2l.rundir import latest_checkpoint, save_checkpoint

__all__ = ["MOVEMENT_PHASES", "RunState", "movement_record"]

#: The phases of an iteration that move the robot, as ``metrics.json`` names them
#: (``robot_movements``): ``validate`` runs the training starts, ``validate_fresh`` the
#: iteration's fresh starts (the candidate and the skill accepted so far).
MOVEMENT_PHASES = ("acquire", "extend", "validate", "validate_fresh", "validate_heldout")


@dataclass
class RunState:
    """What a run carries from one iteration to the next (and what a checkpoint holds).

    ``best_val`` are the validation rollouts the next extension grows from: the accepted
    skill's on the training starts and, with ``validation.starts = "fresh"``, on the newest
    iteration's fresh starts (``best_rate`` is its success rate there).
    """

    dataset: pd.DataFrame | None = None
    best_val: list[Rollout] = field(default_factory=list)
    history: list[dict[str, Any]] = field(default_factory=list)
    best_score: float = -1.0
    best_rate: float = -1.0
    stuck: dict[tuple[int, int], int] = field(default_factory=dict)
    heldout: list[dict[str, Any]] = field(default_factory=list)
    best_held: list[Rollout] = field(default_factory=list)
    #: None: resumed from a checkpoint written before movements were counted
    movement_log: list[dict[str, Any]] | None = field(default_factory=list)
    next_iteration: int = 0

    def done(self, cfg: FrameworkConfig) -> bool:
        """Whether the run stops: the accepted skill's training score is 100 and, with
        ``validation.starts = "fresh"``, its success rate on the newest fresh starts reached
        ``validation.stop_success``."""
        fresh_ok = not cfg.validation.fresh or self.best_rate >= cfg.validation.stop_success
        return self.best_score >= 100.0 and fresh_ok

    @classmethod
    def resume(cls, run_dir: Path) -> RunState:
        """The state after the newest checkpoint in `run_dir` (a fresh one without)."""
        ck = latest_checkpoint(run_dir)
        if ck is None:
            return cls()
        last, state, frames = ck
        history = state["iterations"]
        return cls(
            dataset=frames["dataset"], best_val=rollouts_from_table(frames["validation"]),
            history=history, best_score=float(state["best_score"]),
            best_rate=float(state.get("best_rate", -1.0)),
            stuck={(int(k.split(",")[0]), int(k.split(",")[1])): int(v)
                   for k, v in state["stuck"].items()},
            heldout=state.get("heldout", []),
            best_held=(rollouts_from_table(frames["heldout"]) if "heldout" in frames
                       else []),
            movement_log=state.get("movements", None if history else []),
            next_iteration=last + 1)

    def save(self, run_dir: Path, iteration: int) -> None:
        """Write the checkpoint of iteration `iteration`."""
        save_checkpoint(run_dir, iteration, {
            "iterations": self.history, "best_score": self.best_score,
            "best_rate": self.best_rate,
            "stuck": {f"{s},{e}": n for (s, e), n in self.stuck.items()},
            "heldout": self.heldout,
            **({"movements": self.movement_log} if self.movement_log is not None else {}),
        }, {"dataset": self.dataset, "validation": rollouts_table(self.best_val),
            "heldout": rollouts_table(self.best_held)})


def movement_record(it: int, phases: dict[str, int], last: dict[str, Any] | None
                    ) -> dict[str, Any]:
    """Iteration `it`'s robot movements: ``{"iteration", "robot_movements": {phase: n},
    "robot_movements_total", "robot_movements_training"}``, the totals cumulative since
    iteration 0 (`last` is the previous iteration's record), the training one without the
    held-out rollouts (they only measure)."""
    total = sum(phases.values())
    training = total - phases["validate_heldout"]
    if last is not None:
        total += last["robot_movements_total"]
        training += last["robot_movements_training"]
    return {"iteration": it, "robot_movements": dict(phases),
            "robot_movements_total": total, "robot_movements_training": training}
