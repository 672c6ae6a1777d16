"""The one per-thread scene cache: a scene is built once per thread and reused by the
rollouts that run there (:func:`thread_scene`).

A Dask worker runs tasks in several threads, and two rollouts must never share a scene;
building a PyBullet scene takes long, so each thread keeps its own. A thread keeps one
scene per slot (the framework's env, the babbling world...): asking for another key in a
slot closes the one it held.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Hashable
from typing import Protocol, TypeVar

__all__ = ["thread_scene"]


class _Closable(Protocol):
    def close(self) -> None: ...


S = TypeVar("S", bound=_Closable)

_LOCAL = threading.local()


def thread_scene(slot: str, key: Hashable, build: Callable[[], S]) -> S:
    """The scene of this thread in `slot` for `key`, built by ``build()`` the first time.

    Parameters
    ----------
    slot : str
        Which of the thread's scenes (one per slot).
    key : hashable
        What the scene was built from; another key closes the slot's scene and builds anew.
    build : callable ``() -> scene``
        Builds the scene (anything with ``close()``).
    """
    cache: dict[Hashable, S] = _LOCAL.__dict__.setdefault(slot, {})
    scene = cache.get(key)
    if scene is None:
        for old in cache.values():
            old.close()
        cache.clear()
        scene = cache[key] = build()
    return scene
