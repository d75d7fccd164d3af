"""Subcommands of the ``blockmesh`` command line, one module each.

A command module has ``register(subparsers)``, which adds its parser and sets ``run`` as the
parser's default, and ``run(args) -> int``. Shared options and output helpers are in
:mod:`blockmesh.commands._common`.
"""

from __future__ import annotations

from . import catalogue, check, convert, integrate, mesh, show, solve, tables

COMMANDS = (catalogue, check, show, mesh, integrate, solve, convert, tables)

__all__ = ["COMMANDS"]
