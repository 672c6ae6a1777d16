"""The parts of an A2L run's configuration (:class:`a2l.framework.FrameworkConfig`), each a
frozen dataclass that validates itself when it is made: where training starts
(:class:`StartsConfig`), babbling (:class:`BabblingConfig`), the network's structure
(:class:`LearningConfig`), how the skill runs (:class:`SkillConfig`), where each iteration
validates, accepts and stops (:class:`ValidationConfig`), the dataset's extension
(:class:`ExtensionConfig`), effect-directed babbling (:class:`DirectedConfig`) and the
held-out starts (:class:`HeldoutConfig`). The discretization part is the one of the whole
package, :class:`a2l.skills.discretization.DiscretizationConfig`.

A field out of its domain raises :class:`a2l.errors.ConfigError` naming it as
``<part>.<field>`` (``starts.n_starts``), the option of that name on the command line.
"""

from __future__ import annotations

from dataclasses import dataclass

from a2l.checks import (
    check_choice,
    check_count,
    check_fraction,
    check_length,
    check_names,
    check_range,
)

__all__ = ["FALLBACK_RULES", "BabblingConfig", "DirectedConfig", "ExtensionConfig",
           "HeldoutConfig", "LearningConfig", "SkillConfig", "StartsConfig", "ValidationConfig"]

#: The C++ step's rules for a context cell without data (``skill.fallback``,
#: ``skill.train_fallback``).
FALLBACK_RULES = ("approach", "nearest", "none")


@dataclass(frozen=True)
class StartsConfig:
    """Where the training rollouts (babbling, validation) start, around the object.

    Attributes
    ----------
    n_starts : int
        Training start positions around the object, evenly spaced in angle.
    layout : {"circle", "ring"}
        Their distances from the object: ``"circle"`` (default) puts them all at
        ``radius`` (the authors' layout); ``"ring"`` spreads them over ``[r_low, r_high]``,
        the region users start a skill from (the held-out starts' ring), neighbouring angles
        at distant radii (:meth:`a2l.framework.FrameworkConfig.start_offsets`).
    radius : float
        Radius of the circle (m), with ``layout="circle"``.
    r_low, r_high : float
        Range of the ring's radii (m), with ``layout="ring"``.
    """

    n_starts: int = 8
    layout: str = "circle"
    radius: float = 0.2
    r_low: float = 0.10
    r_high: float = 0.25

    def __post_init__(self) -> None:
        check_count("starts", "n_starts", self.n_starts)
        check_choice("starts", "layout", self.layout, ("circle", "ring"))
        for name in ("radius", "r_low", "r_high"):
            check_length("starts", name, getattr(self, name))
        check_range("starts", "r_low", "r_high", self.r_low, self.r_high)

    @property
    def outer_radius(self) -> float:
        """The largest distance of a training start from the object (m)."""
        return self.radius if self.layout == "circle" else self.r_high


@dataclass(frozen=True)
class BabblingConfig:
    """Random motor babbling, the first acquisition.

    Attributes
    ----------
    max_steps : int
        Most random movements of a babbling trajectory.
    try_cap : int
        Most babbling trajectories tried in one acquisition.
    erase_loops : bool
        Cut the loops out of babbling trajectories
        (:func:`a2l.acquisition.interactions.erase_loops`).
    """

    max_steps: int = 7
    try_cap: int = 5000
    erase_loops: bool = False

    def __post_init__(self) -> None:
        check_count("babbling", "max_steps", self.max_steps)
        check_count("babbling", "try_cap", self.try_cap)


@dataclass(frozen=True)
class LearningConfig:
    """The Bayesian network's structure.

    Attributes
    ----------
    structure : {"hc-k2", "hand-coded"}
        ``"hc-k2"`` (default: hill-climbing + K2; it drops ``distance`` while the dataset is
        small, ``docs/framework.md``, "The aliasing cell") or ``"hand-coded"`` (the
        baseline: every context variable a parent of ``move`` from iteration 0).
    effect_parent : bool
        With ``hc-k2``, fix the edge ``effect -> move`` (the action generator is queried with
        the wanted effect; without the edge, small datasets give a skill that ignores it).
        Hill-climbing still chooses every other parent.
    fixed_parents : tuple of str
        With ``hc-k2``, context variables also fixed as parents of ``move``, like the effect
        (default ``("distance",)``: hill-climbing + K2 drops ``distance`` while the dataset
        is small, and the orientation wedges around the object then alias,
        ``docs/framework.md``). Hill-climbing still chooses every other parent; ``()``
        leaves ``distance`` to it too. On the command line ``distance,orientation`` or
        ``[distance,orientation]``.
    """

    structure: str = "hc-k2"
    effect_parent: bool = True
    fixed_parents: tuple[str, ...] = ("distance",)

    def __post_init__(self) -> None:
        if isinstance(self.fixed_parents, list):  # from JSON (config.json, --set)
            object.__setattr__(self, "fixed_parents", tuple(self.fixed_parents))
        check_choice("learning", "structure", self.structure, ("hc-k2", "hand-coded"))
        check_names("learning", "fixed_parents", self.fixed_parents)


