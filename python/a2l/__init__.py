"""a2l: Adaptive Affordance Learning.

A robot learns manipulation skills by itself (babbling, Bayesian networks, demonstrations)
and runs them adapted, online, through a C++ runtime. A script takes what it needs from the
top package, ``from a2l import learn_bundle, make_scene, run_skill``; every name below is
loaded from its module on first use, so ``import a2l`` loads only the C++ core. The command
line is ``a2l --help``; the API reference is built by ``make docs`` (``build/docs``).

Learn a skill from interactions:

    learn_bundle
        Interaction rows -> discretized -> Bayesian network -> policy table -> skill bundle
        file; returns a LearnedBundle.
    Discretizer
        The bins of the context and effect variables and the movement repertoire that turn
        raw rows into discrete ones.
    DiscretizationConfig
        The discretization of a skill's dataset (makes its Discretizer).

Learn a skill from demonstrations:

    Demonstration, load_demonstrations, save_demonstrations
        One demonstrated trajectory; a file of them read and written.
    DiffeoDS
        The diffeomorphic dynamical system fitted to a demonstration.
    learn_skill, Behaviour, LearnedSkill, LfDConfig
        Demonstrated behaviours -> skill bundle (table + DS phases), with its parameters.
    learn_recipe
        A skill of the library (``push_far``, ``grasp``...) demonstrated by its script and
        learned.
    record_demonstrations
        Demonstrations recorded by teleoperation in the PyBullet GUI.

Load, save and inspect a bundle (``a2l skill show BUNDLE`` prints one):

    load_bundle, save_bundle, SkillSpec
        A skill bundle file and its content: variables, bins, movements, posterior table,
        robot.
    load_ds_phases
        The DS phases a skill bundle holds.
    load_ds_bundle
        The DS of a DS bundle (or of a skill bundle holding one).

Run a skill:

    make_scene
        A scene by name: push, grasp, grasp_light, press, task, virtual.
    make_skill_scene, reset_for_trial
        The scene a library skill is tried in, placed for a trial seed.
    run_skill, SkillRun
        A bundle in closed loop in a scene until its effect test says done.
    CppSkillRunner, StepResult
        A bundle stepped by the C++ runtime, one context at a time.

Run the A2L framework (acquire interactions, learn, validate, repeat):

    run_framework, FrameworkConfig, FrameworkResult
        The iterative loop, resumable from its run directory, every parameter of a run
        (composed of frozen parts: ``cfg.discretization``, ``cfg.starts``, ``cfg.heldout``...;
        ``cfg.with_({"directed.per_pair": 20})``) and what it returns.
    Executor
        Where the rollouts run (this process, worker processes, a Dask cluster).

Kinematics, the C++ core (:mod:`a2l._core`):

    Kinematics, IkOptions, IkReport, Status
        Forward and inverse kinematics of a URDF chain; the outcome of a call into the core.

Errors:

    A2LError
        The base of A2LValueError, A2LFileNotFoundError, BundleError, URDFError, IKError,
        UnknownLinkError, UnreachableError.
"""

from __future__ import annotations

from a2l import _core
from a2l._core import IkOptions, IkReport, Kinematics, Status
from a2l.errors import (
    A2LError,
    A2LFileNotFoundError,
    A2LValueError,
    BundleError,
    IKError,
    UnknownLinkError,
    UnreachableError,
    URDFError,
)
from a2l.lazy import lazy_exports

__version__ = _core.__version__

# The top package stands above every layer: its lazy names come from any of them (the
# import contracts order the subpackages, not this file). Nothing is imported before a name
# is used, so a module of a low layer, which imports this package first, loads no upper one.
# A module of the package imports from here only the names imported above.
_EXPORTS: dict[str, str] = {
    # learn a skill from interactions
    "learn_bundle": "a2l.skills.pipeline",
    "LearnedBundle": "a2l.skills.pipeline",
    "Discretizer": "a2l.skills.discretizer",
    "DiscretizationConfig": "a2l.skills.discretization",
    # learn a skill from demonstrations
    "Demonstration": "a2l.lfd.demonstration",
    "load_demonstrations": "a2l.lfd.demonstration",
    "save_demonstrations": "a2l.lfd.demonstration",
    "DiffeoDS": "a2l.lfd.ds",
    "learn_skill": "a2l.lfd.skill",
    "Behaviour": "a2l.lfd.skill",
    "LearnedSkill": "a2l.lfd.skill",
    "LfDConfig": "a2l.lfd.config",
    "learn_recipe": "a2l.lfd.library",
    "record_demonstrations": "a2l.lfd.teleop",
    # load, save and inspect a bundle
    "load_bundle": "a2l.skills.bundle",
    "save_bundle": "a2l.skills.bundle",
    "SkillSpec": "a2l.skills.spec",
    "load_ds_phases": "a2l.skills.phases",
    "load_ds_bundle": "a2l.skills.ds_bundle",
    # run a skill
    "make_scene": "a2l.sim",
    "make_skill_scene": "a2l.lfd.library",
    "reset_for_trial": "a2l.lfd.library",
    "run_skill": "a2l.rollout.run",
    "SkillRun": "a2l.rollout.run",
    "CppSkillRunner": "a2l.skills.runner",
    "StepResult": "a2l.skills.runner",
    # run the A2L framework
    "run_framework": "a2l.framework.loop",
    "FrameworkConfig": "a2l.framework.config",
    "FrameworkResult": "a2l.framework.result",
    "Executor": "a2l.parallel",
}

__all__ = [
    # learn a skill from interactions
    "learn_bundle",
    "LearnedBundle",
    "Discretizer",
    "DiscretizationConfig",
    # learn a skill from demonstrations
    "Demonstration",
    "load_demonstrations",
    "save_demonstrations",
    "DiffeoDS",
    "learn_skill",
    "Behaviour",
    "LearnedSkill",
    "LfDConfig",
    "learn_recipe",
    "record_demonstrations",
    # load, save and inspect a bundle
    "load_bundle",
    "save_bundle",
    "SkillSpec",
    "load_ds_phases",
    "load_ds_bundle",
    # run a skill
    "make_scene",
    "make_skill_scene",
    "reset_for_trial",
    "run_skill",
    "SkillRun",
    "CppSkillRunner",
    "StepResult",
    # run the A2L framework
    "run_framework",
    "FrameworkConfig",
    "FrameworkResult",
    "Executor",
    # kinematics (the C++ core)
    "Kinematics",
    "IkOptions",
    "IkReport",
    "Status",
    # errors
    "A2LError",
    "A2LValueError",
    "A2LFileNotFoundError",
    "BundleError",
    "URDFError",
    "IKError",
    "UnknownLinkError",
    "UnreachableError",
    "__version__",
]

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
