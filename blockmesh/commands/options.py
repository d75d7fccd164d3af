"""The options several subcommands share, each defined once.

``--level``/``-l``, ``--smooth``, ``--placement`` (earlier ``--quality-rule``), ``--max-memory``,
``--json``, ``--plot`` and the split scheme of marked cells (``--refine-scheme``, ``--scheme``)
mean the same on every command that takes them; only the sentence that says what they apply to
changes. An earlier spelling of a renamed option still works and prints one note on stderr naming
the current one.

Examples
--------
>>> import argparse
>>> parser = argparse.ArgumentParser(prog="demo")
>>> add_level_option(parser, "refinement level")
>>> add_placement_options(parser, "the mesh")
>>> parser.parse_args(["-l", "3", "--placement", "angles"])
Namespace(level=3, smooth=0, quality_rule='angles')
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from blockmesh.commands.common import parse_size
from blockmesh.refinement.improve import QUALITY_RULES
from blockmesh.refinement.local import SCHEMES

__all__ = [
    "RenamedOption",
    "add_json_option",
    "add_level_option",
    "add_max_memory_option",
    "add_placement_options",
    "add_plot_option",
    "add_renamed_flag",
    "add_scheme_option",
]


class RenamedOption(argparse.Action):
    """An option with earlier spellings: a note on stderr when one of them is used.

    ``add_argument(CURRENT, EARLIER, ..., action=RenamedOption)``: the first option string is the
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


def add_renamed_flag(
    parser: argparse.ArgumentParser, current: str, earlier: str, **kwargs: Any
) -> None:
    """Add the flag ``current`` with ``earlier`` as its earlier spelling (a note when used)."""
    parser.add_argument(
        current, earlier, action=RenamedOption, nargs=0, const=True, default=False, **kwargs
    )


def add_level_option(
    parser: argparse.ArgumentParser,
    help: str,
    default: int | None = None,
) -> None:
    """Add ``--level``/``-l L`` (an int; ``default`` when absent, ``None`` by default)."""
    parser.add_argument("--level", "-l", type=int, default=default, metavar="L", help=help)


def add_placement_options(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--smooth K`` and ``--placement NAME`` (earlier ``--quality-rule``) for ``what``.

    The destinations stay ``smooth`` and ``quality_rule`` (the names the commands' JSON reports
    carry).
    """
    parser.add_argument(
        "--smooth",
        type=int,
        default=0,
        metavar="K",
        help=f"Laplacian sweeps of {what} after every level (default 0)",
    )
    parser.add_argument(
        "--placement",
        "--quality-rule",
        dest="quality_rule",
        choices=QUALITY_RULES,
        default="paper",
        action=RenamedOption,
        help=f"node placement of {what}: the paper's (default); optimized after every level, "
        "cell sizes made uniform; or angles: optimized after every level against the worst "
        "corners, cells keeping their sizes (for decomposed, graded domains). Every node off the "
        "boundary moves, boundary nodes slide along it (see blockmesh.refinement.placement). "
        "--quality-rule is the earlier spelling",
    )


def add_max_memory_option(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--max-memory SIZE`` (a byte count, see :func:`.common.parse_size`) for ``what``."""
    parser.add_argument(
        "--max-memory",
        type=parse_size,
        metavar="SIZE",
        help=f"refuse {what} predicted to need more memory (e.g. 4G; default: what is available)",
    )


def add_json_option(parser: argparse.ArgumentParser) -> None:
    """Add ``--json``: the command prints exactly one JSON object on stdout."""
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def add_plot_option(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--plot PNG``: draw ``what`` into a PNG file."""
    parser.add_argument("--plot", metavar="PNG", help=f"draw {what} (PNG)")


def add_scheme_option(parser: argparse._ActionsContainer, flag: str) -> None:
    """Add ``flag`` (a :data:`~blockmesh.refinement.local.SCHEMES` name): how marked cells split.

    ``blockmesh mesh --refine-scheme`` and ``blockmesh solve --adapt --scheme``; a parser or an
    argument group.
    """
    parser.add_argument(
        flag,
        choices=tuple(SCHEMES),
        default="pentagons",
        help="how a marked cell is split: the paper's six pentagons (default; other polygons "
        "into corner pentagons and a central polygon), or quadrilaterals through its centre",
    )
