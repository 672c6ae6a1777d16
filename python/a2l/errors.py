"""Exceptions raised by a2l (the C++ core raises these through :mod:`a2l._core`)."""

from __future__ import annotations

__all__ = [
    "A2LError",
    "A2LFileNotFoundError",
    "A2LValueError",
    "BundleError",
    "ConfigError",
    "IKError",
    "RobotEntryError",
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


class RobotEntryError(A2LValueError):
    """A robot entry (a robot file, or a built-in robot) is wrong: a missing or unknown key,
    a link or joint the URDF does not have, a value of the wrong size or not finite.

    Parameters
    ----------
    source : str
        What holds the entry: ``robot file '/path/arm.yaml'``, ``robot 'panda'``.
    key : str
        The key at fault (``base_link``, ``gripper.joints``, ``mount.xyz``...); empty when the
        fault is the file's as a whole (not YAML, not a mapping).
    message : str
        What is wrong with it (valid keys, links or joints included).
    """

    def __init__(self, source: str, key: str, message: str) -> None:
        super().__init__(f"{source}: {key}: {message}" if key else f"{source}: {message}")
        self.source = source
        self.key = key
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
