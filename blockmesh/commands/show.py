"""``blockmesh show``: a picture of a domain's blocks, vertices and patches."""

from __future__ import annotations

import argparse

from ..plot import plot_domain
from ._common import add_domain_arguments, resolve_domain


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``show`` subcommand and its options to ``subparsers``."""
    parser = subparsers.add_parser(
        "show",
        help="draw a domain's blocks, vertices and patches",
        description="Draw the blocks (numbered), vertices (numbered), regions (shaded) and "
        "patches (coloured, with a legend) of a domain: what to look at before meshing.",
    )
    add_domain_arguments(parser)
    parser.add_argument("-o", "--output", required=True, metavar="FILE.png", help="picture file")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh show`` with the parsed ``args``; returns the exit code."""
    domain = resolve_domain(args)
    path = plot_domain(domain, args.output)
    print(f"wrote {path} ({domain.name}: {domain.n_blocks} blocks)")
    return 0
