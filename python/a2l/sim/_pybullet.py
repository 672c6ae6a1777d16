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
    """Silence PyBullet's C-level output (build banner, URDF importer warnings) on the
    process's stdout and stderr file descriptors."""
    fds = []
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
            fds.append(stream.fileno())
        except (AttributeError, OSError, ValueError):
            pass
    saved = [os.dup(fd) for fd in fds]
    try:
        with open(os.devnull, "w") as null:
            for fd in fds:
                os.dup2(null.fileno(), fd)
            yield
    finally:
        with contextlib.suppress(Exception):
            ctypes.CDLL(None).fflush(None)  # C stdio buffers go to /dev/null too
        for fd, s in zip(fds, saved, strict=True):
            os.dup2(s, fd)
            os.close(s)


with quiet():
    import pybullet as p
