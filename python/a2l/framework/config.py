"""The configuration of an A2L run (:class:`FrameworkConfig`) and the discretization it
defines (:func:`discretizers`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from a2l.errors import ConfigError
from a2l.framework.starts import heldout_offsets, heldout_redraw, spread_ranks
from a2l.skills.discretization import DiscretizationConfig
from a2l.skills.discretize import Discretizer

__all__ = ["DIRECTED_TRY_CAP", "FALLBACK", "FALLBACK_RULES", "TRAIN_FALLBACK", "FrameworkConfig",
           "discretizers", "task_config"]

#: Default ``directed_try_cap`` of each scene.
DIRECTED_TRY_CAP = {"virtual": 2000, "baxter": 100}

#: Default ``fallback`` of each scene (``docs/experiments/push.md``, issue 27): on Baxter
#: the held-out starts reach context cells the training never did (``unknown_context`` was
#: half of the held-out misses), and heading for the nearest cell with data, never undoing
#: the previous movement (``approach``), ends the two-cell loops that taking its movement
#: (``nearest``) ran into (tuning seeds 3 and 4); on the virtual scene such cells are rare
#: and the fallback measured no gain.
FALLBACK = {"virtual": "none", "baxter": "approach"}

#: The C++ step's rules for a context cell without data (``fallback``, ``train_fallback``).
FALLBACK_RULES = ("approach", "nearest", "none")

#: Default ``train_fallback`` of each scene: the rule of the skill the training validation
#: runs. A fallback that carries a rollout through a cell without data also hides that cell
#: from the extension, which babbles where validation failed: trained with ``approach``,
#: Baxter tuning seeds 3 and 4 reached 75.8 / 79.7 % held-out success at iteration 1;
#: trained with ``nearest`` and run with ``approach``, 94.5 / 92.2 %
#: (``docs/experiments/push.md``).
TRAIN_FALLBACK = {"virtual": "none", "baxter": "nearest"}

@dataclass
class FrameworkConfig:
    """Every parameter of an A2L run (defaults explained in ``docs/method.md``).

    Attributes
    ----------
    scene : str
        ``"virtual"`` (C++ kinematic push model) or ``"baxter"`` (PyBullet push scene).
    n_effects : {4, 8}
        Push effects to learn.
    n_starts : int
        Training start positions around the object, evenly spaced in angle.
    start_layout : {"circle", "ring"}
        Their distances from the object: ``"circle"`` (default) puts them all at
        ``start_radius`` (the authors' layout); ``"ring"`` spreads them over
        ``[start_r_low, start_r_high]``, the region users start a skill from (the held-out
        starts' ring), neighbouring angles at distant radii (:meth:`start_offsets`).
    start_radius : float
        Radius of the circle (m), with ``start_layout="circle"``.
    start_r_low, start_r_high : float
        Range of the ring's radii (m), with ``start_layout="ring"``.
    max_babble_steps : int
        Most random movements of a babbling trajectory.
    try_cap : int
        Most babbling trajectories tried in one acquisition.
    max_iterations : int
        Iteration cap (iteration 0 included).
    step_cap : int
        Most movements a skill may take in validation.
    planar : bool
        8 planar movements instead of 26 in 3-D.
    step : float
        Movement length (m).
    n_orient, n_dist, n_incl : int
        Bins of the context variables (``n_incl = 0`` leaves inclination out).
    dist_low, dist_high : float
        Range of the distance bins (m).
    n_offset : int
        Bins of each planar offset of the end-effector from the object (``offset_x``,
        ``offset_y``: :meth:`a2l.skills.bins.OffsetBins.strip`); 0 leaves them out, else odd.
        With 3, each tells whether the end-effector is in front of the box's faces across
        that axis (``|dx| < offset_half_x``) or beside them: the distance and orientation
        cells near the box alias the two (``docs/framework.md``).
    offset_half_x, offset_half_y : float
        Half-width of an offset bin (m): the box's half-size plus the end-effector's radius
        along that axis (the virtual box: 0.035 + 0.01, 0.0425 + 0.01).
    effect_threshold : float
        Smallest object displacement that counts as an effect (m).
    structure : str
        ``"hc-k2"`` (default: hill-climbing + K2; it drops ``distance`` while the
        dataset is small, ``docs/framework.md``, "The aliasing cell") or ``"hand-coded"``
        (the baseline: every context variable a parent of ``move`` from iteration 0).
    effect_parent : bool
        With ``hc-k2``, fix the edge ``effect -> move`` (the action generator is queried with
        the wanted effect; without the edge, small datasets give a skill that ignores it).
        Hill-climbing still chooses every other parent.
    fixed_parents : tuple of str
        With ``hc-k2``, context variables also fixed as parents of ``move``, like the effect
        (default ``("distance",)``, since issue 14: hill-climbing + K2 drops ``distance`` while
        the dataset is small, and the orientation wedges around the object then alias,
        ``docs/framework.md``; ``docs/experiments/push.md`` is measured with it). Hill-climbing
        still chooses every other parent; ``()`` leaves ``distance`` to it too.
    extension_cut : int
        Most steps cut from the end of a trajectory before extending it (each extension
        cuts 1 to ``extension_cut`` steps, drawn at random).
    erase_loops : bool
        Cut the loops out of babbling trajectories (:func:`erase_loops`).
    fallback : {"none", "nearest", "approach"} or None
        The C++ step's answer in a context cell the training never reached (a uniform row of
        the table): ``"none"`` stops with ``unknown_context``; ``"nearest"`` takes the
        movement of the nearest cell with data, same effect, never one past the distance
        range nor into its first bin; ``"approach"`` heads for that cell instead (the
        movement within the same limits that ends nearest its centre), and no step of a run
        undoes its previous movement when another is allowed; the trace marks a fallback
        step. It is the rule of the exported skill and of the held-out starts. None: the
        scene's default (:data:`FALLBACK`: ``"approach"`` on Baxter, ``"none"`` on the
        virtual scene).
    train_fallback : {"none", "nearest", "approach"} or None
        The rule of the skill the training validation runs (its failures direct the
        extension; a rule that rescues a cell without data hides it from the extension).
        None: the scene's default (:data:`TRAIN_FALLBACK`: ``"nearest"`` on Baxter,
        ``"none"`` on the virtual scene).
    smoothing : bool
        Neighbour smoothing (``docs/method.md``) in the C++ step (default on: with
        hill-climbing + K2, 27 of virtual seeds 0-29 reach 100 within 3 iterations, 21
        without it; with the hand-coded structure 30 and 23; ``docs/framework.md``).
    keep_validation : bool
        Add the validation trajectories that moved the object to the next dataset (they
        are interactions too, labelled with the effect they produced).
    max_extensions : int
        Most extension trajectories added per iteration.
    stuck_after : int
        Iterations a (start, effect) pair must fail before effect-directed babbling.
    directed_per_pair : int
        Effect-directed trajectories added for a stuck pair.
    directed_try_cap : int or None
        Most tries to find them; None: the scene's default (:data:`DIRECTED_TRY_CAP`: a
        Baxter movement costs ~20-30 ms of physics, a virtual one ~20 µs).
    directed_steps : int
        Most movements of an effect-directed trajectory (going around the object takes
        more than ``max_babble_steps``).
    directed_growth : int
        Most times the effect-directed budget of a pair grows while it stays stuck
        (1: a fixed budget).
    directed_mode : str
        How effect-directed trajectories move: ``"waypoints"`` (random via-points around
        the object, then a random point on it, :func:`directed_task`) or ``"random"``
        (uniformly random movements, like acquisition).
    waypoints_max : int
        Most via-points of a waypoint trajectory (0 to this many, uniformly).
    waypoint_aim : float
        The last point of a waypoint trajectory is drawn within ± this of the object's
        start position on each table axis (m).
    heldout_starts : int
        Held-out start positions (0: no held-out evaluation): every iteration's skill is
        also run for each effect from each of them, positions no phase of training starts
        from (:meth:`heldout_offsets`); they only measure, nothing is learnt from them.
    heldout_r_low, heldout_r_high : float
        Range of their distance from the object (m); their angle is uniform.
    seed : int
        Seed of every random draw.
    context_source : {"perceived", "ground_truth"}
        Where every rollout (babbling, extension, validation, held-out) reads the object's
        position: the scene's camera (``"perceived"``, the default: OpenCV segmentation of
        the rendered frames, one frame per movement) or the simulator's truth. The virtual
        scene has no camera: both read its true state. A ``source`` (or ``context_source``)
        key of ``scene_config`` overrides it.
    scene_config : dict
        Extra keyword arguments for :func:`a2l.sim.make_scene`.
    """

    scene: str = "virtual"
    n_effects: int = 4
    n_starts: int = 8
    start_layout: str = "circle"
    start_radius: float = 0.2
    start_r_low: float = 0.10
    start_r_high: float = 0.25
    max_babble_steps: int = 7
    try_cap: int = 5000
    max_iterations: int = 10
    step_cap: int = 12
    planar: bool = True
    step: float = 0.05
    n_orient: int = 16
    n_dist: int = 3
    n_incl: int = 0
    dist_low: float = 0.05
    dist_high: float = 0.20
    n_offset: int = 0
    offset_half_x: float = 0.045
    offset_half_y: float = 0.0525
    effect_threshold: float = 0.01
    structure: str = "hc-k2"
    effect_parent: bool = True
    fixed_parents: tuple[str, ...] = ("distance",)
    extension_cut: int = 3
    keep_validation: bool = True
    smoothing: bool = True
    fallback: str | None = None
    train_fallback: str | None = None
    erase_loops: bool = False
    max_extensions: int = 50
    stuck_after: int = 1
    directed_per_pair: int = 40
    directed_try_cap: int | None = None
    directed_steps: int = 20
    directed_growth: int = 5
    directed_mode: str = "waypoints"
    waypoints_max: int = 2
    waypoint_aim: float = 0.04
    heldout_starts: int = 32
    heldout_r_low: float = 0.10
    heldout_r_high: float = 0.25
    seed: int = 0
    context_source: str = "perceived"
    scene_config: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.directed_try_cap is None:
            self.directed_try_cap = DIRECTED_TRY_CAP.get(self.scene, 2000)
        if self.fallback is None:
            self.fallback = FALLBACK.get(self.scene, "none")
        if self.train_fallback is None:
            self.train_fallback = TRAIN_FALLBACK.get(self.scene, "none")
        if isinstance(self.fixed_parents, list):  # from JSON (config.json, --set)
            self.fixed_parents = tuple(self.fixed_parents)

    def validate(self) -> None:
        """Raise :class:`a2l.errors.ConfigError` (a ValueError) naming the first field out of
        its domain, variable names in ``fixed_parents`` included."""
        if self.scene not in ("virtual", "baxter"):
            raise ConfigError("scene", f"unknown scene {self.scene!r}; choose 'virtual' or "
                              "'baxter'")
        if self.n_effects not in (4, 8):
            raise ConfigError("n_effects", f"must be 4 or 8, got {self.n_effects}")
        positive_ints = ("n_starts", "max_babble_steps", "try_cap", "max_iterations",
                         "step_cap", "n_orient", "n_dist", "max_extensions",
                         "directed_per_pair", "directed_try_cap", "directed_steps", "stuck_after",
                         "directed_growth")
        for name in positive_ints:
            v = getattr(self, name)
            if not isinstance(v, int) or v < 1:
                raise ConfigError(name, f"must be a positive integer, got {v!r}")
        for name in ("start_radius", "start_r_low", "start_r_high", "step", "effect_threshold",
                     "waypoint_aim", "heldout_r_low", "heldout_r_high",
                     "offset_half_x", "offset_half_y"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise ConfigError(name, f"must be a positive length, got {v!r}")
        if not 0 < self.dist_low < self.dist_high:
            raise ConfigError("dist_low, dist_high", f"need 0 < low < high, got "
                             f"{self.dist_low}, {self.dist_high}")
        if not isinstance(self.n_offset, int) or self.n_offset < 0 or (
                self.n_offset and self.n_offset % 2 == 0):
            raise ConfigError("n_offset", f"must be 0 or an odd positive integer, got "
                             f"{self.n_offset!r}")
        if self.start_layout not in ("ring", "circle"):
            raise ConfigError("start_layout", f"unknown {self.start_layout!r}; choose 'ring' "
                              "or 'circle'")
        if self.start_r_low > self.start_r_high:
            raise ConfigError("start_r_low, start_r_high", f"need low <= high, got "
                             f"{self.start_r_low}, {self.start_r_high}")
        for name in ("fallback", "train_fallback"):
            if getattr(self, name) not in FALLBACK_RULES:
                raise ConfigError(name, f"unknown {getattr(self, name)!r}; choose "
                                  "'approach', 'nearest' or 'none'")
        if self.n_incl < 0:
            raise ConfigError("n_incl", f"must be >= 0, got {self.n_incl}")
        if self.extension_cut < 1:
            raise ConfigError("extension_cut", f"must be >= 1, got {self.extension_cut}")
        if self.structure not in ("hc-k2", "hand-coded"):
            raise ConfigError("structure", f"unknown {self.structure!r}")
        if not isinstance(self.fixed_parents, tuple | list) or not all(
                isinstance(v, str) for v in self.fixed_parents):
            raise ConfigError("fixed_parents", f"must be a list of variable names, got "
                             f"{self.fixed_parents!r}")
        if self.directed_mode not in ("waypoints", "random"):
            raise ConfigError("directed_mode", f"unknown {self.directed_mode!r}; choose "
                             "'waypoints' or 'random'")
        if not isinstance(self.waypoints_max, int) or self.waypoints_max < 0:
            raise ConfigError("waypoints_max", f"must be an integer >= 0, got "
                             f"{self.waypoints_max!r}")

        if not isinstance(self.heldout_starts, int) or self.heldout_starts < 0:
            raise ConfigError("heldout_starts", f"must be an integer >= 0, got "
                             f"{self.heldout_starts!r}")
        if self.heldout_r_low > self.heldout_r_high:
            raise ConfigError("heldout_r_low, heldout_r_high", f"need low <= high, got "
                             f"{self.heldout_r_low}, {self.heldout_r_high}")
        if not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigError("seed", f"must be an integer >= 0, got {self.seed!r}")
        if self.context_source not in ("perceived", "ground_truth"):
            raise ConfigError("context_source", f"must be 'perceived' (the camera) or "
                              f"'ground_truth', got {self.context_source!r}")
        names = self.discretization.context_names()
        unknown = [v for v in self.fixed_parents if v not in names]
        if unknown:
            raise ConfigError("fixed_parents", f"{unknown} not context variables; they are "
                             f"{names}")

    @property
    def discretization(self) -> DiscretizationConfig:
        """The discretization fields, as the configuration the LfD skills use too."""
        return DiscretizationConfig(
            n_effects=self.n_effects, effect_threshold=self.effect_threshold,
            planar=self.planar, step=self.step, n_orient=self.n_orient, n_dist=self.n_dist,
            n_incl=self.n_incl, dist_low=self.dist_low, dist_high=self.dist_high,
            n_offset=self.n_offset, offset_half_x=self.offset_half_x,
            offset_half_y=self.offset_half_y)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> FrameworkConfig:
        """Build from a dict (e.g. a run's ``config.json``); unknown keys are errors."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(d) - known)
        if unknown:
            raise ValueError(f"unknown config key(s) {unknown}; known: {sorted(known)}")
        cfg = cls(**d)
        cfg.validate()
        return cfg

    def start_offsets(self) -> np.ndarray:
        """End-effector training start positions relative to the object, shape (n_starts, 3).

        Start ``i`` is at angle ``2πi / n_starts``; its distance is ``start_radius``
        (``start_layout="circle"``) or, on the ring, ``start_r_low + (start_r_high - start_r_low)
        · k / (n_starts - 1)`` with ``k`` the bit-reversed rank of ``i`` (0, 4, 2, 6, 1, 5,
        3, 7 for 8 starts): every radius from the inner to the outer edge once, neighbouring
        angles far apart in radius. A fixed layout, independent of the held-out starts'
        random draw (:meth:`heldout_offsets`).
        """
        n = self.n_starts
        a = 2 * np.pi * np.arange(n) / n
        if self.start_layout == "circle" or n == 1:
            r = np.full(n, self.start_radius)
        else:
            r = self.start_r_low + (self.start_r_high - self.start_r_low) * \
                spread_ranks(n) / (n - 1)
        return np.stack([r * np.cos(a), r * np.sin(a), np.zeros_like(a)], axis=1)

    def outer_start_radius(self) -> float:
        """The largest distance of a training start from the object (m)."""
        return self.start_radius if self.start_layout == "circle" else self.start_r_high

    def heldout_offsets(self) -> np.ndarray:
        """Held-out end-effector start positions relative to the object, shape
        (heldout_starts, 3): uniform angle, distance uniform in ``[heldout_r_low,
        heldout_r_high]``, drawn from their own stream
        (:func:`a2l.framework.starts.heldout_offsets`)."""
        return heldout_offsets(self.seed, self.heldout_starts, self.heldout_r_low,
                               self.heldout_r_high)

    def heldout_redraw(self, start: int, attempt: int) -> np.ndarray:
        """Replacement `attempt` (1, 2, ...) for held-out start `start` when the arm cannot
        reach it, shape (3,) (:func:`a2l.framework.starts.heldout_redraw`)."""
        return heldout_redraw(self.seed, start, attempt, self.heldout_r_low,
                              self.heldout_r_high)


#: The last config dict :func:`task_config` built a config from, and that config.
_TASK_CONFIG: tuple[Any, Any] = (None, None)


def task_config(cfg: FrameworkConfig | dict[str, Any]) -> FrameworkConfig:
    """The :class:`FrameworkConfig` of a rollout task, which carries it as a dict.

    The tasks of one batch share one dict object (pickled once per batch, and the same
    object after unpickling): the config is built once for it, not once per task. The
    cache holds that one dict, compared by identity; a config passed as such is returned.
    """
    global _TASK_CONFIG
    if isinstance(cfg, FrameworkConfig):
        return cfg
    last, built = _TASK_CONFIG
    if cfg is last:
        return built
    built = FrameworkConfig(**cfg)
    _TASK_CONFIG = (cfg, built)
    return built


def discretizers(cfg: FrameworkConfig) -> Discretizer:
    """The discretization of `cfg` (:attr:`FrameworkConfig.discretization`'s discretizer,
    built once per set of its parameters: rollouts call this for every task)."""
    return cfg.discretization.discretizer()
