"""The parser class of the ``a2l`` command (jsonargparse) and the pieces every command group
shares: configuration flags generated from a dataclass, config files checked name by name,
the command path of a parse.

Every field of a configuration dataclass becomes a flag ``--field`` (``--field-name`` is
accepted too) through :meth:`jsonargparse.ArgumentParser.add_class_arguments`, which also
checks each value's type; ``--config FILE`` (JSON or YAML) sets any flag of the command. A
misspelt flag or config-file key is refused with the list of valid names before any work
starts.
"""

from __future__ import annotations

import dataclasses
import difflib
import inspect
import re
from collections.abc import Sequence
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
    """Add one flag per field of the dataclass `cls` (``--field``, or ``--<nested_key>.field``)
    and, once per parser, ``--config FILE``."""
    add_config_option(parser)
    parser.add_class_arguments(cls, nested_key=nested_key, as_group=True, skip=skip,
                               instantiate=False)
    docs = attribute_docs(cls)
    prefix = f"{nested_key}." if nested_key else ""
    for action in parser._actions:
        name = action.dest[len(prefix):] if action.dest.startswith(prefix) else None
        if name in docs and not action.help:
            action.help = docs[name].replace("``", "")


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
    """The `cls` instance of the fields in `ns` (the flags of :func:`add_config_fields`)."""
    names = [f.name for f in dataclasses.fields(cls) if f.init]
    return cls(**{n: ns[n] for n in names if n in ns})


def normalize_argv(argv: Sequence[str], parser: ArgumentParser,
                   aliases: dict[str, str] | None = None) -> list[str]:
    """`argv` with ``--field-name`` spelt ``--field_name`` where only that one is an option
    of `parser`, the `aliases` replaced, and the keys of ``--config FILE`` checked.

    Raises
    ------
    SystemExit
        A config file key that is no option (through :meth:`Parser.error`, with the valid
        names).
    """
    valid = set(option_names(parser))
    spelled: dict[str, str] = {}
    out: list[str] = []
    words = list(argv)
    for i, word in enumerate(words):
        flag, eq, value = word.partition("=")
        if flag.startswith("--") and flag not in valid:
            if aliases and flag in aliases:
                flag = aliases[flag]
            elif "--" + flag[2:].replace("-", "_") in valid:
                flag = "--" + flag[2:].replace("-", "_")
            if flag != word.partition("=")[0]:
                spelled[flag] = word.partition("=")[0]
        if flag == "--config" and (eq or i + 1 < len(words)):
            _check_config_keys(Path(value if eq else words[i + 1]), valid, parser)
        out.append(flag + eq + value)
    if isinstance(parser, Parser):
        parser.spelled = spelled
    return out


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
    unknown = sorted(k for k in data if str(k).replace("-", "_") not in names)
    if unknown:
        parser.error(f"argument --config: unknown key(s) {unknown} in '{path}'; valid "
                     f"keys: {', '.join(names)}")


def command_path(ns: Namespace) -> tuple[tuple[str, ...], Namespace]:
    """The subcommands chosen (``("experiment", "push")``) and the namespace of the last."""
    path: list[str] = []
    while isinstance(ns, Namespace) and ns.get("subcommand"):
        name = ns["subcommand"]
        path.append(name)
        ns = ns[name]
    return tuple(path), ns
