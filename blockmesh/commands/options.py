"""The options several subcommands share, each defined once.

``--level``/``-l``, ``--smooth``, ``--placement`` (earlier ``--quality-rule``), ``--max-memory``,
``--json``, ``--plot`` and the split scheme of marked cells (``--refine-scheme``, ``--scheme``)
mean the same on every command that takes them; only the sentence that says what they apply to
changes. An earlier spelling of a renamed option still works and prints one note on stderr naming
the current one.

Each is an :class:`~blockmesh.commands.Option` record (or a tuple of them) that a command lists
among its ``OPTIONS``.

Examples
--------
>>> import argparse
>>> parser = argparse.ArgumentParser(prog="demo")
>>> for option in (level_option("refinement level"), *placement_options("the mesh")):
...     option.add_to(parser)
>>> parser.parse_args(["-l", "3", "--placement", "angles"])
Namespace(level=3, smooth=0, quality_rule='angles')
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from blockmesh.commands import Option
from blockmesh.commands.common import parse_size
from blockmesh.refinement.improve import QUALITY_RULES
from blockmesh.refinement.local import SCHEMES

__all__ = [
    "JSON_OPTION",
    "RenamedOption",
    "level_option",
    "max_memory_option",
    "placement_options",
    "plot_option",
    "renamed_flag",
    "scheme_option",
]


class RenamedOption(argparse.Action):
    """An option with earlier spellings: a note on stderr when one of them is used.

    ``Option(CURRENT, EARLIER, ..., action=RenamedOption)``: the first option string is the
    current name, the others earlier spellings that keep working. With ``nargs=0`` it is a flag
    that stores ``const``.
    """

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        """Store ``values`` (``const`` for a flag), with a note if ``option_string`` is earlier."""
        current = self.option_strings[0]
        if option_string is not None and option_string != current:
            print(
                f"{parser.prog}: note: {option_string} is now spelled {current} "
                "(the earlier spelling still works)",
                file=sys.stderr,
            )
        setattr(namespace, self.dest, self.const if self.nargs == 0 else values)


def renamed_flag(current: str, earlier: str, **settings: Any) -> Option:
    """The flag ``current`` with ``earlier`` as its earlier spelling (a note when used)."""
    return Option(
        current, earlier, action=RenamedOption, nargs=0, const=True, default=False, **settings
    )


def level_option(help: str, default: int | None = None) -> Option:
    """``--level``/``-l L`` (an int; ``default`` when absent, ``None`` by default)."""
    return Option("--level", "-l", type=int, default=default, metavar="L", help=help)


def placement_options(what: str) -> tuple[Option, Option]:
    """``--smooth K`` and ``--placement NAME`` (earlier ``--quality-rule``) for ``what``.

    The destinations stay ``smooth`` and ``quality_rule`` (the names the commands' JSON reports
    carry).
    """
    return (
        Option(
            "--smooth",
            type=int,
            default=0,
            metavar="K",
            help=f"Laplacian sweeps of {what} after every level (default 0)",
        ),
        Option(
            "--placement",
            "--quality-rule",
            dest="quality_rule",
            choices=QUALITY_RULES,
            default="paper",
            action=RenamedOption,
            help=f"node placement of {what}: the paper's (default); optimized after every level, "
            "cell sizes made uniform; or angles: optimized after every level against the worst "
            "corners, cells keeping their sizes (for decomposed, graded domains). Every node off "
            "the boundary moves, boundary nodes slide along it "
            "(see blockmesh.refinement.placement). --quality-rule is the earlier spelling",
        ),
    )


def max_memory_option(what: str) -> Option:
    """``--max-memory SIZE`` (a byte count, see :func:`.common.parse_size`) for ``what``."""
    return Option(
        "--max-memory",
        type=parse_size,
        metavar="SIZE",
        help=f"refuse {what} predicted to need more memory (e.g. 4G; default: what is available)",
    )


#: ``--json``: the command prints exactly one JSON object on stdout.
JSON_OPTION = Option("--json", action="store_true", help="print one JSON object")


def plot_option(what: str) -> Option:
    """``--plot PNG``: draw ``what`` into a PNG file."""
    return Option("--plot", metavar="PNG", help=f"draw {what} (PNG)")


def scheme_option(flag: str) -> Option:
    """``flag`` (a :data:`~blockmesh.refinement.local.SCHEMES` name): how marked cells split.

    ``blockmesh mesh --refine-scheme`` and ``blockmesh solve --adapt --scheme``.
    """
    return Option(
        flag,
        choices=tuple(SCHEMES),
        default="pentagons",
        help="how a marked cell is split: the paper's six pentagons (default; other polygons "
        "into corner pentagons and a central polygon), or quadrilaterals through its centre",
    )
