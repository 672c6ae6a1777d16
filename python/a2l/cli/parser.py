"""The parser class of the ``a2l`` command (jsonargparse) and the pieces every command group
shares: configuration flags generated from a dataclass, config files checked name by name,
the command path of a parse.

Every field of a configuration dataclass becomes a flag ``--field`` (``--field-name`` is
accepted too) through :meth:`jsonargparse.ArgumentParser.add_class_arguments`, which also
checks each value's type; a field that is itself a dataclass (a part of a composed
configuration) gives one flag per field of it, ``--part.field``. A list option takes
``a,b`` as well as ``[a,b]``. ``--config FILE`` (JSON or YAML; parts as nested mappings)
sets any flag of the command. A misspelt flag or config-file key is refused with the list of
valid names before any work starts; an option of an earlier version (``Parser.renamed``)
is read as its name now, with a warning.
"""

from __future__ import annotations

import dataclasses
import difflib
import inspect
import json
import re
import sys
import types
import typing
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, NoReturn

import yaml
from jsonargparse import ActionConfigFile, ArgumentParser, Namespace

__all__ = ["Parser", "add_config_fields", "add_config_option", "attribute_docs", "command_path",
           "config_from", "normalize_argv", "option_names"]


class Parser(ArgumentParser):
    """A jsonargparse parser whose error names the valid options when a flag is unknown."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("exit_on_error", True)
        super().__init__(*args, **kwargs)

    #: The options as the user spelt them, by their canonical spelling (set by
    #: :func:`normalize_argv`): messages name an option the way it was given.
    spelled: dict[str, str] = {}

    #: Earlier spellings of aliases still accepted (``--effects``), by their option now.
    aliases: dict[str, str] = {}

    #: Options of an earlier version, with the option now (``--n_orient``:
    #: ``--discretization.n_orient``): read as that one, with a warning naming it.
    renamed: dict[str, str] = {}

    #: Named sets of option values (``--preset NAME``, expanded in place by
    #: :func:`normalize_argv`: options after it override it), by name.
    presets: dict[str, dict[str, Any]] = {}

    #: The options whose value is a list (set by :func:`add_config_fields`).
    list_options: set[str] = set()

    def error(self, message: str, ex: Exception | None = None) -> NoReturn:
        """Print the usage and `message` (with the valid options after an unknown one) and
        exit with code 2."""
        key = re.match(r'Parser key "([\w.]+)":\s*(.*)', message, re.S)
        if key:  # a value of the wrong type
            message = f"argument {self.spell(key.group(1))}: {' '.join(key.group(2).split())}"
        if message.startswith("the following arguments are required"):
            message = re.sub(r"\b(?:[\w-]+\.)+(\w+)", r"--\1", message)
        if message.startswith("unrecognized arguments"):
            valid = option_names(self)
            given = [w.split("=", 1)[0] for w in message.split(":", 1)[1].split()
                     if w.startswith("--")]
            close = [m for g in given for m in difflib.get_close_matches(g, valid, n=3)]
            message += (f" (did you mean {', '.join(close)}?)" if close else "") + \
                f"; valid options: {', '.join(valid)}"
        self.print_usage()
        self.exit(2, f"{self.prog}: error: {message}\n")


    def spell(self, dest: str) -> str:
        """The option of `dest` as the user gave it (``--effects`` for ``n_effects``)."""
        option = f"--{dest}"
        return self.spelled.get(option, option)


def option_names(parser: ArgumentParser) -> list[str]:
    """The long option strings of `parser`, in order (help and config options left out)."""
    skip = {"--help", "--print_config", "--config"}
    return [o for a in parser._actions for o in a.option_strings
            if o.startswith("--") and o not in skip]


def add_config_fields(parser: ArgumentParser, cls: type, skip: set[str] | None = None,
                      nested_key: str | None = None) -> None:
    """Add one flag per field of the dataclass `cls` (``--field``, or ``--<nested_key>.field``;
    a dataclass field gives ``--field.sub`` per field of its own), each with its description
    from the classes' numpydoc ``Attributes``, and, once per parser, ``--config FILE``."""
    add_config_option(parser)
    parser.add_class_arguments(cls, nested_key=nested_key, as_group=True, skip=skip,
                               instantiate=False)
    prefix = f"{nested_key}." if nested_key else ""
    docs, lists = _field_docs(cls, prefix)
    if isinstance(parser, Parser):
        parser.list_options = parser.list_options | lists
    for action in parser._actions:
        if action.dest in docs and not action.help:
            action.help = docs[action.dest].replace("``", "")


