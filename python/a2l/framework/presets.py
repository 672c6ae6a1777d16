"""Named configurations of an A2L run (:data:`PRESETS`): ``FrameworkConfig.preset(name)`` in
Python, ``--preset NAME`` on the command line."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

__all__ = ["PRESETS", "preset_of"]

#: Named configurations (``FrameworkConfig.preset(name)``, ``--preset NAME``), each the
#: fields it pins by their dotted names. ``thesis``: the thesis' loop and representation, the
#: baseline of every push table (the loop validates, accepts, extends and stops on 8
#: training starts on a 0.2 m circle; planar 5 cm movements; 16 orientation x 3 distance
#: equal bins over [0.05, 0.20] m; a step cap of 12; none of the clearance, alignment and
#: revisit rules); what the thesis left open keeps the package's choices (structure constraints,
#: smoothing, fallbacks, effect-directed babbling), as the push tables up to this preset
#: measured them.
PRESETS: dict[str, dict[str, Any]] = {
    "thesis": {
        "validation.starts": "fixed", "starts.n_starts": 8, "starts.layout": "circle",
        "starts.radius": 0.2, "discretization.planar": True, "discretization.step": 0.05,
        "discretization.n_orient": 16, "discretization.n_dist": 3,
        "discretization.dist_low": 0.05, "discretization.dist_high": 0.20,
        "discretization.dist_edges": (), "discretization.n_incl": 0,
        "discretization.n_offset": 0, "skill.step_cap": 12, "skill.train_step_cap": 12,
        "skill.clearance": 0.0, "skill.align": 0.0, "skill.avoid_revisits": False,
    },
}


def preset_of(config: Mapping[str, Any]) -> str | None:
    """The name of the first preset (:data:`PRESETS`) whose every field `config` (a
    configuration's ``to_dict()``, as a run's ``config.json`` holds it) has, or None: how a
    table tells a baseline run from a run of the defaults, however it was configured."""
    def value(path: str) -> Any:
        part, _, name = path.partition(".")
        got = config.get(part, {}).get(name, value)  # `value` itself: missing
        return list(got) if isinstance(got, tuple) else got

    for name, fields in PRESETS.items():
        if all(value(path) == (list(v) if isinstance(v, tuple) else v)
               for path, v in fields.items()):
            return name
    return None
