"""Perturbation success per condition (issue 24, part 4): a few skills, a short
configuration, each condition's success count held to a one-sided binomial bound.

Each skill is learned with its own configuration and run as the context skill (the compiled
table through the C++ step, the context from the ground truth: cheaper than the camera, and
the reported runs gave the same rates with either) from ``TRIALS[skill]`` evaluation trial
seeds of the perturbations block (``SEED`` ...: no setting was chosen on them), unperturbed
and under every perturbation (:func:`a2l.experiments.perturbations.trial_task`). The bound
of a condition is the smallest success count a skill at the claimed rate (:func:`_rate`)
reaches with probability >= 1 - ALPHA: a skill as good as claimed fails a bound with
probability < ALPHA = 1 %.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from scipy.stats import binom

from a2l.experiments.perturbation_report import target
from a2l.experiments.perturbation_trials import skill_scene
from a2l.experiments.perturbations import CONDITIONS, skill_cfg, trial_task
from a2l.lfd.library import SKILLS, learn_recipe

#: First trial seed: evaluation seeds of the perturbations block (docs/seeds.md), apart
#: from the reported runs' (5000 ..., 5100 ..., 5200 ...).
SEED = 6500
#: Trials per skill: the sideways pushes (issue 27's) and the press.
TRIALS = {"push_right": 24, "push_left": 24, "press": 12}
#: Probability that a skill at its claimed rate fails a condition's bound.
ALPHA = 0.01


def _rate(skill: str, condition: str) -> float:
    """The success rate claimed for `skill` under `condition`: the issue's target
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
    assert binom.cdf(_bound(24, 0.90) - 1, 24, 0.90) <= ALPHA < binom.cdf(_bound(24, 0.90),
                                                                           24, 0.90)


@pytest.mark.parametrize("skill", list(TRIALS))
def test_success_per_condition_stays_above_its_binomial_bound(skill: str,
                                                              tmp_path: Path) -> None:
    cfg = skill_cfg(skill)
    bundle = str(learn_recipe(skill, tmp_path, cfg).bundle)
    n = TRIALS[skill]
    wins = dict.fromkeys(CONDITIONS, 0)
    applied = dict.fromkeys(CONDITIONS, 0)
    for seed in range(SEED, SEED + n):
        rows = trial_task({"skill": skill, "bundle": bundle, "mode": "table", "seed": seed,
                           "scene": skill_scene(SKILLS[skill]), "conditions": list(CONDITIONS),
                           "cfg": cfg.to_json(), "context_source": "ground_truth"})
        for r in rows:
            wins[r["condition"]] += bool(r["success"])
            applied[r["condition"]] += r["condition"] == "none" or bool(r["applied"])
    for cond in CONDITIONS:
        assert applied[cond] == n, (cond, applied)  # every trial really perturbed
        bound = _bound(n, _rate(skill, cond))
        assert wins[cond] >= bound, (f"{skill} {cond}: {wins[cond]}/{n} successes, below "
                                     f"{bound}/{n} (claimed {_rate(skill, cond):.0%})", wins)
