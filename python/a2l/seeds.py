"""The seed registry: which seeds may tune and which may be reported (``docs/seeds.md``).

Every random draw of an experiment comes from a seed. Seeds ``0 .. 999`` are **tuning
seeds**: any choice of a default, a threshold or a configuration is made on them. Seeds
``>= 1000`` are **evaluation seeds**: every reported result is measured on them, and no
choice ever looks at them. :data:`REGISTRY` refines the split per experiment (which block of
evaluation seeds it uses by default, which tuning seeds its choices were made on, which other
seed streams it has); the split itself is the same for all.

A run records its use of seeds in its ``config.json`` (:func:`seed_record`) and, when any of
its seeds is a tuning seed, its ``report.md`` says so (:func:`mark_report`)::

    record = seed_record("push", [cfg.seed])
    write_json(run_dir / "config.json", {..., "seed_use": record})
    atomic_write_text(run_dir / "report.md", mark_report(text, record))
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = [
    "EVALUATION_FIRST",
    "REGISTRY",
    "ExperimentSeeds",
    "experiment_seeds",
    "format_seeds",
    "is_tuning",
    "mark_report",
    "seed_record",
    "seed_use",
    "tuning_note",
]

#: The first evaluation seed: seeds below are tuning seeds, seeds from here on evaluation seeds.
EVALUATION_FIRST = 1000


@dataclass(frozen=True)
class ExperimentSeeds:
    """One experiment's seeds.

    Parameters
    ----------
    experiment : str
        The experiment's name (``a2l experiment NAME``).
    draws : str
        What its seed draws.
    evaluation : tuple of int
        ``(first, last)``: its block of evaluation seeds (``first`` is where reported runs
        start); both ``>= EVALUATION_FIRST``.
    tuned_on : str
        Which tuning seeds its choices were made on, and which choices.
    streams : str
        Other seed streams of the experiment (e.g. demonstrations), neither tuning nor
        evaluation trials; empty when none.
    looked_at : tuple of int
        Seeds of ``EVALUATION_FIRST`` and above that were looked at before a choice: tuning
        seeds of this experiment since (:func:`is_tuning`), below its block.
    """

    experiment: str
    draws: str
    evaluation: tuple[int, int]
    tuned_on: str
    streams: str = ""
    looked_at: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        first, last = self.evaluation
        if not EVALUATION_FIRST <= first <= last:
            raise ValueError(f"{self.experiment}: evaluation seeds {first}-{last} must lie "
                             f"at or above {EVALUATION_FIRST}")
        if any(not EVALUATION_FIRST <= s < first for s in self.looked_at):
            raise ValueError(f"{self.experiment}: seeds looked at {list(self.looked_at)} "
                             f"must lie in {EVALUATION_FIRST}-{first - 1}, below its block")


_FRAMEWORK = ("babbling around the object, the validation starts and the held-out starts of "
              "every iteration")
#: What the push experiments (push, sweep, discretization, heldout) share: their block of
#: evaluation seeds, the tuning seeds their defaults were chosen on, and the evaluation seeds
#: looked at before a choice (the exported skill's step cap of 16 was tried after seed
#: 1001's misses, whose analysis covered seeds 1000-1002; the alignment rule after the
#: off-centre pushes of seeds 1003-1005's runs; docs/experiments/push.md; the cameras' join
#: of top faces after the robots table's runs on seeds 1006, 1007 and 1009, docs/robots.md).
_PUSH_SEEDS: dict[str, Any] = {
    "evaluation": (1010, 1999),
    "tuned_on": ("the push defaults (FrameworkConfig: bins, structure, smoothing, "
                 "effect-directed babbling) were chosen on virtual seeds 0-29 and Baxter "
                 "seeds 0-2 (docs/framework.md), Baxter's fallback on seeds 3 and 4 "
                 "(docs/experiments/push.md); the exported skill's step cap on Baxter seeds "
                 "0, 5 and 6 and virtual seeds 0-9, after looking at seeds 1000-1002; the "
                 "alignment rule on Baxter seeds 5, 6 and 1000-1002, the Panda's and the "
                 "UR5's seed 5 and virtual seeds 0-9, after looking at seeds 1003-1005 "
                 "(tuning seeds of these experiments since); the SO-101's jaw pushing "
                 "closed from its geometry, after looking at its run on seed 1006; the cameras' "
                 "join of top faces (a view that sees only the side faces left out, "
                 "docs/tabletop.md) after looking at the robots table's runs on seeds 1006, "
                 "1007 and 1009 (tuning seeds since, 1008 with them: the block starts at 1010)"),
    "looked_at": tuple(range(1000, 1010)),
}
_LFD_STREAMS = ("demonstrations: seeds 0 .. 2 n_demos - 1 of each skill (training data drawn "
                "by the scripted demonstrator; never a trial seed)")

#: Every experiment's seeds. Tuning seeds are 0-999 for every experiment; the evaluation
#: block of each starts at its command's default first evaluation seed. Experiments that
#: draw the same things (push, sweep, discretization; babbling and its comparison; the
#: demonstrated skills and their parametrization) share a block.
REGISTRY: dict[str, ExperimentSeeds] = {e.experiment: e for e in (
    ExperimentSeeds("push", _FRAMEWORK, **_PUSH_SEEDS),
    ExperimentSeeds("sweep", "one push run per seed (" + _FRAMEWORK + ")", **_PUSH_SEEDS),
    ExperimentSeeds("discretization", "one push run per grid cell (" + _FRAMEWORK + ")",
                    **_PUSH_SEEDS),
    ExperimentSeeds("heldout", "none of its own: a push run's held-out starts again, from "
                    "that run's seed", **_PUSH_SEEDS),
    ExperimentSeeds("babbling", "the exploration strategy and the scene", (1000, 1999),
                    "NovEB's and goal babbling's settings were tried on seeds 0-4, the seeds "
                    "of the first published comparison"),
    ExperimentSeeds("babbling-compare", "one babbling run per method and seed", (1000, 1999),
                    "as babbling: seeds 0-4"),
    ExperimentSeeds("lasa", "the random starts of the convergence test (shape i: seed + i)",
                    (1000, 1999), "every run chooses the DS's beta, mu and arrival and the "
                    "DMP's weights and regularisation on 10 tuning shapes drawn with seed 0 "
                    "(held-out DTW, no random starts), reported on the other 20; the "
                    "schedules, map placement and K were set earlier on all 30 shapes with "
                    "starts from seeds 0-29", "the tuning split of the shapes: seed 0"),
    ExperimentSeeds("lfd-skills", "each trial's set-up (object and arm start)", (1040, 4999),
                    "the LfD defaults come from the parametrization study (trial seeds "
                    "500-539); the sideways pushes' turned gripper from trial seeds 500-579; "
                    "the Panda's grasp opening (its gripper's grasp_open) from trial seeds "
                    "500-579, after looking at the Panda's grasp on trials 1000-1039 (tuning "
                    "seeds since)", _LFD_STREAMS, looked_at=tuple(range(1000, 1040))),
    ExperimentSeeds("parametrization", "each trial's set-up (object and arm start)",
                    (1000, 4999), "a tuning study: it runs on seeds 500-539 by default, and "
                    "its choice became the LfD defaults", _LFD_STREAMS),
    ExperimentSeeds("perturbations", "each trial's set-up and its perturbation", (5000, 6999),
                    "the perturbation sizes and windows were set without trial seeds of this "
                    "block; the sideways pushes' turned gripper on lfd trial seeds 500-579",
                    _LFD_STREAMS),
    ExperimentSeeds("panda-gym", "the framework's draws inside panda-gym (" + _FRAMEWORK
                    + "); --eval_seed draws the evaluation episodes' resets from a stream "
                    "of its own", (1002, 1999), "its framework settings (a2l.experiments."
                    "panda_gym.SETTINGS) and the goal controller's keep and transit were "
                    "chosen on learning seeds 0-2 with evaluation seed 500 (docs/gym.md); the "
                    "transit after looking at the misses of learning seeds 1000 and 1001 "
                    "(evaluation seed 1500; tuning seeds since)", looked_at=(1000, 1001)),
    ExperimentSeeds("tasks", "each trial's set-up and its fault", (7000, 7999),
                    "the planning and transit settings were set without trial seeds of this "
                    "block", _LFD_STREAMS),
)}


def experiment_seeds(experiment: str) -> ExperimentSeeds:
    """The registry's entry of `experiment` (a ``KeyError`` naming the known ones)."""
    try:
        return REGISTRY[experiment]
    except KeyError:
        raise KeyError(f"no seed registry entry for experiment {experiment!r}; known: "
                       f"{', '.join(REGISTRY)}") from None


