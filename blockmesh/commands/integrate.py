"""``blockmesh integrate``: integrate a function over a domain's pentagon mesh."""

from __future__ import annotations

import argparse
import math
import sys
from decimal import Decimal, localcontext
from fractions import Fraction

from ..errors import BlockMeshError
from ..exact import exact_integral
from ..quadrature import RULES, integrate, integrate_to_tolerance, rule_info
from ._common import add_domain_arguments, print_json, resolve_domain
from ._partitions import add_partition_arguments, check_partition_arguments

__all__ = ["register", "run"]

_DEFAULT_LEVEL = 2
_DEFAULT_ORDER = 10


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``integrate`` subcommand and its options to ``subparsers``."""
    parser = subparsers.add_parser(
        "integrate",
        help="integrate f(x, y) over a domain with a composite Gauss rule",
        description="Integrate a function of x and y over the domain's pentagon mesh at a level, "
        "with the paper's composite Gauss-Legendre rule (or a cheaper one), or to a tolerance "
        "(--tol picks the order and level). --exact adds the exact integral of a polynomial.",
        epilog='example: blockmesh integrate sp --function "(x^4 + y^3)/(1 + x^2)" --level 3',
    )
    add_domain_arguments(parser)
    parser.add_argument(
        "--function",
        "-f",
        required=True,
        metavar="EXPR",
        help="f(x, y): numbers, x, y, pi, e, + - * / ^ (or **), and sin cos tan exp log sqrt abs "
        "... (see blockmesh.expr.FUNCTIONS)",
    )
    parser.add_argument(
        "--level",
        type=int,
        metavar="L",
        help=f"refinement level (default {_DEFAULT_LEVEL}; with --tol: the starting level, "
        "default 0)",
    )
    parser.add_argument(
        "--order",
        type=int,
        metavar="N",
        help=f"order n of the rule, exact to degree 2n-1 (default {_DEFAULT_ORDER}; with --tol: "
        "the starting order, default 2)",
    )
    parser.add_argument(
        "--rule",
        choices=tuple(RULES),
        help="paper: the paper's rule (default); jacobi, fan: fewer points, same degree "
        "(jacobi is the default with --tol)",
    )
    parser.add_argument(
        "--exact",
        action="store_true",
        help="also the exact integral over the domain (polynomials only), as a fraction",
    )
    parser.add_argument(
        "--tol",
        type=float,
        metavar="T",
        help="integrate to an absolute error estimate <= T, choosing order and level",
    )
    parser.add_argument(
        "--max-level", type=int, default=6, metavar="L", help="with --tol: highest level (6)"
    )
    add_partition_arguments(parser, "integrate")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(run=run)


def _decimal(value: Fraction, digits: int = 22) -> str:
    with localcontext() as context:
        context.prec = digits
        return str(Decimal(value.numerator) / Decimal(value.denominator))


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh integrate`` with the parsed ``args``; returns the exit code."""
    partitioned = check_partition_arguments(args)
    if partitioned and args.tol is not None:
        raise BlockMeshError("--partitions integrates at one --level and --order, not to --tol")
    domain = resolve_domain(args)
    exact = exact_integral(domain, args.function) if args.exact else None
    converged = True
    if args.tol is not None:
        result = integrate_to_tolerance(
            domain,
            args.function,
            args.tol,
            rule=args.rule or "jacobi",
            level=args.level,
            start_order=args.order or 2,
            max_level=args.max_level,
        )
        value, level, order, rule = result.value, result.level, result.order, result.rule
        cells, points, estimate = result.cells, result.points, result.error_estimate
        converged = result.converged
        message = result.message
    else:
        level = _DEFAULT_LEVEL if args.level is None else args.level
        order = _DEFAULT_ORDER if args.order is None else args.order
        rule = args.rule or "paper"
        if partitioned:  # each worker integrates over its partition; the values are added
            from ..distributed import integrate as integrate_partitions

            value = integrate_partitions(
                domain, args.function, level=level, order=order, rule=rule,
                partitions=args.partitions, workers=args.workers, scheduler=args.scheduler,
            )  # fmt: skip
        else:
            value = integrate(domain, args.function, order=order, level=level, rule=rule)
        cells = domain.n_blocks * 6**level
        points = cells * rule_info(rule, order).points_per_cell
        estimate = abs(value - float(exact)) if exact is not None else None
        message = ""

    if args.json:
        payload: dict = {
            "value": value,
            "level": level,
            "order": order,
            "rule": rule,
            "cells": cells,
            "points": points,
        }
        if estimate is not None and math.isfinite(estimate):
            payload["error_estimate"] = estimate
        if args.tol is not None:
            payload["converged"] = converged
        if exact is not None:
            payload["exact"] = str(exact) if isinstance(exact, Fraction) else repr(exact)
        print_json(payload)
    else:
        print(f"∫∫ {args.function} dx dy over {domain.name}")
        print(f"  value           {value!r}")
        print(f"  mesh            level {level}, {cells:,} cell{'s' if cells != 1 else ''}")
        print(
            f"  rule            {rule}, order {order} (exact to degree {2 * order - 1}), "
            f"{points:,} points"
        )
        if args.tol is not None:
            print(f"  error estimate  {estimate:.3g}  ({message})")
        if exact is not None:
            if isinstance(exact, Fraction):
                print(f"  exact           {exact}")
                print(f"                  = {_decimal(exact)}")
            else:
                print(f"  exact           {exact!r}")
            print(f"  |value - exact| {abs(value - float(exact)):.3g}")
    if not converged:
        print(f"blockmesh integrate: warning: {message}", file=sys.stderr)
        return 1
    return 0
