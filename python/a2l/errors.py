"""Exceptions raised by a2l (the C++ core raises these through :mod:`a2l._core`)."""

from __future__ import annotations

__all__ = [
    "A2LError",
    "A2LFileNotFoundError",
    "A2LValueError",
    "BundleError",
    "ConfigError",
    "IKError",
    "URDFError",
    "UnknownLinkError",
    "UnreachableError",
]


class A2LError(Exception):
    """Base class of every a2l error."""


class A2LFileNotFoundError(A2LError, FileNotFoundError):
    """A file (URDF, bundle, dataset) is missing or unreadable."""


class A2LValueError(A2LError, ValueError):
    """An argument has the wrong size, NaN, or is out of its domain."""


class ConfigError(A2LValueError):
    """A configuration value or an experiment's argument out of its domain.

    Parameters
    ----------
    field : str
        The field or argument at fault (``n_effects``, ``--skills``...): the command line
        reports it as the option of that name.
    message : str
        What is wrong with it (valid values or names included).
    """

    def __init__(self, field: str, message: str) -> None:
        super().__init__(f"{field}: {message}")
        self.field = field
        self.message = message


class URDFError(A2LError, ValueError):
    """A URDF file is malformed."""


class UnknownLinkError(A2LError, ValueError):
    """A link name is not in the robot description."""


class IKError(A2LError):
    """Inverse kinematics found no solution within the joint limits."""


class BundleError(A2LError, ValueError):
    """A skill bundle is malformed, corrupted or of another schema version."""


class UnreachableError(A2LValueError):
    """A target the arm cannot reach in the asked orientation (e.g. a scene reset with the
    end-effector beyond the arm's reach with the gripper pointing down)."""
