"""Skills: discretization, Bayesian-network learning, compiled policy tables, bundles.

From a raw interaction dataset to a skill bundle::

    disc = Discretizer()
    data = disc.discretize(raw)                      # categorical columns, every state known
    net = learn_network(data, "hc-k2")               # hill-climbing + K2, BDeu parameters
    table = compile_policy(net, "move", disc.evidence)
    spec = make_skill_spec(table, disc, name="push")  # what save_bundle writes
"""

from __future__ import annotations

from a2l.skills.bins import DistanceBins, InclinationBins, OffsetBins, OrientationBins
from a2l.skills.bundle import load_bundle, save_bundle
from a2l.skills.compile import PolicyTable, compile_policy, relevant_evidence
from a2l.skills.discretize import Discretizer
from a2l.skills.effects import AXIS_EFFECTS, DIAGONAL_EFFECTS, EffectDiscretizer
from a2l.skills.export import make_skill_spec
from a2l.skills.k2 import K2Score, k2_local_score
from a2l.skills.learning import (
    STRUCTURES,
    hand_coded_structure,
    learn_network,
    learn_structure,
)
from a2l.skills.phases import DSPhase, load_ds_phases
from a2l.skills.repertoire import MovementRepertoire
from a2l.skills.runner import CppSkillRunner, StepResult
from a2l.skills.spec import (
    ACTIONS,
    BUNDLE_SCHEMA_VERSION,
    VARIABLE_KINDS,
    SkillSpec,
    VariableSpec,
)
from a2l.skills.states import HighLevelState
from a2l.skills.synthetic import KnownStructure, known_structure_dataset, push_dataset

__all__ = [
    "ACTIONS",
    "AXIS_EFFECTS",
    "BUNDLE_SCHEMA_VERSION",
    "CppSkillRunner",
    "DIAGONAL_EFFECTS",
    "DSPhase",
    "Discretizer",
    "DistanceBins",
    "EffectDiscretizer",
    "HighLevelState",
    "InclinationBins",
    "K2Score",
    "KnownStructure",
    "MovementRepertoire",
    "OffsetBins",
    "OrientationBins",
    "PolicyTable",
    "STRUCTURES",
    "SkillSpec",
    "StepResult",
    "VARIABLE_KINDS",
    "VariableSpec",
    "compile_policy",
    "hand_coded_structure",
    "k2_local_score",
    "known_structure_dataset",
    "learn_network",
    "learn_structure",
    "load_bundle",
    "load_ds_phases",
    "make_skill_spec",
    "push_dataset",
    "relevant_evidence",
    "save_bundle",
]