def is_tuning(seed: int, experiment: str | None = None) -> bool:
    """True for a tuning seed: ``0 .. EVALUATION_FIRST - 1``, and of `experiment` (a
    :data:`REGISTRY` name) the seeds it looked at before a choice
    (:attr:`ExperimentSeeds.looked_at`); a negative seed is an error."""
    if int(seed) < 0:
        raise ValueError(f"seed: must be >= 0, got {seed}")
    looked = experiment_seeds(experiment).looked_at if experiment is not None else ()
    return int(seed) < EVALUATION_FIRST or int(seed) in looked


def seed_use(seeds: Iterable[int], experiment: str | None = None) -> str:
    """``"tuning"`` (every seed a tuning seed of `experiment`, :func:`is_tuning`),
    ``"evaluation"`` (none) or ``"mixed"``."""
    flags = {is_tuning(s, experiment) for s in seeds}
    if not flags:
        raise ValueError("seeds: none given")
    return "mixed" if len(flags) == 2 else ("tuning" if True in flags else "evaluation")


def format_seeds(seeds: Iterable[int]) -> str:
    """Seeds as ranges: ``[0, 1, 2, 5]`` -> ``"0-2, 5"``; empty -> ``"-"``."""
    values = sorted({int(s) for s in seeds})
    parts: list[str] = []
    i = 0
    while i < len(values):
        j = i
        while j + 1 < len(values) and values[j + 1] == values[j] + 1:
            j += 1
        parts.append(str(values[i]) if i == j else f"{values[i]}-{values[j]}")
        i = j + 1
    return ", ".join(parts) or "-"