def _field_docs(cls: type, prefix: str) -> tuple[dict[str, str], set[str]]:
    """The description of each field of `cls` by its dotted destination (parts recursed
    into), and the options of the fields whose value is a list."""
    hints = typing.get_type_hints(cls)
    docs: dict[str, str] = {}
    lists: set[str] = set()
    for name, text in attribute_docs(cls).items():
        docs[prefix + name] = text
    for f in dataclasses.fields(cls):
        hint = hints.get(f.name)
        if dataclasses.is_dataclass(hint):
            sub_docs, sub_lists = _field_docs(hint, f"{prefix}{f.name}.")
            docs.update(sub_docs)
            lists |= sub_lists
        elif typing.get_origin(_optional_of(hint)) in (tuple, list):
            lists.add(f"--{prefix}{f.name}")
    return docs, lists


def _optional_of(hint: Any) -> Any:
    """``T`` of ``T | None`` (``Optional[T]``), else `hint`."""
    args = typing.get_args(hint)
    if typing.get_origin(hint) in (typing.Union, types.UnionType) and type(None) in args:
        rest = [a for a in args if a is not type(None)]
        return rest[0] if len(rest) == 1 else hint
    return hint


def attribute_docs(cls: type) -> dict[str, str]:
    """The description of each field in the numpydoc ``Attributes`` section of `cls`'s
    docstring (``a, b : type`` lines describe several fields), by field name."""
    lines = (inspect.getdoc(cls) or "").splitlines()
    if "Attributes" not in lines:
        return {}
    out: dict[str, str] = {}
    names: list[str] = []
    text: list[str] = []
    for line in lines[lines.index("Attributes") + 2:]:
        if line and not line[0].isspace():
            if ":" not in line:  # the next section
                break
            out.update(dict.fromkeys(names, " ".join(text)))
            names, text = [n.strip() for n in line.split(":", 1)[0].split(",")], []
        elif line.strip():
            text.append(line.strip())
    out.update(dict.fromkeys(names, " ".join(text)))
    return out


def add_config_option(parser: ArgumentParser) -> None:
    """Add ``--config FILE`` (JSON or YAML: any option of the command) unless it is there."""
    if "--config" not in {o for a in parser._actions for o in a.option_strings}:
        parser.add_argument("--config", action=ActionConfigFile,
                            help="JSON or YAML file of option values (keys: the option names "
                            "without --); options given after it override it")


def config_from(ns: Namespace, cls: type) -> Any:
    """The `cls` instance of the fields in `ns` (the flags of :func:`add_config_fields`;
    a part of a composed configuration from its own namespace)."""
    hints = typing.get_type_hints(cls)
    values: dict[str, Any] = {}
    for f in dataclasses.fields(cls):
        if not f.init or f.name not in ns:
            continue
        value = ns[f.name]
        if dataclasses.is_dataclass(hints.get(f.name)) and isinstance(value, Namespace):
            value = config_from(value, hints[f.name])
        values[f.name] = value
    return cls(**values)


def normalize_argv(argv: Sequence[str], parser: ArgumentParser,
                   aliases: dict[str, str] | None = None) -> list[str]:
    """`argv` with ``--field-name`` spelt ``--field_name`` where only that one is an option
    of `parser`, the `aliases` replaced, a list option's ``a,b`` written ``["a", "b"]``,
    and the keys of ``--config FILE`` checked.

    An option of an earlier version (``Parser.renamed``) is read as its option now, with a
    warning on stderr naming it.

    Raises
    ------
    SystemExit
        A config file key that is no option, or of the flat form of an earlier version
        (through :meth:`Parser.error`, with the valid names or the names now).
    """
    if isinstance(parser, Parser) and parser.presets:
        argv = expand_presets(argv, parser)
    valid = set(option_names(parser))
    renamed = parser.renamed if isinstance(parser, Parser) else {}
    lists = parser.list_options if isinstance(parser, Parser) else set()
    spelled: dict[str, str] = {}
    out: list[str] = []
    words = list(argv)
    for i, word in enumerate(words):
        flag, eq, value = word.partition("=")
        if aliases and flag in aliases:  # before the options: ``--starts`` is a part's too
            flag = aliases[flag]
            spelled[flag] = word.partition("=")[0]
        elif flag.startswith("--") and flag not in valid:
            if "--" + flag[2:].replace("-", "_") in valid:
                flag = "--" + flag[2:].replace("-", "_")
            elif flag in renamed or "--" + flag[2:].replace("-", "_") in renamed:
                old = flag if flag in renamed else "--" + flag[2:].replace("-", "_")
                print(f"{parser.prog}: warning: {flag} is renamed; read as {renamed[old]}",
                      file=sys.stderr)
                flag = renamed[old]
            if flag != word.partition("=")[0]:
                spelled[flag] = word.partition("=")[0]
        if flag == "--config" and (eq or i + 1 < len(words)):
            _check_config_keys(Path(value if eq else words[i + 1]), valid, parser)
        out.append(flag + eq + value)
        if i and out[i - 1] in lists and not eq:  # the value of a list option
            out[i] = list_value(out[i])
        elif flag in lists and eq:
            out[i] = flag + eq + list_value(value)
    if isinstance(parser, Parser):
        parser.spelled = spelled
    return out


