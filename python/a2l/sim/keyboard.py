"""Keyboard input of a PyBullet GUI window: key codes by name and the keys pressed."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from a2l.sim._pybullet import p
from a2l.sim.bullet.base import BulletScene

__all__ = ["KEY_CODES", "WindowClosed", "keys_pressed", "take_keyboard", "window_guard"]

#: PyBullet key codes by name.
KEY_CODES: dict[str, int] = {
    "up": p.B3G_UP_ARROW, "down": p.B3G_DOWN_ARROW, "left": p.B3G_LEFT_ARROW,
    "right": p.B3G_RIGHT_ARROW, "page_up": p.B3G_PAGE_UP, "page_down": p.B3G_PAGE_DOWN,
    "space": p.B3G_SPACE, "return": p.B3G_RETURN, "q": ord("q"), "escape": 27,
}


class WindowClosed(Exception):
    """The scene's GUI window was closed."""


def take_keyboard(scene: BulletScene) -> None:
    """Turn the GUI's own keyboard shortcuts off, so that every key reaches the caller.

    Parameters
    ----------
    scene : a2l.sim.bullet.BulletScene
        A scene opened with ``gui=True``.
    """
    p.configureDebugVisualizer(p.COV_ENABLE_KEYBOARD_SHORTCUTS, 0,
                               physicsClientId=scene.client)


def keys_pressed(scene: BulletScene) -> list[int]:
    """The keys pressed in the scene's window since the last call (key codes).

    Raises
    ------
    WindowClosed
        The window is gone.
    """
    with window_guard():
        events = p.getKeyboardEvents(physicsClientId=scene.client)
    return [key for key, state in events.items() if state & p.KEY_WAS_TRIGGERED]


@contextlib.contextmanager
def window_guard() -> Iterator[None]:
    """Turn PyBullet's error of a closed GUI window, raised inside, into :class:`WindowClosed`."""
    try:
        yield
    except p.error:
        raise WindowClosed("the PyBullet window was closed") from None
