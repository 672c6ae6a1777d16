"""Running an a2l ROS 2 node: rclpy's set-up (remaps, namespace, localhost-only discovery by
default), spinning until the node is done, SIGINT and SIGTERM as a clean stop."""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import fields
from typing import Any

from a2l.errors import A2LValueError

__all__ = ["declare_config", "overrides", "ros_args", "ros_session", "spin_until"]

#: Set by SIGINT/SIGTERM inside :func:`ros_session`; :func:`spin_until` stops on it. A flag,
#: not an exception: an exception raised by the handler lands in whatever runs at that
#: instant, e.g. inside rclpy's C++ message conversion, where pybind11 turns it into a
#: ``RuntimeError`` that ends the process with the wrong exit code.
_STOP = threading.Event()


def ros_args(remap: Sequence[str] = (), namespace: str | None = None) -> list[str]:
    """rclpy's command-line arguments for topic remaps (``from:=to``) and a namespace.

    Raises
    ------
    a2l.A2LValueError
        A remap that is not ``from:=to``.
    """
    out = ["--ros-args"]
    for r in remap:
        a, sep, b = r.partition(":=")
        if not sep or not a or not b:
            raise A2LValueError(f"remap {r!r}: write it as from:=to (joint_states:=/robot/js)")
        out += ["-r", r]
    if namespace:
        out += ["-r", f"__ns:={namespace if namespace.startswith('/') else '/' + namespace}"]
    return out


@contextmanager
def ros_session(args: Sequence[str] = ()) -> Iterator[None]:
    """rclpy initialised with `args` (discovery stays on this machine unless the environment
    says otherwise: ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``), shut down on exit. SIGINT
    and SIGTERM set a stop flag that :func:`spin_until` obeys."""
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")

    def interrupt(signum: int, frame: Any) -> None:
        _STOP.set()

    # SIGINT too: a process started in the background by a shell inherits it ignored
    _STOP.clear()
    old = {s: signal.signal(s, interrupt) for s in (signal.SIGINT, signal.SIGTERM)}
    rclpy.init(args=list(args) or None, signal_handler_options=SignalHandlerOptions.NO)
    try:
        yield
    finally:
        rclpy.try_shutdown()
        for s, handler in old.items():
            signal.signal(s, handler)


def overrides(values: dict[str, Any]) -> list[Any]:
    """`values` as rclpy parameter overrides (a node's ``parameter_overrides``)."""
    from rclpy.parameter import Parameter

    return [Parameter(k, value=v) for k, v in values.items()]


def declare_config(node: Any, cls: type) -> Any:
    """Declare every field of the dataclass `cls` as a ROS parameter of `node` (its
    default, overridden by the node's parameter overrides) and return their values as a
    `cls`."""
    for f in fields(cls):
        node.declare_parameter(f.name, f.default)
    return cls(**{f.name: node.get_parameter(f.name).value for f in fields(cls)})


def spin_until(node: Any, done: Callable[[], bool], period: float = 0.02,
               interruptible: bool = True) -> bool:
    """Spin `node` until ``done()``; False if interrupted (SIGINT, SIGTERM, or rclpy shut
    down from outside). With ``interruptible=False`` a signal already received does not
    stop it (a short linger after the stop, so the final messages go out)."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    try:
        while rclpy.ok() and not done():
            if interruptible and _STOP.is_set():
                return False
            rclpy.spin_once(node, timeout_sec=period)
    except (KeyboardInterrupt, ExternalShutdownException):
        return False
    return rclpy.ok() and not (interruptible and _STOP.is_set())