def expand_presets(argv: Sequence[str], parser: Parser) -> list[str]:
    """`argv` with each ``--preset NAME`` (or ``--preset=NAME``) replaced, where it stands,
    by the options it sets (so options after it override it); an unknown name exits through
    :meth:`Parser.error` naming the presets."""
    out: list[str] = []
    words = list(argv)
    i = 0
    while i < len(words):
        flag, eq, value = words[i].partition("=")
        if flag != "--preset":
            out.append(words[i])
            i += 1
            continue
        if not eq:
            if i + 1 >= len(words):
                parser.error("--preset: expected a name: " + ", ".join(parser.presets))
            value, i = words[i + 1], i + 1
        if value not in parser.presets:
            parser.error(f"--preset: unknown {value!r}; choose "
                         + ", ".join(parser.presets))
        for key, v in parser.presets[value].items():
            out += [f"--{key}", str(v).lower() if isinstance(v, bool)
                    else json.dumps(list(v)) if isinstance(v, list | tuple) else str(v)]
        i += 1
    return out


def list_value(text: str) -> str:
    """A list option's value as JSON: ``a,b`` (or ``a, b``) becomes ``["a", "b"]``; a value
    already in brackets (``[a,b]``, JSON or YAML) is kept."""
    if text.lstrip().startswith("["):
        return text
    return json.dumps([x.strip() for x in text.split(",") if x.strip()])


def _check_config_keys(path: Path, valid: set[str], parser: ArgumentParser) -> None:
    if not path.is_file():
        parser.error(f"argument --config: '{path}' is not a file")
    try:
        data = yaml.safe_load(path.read_text())  # JSON is YAML
    except yaml.YAMLError as exc:
        parser.error(f"argument --config: '{path}' is neither JSON nor YAML: {exc}")
    if not isinstance(data, dict):
        parser.error(f"argument --config: '{path}' must hold a mapping of option names")
    names = sorted(v[2:].replace("-", "_") for v in valid)
    renamed = parser.renamed if isinstance(parser, Parser) else {}
    old = {k: renamed[f"--{k}"][2:] for k in data if f"--{k}" in renamed
           and str(k).replace("-", "_") not in names}
    if old:
        parser.error(f"argument --config: '{path}' holds the flat form of an earlier version; "
                     "renamed: " + ", ".join(f"{k} is now {v}" for k, v in old.items()))
    unknown = sorted(_config_keys(data, set(names)))
    if unknown:
        parser.error(f"argument --config: unknown key(s) {unknown} in '{path}'; valid "
                     f"keys: {', '.join(names)}")


def _config_keys(data: Mapping[str, Any], names: set[str], prefix: str = "") -> list[str]:
    """The keys of a config file's mapping that are no option (a part's keys, nested or
    dotted, checked against its fields)."""
    bad: list[str] = []
    for k, v in data.items():
        key = prefix + str(k).replace("-", "_")
        if isinstance(v, Mapping) and any(n.startswith(key + ".") for n in names):
            bad += _config_keys(v, names, key + ".")
        elif key not in names:
            bad.append(key)
    return bad


def command_path(ns: Namespace) -> tuple[tuple[str, ...], Namespace]:
    """The subcommands chosen (``("experiment", "push")``) and the namespace of the last."""
    path: list[str] = []
    while isinstance(ns, Namespace) and ns.get("subcommand"):
        name = ns["subcommand"]
        path.append(name)
        ns = ns[name]
    return tuple(path), ns
