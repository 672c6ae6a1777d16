"""Shared pieces of the ``a2l`` command: the usage error and the argument types."""

from __future__ import annotations

import argparse


class UsageError(Exception):
    """A bad command-line argument found after parsing (exit code 2, no traceback).

    Parameters
    ----------
    argument : str
        The argument at fault (``--resume``...).
    message : str
        What is wrong with it.
    """

    def __init__(self, argument: str, message: str) -> None:
        super().__init__(f"argument {argument}: {message}")
        self.argument = argument


def comma_list(text: str | None) -> list[str] | None:
    """Names given as ``"a, b,c"``: stripped, empty ones dropped; None when nothing was given."""
    return [x.strip() for x in text.split(",") if x.strip()] if text else None


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def nonnegative_int(text: str) -> int:
    """argparse type: an integer >= 0 (seeds)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {value}")
    return value


def framework_config(args: argparse.Namespace, options: dict[str, str]) -> object:
    """The FrameworkConfig of the given options (defaults for the others).

    Raises
    ------
    UsageError
        A value out of its domain (the message names the option).
    """
    from a2l.framework import FrameworkConfig

    given = {field: getattr(args, opt) for opt, field in options.items()
             if getattr(args, opt, None) is not None}
    cfg = FrameworkConfig(**given)
    try:
        cfg.validate()
    except ValueError as exc:
        bad = str(exc).split(":", 1)[0]
        opt = next((o for o, f in options.items() if f == bad), bad)
        raise UsageError(f"--{opt}", str(exc)) from None
    return cfg


def check_cluster(address: str | None) -> None:
    """Fail early, as a usage error, if the Dask scheduler at `address` is unreachable."""
    if address is None:
        return
    from a2l.parallel import Executor

    try:
        Executor(cluster=address).close()
    except ConnectionError as exc:  # the Executor's message names the address
        raise UsageError("--cluster", str(exc)) from None
    except (OSError, ValueError, TypeError) as exc:  # e.g. a malformed address
        raise UsageError("--cluster", f"cannot reach a Dask scheduler at {address!r}: "
                         f"{exc}") from None


