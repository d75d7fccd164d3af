"""``blockmesh solve``: a boundary-value problem on a domain's pentagon mesh, by virtual elements.

``--equation poisson`` solves ``-div(kappa grad u) + c u = f`` (``--source``, ``--diffusion``,
``--reaction``); ``--equation elasticity`` plane linear elasticity (``--young``,
``--poisson-ratio``, ``--plane``; vector data as ``"EXPR_X, EXPR_Y"``). ``--dirichlet PATCH=EXPR``
prescribes the solution (the displacement) on a patch, ``--neumann PATCH=EXPR`` the outward flux
(the traction); other patches are natural (zero flux, traction-free).
"""

from __future__ import annotations

import argparse
import re
import time
from typing import Any

import numpy as np

from ..errors import BlockMeshError, SolverError
from ..improve import QUALITY_RULES, refine_with_rule
from ..vem import SOLVERS, STABILIZATIONS, solve_elasticity, solve_poisson
from ..vem.fields import split_pair
from ..vem.output import SOLUTION_FORMATS
from ._common import (
    add_domain_arguments,
    check_folders,
    check_level_options,
    print_json,
    printable,
    resolve_domain,
)

__all__ = ["register", "run"]

EQUATIONS = ("poisson", "elasticity")

#: The level solved on when none is given (as ``blockmesh mesh`` and ``blockmesh integrate``).
DEFAULT_LEVEL = 2


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``solve`` subcommand and its options to ``subparsers``."""
    parser = subparsers.add_parser(
        "solve",
        help="solve a Poisson or elasticity problem on the mesh (virtual elements)",
        description="Solve a diffusion-reaction (Poisson) or plane elasticity problem on "
        "DOMAIN's pentagon mesh at LEVEL with lowest-order virtual elements; report unknowns, "
        "cost and, with --exact, the errors; write the solution for ParaView.",
        epilog='example: blockmesh solve square --level 3 --source "2*pi^2*sin(pi*x)*sin(pi*y)" '
        "--dirichlet left=0 --dirichlet right=0 --dirichlet top=0 --dirichlet bottom=0 "
        '--exact "sin(pi*x)*sin(pi*y)"',
    )
    add_domain_arguments(parser)
    parser.add_argument(
        "--level",
        "-l",
        type=int,
        default=DEFAULT_LEVEL,
        metavar="L",
        help=f"refinement level: every block becomes 6**L pentagons (default {DEFAULT_LEVEL})",
    )
    parser.add_argument("--equation", choices=EQUATIONS, default="poisson", help="the problem")
    parser.add_argument(
        "--source",
        metavar="EXPR",
        help="f(x, y) (poisson, default 0) or the body force 'FX, FY' (elasticity, default 0, 0)",
    )
    parser.add_argument(
        "--dirichlet",
        action="append",
        default=[],
        metavar="PATCH=EXPR",
        help="the solution on PATCH (repeatable); elasticity: 'UX, UY', a component may be 'free'",
    )
    parser.add_argument(
        "--neumann",
        action="append",
        default=[],
        metavar="PATCH=EXPR",
        help="outward flux kappa du/dn on PATCH (repeatable); elasticity: the traction 'TX, TY'",
    )
    parser.add_argument(
        "--exact", metavar="EXPR", help="exact solution ('UX, UY' for elasticity): report errors"
    )
    parser.add_argument("--diffusion", default="1", metavar="EXPR", help="kappa(x, y) (1)")
    parser.add_argument("--reaction", default="0", metavar="EXPR", help="c(x, y) (0)")
    parser.add_argument("--young", type=float, default=1.0, metavar="E", help="elasticity: E (1)")
    parser.add_argument(
        "--poisson-ratio", type=float, default=0.3, metavar="NU", help="elasticity: nu (0.3)"
    )
    parser.add_argument(
        "--plane", choices=("stress", "strain"), default="stress", help="elasticity: the model"
    )
    parser.add_argument(
        "--constraint",
        choices=("mean", "rigid"),
        help="pure Neumann problems: zero mean (poisson) or no rigid motion (elasticity)",
    )
    parser.add_argument(
        "--smooth", type=int, default=0, metavar="K", help="Laplacian sweeps per level (0)"
    )
    parser.add_argument(
        "--quality-rule",
        choices=QUALITY_RULES,
        default="paper",
        help="node placement of the mesh: the paper's (default), or optimized or angles after "
        "every level (see blockmesh mesh --help)",
    )
    parser.add_argument(
        "--order", type=int, default=3, metavar="N", help="quadrature order of the loads (3)"
    )
    parser.add_argument(
        "--stabilization",
        choices=tuple(STABILIZATIONS),
        help="VEM stabilisation (default trace; identity is for poisson only)",
    )
    parser.add_argument(
        "--stabilization-scale", type=float, default=1.0, metavar="A", help="its factor (1)"
    )
    parser.add_argument("--solver", choices=SOLVERS, default="direct", help="linear solver")
    parser.add_argument(
        "-o", "--output", metavar="PATH", help="write the solution (.vtu, or .xdmf with a .h5)"
    )
    parser.add_argument("--plot", metavar="PNG", help="draw the solution")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(run=run)


def _patch_values(items: list[str], flag: str, seen: dict[str, str]) -> dict[str, str]:
    values: dict[str, str] = {}
    for item in items:
        patch, sign, expression = item.partition("=")
        patch, expression = patch.strip(), expression.strip()
        if not sign or not patch or not expression:
            raise BlockMeshError(f"{flag} {item!r}: write PATCH=EXPR, e.g. {flag} left=0")
        if patch in seen:
            raise BlockMeshError(
                f"patch {patch!r} is given twice ({seen[patch]} and {flag} {item}); give each "
                "patch one condition"
            )
        seen[patch] = f"{flag} {item}"
        values[patch] = expression
    return values


def _check(args: argparse.Namespace) -> None:
    check_level_options(args)
    if args.output and not args.output.lower().endswith((*SOLUTION_FORMATS, ".xmf")):
        raise BlockMeshError(
            f"--output {args.output}: a solution is written to .vtu (ParaView) or .xdmf"
        )
    wanted = {"poisson": "mean", "elasticity": "rigid"}[args.equation]
    if args.constraint not in (None, wanted):
        raise BlockMeshError(
            f"--constraint {args.constraint} is for the other equation; "
            f"{args.equation} takes --constraint {wanted}"
        )
    if args.equation == "elasticity" and args.stabilization == "identity":
        raise BlockMeshError(
            "--stabilization identity is for poisson; elasticity takes trace or diagonal"
        )
    check_folders(args.output, args.plot)


def _solve(args: argparse.Namespace, mesh, dirichlet: dict, neumann: dict):
    common: dict[str, Any] = {
        "order": args.order,
        "stabilization_scale": args.stabilization_scale,
        "solver": args.solver,
        "constraint": args.constraint,
    }
    if args.stabilization:
        common["stabilization"] = args.stabilization
    if args.equation == "poisson":
        return solve_poisson(
            mesh,
            args.source or "0",
            diffusion=args.diffusion,
            reaction=args.reaction,
            dirichlet=dirichlet,
            neumann=neumann,
            **common,
        )
    return solve_elasticity(
        mesh,
        young=args.young,
        poisson=args.poisson_ratio,
        plane=args.plane,
        body_force=args.source or "0, 0",
        displacement=dirichlet,
        traction=neumann,
        **common,
    )


def _nodal_error(solution, exact: str, equation: str) -> np.ndarray:
    from ..vem.fields import scalar_field

    x, y = solution.mesh.points.T
    if equation == "poisson":
        return solution.values - scalar_field(exact, "exact solution")(x, y)
    parts = split_pair(exact, "exact displacement")
    u = np.column_stack([scalar_field(p, "exact displacement")(x, y) for p in parts])
    return np.column_stack([solution.displacement - u, np.zeros(x.size)])


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh solve`` with the parsed ``args``; returns the exit code."""
    _check(args)
    seen: dict[str, str] = {}
    dirichlet = _patch_values(args.dirichlet, "--dirichlet", seen)
    neumann = _patch_values(args.neumann, "--neumann", seen)
    domain = resolve_domain(args)
    started = time.perf_counter()
    mesh = refine_with_rule(domain, args.level, rule=args.quality_rule, smooth=args.smooth)
    try:
        solution = _solve(args, mesh, dirichlet, neumann)
    except SolverError as error:  # the library names its keyword; here the flag is meant
        raise SolverError(re.sub(r"constraint='(\w+)'", r"--constraint \1", str(error))) from None
    seconds = time.perf_counter() - started
    info = solution.info
    report: dict[str, Any] = {
        "domain": domain.name,
        "equation": args.equation,
        "level": mesh.level,
        "quality_rule": args.quality_rule,
        "cells": mesh.n_cells,
        "nodes": mesh.n_points,
        "dof": info.dof,
        "nonzeros": info.nonzeros,
        "solver": info.solver,
        "iterations": info.iterations,
        "residual": info.residual,
        "seconds": seconds,
        "solve_seconds": info.seconds,
    }
    if args.equation == "poisson":
        report["u_min"] = float(solution.values.min())
        report["u_max"] = float(solution.values.max())
    else:
        report["max_displacement"] = float(np.hypot(*solution.displacement.T).max())
        report["max_von_mises"] = float(solution.von_mises.max())
    extra = {}
    if args.exact:
        errors = solution.errors(args.exact)
        report.update(errors.as_dict())
        extra["error"] = _nodal_error(solution, args.exact, args.equation)
    if args.output:
        from ..vem.output import write_solution

        report["output"] = str(write_solution(solution, args.output, extra_point_data=extra))
    if args.plot:
        from ..vem.plot import plot_solution

        report["plot"] = str(plot_solution(solution, args.plot))
    if args.json:
        print_json(report)
    else:
        _print_report(report, args)
    return 0


def _print_report(report: dict[str, Any], args: argparse.Namespace) -> None:
    print(
        f"{report['domain']}: {report['equation']} on level {report['level']}, "
        f"{report['cells']:,} cells, {report['nodes']:,} nodes"
    )
    iterations = "" if report["iterations"] is None else f", {report['iterations']} iterations"
    print(
        f"  unknowns {report['dof']:,}, non-zeros {report['nonzeros']:,}; {report['solver']} "
        f"solve{iterations}, residual {report['residual']:.1e}; {report['seconds']:.3f} s in all"
    )
    if "u_min" in report:
        print(f"  u in [{report['u_min']:.6g}, {report['u_max']:.6g}]")
    else:
        print(
            f"  largest displacement {report['max_displacement']:.6g}, largest von Mises stress "
            f"{report['max_von_mises']:.6g}"
        )
    if args.exact:
        print(
            f"  errors against {args.exact}: L2 {report['l2_error']:.3e} (relative "
            f"{report['l2_relative']:.3e}), H1 {report['h1_error']:.3e} (relative "
            f"{report['h1_relative']:.3e})"
        )
    for given, label in ((args.output, "solution"), (args.plot, "plot")):
        if given:
            print(f"  wrote {label} {printable(given)}")
