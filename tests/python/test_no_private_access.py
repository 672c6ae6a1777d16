"""No module of ``python/a2l`` and no script of ``examples/`` touches another module's
private members.

A private member is a name with one leading underscore (not a dunder). The test reads
every module's syntax tree and lists:

- ``obj._name`` where ``obj`` is not ``self``, ``cls`` or ``super()`` and ``_name`` is not
  defined in the same module (a module may reach the private members of its own classes);
- ``from x import _name`` (a private function, class or constant of another module);
- an import of a private module ``pkg._mod`` from outside its package ``pkg`` (inside it,
  the package's own modules share it, as the ``private_modules`` import contract says).

An example is a user's script: it is inside no package of a2l, so every private module
of the package is another's.

A justified exception goes in :data:`ALLOWED` with its reason.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "python" / "a2l"
EXAMPLES = ROOT / "examples"

#: (module path relative to python/a2l or "*", private name) -> why it is allowed.
ALLOWED: dict[tuple[str, str], str] = {
    ("*", "_core"): "a2l._core is the compiled C++ module (pybind11); its name is private "
                    "so that users import the Python API, the package's modules import it",
    ("*", "_asdict"): "public API of namedtuple",
    ("*", "_replace"): "public API of namedtuple",
    ("*", "_fields"): "public API of namedtuple",
    ("*", "_SubParsersAction"): "argparse's type of add_subparsers()' result has no public "
                                "name (typing only)",
    ("cli/parser.py", "_actions"): "argparse (and jsonargparse on it) lists a parser's "
                                   "options only in this attribute",
    ("parallel.py", "_exit"): "os._exit is the standard library's way to end a process at "
                              "once from a thread (a worker whose parent died)",
}


def _defined(tree: ast.AST) -> set[str]:
    """Private names a module defines: functions, classes, assigned names and attributes."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            names.add(node.attr)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
    return {n for n in names if _private(n)}


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _own(value: ast.expr) -> bool:
    if isinstance(value, ast.Name):
        return value.id in ("self", "cls")
    return (isinstance(value, ast.Call) and isinstance(value.func, ast.Name)
            and value.func.id == "super")


def _allowed(rel: str | None, name: str) -> bool:
    return (rel, name) in ALLOWED or ("*", name) in ALLOWED


def _module_inside(rel: str | None, dotted: list[str]) -> bool:
    """Whether ``a2l.x...`` (`dotted`) is a module of the package the file `rel` is in or
    below (a private module its own package may share); `rel` None: a file outside the
    package (an example), inside none of its packages."""
    if rel is None or not dotted or dotted[0] != "a2l":
        return False
    *package, _ = dotted
    here = ["a2l", *rel.split("/")[:-1]]
    return (PACKAGE / Path(*dotted[1:])).with_suffix(".py").exists() \
        and here[:len(package)] == package


def _private_module(rel: str | None, dotted: list[str]) -> bool:
    """Whether the module path `dotted` goes through a private module from outside its
    package (:data:`ALLOWED` names excepted)."""
    for i, part in enumerate(dotted):
        if _private(part) and not _allowed(rel, part):
            if not _module_inside(rel, dotted[: i + 1]):
                return True
    return False


def private_accesses(root: Path = PACKAGE, in_package: bool = True) -> list[str]:
    """Every access to another module's private member under `root`, as
    ``path:line: what``; `in_package` false: the files are scripts outside the package
    (``examples/``), which may import none of its private modules."""
    found: list[str] = []
    for path in sorted(root.rglob("*.py")):
        name = path.relative_to(root).as_posix()
        rel = name if in_package else None
        tree = ast.parse(path.read_text(), filename=str(path))
        own = _defined(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and _private(node.attr):
                if _own(node.value) or node.attr in own or _allowed(rel, node.attr):
                    continue
                found.append(f"{name}:{node.lineno}: {ast.unparse(node)}")
            elif isinstance(node, ast.ImportFrom):
                module = node.module or ""
                for alias in node.names:
                    if (_private_module(rel, module.split("."))
                            or _private(alias.name) and not _allowed(rel, alias.name)
                            and not _module_inside(rel, [*module.split("."), alias.name])):
                        found.append(f"{name}:{node.lineno}: from {module} import {alias.name}")
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if _private_module(rel, alias.name.split(".")):
                        found.append(f"{name}:{node.lineno}: import {alias.name}")
    return found


def test_no_module_touches_another_modules_private_members() -> None:
    found = private_accesses()
    assert not found, ("private members of other modules are used (make them public, or add "
                       "a justified entry to ALLOWED):\n" + "\n".join(found))


def test_no_example_touches_a_private_member() -> None:
    found = private_accesses(EXAMPLES, in_package=False)
    assert not found, ("examples use private members of a2l (an example uses the public "
                       "API only):\n" + "\n".join(found))


def test_the_check_sees_a_private_access(tmp_path: Path) -> None:
    (tmp_path / "a.py").write_text("def f(scene):\n    return scene._tick\n")
    (tmp_path / "b.py").write_text("from a2l.sim.scene import _PERTURB_PARAMS\n")
    (tmp_path / "c.py").write_text(
        "class A:\n    def __init__(self):\n        self._x = 1\n\n"
        "    def same(self, other):\n        return other._x + self._x\n")
    (tmp_path / "d.py").write_text("from a2l.sim._pybullet import p\n")
    (tmp_path / "sim").mkdir()
    (tmp_path / "sim" / "x.py").write_text("from a2l.sim._pybullet import p\n")
    assert private_accesses(tmp_path) == ["a.py:2: scene._tick",
                                          "b.py:1: from a2l.sim.scene import _PERTURB_PARAMS",
                                          "d.py:1: from a2l.sim._pybullet import p"]


def test_the_check_sees_an_example_import_a_private_module(tmp_path: Path) -> None:
    """A script outside the package is inside none of its packages: the private module a
    module of ``a2l.sim`` may import is another's for an example at ``sim/x.py`` too."""
    (tmp_path / "sim").mkdir()
    (tmp_path / "sim" / "x.py").write_text("from a2l.sim._pybullet import p\n")
    (tmp_path / "y.py").write_text("from a2l.framework.loop import _iteration\n"
                                   "from a2l import _core\n")
    assert private_accesses(tmp_path, in_package=False) == [
        "sim/x.py:1: from a2l.sim._pybullet import p",
        "y.py:1: from a2l.framework.loop import _iteration"]
