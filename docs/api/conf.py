"""Sphinx configuration of the API reference: ``make docs`` builds it into ``build/docs``.

The pages are made from the numpydoc docstrings of the installed package (autodoc +
numpydoc). A page per subpackage lists its modules with the ``a2l-modules`` directive
defined here, so that a module added to a package appears without editing the page.
"""

from __future__ import annotations

import importlib
import pkgutil
import types

from docutils import nodes
from docutils.parsers.rst import Directive, directives
from sphinx.application import Sphinx

import a2l

project = "a2l"
author = "the a2l developers"
release = version = a2l.__version__

extensions = ["sphinx.ext.autodoc", "numpydoc"]

root_doc = "index"
exclude_patterns = ["_build"]
html_theme = "alabaster"
html_static_path: list[str] = []
html_title = f"a2l {release} API reference"

autodoc_member_order = "bysource"
autodoc_default_options = {"members": True}
# the signatures stay readable: the types are in the numpydoc Parameters sections
autodoc_typehints = "none"
# numpydoc: no autosummary tables of class members (autodoc lists the members), no
# cross-reference of every parameter type (prose types such as "str or PathLike")
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()


def public_modules(package: str, subpackages: bool = True) -> list[str]:
    """The public modules of `package` (not ``_private``, not ``__main__``), sorted: with
    those of its subpackages, or (`subpackages` false) only its own plain modules."""
    pkg = importlib.import_module(package)
    found = (pkgutil.walk_packages(pkg.__path__, f"{package}.") if subpackages
             else (m for m in pkgutil.iter_modules(pkg.__path__, f"{package}.") if not m.ispkg))
    return sorted(m.name for m in found
                  if not any(part.startswith("_") for part in m.name.split(".")))


class ModulesDirective(Directive):
    """``.. a2l-modules:: a2l.skills``: a section per public module of the package, each
    documented by ``automodule`` with its members; with ``:no-subpackages:``, only the
    package's own plain modules (those of ``a2l`` outside its subpackages)."""

    required_arguments = 1
    option_spec = {"no-subpackages": directives.flag}

    def run(self) -> list[nodes.Node]:
        lines: list[str] = []
        for name in public_modules(self.arguments[0], "no-subpackages" not in self.options):
            lines += [name, "-" * len(name), "", f".. automodule:: {name}", ""]
        source = self.state_machine.input_lines.source(
            self.lineno - self.state_machine.input_offset - 1)
        self.state_machine.insert_input(lines, source)
        return []


def alias_signature(app: Sphinx, what: str, name: str, obj: object, options: object,
                    signature: str | None, return_annotation: str | None
                    ) -> tuple[str | None, str | None] | None:
    """No signature for a module's type alias (``RGBA = tuple[float, float, float,
    float]``): a ``tuple[...]`` is callable, so numpydoc would look for one in ``tuple``'s
    docstring and fail."""
    if isinstance(obj, types.GenericAlias):
        return (None, None)
    return None


def setup(app: Sphinx) -> dict[str, bool]:
    app.add_directive("a2l-modules", ModulesDirective)
    # before numpydoc's handler (priority 500): the first answer is taken
    app.connect("autodoc-process-signature", alias_signature, priority=400)
    return {"parallel_read_safe": True}
