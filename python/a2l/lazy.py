"""Names re-exported by a package and imported from their module on first use (PEP 562).

A worker process that needs one module of a package then does not import the others
(pgmpy, scikit-learn, OpenCV: seconds per process).

Example, in a package's ``__init__.py``::

    __getattr__, __dir__ = lazy_exports(__name__, {"Discretizer": "a2l.skills.discretizer"})
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any


def lazy_exports(
    package: str, homes: Mapping[str, str | tuple[str, str]]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of a package with lazy names.

    Parameters
    ----------
    package : str
        The package's ``__name__`` (named in the AttributeError of an unknown name).
    homes : mapping of str to str or (str, str)
        Each exported name to the module that defines it, or to ``(module, attribute)``
        when the attribute is called otherwise there.

    Returns
    -------
    getattr, dir : callables
        To assign to the package's ``__getattr__`` and ``__dir__``: the first imports the
        name's module on first use and caches the value in the package's namespace.
    """
    namespace = importlib.import_module(package).__dict__

    def __getattr__(name: str) -> Any:
        home = homes.get(name)
        if home is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module, attr = home if isinstance(home, tuple) else (home, name)
        value = getattr(importlib.import_module(module), attr)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(homes))

    return __getattr__, __dir__
