"""``blockmesh mesh``'s arguments checked and gathered into the options of a run.

Every check that needs no meshing runs here, before any domain is loaded: a bad size, a format
that does not take an option, a local refinement that cannot go with ``--numbering rcm``.
"""

from __future__ import annotations

import argparse
from typing import Any

from blockmesh.commands.common import check_folders, check_level_options
from blockmesh.errors import BlockMeshError
from blockmesh.io import check_options, format_for_path
from blockmesh.refinement.marking import Marking, any_of, in_region, near_patch, parse_near, where
from blockmesh.sizing.gradation import checked_gradation
from blockmesh.sizing.spec import as_size_spec

#: The level meshed when none is given (as ``blockmesh integrate``).
DEFAULT_LEVEL = 2


def _size_value(text: str) -> float | str:
    """``--size`` as a number when it is one, else the expression text."""
    try:
        return float(text)
    except ValueError:
        return text


def _marking(args: argparse.Namespace) -> Marking | None:
    """The union of the --refine-* options as one marking (None without them)."""
    parts: list[Marking] = [where(text) for text in args.refine_where]
    parts += [in_region(name) for name in args.refine_region]
    parts += [near_patch(*parse_near(text)) for text in args.refine_near]
    if args.refine_rounds < 1:
        raise BlockMeshError(f"--refine-rounds must be 1 or more, got {args.refine_rounds}")
    if not parts:
        if args.refine_rounds != 1:
            raise BlockMeshError(
                "--refine-rounds counts rounds of local refinement: give --refine-where, "
                "--refine-region or --refine-near too"
            )
        return None
    return parts[0] if len(parts) == 1 else any_of(*parts)


def mesh_options(args: argparse.Namespace) -> dict[str, Any]:
    """The options of a run from the parsed ``args``, every check that needs no mesh made."""
    check_level_options(args)
    if args.uniform and args.size is not None:
        raise BlockMeshError("give --uniform (one size, the count of --level) or --size, not both")
    if args.gradation is not None and args.size is None:
        raise BlockMeshError("--gradation goes with --size (how fast the sizes asked may grow)")
    size = None
    if args.size is not None:
        size = _size_value(args.size)
        as_size_spec(size, source="--size")  # a located message for a bad size, before meshing
    if args.gradation is not None:
        checked_gradation(args.gradation)
    check_folders(args.output, args.plot, args.quality_plot, args.size_plot)
    if args.output:
        # Fail before meshing: an unknown format or an option it does not take is known now.
        fmt = format_for_path(args.output, args.format)
        check_options(fmt, split=args.split, compression=args.compression)
    marking = _marking(args)
    if marking is not None and args.numbering != "nested":
        raise BlockMeshError(
            "--numbering rcm renumbers an all-pentagon mesh; local refinement keeps the nested "
            "numbering"
        )
    return {
        "marking": marking,
        "refine_rounds": args.refine_rounds,
        "refine_scheme": args.refine_scheme,
        "level": args.level,
        "size": size,
        "uniform": args.uniform,
        "gradation": args.gradation,
        "size_plot": args.size_plot,
        "numbering": args.numbering,
        "smooth": args.smooth,
        "quality_rule": args.quality_rule,
        "max_memory": args.max_memory,
        "plot": args.plot,
        "quality_plot": args.quality_plot,
        "format": args.format,
        "split": args.split,
        "compression": args.compression,
    }
