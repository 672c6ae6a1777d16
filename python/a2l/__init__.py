"""a2l: Adaptive Affordance Learning.

A robot learns manipulation skills by itself (babbling, Bayesian networks, demonstrations)
and runs them adapted, online, through a C++ runtime.

The C++ core is :mod:`a2l._core`; its main classes are re-exported here.
"""

from __future__ import annotations

from a2l import _core
from a2l._core import IkOptions, IkReport, Kinematics, Status
from a2l.errors import (
    A2LError,
    A2LFileNotFoundError,
    A2LValueError,
    BundleError,
    IKError,
    UnknownLinkError,
    UnreachableError,
    URDFError,
)

__version__ = _core.__version__

__all__ = [
    "A2LError",
    "A2LFileNotFoundError",
    "A2LValueError",
    "BundleError",
    "IKError",
    "IkOptions",
    "IkReport",
    "Kinematics",
    "Status",
    "URDFError",
    "UnknownLinkError",
    "UnreachableError",
    "__version__",
]
