"""Named configurations of an A2L run (:data:`PRESETS`): ``FrameworkConfig.preset(name)`` in
Python, ``--preset NAME`` on the command line."""

from __future__ import annotations

from typing import Any

__all__ = ["PRESETS"]

#: Named configurations (``FrameworkConfig.preset(name)``, ``--preset NAME``), each the
#: fields it pins by their dotted names. ``thesis``: the thesis' loop and representation, the
#: baseline of every push table (the loop validates, accepts, extends and stops on 8
#: training starts on a 0.2 m circle; planar 5 cm movements; 16 orientation x 3 distance
#: equal bins over [0.05, 0.20] m; a step cap of 12; neither the clearance nor the revisit
#: rule); what the thesis left open keeps the package's choices (structure constraints,
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
