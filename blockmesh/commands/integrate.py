"""``blockmesh integrate``: integrate a function over a domain's pentagon mesh."""

from __future__ import annotations

import argparse
import sys
import warnings
from decimal import Decimal, localcontext
from fractions import Fraction
from typing import Any

from blockmesh.commands import Option, Options, registration
from blockmesh.commands._partitions import (
    check_partition_arguments,
    partition_keywords,
    partition_options,
)
from blockmesh.commands.common import (
    check_level_options,
    check_range,
    domain_arguments,
    levels_to_add,
    print_json,
    printable,
    resolve_target,
)
from blockmesh.commands.options import JSON_OPTION, level_option, renamed_flag
from blockmesh.errors import BlockMeshError, BlockMeshWarning, ResourceError
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.quadrature import (
    RULES,
    IntegrationResult,
    integrate_to_tolerance,
    integrate_with_estimate,
)
from blockmesh.quadrature.exact import exact_integral
from blockmesh.refinement.pipeline import MAX_LEVEL

__all__ = ["OPTIONS", "register", "run"]

_DEFAULT_LEVEL = 2
_DEFAULT_ORDER = 10


#: The options of ``blockmesh integrate``, in the order of its ``--help``.
OPTIONS: Options = (
    *domain_arguments(),
    Option(
        "--function",
        "-f",
        required=True,
        metavar="EXPR",
        help="f(x, y): numbers, x, y, pi, e, + - * / ^ (or **), and sin cos tan exp log sqrt abs "
        "... (see blockmesh.numerics.expr.FUNCTIONS)",
    ),
    level_option(
        f"refinement level: 6^L cells per block (default {_DEFAULT_LEVEL}; a mesh file keeps "
        "its own level, and L more levels refine it further; with --tol: the starting level, "
        "default 0)",
    ),
    Option(
        "--order",
        type=int,
        metavar="N",
        help=f"order n of the rule, exact to degree 2n-1 (default {_DEFAULT_ORDER}; with --tol: "
        "the starting order, default 2)",
    ),
    Option(
        "--rule",
        choices=tuple(RULES),
        help="paper: the paper's rule (default); jacobi, fan: fewer points, same degree "
        "(jacobi is the default with --tol)",
    ),
    renamed_flag(
        "--exact-integral",
        "--exact",
        dest="exact",
        help="also the exact integral over the domain (polynomials only), as a fraction "
        "(--exact is the earlier spelling)",
    ),
    Option(
        "--exact-geometry",
        action="store_true",
        help="integrate the cells with curved edges over their true curved shape (default: the "
        "straight cells through their nodes)",
    ),
    Option(
        "--tol",
        type=float,
        metavar="T",
        help="integrate to an absolute error estimate <= T, choosing order and level",
    ),
    Option("--max-level", type=int, default=6, metavar="L", help="with --tol: highest level (6)"),
    Option(
        "--max-points",
        type=int,
        metavar="P",
        help="most evaluations of f (default 1,000,000,000; with --tol 200,000,000): larger "
        "requests are refused before any work",
    ),
    *partition_options("integrate"),
    JSON_OPTION,
)


def _decimal(value: Fraction, digits: int = 22) -> str:
    with localcontext() as context:
        context.prec = digits
        return str(Decimal(value.numerator) / Decimal(value.denominator))


def _difference(value: float, exact: Fraction | float) -> float:
    """``|value - exact|`` computed exactly, then rounded (inf beyond the float range)."""
    try:
        return float(abs(Fraction(value) - Fraction(exact)))
    except OverflowError:
        return float("inf")


