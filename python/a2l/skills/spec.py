"""The in-memory form of a skill bundle (see ``docs/bundle_format.md``).

:class:`SkillSpec` is what :func:`a2l.skills.save_bundle` writes and
:func:`a2l.skills.load_bundle` returns; learning code builds it from a compiled policy table.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from a2l import _core

__all__ = ["ACTIONS", "BUNDLE_SCHEMA_VERSION", "RANGED_KINDS", "VARIABLE_KINDS", "SkillSpec",
           "VariableSpec"]

#: Schema version written and read by this version of a2l.
BUNDLE_SCHEMA_VERSION = 4

#: Actions a movement repertoire may hold besides its directions (``movements.actions``):
#: open and close the gripper, stay (hold still for one movement's duration).
ACTIONS = ("open", "close", "stay")

#: Kinds of evidence variables a bundle may hold.
VARIABLE_KINDS = ("effect", "distance", "orientation", "inclination", "high_level", "offset_x",
                  "offset_y")

#: Kinds whose variables have a range ``[low, high]`` (m).
RANGED_KINDS = ("distance", "offset_x", "offset_y")


@dataclass(frozen=True)
class VariableSpec:
    """One evidence variable of a compiled table (one axis of the posterior).

    Attributes
    ----------
    name : str
        Unique name (``"effect"``, ``"distance"``, ``"light"``, ...).
    kind : str
        One of :data:`VARIABLE_KINDS`.
    n_bins : int
        Number of bins (for ``effect`` and ``high_level``: number of values).
    low, high : float or None
        Range of a ``distance``, ``offset_x`` or ``offset_y`` variable (m); None otherwise.
    values : tuple of str
        Value names of an ``effect`` or ``high_level`` variable; empty otherwise.
    edges : tuple of float
        A ``distance`` variable's explicit interior bin edges (m; manifest key ``edges``),
        with ``n_bins = len(edges) + 1``; empty: ``n_bins`` equal bins over [low, high].
    """

    name: str
    kind: str
    n_bins: int
    low: float | None = None
    high: float | None = None
    values: tuple[str, ...] = ()
    edges: tuple[float, ...] = ()

    def to_json(self) -> dict[str, Any]:
        """The manifest entry of this variable."""
        d: dict[str, Any] = {"name": self.name, "kind": self.kind}
        if self.kind in ("effect", "high_level"):
            d["values"] = list(self.values)
        else:
            d["n_bins"] = int(self.n_bins)
        if self.kind in RANGED_KINDS:
            d["low"] = float(self.low)  # type: ignore[arg-type]
            d["high"] = float(self.high)  # type: ignore[arg-type]
        if self.edges:
            d["edges"] = [float(x) for x in self.edges]
        return d


@dataclass
class SkillSpec:
    """Everything a skill bundle holds.

    Attributes
    ----------
    name : str
        The skill's name (e.g. ``"push"``).
    variables : list of VariableSpec
        Evidence variables, in the axis order of `posterior`.
    directions : ndarray of int, shape (n_directions, 3)
        Movement repertoire's directions: signs in {-1, 0, 1}, not all zero.
    posterior : ndarray of float64, shape ``(*bins, n_moves)``
        P(move | evidence) for every evidence combination; n_moves = n_directions +
        len(actions), the actions last.
    argmax : ndarray of int32, shape ``(*bins,)``
        Most probable movement, or -1 where the posterior is uniform.
    step : float
        Movement length (m).
    labels : list of str
        A name per direction.
    step_cap : int
        Most movements a run may take.
    smoothing : bool
        Neighbour smoothing (``docs/method.md``).
    uniform_tolerance : float
        A row whose entries all lie within this of 1/n_moves is uniform.
    fallback : {"none", "nearest", "approach"}
        The runtime's answer in a context cell with no data (a uniform row): stop with
        ``unknown_context``, the movement of the nearest informative cell with the same
        effect and high-level values (``nearest``), or the movement heading for that cell
        (``approach``); compiled when the bundle is loaded, the trace marks the step
        (``docs/runtime.md``).
    clearance : float
        The step's clearance rule (m; 0: off): away from the side the wanted push effect
        pushes from, a movement that would end nearer the object than this gives way to a
        near-equal one that does not (``docs/runtime.md``).
    clearance_ratio : float
        The clearance rule's bar in (0, 1]: the share of the chosen movement's probability
        an alternative that keeps clearance needs (default ``_core.CLEARANCE_RATIO``, 0.5,
        the bar of bundles that write none).
    align : float
        The step's alignment rule (m; 0: off), the clearance rule's counterpart on the
        pushing side: there, a movement towards the object that would end nearer it than
        `clearance`, started more than this off the push line through the object's centre,
        gives way to the movement that does not approach and ends nearest that line
        (``docs/runtime.md``).
    avoid_revisits : bool
        The step's revisit rule: a run that comes back within half a movement of where it
        was, having left, does not repeat there a movement it chose there
        (``docs/runtime.md``).
    robot : dict or None
        ``{"name", "urdf_sha256", "base_link", "tip_link"}``, or None.
    extra : dict
        Free-form metadata kept in the manifest under ``"extra"``.
    actions : list of str
        Actions of the repertoire after the directions (names of :data:`ACTIONS`, each at
        most once): movement ``n_directions + j`` is ``actions[j]``.
    """

    name: str
    variables: list[VariableSpec]
    directions: np.ndarray
    posterior: np.ndarray
    argmax: np.ndarray
    step: float = 0.05
    labels: list[str] = field(default_factory=list)
    step_cap: int = 12
    smoothing: bool = False
    uniform_tolerance: float = 1e-9
    fallback: str = "none"
    clearance: float = 0.0
    clearance_ratio: float = _core.CLEARANCE_RATIO
    align: float = 0.0
    avoid_revisits: bool = False
    robot: dict[str, str] | None = None
    extra: dict[str, Any] = field(default_factory=dict)
    actions: list[str] = field(default_factory=list)

    @property
    def scene_settings(self) -> dict[str, Any]:
        """The scene settings the skill was learned with and is meant to run with (``extra``'s
        ``lfd.scene``, written by :func:`a2l.lfd.skill.learn_skill`: the sideways pushes'
        ``{"gripper_yaw": 90.0}``); ``{}`` when the bundle names none."""
        return dict((self.extra.get("lfd") or {}).get("scene") or {})