@dataclass(frozen=True)
class SkillConfig:
    """How the learned skill runs, in validation and once exported.

    Attributes
    ----------
    step_cap : int
        Most movements the exported skill takes, and a run from the held-out starts
        (default 16, chosen on tuning seeds, ``docs/experiments/push.md``: a start on the
        side the box is pushed toward needs most of 12 movements to go round it).
    train_step_cap : int
        Most movements a run of the training validation takes (the training starts and the
        fresh starts; default 12, the thesis' cap): a run that needs more is a failure the
        extension learns from, as without the fallback and the clearance rule.
    smoothing : bool
        Neighbour smoothing (``docs/method.md``) in the C++ step (default on: with
        hill-climbing + K2, 27 of virtual seeds 0-29 reach 100 within 3 iterations, 21
        without it; with the hand-coded structure 30 and 23; ``docs/framework.md``).
    fallback : {"none", "nearest", "approach"} or None
        The C++ step's answer in a context cell the training never reached (a uniform row of
        the table): ``"none"`` stops with ``unknown_context``; ``"nearest"`` takes the
        movement of the nearest cell with data, same effect, never one past the distance
        range nor into its first bin; ``"approach"`` heads for that cell instead (the
        movement within the same limits that ends nearest its centre), and no step of a run
        undoes its previous movement when another is allowed; the trace marks a fallback
        step. It is the rule of the exported skill and of the held-out starts. None: the
        scene's default (:data:`a2l.framework.config.FALLBACK`: ``"approach"`` on Baxter,
        ``"none"`` on the virtual scene).
    train_fallback : {"none", "nearest", "approach"} or None
        The rule of the skill the training validation runs (its failures direct the
        extension; a rule that rescues a cell without data hides it from the extension).
        None: the scene's default (:data:`a2l.framework.config.TRAIN_FALLBACK`:
        ``"nearest"`` on Baxter, ``"none"`` on the virtual scene).
    clearance : float
        The step's clearance rule (m; 0: off) in the exported skill and from the held-out
        starts: away from the side the wanted effect pushes from, a movement that would end
        nearer the object than this gives way to a near-equal one that does not
        (``docs/runtime.md``). The training validation runs without it, like its own
        fallback: what it would rescue stays a failure the extension learns from. Default
        0.10 m, chosen on tuning seeds (``docs/experiments/push.md``).
    clearance_ratio : float
        The clearance rule's bar in (0, 1]: an alternative that keeps clearance is taken if
        it scores at least this share of the chosen movement. Default 0.25, chosen on tuning
        seeds (``docs/experiments/push.md``; 0.5 before, the bar of bundles that write none).
    align : float
        The step's alignment rule (m; 0: off) in the exported skill and from the held-out
        starts, the clearance rule's counterpart on the pushing side: there, a movement
        towards the object that would end nearer it than `clearance`, started more than
        this off the push line through the object's centre, gives way to the movement that
        does not approach and ends nearest that line (``docs/runtime.md``). The training
        validation runs without it, as without the clearance rule. Default 0.05 m (the
        8 cm box's half width and a centimetre), chosen on tuning seeds
        (``docs/experiments/push.md``).
    avoid_revisits : bool
        The step's revisit rule in the exported skill and from the held-out starts: a run
        that comes back within half a movement of where it was (having left) takes there
        the best-scored movement it has not taken there (``docs/runtime.md``). The training
        validation runs without it, as without the clearance rule. Default on, chosen on
        tuning seeds (``docs/experiments/push.md``).
    """

    step_cap: int = 16
    train_step_cap: int = 12
    smoothing: bool = True
    fallback: str | None = None
    train_fallback: str | None = None
    clearance: float = 0.10
    clearance_ratio: float = 0.25
    align: float = 0.05
    avoid_revisits: bool = True

    def __post_init__(self) -> None:
        check_count("skill", "step_cap", self.step_cap)
        check_count("skill", "train_step_cap", self.train_step_cap)
        for name in ("fallback", "train_fallback"):
            if getattr(self, name) is not None:
                check_choice("skill", name, getattr(self, name), FALLBACK_RULES)
        check_length("skill", "clearance", self.clearance, allow_zero=True)
        check_fraction("skill", "clearance_ratio", self.clearance_ratio)
        check_length("skill", "align", self.align, allow_zero=True)


