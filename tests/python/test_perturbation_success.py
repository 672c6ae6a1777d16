"""Perturbation success per condition: a few skills, a short
configuration, each condition's success count held to a one-sided binomial bound.

Each skill is learned with its own configuration and run as the context skill (the compiled
table through the C++ step, the context from the ground truth: cheaper than the camera, and
the reported runs gave the same rates with either) from ``TRIALS[skill]`` evaluation trial
seeds of the perturbations block (``SEED`` ...: no setting was chosen on them), unperturbed
and under every perturbation (:func:`a2l.experiments.perturbations.trial_task`). The bound
of a condition is the smallest success count a skill at the claimed rate (:func:`_rate`)
reaches with probability >= 1 - ALPHA: a skill as good as claimed fails a bound with
probability < ALPHA = 1 %. Every perturbation must be measured in the world (the box moved
by 3-5 cm, commanded movements held, the light flipped), and the three skills'
successes with the box moved, pooled, must reach the bound of the rate the table measured
there (:data:`MOVED_RATE`): a skill that reads the box once and does not see it move keeps
above the 90 % target of each skill (23, 21 and 10 of 24, 24 and 12, docs/evidence.md) but
not above this bound.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from scipy.stats import binom

from a2l.experiments.perturbation_report import target
from a2l.experiments.perturbation_trials import MOVE_RANGE, skill_scene
from a2l.experiments.perturbations import CONDITIONS, PerturbationTrial, skill_cfg, trial_task
from a2l.lfd.library import SKILLS, learn_recipe

#: First trial seed: evaluation seeds of the perturbations block (docs/seeds.md), apart
#: from the reported runs' (5000 ..., 5100 ..., 5200 ...).
SEED = 6500
#: Trials per skill: the sideways pushes and the press.
TRIALS = {"push_right": 24, "push_left": 24, "press": 12}
#: Probability that a skill at its claimed rate fails a condition's bound.
ALPHA = 0.01
#: The table's success rate with the box moved, pooled over the skills: measured 98-100 %
#: (docs/experiments/perturbations.md: the sideways pushes 396 of 400 on seeds 5200-5399).
MOVED_RATE = 0.98


def _rate(skill: str, condition: str) -> float:
    """The success rate claimed for `skill` under `condition`: the target
    (:func:`a2l.experiments.perturbation_report.target`), which the sideways pushes reach
    since their gripper is turned (docs/experiments/perturbations.md: seeds 5200-5249, 98-100 %
    with the camera and with the ground truth)."""
    return target(skill, condition)


def _bound(n: int, p: float, alpha: float = ALPHA) -> int:
    """The largest k with P(X < k) <= alpha for X ~ Binomial(n, p)."""
    k = 0
    while binom.cdf(k, n, p) <= alpha:
        k += 1
    return k


def test_bound_is_the_binomial_quantile() -> None:
    assert _bound(24, 0.90) == 18 and _bound(24, 0.95) == 20 and _bound(12, 0.95) == 9
    assert _bound(60, MOVED_RATE) == 56
    assert binom.cdf(_bound(24, 0.90) - 1, 24, 0.90) <= ALPHA < binom.cdf(_bound(24, 0.90),
                                                                           24, 0.90)


def _trials(skill: str, out: Path) -> list[dict]:
    """The rows of `skill`'s trials (:func:`trial_task`, every condition), TRIALS[skill]
    trial seeds from SEED."""
    cfg = skill_cfg(skill)
    bundle = str(learn_recipe(skill, out, cfg).bundle)
    return [r for seed in range(SEED, SEED + TRIALS[skill])
            for r in trial_task(PerturbationTrial(skill, bundle, "table", seed,
                                                  skill_scene(SKILLS[skill]), CONDITIONS, cfg,
                                                  context_source="ground_truth"))]


def _unmeasured(r: dict) -> str | None:
    """Why the perturbation of row `r` did not happen in the world (None: it did)."""
    cond = r["condition"]
    if cond == "none":
        return None
    if not r["applied"]:
        return "not applied"
    if cond == "move_object" and not (MOVE_RANGE[0] - 1e-3 <= r["displacement_m"]
                                      <= MOVE_RANGE[1] + 1e-3):
        return f"box moved {r['displacement_m']:.4f} m"
    if cond == "hold" and r["held_observed"] == 0:  # (a run may stop before the hold ends)
        return "no movement held"
    if cond == "toggle_light" and r["light_before"] == r["light_after"]:
        return f"light stayed {r['light_after']!r}"
    return None


@pytest.mark.slow
def test_success_per_condition_stays_above_its_binomial_bound(tmp_path: Path) -> None:
    rows = {skill: _trials(skill, tmp_path / skill) for skill in TRIALS}
    below, moved = [], 0
    for skill, n in TRIALS.items():
        unmeasured = [(r["condition"], r["seed"], why) for r in rows[skill]
                      if (why := _unmeasured(r))]
        assert not unmeasured, (skill, unmeasured)  # every trial really perturbed
        for cond in CONDITIONS:
            cell = [r for r in rows[skill] if r["condition"] == cond]
            assert len(cell) == n, (skill, cond, len(cell))
            wins = sum(bool(r["success"]) for r in cell)
            moved += wins if cond == "move_object" else 0
            if wins < (bound := _bound(n, _rate(skill, cond))):
                below.append(f"{skill} {cond}: {wins}/{n} successes, below {bound}/{n} "
                             f"(claimed {_rate(skill, cond):.0%})")
    assert not below, below
    total = sum(TRIALS.values())
    bound = _bound(total, MOVED_RATE)
    assert moved >= bound, (f"box moved: {moved}/{total} successes over {list(TRIALS)}, "
                            f"below {bound}/{total} (measured {MOVED_RATE:.0%})")
