"""The step's rules a skill bundle of a run carries: the exported skill's (``skill.fallback``,
``skill.clearance``, ``skill.avoid_revisits``) and the training validation's
(``skill.train_fallback``, neither the clearance nor the revisit rule),
written as copies of one learned table (:func:`bundle_with_fallback`,
:func:`training_bundle`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from a2l.framework.config import FrameworkConfig

if TYPE_CHECKING:
    from a2l.skills.spec import SkillSpec

__all__ = ["bundle_with_fallback", "training_bundle"]


def bundle_with_fallback(src: Path, dst: Path, rule: str | None = None,
                         clearance: float | None = None,
                         avoid_revisits: bool | None = None,
                         clearance_ratio: float | None = None,
                         step_cap: int | None = None) -> SkillSpec:
    """Write the push skill bundle `src` to `dst` with the fallback `rule`, the clearance
    rule `clearance` (m) and its bar `clearance_ratio`, the revisit rule `avoid_revisits` and
    the step cap `step_cap` (each None: its own), the same table otherwise; returns the skill
    written."""
    from a2l.skills.bundle import load_bundle, save_bundle

    spec = load_bundle(src)
    if rule is not None:
        spec = replace(spec, fallback=rule)
    if clearance is not None:
        spec = replace(spec, clearance=float(clearance))
    if clearance_ratio is not None:
        spec = replace(spec, clearance_ratio=float(clearance_ratio))
    if avoid_revisits is not None:
        spec = replace(spec, avoid_revisits=bool(avoid_revisits))
    if step_cap is not None:
        spec = replace(spec, step_cap=int(step_cap))
    save_bundle(spec, dst)
    return spec


def training_bundle(cfg: FrameworkConfig, bundle: Path) -> Path:
    """The skill the training validation runs: `bundle` itself, or, when
    ``cfg.skill.train_fallback`` differs from its ``cfg.skill.fallback`` or the skill keeps
    a clearance (``cfg.skill.clearance``) or the revisit rule (``cfg.skill.avoid_revisits``),
    a copy beside it (``<name>.train.a2lb``) with the training rule and neither of the two
    (the same table otherwise)."""
    skill = cfg.skill
    if (skill.train_fallback == skill.fallback and not skill.clearance
            and not skill.avoid_revisits):
        return bundle
    out = bundle.with_suffix(".train.a2lb")
    bundle_with_fallback(bundle, out, skill.train_fallback, clearance=0.0, avoid_revisits=False)
    return out