@dataclass(frozen=True)
class ValidationConfig:
    """Where each iteration's skill is validated, and what accepts it and stops the run.

    Attributes
    ----------
    starts : {"fixed", "fresh"}
        ``"fixed"`` (the thesis' loop, default): each iteration validates from the training
        starts (``starts``), accepts a skill whose score did not drop, extends from its
        rollouts there and stops at score 100. ``"fresh"``: each iteration also validates
        from ``n_fresh`` start positions drawn anew over the ring users start from
        (``[r_low, r_high]`` from the object, uniform angle; the training seed stream,
        never a held-out start: :func:`a2l.framework.starts.fresh_offsets`); the candidate
        and the skill accepted so far both run from them, the candidate is accepted when
        its success rate over the training and the fresh starts is not lower, the next
        extension grows from the accepted skill's rollouts from both (effect-directed
        babbling from each failed fresh pair), and the run stops when the training score is
        100 and the success rate on the fresh starts reached ``stop_success``. Either way
        ``score`` in ``metrics.json`` is the thesis' figure, from the training starts.
    n_fresh : int
        Fresh start positions per iteration (each runs every effect).
    r_low, r_high : float
        Range of their distance from the object (m).
    stop_success : float
        With ``"fresh"``: the success rate on an iteration's fresh starts, in (0, 1], that
        stops the run (with the training score 100).
    """

    starts: str = "fixed"
    n_fresh: int = 8
    r_low: float = 0.10
    r_high: float = 0.25
    stop_success: float = 1.0

    def __post_init__(self) -> None:
        check_choice("validation", "starts", self.starts, ("fresh", "fixed"))
        check_count("validation", "n_fresh", self.n_fresh)
        for name in ("r_low", "r_high"):
            check_length("validation", name, getattr(self, name))
        check_range("validation", "r_low", "r_high", self.r_low, self.r_high)
        check_fraction("validation", "stop_success", self.stop_success)

    @property
    def fresh(self) -> bool:
        """Whether iterations validate from fresh starts."""
        return self.starts == "fresh"


@dataclass(frozen=True)
class ExtensionConfig:
    """The dataset's extension from the validation trajectories.

    Attributes
    ----------
    cut : int
        Most steps cut from the end of a trajectory before extending it (each extension
        cuts 1 to ``cut`` steps, drawn at random).
    keep_validation : bool
        Add the validation trajectories that moved the object to the next dataset (they
        are interactions too, labelled with the effect they produced).
    max_extensions : int
        Most extension trajectories added per iteration.
    """

    cut: int = 3
    keep_validation: bool = True
    max_extensions: int = 50

    def __post_init__(self) -> None:
        check_count("extension", "cut", self.cut)
        check_count("extension", "max_extensions", self.max_extensions)


@dataclass(frozen=True)
class DirectedConfig:
    """Effect-directed babbling for (start, effect) pairs that stay failed.

    Attributes
    ----------
    stuck_after : int
        Iterations a (start, effect) pair must fail before effect-directed babbling.
    per_pair : int
        Effect-directed trajectories added for a stuck pair.
    try_cap : int or None
        Most tries to find them; None: the scene's default
        (:data:`a2l.framework.config.DIRECTED_TRY_CAP`: a Baxter movement costs ~20-30 ms
        of physics, a virtual one ~20 µs).
    steps : int
        Most movements of an effect-directed trajectory (going around the object takes
        more than ``babbling.max_steps``).
    growth : int
        Most times the effect-directed budget of a pair grows while it stays stuck
        (1: a fixed budget).
    mode : {"waypoints", "random"}
        How effect-directed trajectories move: ``"waypoints"`` (random via-points around
        the object, then a random point on it, :func:`a2l.framework.directed_task`) or
        ``"random"`` (uniformly random movements, like acquisition).
    waypoints_max : int
        Most via-points of a waypoint trajectory (0 to this many, uniformly).
    waypoint_aim : float
        The last point of a waypoint trajectory is drawn within ± this of the object's
        start position on each table axis (m).
    """

    stuck_after: int = 1
    per_pair: int = 40
    try_cap: int | None = None
    steps: int = 20
    growth: int = 5
    mode: str = "waypoints"
    waypoints_max: int = 2
    waypoint_aim: float = 0.04

    def __post_init__(self) -> None:
        for name in ("stuck_after", "per_pair", "steps", "growth"):
            check_count("directed", name, getattr(self, name))
        if self.try_cap is not None:
            check_count("directed", "try_cap", self.try_cap)
        check_choice("directed", "mode", self.mode, ("waypoints", "random"))
        check_count("directed", "waypoints_max", self.waypoints_max, minimum=0)
        check_length("directed", "waypoint_aim", self.waypoint_aim)


@dataclass(frozen=True)
class HeldoutConfig:
    """The held-out starts: they only measure, nothing is learnt from them.

    Attributes
    ----------
    n_starts : int
        Held-out start positions (0: no held-out evaluation): every iteration's skill is
        also run for each effect from each of them, positions no phase of training starts
        from (:meth:`a2l.framework.FrameworkConfig.heldout_offsets`).
    r_low, r_high : float
        Range of their distance from the object (m); their angle is uniform.
    """

    n_starts: int = 32
    r_low: float = 0.10
    r_high: float = 0.25

    def __post_init__(self) -> None:
        check_count("heldout", "n_starts", self.n_starts, minimum=0)
        for name in ("r_low", "r_high"):
            check_length("heldout", name, getattr(self, name))
        check_range("heldout", "r_low", "r_high", self.r_low, self.r_high)
