"""Subcommands of the ``blockmesh`` command line, one module each.

A command module declares its options as data, next to its ``run(args) -> int``: ``OPTIONS``, a
tuple of :class:`Option` records (``add_argument``'s arguments) and :class:`Group` records (a
heading of its own in ``--help``), and ``register = registration(NAME, OPTIONS, run)``, which adds
its parser with :func:`add_command` and then the options. The texts around a command's options,
its summary, description and example, are here, one table each; shared options are in
:mod:`blockmesh.commands.options`, output helpers in :mod:`blockmesh.commands.common`.

The modules are imported only when their command runs (:func:`load`): ``blockmesh --help`` lists
the commands from :data:`SUMMARIES` alone, so that it and ``--version`` start fast. A test checks
that each module registers its command under its own name.
"""

from __future__ import annotations

import argparse
import importlib
from collections.abc import Callable
from types import ModuleType
from typing import Any

#: Subcommand name -> its one-line help, in the order ``blockmesh --help`` lists them.
SUMMARIES = {
    "catalogue": "list the catalogue of ready-made domains",
    "check": "validate a domain and print its conformity certificate",
    "show": "draw a domain's blocks, vertices and patches",
    "mesh": "refine domains into all-pentagon meshes; report, draw, export",
    "integrate": "integrate f(x, y) over a domain with a composite Gauss rule",
    "solve": "solve a Poisson or elasticity problem on the mesh (virtual elements)",
    "convert": "convert a triangle/quadrilateral mesh into pentagonal blocks",
    "tables": "regenerate the paper's Tables 1-11 (both pentagons) with their errors",
}

#: Subcommand name -> the paragraph that opens its ``--help`` (after the usage line).
DESCRIPTIONS = {
    "catalogue": "List the catalogue domains: name, blocks, area, patches, description.",
    "check": (
        "Validate a domain (catalogue name, .toml file or --polygon). Prints the certificate "
        "(blocks, shared edges, boundary edges per patch, regions and the interfaces between "
        "them, Euler characteristic and connected pieces, orientation, strict convexity and "
        "angles of every block) and exits 0 when valid; prints the located errors and exits 1 "
        "otherwise."
    ),
    "show": (
        "Draw the blocks (numbered), vertices (numbered), regions (shaded) and patches (coloured, "
        "with a legend) of a domain: what to look at before meshing. A mesh file is drawn as a "
        "mesh."
    ),
    "mesh": (
        "Refine DOMAIN (or several) LEVEL times: every block becomes 6**LEVEL pentagons. Prints "
        "counts and quality; draws and writes the mesh on request."
    ),
    "integrate": (
        "Integrate a function of x and y over the domain's pentagon mesh at a level, with the "
        "paper's composite Gauss-Legendre rule (or a cheaper one), or to a tolerance (--tol picks "
        "the order and level). Every result comes with an error estimate, and a warning when it "
        "is large (a singular, divergent or unresolved integrand). --exact-integral adds the "
        "exact integral of a polynomial."
    ),
    "solve": (
        "Solve a diffusion-reaction (Poisson) or plane elasticity problem on DOMAIN's pentagon "
        "mesh at LEVEL with lowest-order virtual elements; report unknowns, cost and, with "
        "--exact-solution, the errors; write the solution for ParaView. DOMAIN may be a mesh "
        "file: the problem is solved on the mesh read, refined further by --level if given. The "
        "memory the solve needs (the direct solver's factorisation above all) is predicted first: "
        "a problem that does not fit is refused, naming the largest level that does."
    ),
    "convert": (
        "Read a 2-D mesh of triangles, quadrilaterals or both (Gmsh .msh, .vtu, .vtk, .xdmf and "
        "the other formats meshio reads) and turn every element into strictly convex pentagons, "
        "conformingly (a triangle into 9, a quadrilateral into 12). Physical groups become "
        "patches (lines) and regions (surfaces). Writes the blocks as a domain file "
        "(-o NAME.toml) or, refined --level times, as a mesh (-o NAME.vtu, .msh, ...)."
    ),
    "tables": (
        "Recompute the paper's Tables 1-11 (composite Gauss-Legendre rule on the refined "
        "pentagons SP and USP), print them in the paper's layout (OGLR rows x NPMR=6^L columns) "
        "with the error of every entry against a high-precision reference, and optionally write "
        "all entries to CSV and the convergence picture to PNG."
    ),
}

