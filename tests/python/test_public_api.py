"""The public surface: ``from a2l import ...`` gives a user script's entry points, loaded on
first use, and the API reference (``docs/api``) has a page for every part of the package.

``import a2l`` loads only the C++ core (and a2l's errors and lazy names): a worker process
or a tool that needs one name does not pay for pgmpy, PyBullet, OpenCV or pandas.
"""

from __future__ import annotations

import ast
import importlib
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import pytest

import a2l

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "python" / "a2l"
DOCS = ROOT / "docs" / "api"

#: Modules that take seconds to import, which ``import a2l`` must not load.
HEAVY = ("pgmpy", "pybullet", "pandas", "cv2", "sklearn", "scipy", "dask", "matplotlib",
         "jsonargparse", "pyarrow", "rerun", "rclpy")


@pytest.mark.parametrize("name", a2l.__all__)
def test_every_exported_name_resolves(name: str) -> None:
    """Each name of ``a2l.__all__`` is an attribute, and a lazy one is its home's object."""
    value = getattr(a2l, name)
    assert value is not None
    home = a2l._EXPORTS.get(name)
    if home is not None:
        assert value is getattr(importlib.import_module(home), name)
    assert name in dir(a2l)


def test_the_entry_points_are_exported() -> None:
    """What a user script needs, from learning a skill to running it and the framework."""
    wanted = {"learn_bundle", "learn_skill", "load_demonstrations", "load_bundle",
              "save_bundle", "run_skill", "CppSkillRunner", "run_framework",
              "FrameworkConfig", "DiscretizationConfig", "Executor", "make_scene",
              "Kinematics", "Status", "A2LError"}
    assert wanted <= set(a2l.__all__)
    assert len(a2l.__all__) == len(set(a2l.__all__))
    assert set(a2l._EXPORTS) <= set(a2l.__all__)


def test_an_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="'a2l' has no attribute 'learn_bundles'"):
        _ = a2l.learn_bundles


def test_the_docstring_names_every_export() -> None:
    """``help(a2l)`` starts with the guide: every exported name appears in it."""
    doc = a2l.__doc__ or ""
    missing = [n for n in a2l.__all__ if n != "__version__"
               and not re.search(rf"\b{re.escape(n)}\b", doc)]
    assert not missing, f"names of a2l.__all__ the module docstring does not name: {missing}"


def test_import_a2l_loads_no_heavy_module() -> None:
    """In a fresh interpreter, ``import a2l`` loads none of :data:`HEAVY` and no module of
    a2l beyond the core, the errors and the lazy names; a first use loads its module."""
    code = ("import sys, a2l; print(sorted(m for m in sys.modules if m.split('.')[0] in "
            f"{HEAVY!r})); print(sorted(m for m in sys.modules if m.startswith('a2l.')))\n"
            "a2l.learn_bundle; print('pgmpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, check=True).stdout.splitlines()
    assert out[0] == "[]", f"import a2l loads heavy modules: {out[0]}"
    assert out[1] == "['a2l._core', 'a2l.errors', 'a2l.lazy']", out[1]
    assert out[2] == "True"  # the check above could fail: the first use imports pgmpy


def test_the_package_imports_only_eager_names_from_the_top() -> None:
    """A module of the package takes from ``a2l`` itself only what ``__init__`` imports
    (the core, the errors) or a submodule, never a lazy name: that may come from a layer
    above, which import-linter would not see."""
    lazy = set(a2l._EXPORTS)
    assert "learn_bundle" in lazy and "Kinematics" not in lazy
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if path == PACKAGE / "__init__.py":
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            names: list[str] = []
            if isinstance(node, ast.ImportFrom) and node.module == "a2l" and node.level == 0:
                names = [alias.name for alias in node.names]
            elif (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                  and node.value.id == "a2l"):
                names = [node.attr]
            offenders += [f"{path.relative_to(ROOT)}:{node.lineno}: a2l.{n}"
                          for n in names if n in lazy]
    assert not offenders, "lazy top-level names used inside the package:\n" + \
        "\n".join(offenders)


def test_the_reference_has_a_page_per_subpackage() -> None:
    """``docs/api`` documents every public subpackage on a page of its own, each page is in
    the index, and the top-level names have theirs (``make docs`` builds them)."""
    subpackages = sorted(m.name for m in pkgutil.iter_modules([str(PACKAGE)])
                         if m.ispkg and not m.name.startswith("_"))
    index = (DOCS / "index.rst").read_text()
    toctree = set(re.findall(r"^   (\w+)$", index, flags=re.MULTILINE))
    for name in subpackages:
        page = DOCS / f"{name}.rst"
        assert page.is_file(), f"no page docs/api/{name}.rst for a2l.{name}"
        assert f".. a2l-modules:: a2l.{name}" in page.read_text()
    assert toctree == {*subpackages, "a2l", "foundation"}
    assert ".. automodule:: a2l\n" in (DOCS / "a2l.rst").read_text()
