""":class:`CppSkillRunner` runs a skill bundle through the C++ step of :mod:`a2l._core` (the
same step ``a2l-run`` executes): there is no Python implementation of a step.
"""

from __future__ import annotations

import os
import threading
from typing import ClassVar

import numpy as np

from a2l import _core

__all__ = ["CppSkillRunner"]


class CppSkillRunner:
    """A skill bundle run step by step through the C++ runtime.

    Parameters
    ----------
    bundle : str
        Path of the skill bundle.
    """

    #: Runners per thread (a runner's SkillState is mutable: a Dask worker runs tasks in
    #: several threads), keyed by the bundle's path, size and modification time.
    _local: ClassVar[threading.local] = threading.local()

    def __init__(self, bundle: str) -> None:
        self.bundle = bundle
        self.skill = _core.load_bundle(bundle)
        self.state = _core.SkillState(self.skill)
        self.labels = list(self.skill.movements.labels)

    @classmethod
    def cached(cls, bundle: str) -> CppSkillRunner:
        """One runner per bundle per thread (loading validates the whole file).

        A file rewritten at the same path (a new run in the same directory, on a long-lived
        Dask worker) is loaded again.
        """
        cache: dict[tuple[str, int, int], CppSkillRunner] = \
            cls._local.__dict__.setdefault("runners", {})
        st = os.stat(bundle)
        key = (bundle, st.st_size, st.st_mtime_ns)
        runner = cache.get(key)
        if runner is None:
            if len(cache) > 8:
                cache.clear()
            runner = cache[key] = cls(bundle)
        return runner

    def reset(self) -> None:
        """Start a new run."""
        self.state.reset()

    def step_with_probability(self, eef: np.ndarray, obj: np.ndarray, effect: int
                              ) -> tuple[int | None, str, float]:
        """One C++ step.

        Returns
        -------
        (movement or None, status name, probability)
            None with the stop status (``step_cap``, ``unknown_context``...).
        """
        ctx = self.skill.context(np.asarray(eef, float), np.asarray(obj, float), int(effect))
        out = _core.step(self.skill, self.state, ctx)
        if out.status != _core.Status.ok:
            return None, _core.status_name(out.status), 0.0
        return int(out.movement), "ok", float(out.probability)

    def step(self, eef: np.ndarray, obj: np.ndarray, effect: int) -> tuple[int | None, str]:
        """One C++ step: (movement index or None, status name)."""
        move, status, _ = self.step_with_probability(eef, obj, effect)
        return move, status