def seed_record(experiment: str, seeds: Sequence[int]) -> dict[str, Any]:
    """What a run's ``config.json`` records of its seeds (key ``"seed_use"``).

    Parameters
    ----------
    experiment : str
        A :data:`REGISTRY` name.
    seeds : sequence of int
        Every seed the run's trials (or runs) draw from.

    Returns
    -------
    dict
        ``{"experiment", "use": "tuning" | "evaluation" | "mixed", "seeds", "tuning",
        "evaluation", "registry"}``, seeds as range text (:func:`format_seeds`).
    """
    experiment_seeds(experiment)
    return {
        "experiment": experiment, "use": seed_use(seeds, experiment),
        "seeds": format_seeds(seeds),
        "tuning": format_seeds(s for s in seeds if is_tuning(s, experiment)),
        "evaluation": format_seeds(s for s in seeds if not is_tuning(s, experiment)),
        "registry": "docs/seeds.md"}


def tuning_note(record: dict[str, Any]) -> str:
    """The sentence a report shows when `record` (:func:`seed_record`) holds a tuning seed;
    empty when every seed is an evaluation seed."""
    if record["use"] == "evaluation":
        return ""
    entry = experiment_seeds(record["experiment"])
    first = entry.evaluation[0]
    looked = (f" and {format_seeds(entry.looked_at)}, looked at before a choice"
              if entry.looked_at else "")
    return (f"**Tuning seeds**: this run uses seed(s) {record['tuning']}, tuning seeds "
            f"(0-{EVALUATION_FIRST - 1}{looked}, on which defaults are chosen; see "
            "docs/seeds.md): "
            f"not an evaluation result. Report results from evaluation seeds ({entry.experiment}:"
            f" {first}-{entry.evaluation[1]}).")


def mark_report(text: str, record: dict[str, Any]) -> str:
    """`text` (a report's Markdown) with :func:`tuning_note` after its first heading line
    (at the top when it has none); unchanged when every seed is an evaluation seed."""
    note = tuning_note(record)
    if not note:
        return text
    lines = text.split("\n")
    at = next((i + 1 for i, line in enumerate(lines) if line.startswith("#")), 0)
    return "\n".join(lines[:at] + ["", note, ""] + lines[at:])
