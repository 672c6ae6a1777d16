"""The step's rules a skill bundle of a run carries: the exported skill's (``skill.fallback``,
``skill.clearance``, ``skill.avoid_revisits``, ``skill.step_cap``) and the training
validation's (``skill.train_fallback``, ``skill.train_step_cap``, neither the clearance nor
the revisit rule),
written as copies of one learned table (:func:`bundle_with_rules`, :func:`training_bundle`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from a2l.framework.config import FrameworkConfig

if TYPE_CHECKING:
    from a2l.skills.spec import SkillSpec

__all__ = ["bundle_with_rules", "training_bundle"]


def bundle_with_rules(src: Path, dst: Path, **settings: Any) -> SkillSpec:
    """Write the push skill bundle `src` to `dst` with the execution `settings` given, by
    their :class:`~a2l.skills.spec.SkillSpec` names (``fallback``, ``clearance``,
    ``clearance_ratio``, ``avoid_revisits``, ``step_cap``), its own for the others and the
    same table; returns the skill written."""
    from a2l.skills.bundle import load_bundle, save_bundle

    spec = replace(load_bundle(src), **settings)
    save_bundle(spec, dst)
    return spec


def training_bundle(cfg: FrameworkConfig, bundle: Path) -> Path:
    """The skill the training validation runs: `bundle` itself, or, when
    ``cfg.skill.train_fallback`` or ``cfg.skill.train_step_cap`` differs from its exported
    counterpart or the skill keeps a clearance (``cfg.skill.clearance``) or the revisit rule
    (``cfg.skill.avoid_revisits``), a copy beside it (``<name>.train.a2lb``) with the
    training rule and step cap and neither of the two rules (the same table otherwise)."""
    skill = cfg.skill
    training = {"fallback": skill.train_fallback, "clearance": 0.0, "align": 0.0,
                "avoid_revisits": False, "step_cap": skill.train_step_cap}
    if all(getattr(skill, name) == value for name, value in training.items()):
        return bundle
    out = bundle.with_suffix(".train.a2lb")
    bundle_with_rules(bundle, out, **training)
    return out
