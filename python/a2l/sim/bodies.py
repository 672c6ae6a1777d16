"""Scene bodies kept as cached descriptions, so that every episode starts from new ones.

PyBullet keeps, between steps, contact manifolds whose accumulated impulses warm-start the
next solve, and an overlapping-pair cache whose order depends on the history of the world.
``restoreState`` restores positions and velocities but not those caches, so the same
movements from the same restored start could end up to a centimetre apart after different
earlier episodes. Removing a body drops every manifold and pair it is part of; recreating
it from its description (the same collision and visual shapes, created once) gives it the
same body id (PyBullet reuses freed ids last-in first-out) and the same place in the world.
With the overlapping pairs sorted (``deterministicOverlappingPairs``), a rollout then
depends only on its start. A reset that rebuilds the push scene's floor, table and box costs
well under a millisecond, where a new world (a new client, or ``resetSimulation``, and Baxter
loaded again) costs about 0.2 s (``BENCHMARKS.md``, simulation).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from a2l.sim._pybullet import p

__all__ = ["BodyCache"]


@dataclass
class _Recipe:
    key: str
    create: dict[str, Any]  # keyword arguments of createMultiBody (shape ids included)
    dynamics: list[tuple[int, dict[str, Any]]] = field(default_factory=list)


class BodyCache:
    """The bodies of a scene that :meth:`rebuild` removes and creates again.

    Parameters
    ----------
    client : int
        PyBullet physics client.
    """

    def __init__(self, client: int) -> None:
        self._client = client
        self._recipes: list[_Recipe] = []
        #: Body id of each description, by key.
        self.ids: dict[str, int] = {}

    def add(self, key: str, dynamics: list[tuple[int, dict[str, Any]]] | None = None,
            **create: Any) -> int:
        """Create a body and remember how.

        Parameters
        ----------
        key : str
            Name of the body (unique in the cache).
        dynamics : list of (link, dict), optional
            ``changeDynamics`` keyword arguments per link (-1: the base), applied after
            each creation.
        **create
            Keyword arguments of ``p.createMultiBody`` (shapes already created).

        Returns
        -------
        int
            The body id.
        """
        if key in self.ids:
            raise ValueError(f"body '{key}' is already in the cache")
        recipe = _Recipe(key, dict(create), list(dynamics or []))
        self._recipes.append(recipe)
        self.ids[key] = self._create(recipe)
        return self.ids[key]

    def _create(self, recipe: _Recipe) -> int:
        c = self._client
        body = p.createMultiBody(**recipe.create, physicsClientId=c)
        for link, kwargs in recipe.dynamics:
            p.changeDynamics(body, link, **kwargs, physicsClientId=c)
        return int(body)

    def rebuild(self) -> dict[str, int]:
        """Remove every cached body (last created first) and create them again, in order,
        as described (at their described pose, at rest).

        Returns
        -------
        dict of str to int
            The new body ids by key (the same ids as before: PyBullet reuses them).
        """
        c = self._client
        for recipe in reversed(self._recipes):
            p.removeBody(self.ids[recipe.key], physicsClientId=c)
        for recipe in self._recipes:
            self.ids[recipe.key] = self._create(recipe)
        return dict(self.ids)