#: Subcommand name -> the example that closes its ``--help``, for the commands that have one.
EXAMPLES = {
    "integrate": 'blockmesh integrate sp --function "(x^4 + y^3)/(1 + x^2)" --level 3',
    "solve": 'blockmesh solve square --level 3 --source "2*pi^2*sin(pi*x)*sin(pi*y)" '
    "--dirichlet '*=0' --exact-solution \"sin(pi*x)*sin(pi*y)\"",
}

__all__ = [
    "COMMANDS",
    "DESCRIPTIONS",
    "EXAMPLES",
    "SUMMARIES",
    "Group",
    "Option",
    "Options",
    "Register",
    "add_command",
    "load",
    "registration",
]


def load(name: str) -> ModuleType:
    """The module of subcommand ``name`` (imported now if it was not yet)."""
    return importlib.import_module(f".{name}", __name__)


class Option:
    """One option (or positional argument) of a command, as data.

    ``Option(*flags, **settings)`` is added as ``parser.add_argument(*flags, **settings)``:
    ``Option("--order", type=int, metavar="N", help="...")``.
    """

    __slots__ = ("flags", "settings")

    def __init__(self, *flags: str, **settings: Any) -> None:
        self.flags = flags
        self.settings = settings

    def __repr__(self) -> str:
        given = [repr(flag) for flag in self.flags]
        given += [f"{key}={value!r}" for key, value in self.settings.items()]
        return f"Option({', '.join(given)})"

    def add_to(self, parser: argparse._ActionsContainer) -> None:
        """Add the option to ``parser`` (a parser or an argument group)."""
        parser.add_argument(*self.flags, **self.settings)


class Group:
    """Options listed under a heading of their own in ``--help`` (an argparse argument group)."""

    __slots__ = ("description", "options", "title")

    def __init__(self, title: str, description: str, *options: Option) -> None:
        self.title = title
        self.description = description
        self.options = options

    def add_to(self, parser: argparse._ActionsContainer) -> None:
        """Add the group and its options to ``parser``."""
        group = parser.add_argument_group(self.title, self.description)
        for option in self.options:
            option.add_to(group)


#: A command's options, in the order its ``--help`` lists them.
Options = tuple[Option | Group, ...]

#: What ``blockmesh`` calls to add a command: ``register(subparsers)`` returns its parser.
Register = Callable[[argparse._SubParsersAction], argparse.ArgumentParser]


def registration(name: str, options: Options, run: Callable[[argparse.Namespace], int]) -> Register:
    """The ``register(subparsers)`` of subcommand ``name``: :func:`add_command` with ``options``."""

    def register(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
        return add_command(subparsers, name, run, options)

    register.__doc__ = f"Add the ``{name}`` subcommand and its options to ``subparsers``."
    return register


def add_command(
    subparsers: argparse._SubParsersAction,
    name: str,
    run: Callable[[argparse.Namespace], int],
    options: Options = (),
) -> argparse.ArgumentParser:
    """Add subcommand ``name`` to ``subparsers``: its parser, which runs ``run``, and ``options``.

    The parser's texts are the command's entries in :data:`SUMMARIES` (its help),
    :data:`DESCRIPTIONS` and :data:`EXAMPLES` (its epilog, ``example: ...``).

    Parameters
    ----------
    subparsers
        The ``blockmesh`` parser's subcommands.
    name
        The subcommand's name.
    run
        What runs the parsed arguments (the parser's default ``run``).
    options
        The subcommand's options, added in order.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    example = EXAMPLES.get(name)
    parser = subparsers.add_parser(
        name,
        help=SUMMARIES[name],
        description=DESCRIPTIONS[name],
        epilog=None if example is None else f"example: {example}",
    )
    parser.set_defaults(run=run)
    for option in options:
        option.add_to(parser)
    return parser


def __getattr__(name: str) -> tuple[ModuleType, ...]:
    """``COMMANDS``: every command module, in order (imports them all)."""
    if name == "COMMANDS":
        return tuple(load(command) for command in SUMMARIES)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
