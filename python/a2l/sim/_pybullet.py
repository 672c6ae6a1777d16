"""PyBullet, imported without its C-level banner on stdout, and :func:`quiet`."""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from collections.abc import Iterator

__all__ = ["p", "quiet"]


@contextlib.contextmanager
def quiet() -> Iterator[None]:
    """Silence the C-level stdout of PyBullet (build banner, URDF importer warnings)."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):
        yield
        return
    sys.stdout.flush()
    saved = os.dup(fd)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), fd)
            yield
    finally:
        with contextlib.suppress(Exception):
            ctypes.CDLL(None).fflush(None)  # C stdio buffers go to /dev/null too
        os.dup2(saved, fd)
        os.close(saved)


with quiet():
    import pybullet as p
