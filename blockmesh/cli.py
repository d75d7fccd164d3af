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
from signal import SIGINT
from typing import ClassVar, NoReturn

from blockmesh import __version__
from blockmesh._system.interrupts import Terminated, pending, raise_pending, stop_on_signals
from blockmesh.commands import SUMMARIES, load
from blockmesh.errors import BlockMeshError

__all__ = ["Terminated", "build_parser", "main"]


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered.

    With ``only`` (a command name, or ``""`` for none) just that command's module is imported
    and registered in full; the others are listed by name and summary, which is all
    ``blockmesh --help`` needs.
    """
    parser = _Parser(
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
    print(f"blockmesh: warning: {_printable(str(message))}", file=sys.stderr)


def _remove_pending() -> None:
    """Remove temporaries a signal stranded between their creation and their ``try``."""
    atomic = sys.modules.get("blockmesh._system.atomic")  # not imported: nothing was written
    if atomic is not None:
        atomic.remove_pending()


class _Parser(argparse.ArgumentParser):
    """An argument parser that remembers its last usage error (for ``--json``)."""

    last_error: ClassVar[list[str]] = []

    def error(self, message: str) -> NoReturn:
        _Parser.last_error[:] = [message]
        super().error(message)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the process exit code (0 on success).

    Exit codes: 0 success, 1 a check or tolerance that did not pass, 2 an error in the input or
    the request (one readable line on stderr), 3 an unexpected internal error (a bug: set
    ``BLOCKMESH_DEBUG=1`` to see its traceback), 130 Ctrl-C, 128 + N for signal N
    (SIGTERM 143, SIGHUP 129).

    With ``--json`` every outcome is exactly one JSON object on stdout: the command's report,
    or on failure ``{"error": {"type": ..., "message": ..., "exit_code": ...}}`` (the line on
    stderr is printed as well). A usage error raises :class:`SystemExit` (code 2) as argparse
    does, after its JSON object.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    chosen = next((a for a in argv if not a.startswith("-")), "")
    parser = build_parser(chosen if chosen in SUMMARIES else "")
    _Parser.last_error.clear()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:
        if stop.code not in (0, None) and "--json" in argv and _Parser.last_error:
            _print_json_error("UsageError", _Parser.last_error[0], 2)
        raise
    where = f"blockmesh {args.command}"
    wants_json = bool(getattr(args, "json", False))
    printed = _json_objects_printed()
    with warnings.catch_warnings(), stop_on_signals():
        warnings.showwarning = _show_warning
        code, failure = _run(args, where)
    if failure is not None and wants_json and _json_objects_printed() == printed:
        _print_json_error(*failure, code)
    return code


#: A failed command: the error's type name and its message.
Failure = tuple[str, str]


def _run(args: argparse.Namespace, where: str) -> tuple[int, Failure | None]:
    """Run the command: its exit code, and what failed (None on success)."""

    def fail(code: int, kind: str, message: str, line: str | None = None) -> tuple[int, Failure]:
        print(line or f"{where}: error: {message}", file=sys.stderr)
        return code, (kind, message)

    try:
        code = int(args.run(args))
        raise_pending()  # a signal a finaliser swallowed still stops the command
        return code, None
    except BlockMeshError as error:
        return fail(2, type(error).__name__, _printable(str(error)))
    except Terminated as stop:
        _remove_pending()
        message = f"terminated by signal {stop.signum}"
        return fail(128 + stop.signum, "Terminated", message, f"{where}: {message}")
    except KeyboardInterrupt:
        _remove_pending()
        return fail(130, "KeyboardInterrupt", "interrupted", f"{where}: interrupted")
    except BrokenPipeError:
        # The reader went away (e.g. `| head`): stop quietly, as Unix tools do.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141, None
    except MemoryError:
        return fail(
            2,
            "MemoryError",
            "ran out of memory; try a lower level or free memory (--max-memory sets the limit "
            "the size checks use)",
        )
    except RecursionError:
        return fail(2, "RecursionError", "the input is nested too deeply to read")
    except OSError as error:
        target = f" {_printable(str(error.filename))}" if error.filename else ""
        message = f"{target[1:] + ': ' if target else ''}{error.strerror or error}"
        return fail(
            2, type(error).__name__, message, f"{where}: error:{target}: {error.strerror or error}"
        )
    except Exception as error:
        signum = pending()
        if signum is not None:  # the error came of the signal's unwinding (e.g. inside h5py)
            _remove_pending()
            message = "interrupted" if signum == SIGINT else f"terminated by signal {signum}"
            kind = "KeyboardInterrupt" if signum == SIGINT else "Terminated"
            return fail(128 + signum, kind, message, f"{where}: {message}")
        if os.environ.get("BLOCKMESH_DEBUG"):
            raise
        message = (
            f"internal error ({type(error).__name__}: {_printable(str(error))}); this is a bug "
            "in blockmesh: please report it with the command you ran (BLOCKMESH_DEBUG=1 shows "
            "the traceback)"
        )
        return fail(3, type(error).__name__, message, f"{where}: {message}")


def _json_objects_printed() -> int:
    from blockmesh.commands.common import json_objects_printed

    return json_objects_printed()


def _print_json_error(kind: str, message: str, code: int) -> None:
    from blockmesh.commands.common import json_error, print_json

    print_json(json_error(kind, message, code))


def _printable(text: str) -> str:
    from blockmesh.commands.common import printable

    return printable(text, keep="\n")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
