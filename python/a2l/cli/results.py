"""``a2l results``: run the named experiments and write ``docs/results/``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from jsonargparse import Namespace
from jsonargparse.typing import PositiveInt

from a2l.cli.args import UsageError, comma_list
from a2l.cli.parser import Parser
from a2l.results.catalog import ENTRIES


def _cmd_results(args: Namespace) -> int:
    # imported here: parsing and --help do not load this command's stack
    from a2l.results.catalog import entries
    from a2l.results.run import run_results

    only = comma_list(args.only)
    try:
        entries(only)
    except KeyError as exc:
        raise UsageError("--only", str(exc.args[0])) from None
    root = Path(args.root)
    if not (root / "README.md").is_file():
        raise UsageError("--root", f"'{root}' holds no README.md: not the repository")
    done = run_results(args.profile, out=args.out, root=root, only=only, workers=args.workers,
                       run=not args.no_run, quiet=args.quiet)
    for page in done["pages"]:
        print(f"wrote {page}")
    for page in done["copied"]:
        print(f"copied the tables into {page}")
    if done["missing"]:
        print(f"not written (runs not done): {', '.join(done['missing'])}")
    if done["dirty"] and not args.no_run:
        print("the tree was not clean: the tables say 'dirty tree'")
    return 1 if done["missing"] and not args.no_run else 0


def add_results_parser(sub: Any, commands: dict[tuple[str, ...], Any]) -> None:
    """The ``results`` command (its parser and handler in `commands`)."""
    p = Parser(
        prog="a2l results",
        description="Run the experiments behind the published tables on the current commit "
        "(evaluation seeds, docs/seeds.md), one child process per run, and write "
        "docs/results/: each table as Markdown with its commands, commit (clean tree or "
        "not), machine, date and wall time, and its figures; then copy the tables into the "
        "README's and the docs' <!-- results:NAME --> blocks. Rerunning with the same --out "
        "continues: runs already done are not made again.")
    p.add_argument("--profile", choices=("quick", "full"), default="quick",
                   help="quick: fewer seeds and trials (about 30 min on an idle 2-core "
                   "machine), a check: its pages go to docs/results/quick/ and are copied "
                   "nowhere; full: the experiments' pages' sizes (hours), the published "
                   "pages and tables. Default quick")
    p.add_argument("--out", metavar="DIR", default=None,
                   help="where the runs go (default runs/results-<profile>)")
    p.add_argument("--only", metavar="A,B,...", default=None,
                   help="only these tables (default all): "
                   + ", ".join(e.name for e in ENTRIES))
    p.add_argument("--workers", type=PositiveInt, default=2, metavar="N",
                   help="worker processes of each experiment (default 2)")
    p.add_argument("--root", metavar="DIR", default=".",
                   help="the repository (default: the current directory)")
    p.add_argument("--no-run", action="store_true",
                   help="make no run: rewrite docs/results/ from the runs already done and "
                   "copy the tables")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    sub.add_subcommand("results", p, help="regenerate the published tables (docs/results/)")
    commands[("results",)] = (p, _cmd_results)
