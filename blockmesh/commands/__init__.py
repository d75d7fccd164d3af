"""Subcommands of the ``blockmesh`` command line, one module each.

A command module has ``register(subparsers)``, which adds its parser and sets ``run`` as the
parser's default, and ``run(args) -> int``. Shared options and output helpers are in
:mod:`blockmesh.commands.common`.

The modules are imported only when their command runs (:func:`load`): ``blockmesh --help`` lists
the commands from :data:`SUMMARIES` alone, so that it and ``--version`` start fast. A test checks
that each summary is the help its module registers.
"""

from __future__ import annotations

import importlib
from types import ModuleType

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

__all__ = ["COMMANDS", "SUMMARIES", "load"]


def load(name: str) -> ModuleType:
    """The module of subcommand ``name`` (imported now if it was not yet)."""
    return importlib.import_module(f".{name}", __name__)


def __getattr__(name: str) -> tuple[ModuleType, ...]:
    """``COMMANDS``: every command module, in order (imports them all)."""
    if name == "COMMANDS":
        return tuple(load(command) for command in SUMMARIES)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
