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
import contextlib
import os
import signal
import sys
import threading
import warnings
from collections.abc import Iterator, Sequence
from typing import Any

from . import __version__
from .commands import SUMMARIES, load
from .errors import BlockMeshError

__all__ = ["Terminated", "build_parser", "main"]


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
    print(f"blockmesh: warning: {_printable(str(message))}", file=sys.stderr)


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP arrived: unwound like Ctrl-C, so no output is left half-written."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


#: The signals received while the command ran (see :func:`_signals_as_interrupts`).
_RECEIVED: list[int] = []


def _terminate(signum: int, _frame: object) -> None:
    _RECEIVED.append(signum)
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(signum)


@contextlib.contextmanager
def _signals_as_interrupts() -> Iterator[None]:
    """SIGTERM and SIGHUP raise :class:`Terminated`, SIGINT KeyboardInterrupt (main thread only).

    Each signal is also recorded: one that arrives while Python runs a finaliser (a weak
    reference's callback, a ``__del__``) has its exception swallowed ("Exception ignored"), and
    :func:`main` then still stops with the signal's exit code.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _RECEIVED.clear()
    names = ("SIGINT", "SIGTERM", "SIGHUP")
    wanted = [getattr(signal, name) for name in names if hasattr(signal, name)]
    previous = {signum: signal.signal(signum, _terminate) for signum in wanted}
    hook = sys.unraisablehook

    def unraisable(info: Any) -> None:
        if not issubclass(info.exc_type, KeyboardInterrupt):  # a signal's: handled by main
            hook(info)

    sys.unraisablehook = unraisable
    try:
        yield
    finally:
        sys.unraisablehook = hook
        for signum, handler in previous.items():
            signal.signal(signum, handler)


def _remove_pending() -> None:
    """Remove temporaries a signal stranded between their creation and their ``try``."""
    atomic = sys.modules.get("blockmesh.atomic")  # not imported: nothing was written
    if atomic is not None:
        atomic.remove_pending()


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the process exit code (0 on success).

    Exit codes: 0 success, 1 a check or tolerance that did not pass, 2 an error in the input or
    the request (one readable line on stderr), 3 an unexpected internal error (a bug: set
    ``BLOCKMESH_DEBUG=1`` to see its traceback), 130 Ctrl-C, 128 + N for signal N
    (SIGTERM 143, SIGHUP 129).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    chosen = next((a for a in argv if not a.startswith("-")), "")
    parser = build_parser(chosen if chosen in SUMMARIES else "")
    args = parser.parse_args(argv)
    where = f"blockmesh {args.command}"
    with warnings.catch_warnings(), _signals_as_interrupts():
        warnings.showwarning = _show_warning
        try:
            code = int(args.run(args))
            if _RECEIVED:  # its exception was swallowed by a finaliser: stop as it asked
                raise (
                    Terminated(_RECEIVED[0]) if _RECEIVED[0] != signal.SIGINT else KeyboardInterrupt
                )
            return code
        except BlockMeshError as error:
            print(f"{where}: error: {_printable(str(error))}", file=sys.stderr)
            return 2
        except Terminated as stop:
            _remove_pending()
            print(f"{where}: terminated by signal {stop.signum}", file=sys.stderr)
            return 128 + stop.signum
        except KeyboardInterrupt:
            _remove_pending()
            print(f"{where}: interrupted", file=sys.stderr)
            return 130
        except BrokenPipeError:
            # The reader went away (e.g. `| head`): stop quietly, as Unix tools do.
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            return 141
        except MemoryError:
            print(
                f"{where}: error: ran out of memory; try a lower level or free memory "
                "(--max-memory sets the limit the size checks use)",
                file=sys.stderr,
            )
            return 2
        except RecursionError:
            print(f"{where}: error: the input is nested too deeply to read", file=sys.stderr)
            return 2
        except OSError as error:
            target = f" {error.filename}" if error.filename else ""
            print(f"{where}: error:{target}: {error.strerror or error}", file=sys.stderr)
            return 2
        except Exception as error:
            if os.environ.get("BLOCKMESH_DEBUG"):
                raise
            print(
                f"{where}: internal error ({type(error).__name__}: {_printable(str(error))}); "
                "this is a bug in blockmesh: please report it with the command you ran "
                "(BLOCKMESH_DEBUG=1 shows the traceback)",
                file=sys.stderr,
            )
            return 3


def _printable(text: str) -> str:
    from .commands._common import printable

    return printable(text, keep="\n")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
