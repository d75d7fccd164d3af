"""The ``blockmesh`` command line: ``main(argv) -> exit code``.

Each subcommand lives in :mod:`blockmesh.commands` as a module with ``register(subparsers)`` and
``run(args) -> int``. Only this layer prints or exits: library errors (:class:`BlockMeshError`)
become one readable line on stderr and exit code 2; ``--json`` prints exactly one JSON object on
stdout.

Examples
--------
>>> main(["catalogue", "--json"]) == 0  # doctest: +ELLIPSIS
{...}
True
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from collections.abc import Sequence

from . import __version__
from .commands import SUMMARIES, load
from .errors import BlockMeshError

__all__ = ["build_parser", "main"]


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered.

    With ``only`` (a command name, or ``""`` for none) just that command's module is imported
    and registered in full; the others are listed by name and summary, which is all
    ``blockmesh --help`` needs.
    """
    parser = argparse.ArgumentParser(
        prog="blockmesh",
        description="Multi-block all-pentagonal meshes of 2-D domains: check, show, mesh, "
        "integrate, export.",
    )
    parser.add_argument("--version", action="version", version=f"blockmesh {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, summary in SUMMARIES.items():
        if only is None or name == only:
            load(name).register(subparsers)
        else:
            subparsers.add_parser(name, help=summary, add_help=False)
    return parser


def _show_warning(message, *_details: object, **_where: object) -> None:
    print(f"blockmesh: warning: {message}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the process exit code (0 on success)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    chosen = next((a for a in argv if not a.startswith("-")), "")
    parser = build_parser(chosen if chosen in SUMMARIES else "")
    args = parser.parse_args(argv)
    with warnings.catch_warnings():
        warnings.showwarning = _show_warning
        try:
            return int(args.run(args))
        except BlockMeshError as error:
            print(f"blockmesh {args.command}: error: {error}", file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            print(f"blockmesh {args.command}: interrupted", file=sys.stderr)
            return 130
        except BrokenPipeError:
            # The reader went away (e.g. `| head`): stop quietly, as Unix tools do.
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            return 141


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