def _integrate(args: argparse.Namespace, target: Any) -> IntegrationResult:
    limits: dict[str, int] = {} if args.max_points is None else {"max_points": args.max_points}
    try:
        if args.tol is not None:
            if check_partition_arguments(args):
                raise BlockMeshError(
                    "--partitions integrates at one --level and --order; it does not take --tol"
                )
            return integrate_to_tolerance(
                target,
                args.function,
                args.tol,
                rule=args.rule or "jacobi",
                level=None if args.level is None else _level(args, target),
                start_order=args.order or 2,
                max_level=args.max_level,
                exact_geometry=args.exact_geometry,
                **limits,
            )
        if check_partition_arguments(args):  # each worker integrates over its partition
            from blockmesh.distributed import integrate_with_estimate as integrate_partitions

            return integrate_partitions(
                target, args.function, order=_DEFAULT_ORDER if args.order is None else args.order,
                level=_level(args, target), rule=args.rule or "paper", max_points=args.max_points,
                exact_geometry=args.exact_geometry, **partition_keywords(args),
            )  # fmt: skip
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", BlockMeshWarning)  # printed below, with the options
            return integrate_with_estimate(
                target,
                args.function,
                order=_DEFAULT_ORDER if args.order is None else args.order,
                level=_level(args, target),
                rule=args.rule or "paper",
                exact_geometry=args.exact_geometry,
                **limits,
            )
    except ResourceError as error:
        raise ResourceError(f"{error} (--max-points)") from None


def _has_curves(target: Any) -> bool:
    curves = target.curves if isinstance(target, Mesh | PolygonMesh) else target.block_mesh().curves
    return curves is not None and len(curves) > 0


def _level(args: argparse.Namespace, target: Any) -> int:
    """The level to integrate at: ``--level`` (default 2), or a mesh file's own plus ``--level``.

    A mesh file's levels are counted as ``blockmesh mesh`` and ``solve`` count them.
    """
    steps = levels_to_add(args.level, target, _DEFAULT_LEVEL)
    if isinstance(target, PolygonMesh) and steps:
        raise BlockMeshError(
            f"--level {steps}: a locally refined mesh (polygon cells) is integrated on its own "
            "cells; leave --level out, or refine it further with blockmesh mesh FILE --refine-..."
        )
    return target.level + steps if isinstance(target, Mesh | PolygonMesh) else steps


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh integrate`` with the parsed ``args``; returns the exit code."""
    check_level_options(args)
    check_range(args.max_level, "--max-level", 0, MAX_LEVEL)
    target = resolve_target(args)
    exact = exact_integral(target, args.function) if args.exact else None
    result = _integrate(args, target)
    exact_error = None if exact is None else _difference(result.value, exact)
    if args.json:
        print_json(
            {
                "value": result.value,
                "error_estimate": result.error_estimate,
                "converged": result.converged,
                "level": result.level,
                "order": result.order,
                "rule": result.rule,
                "cells": result.cells,
                "points": result.points,
                "exact": None
                if exact is None
                else (str(exact) if isinstance(exact, Fraction) else repr(exact)),
                "exact_error": exact_error,
                "message": result.message,
            }
        )
    else:
        cells, order = result.cells, result.order
        print(f"∫∫ {printable(args.function)} dx dy over {printable(target.name)}")
        print(f"  value           {result.value!r}")
        note = "  (converged)" if args.tol is not None and result.converged else ""
        print(f"  error estimate  {result.error_estimate:.3g}{note}")
        print(f"  mesh            level {result.level}, {cells:,} cell{'s' if cells != 1 else ''}")
        print(
            f"  rule            {result.rule}, order {order} (exact to degree {2 * order - 1}), "
            f"{result.points:,} points"
        )
        if _has_curves(target):
            print(
                "  geometry        "
                + ("the curved cells (exact geometry)" if args.exact_geometry else
                   "straight cells through the nodes (--exact-geometry: the curved cells)")
            )  # fmt: skip
        elif args.exact_geometry:
            print(
                "  geometry        straight: no curved edges here (a .msh, .vtk, .mat or OpenFOAM "
                "file keeps the nodes on the curves but not the curves; .npz, .xdmf and .vtu "
                "keep them)"
            )
        if exact is not None and exact_error is not None:
            if isinstance(exact, Fraction):
                print(f"  exact           {exact}")
                print(f"                  = {_decimal(exact)}")
            else:
                print(f"  exact           {exact!r}")
            print(f"  |value - exact| {exact_error:.3g}")
    if result.converged:
        return 0
    if args.tol is not None:
        print(f"blockmesh integrate: warning: {printable(result.message)}", file=sys.stderr)
        return 1
    print(
        f"blockmesh integrate: warning: {printable(result.message)}; on the command line: a "
        "higher --level or --order, or --tol",
        file=sys.stderr,
    )
    return 0


register = registration("integrate", OPTIONS, run)
