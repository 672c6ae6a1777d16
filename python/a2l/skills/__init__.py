"""Skills: discretization, Bayesian-network learning, compiled policy tables, bundles.

From a raw interaction dataset to a skill bundle::

    disc = Discretizer()
    data = disc.discretize(raw)                      # categorical columns, every state known
    net = learn_network(data, "hc-k2")               # hill-climbing + K2, BDeu parameters
    table = compile_policy(net, "move", disc.evidence)
    spec = make_skill_spec(table, disc, name="push")  # what save_bundle writes

or in one call, the pipeline the framework and LfD use::

    learned = learn_bundle(raw, disc, "push.a2lb", name="push")
"""

from __future__ import annotations

from a2l.lazy import lazy_exports

# Names are imported from their module on first use (PEP 562): a worker process that
# needs one module does not import the others (pgmpy, OpenCV: seconds per process).
_EXPORTS: dict[str, str] = {
    "DistanceBins": "a2l.skills.bins",
    "InclinationBins": "a2l.skills.bins",
    "OffsetBins": "a2l.skills.bins",
    "OrientationBins": "a2l.skills.bins",
    "load_bundle": "a2l.skills.bundle",
    "save_bundle": "a2l.skills.bundle",
    "PolicyTable": "a2l.skills.compile",
    "compile_policy": "a2l.skills.compile",
    "relevant_evidence": "a2l.skills.compile",
    "Discretizer": "a2l.skills.discretizer",
    "AXIS_EFFECTS": "a2l.skills.effects",
    "DIAGONAL_EFFECTS": "a2l.skills.effects",
    "EffectDiscretizer": "a2l.skills.effects",
    "make_skill_spec": "a2l.skills.export",
    "K2Score": "a2l.skills.k2",
    "k2_local_score": "a2l.skills.k2",
    "STRUCTURES": "a2l.skills.learning",
    "hand_coded_structure": "a2l.skills.learning",
    "learn_network": "a2l.skills.learning",
    "learn_structure": "a2l.skills.learning",
    "LearnedBundle": "a2l.skills.pipeline",
    "learn_bundle": "a2l.skills.pipeline",
    "DSPhase": "a2l.skills.phases",
    "load_ds_phases": "a2l.skills.phases",
    "MovementRepertoire": "a2l.skills.repertoire",
    "CppSkillRunner": "a2l.skills.runner",
    "StepResult": "a2l.skills.runner",
    "ACTIONS": "a2l.skills.spec",
    "BUNDLE_SCHEMA_VERSION": "a2l.skills.spec",
    "VARIABLE_KINDS": "a2l.skills.spec",
    "SkillSpec": "a2l.skills.spec",
    "VariableSpec": "a2l.skills.spec",
    "HighLevelState": "a2l.skills.states",
    "KnownStructure": "a2l.skills.synthetic",
    "known_structure_dataset": "a2l.skills.synthetic",
    "push_dataset": "a2l.skills.synthetic",
}

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
    "LearnedBundle",
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
    "learn_bundle",
    "learn_network",
    "learn_structure",
    "load_bundle",
    "load_ds_phases",
    "make_skill_spec",
    "push_dataset",
    "relevant_evidence",
    "save_bundle",
]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
