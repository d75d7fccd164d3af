"""``blockmesh solve``: a boundary-value problem on a domain's pentagon mesh, by virtual elements.

``--equation poisson`` solves ``-div(kappa grad u) + c u = f`` (``--source``, ``--diffusion``,
``--reaction``); ``--equation elasticity`` plane linear elasticity (``--young``,
``--poisson-ratio``, ``--plane``; vector data as ``"EXPR_X, EXPR_Y"``). ``--dirichlet PATCH=EXPR``
prescribes the solution (the displacement) on a patch, ``--neumann PATCH=EXPR`` the outward flux
(the traction); other patches are natural (zero flux, traction-free). PATCH may be a comma list
of patches, or ``*``: every patch the other options do not name.

On a composite domain the coefficients and the source may differ by region: ``--diffusion
fibre=10 --diffusion matrix=1`` (likewise ``--reaction``, ``--young``, ``--poisson-ratio``,
``--source``); a bare value means every region not named. Across an interface u and the flux are
continuous (the natural conditions); a condition on an interface is refused.

``--adapt`` solves adaptively instead (:mod:`blockmesh.commands.solve_adaptive`): estimate,
mark, refine the marked cells locally, repeat until ``--tol`` or ``--max-unknowns``.
"""

from __future__ import annotations

import argparse
import re
import time
from typing import Any

import numpy as np

from blockmesh._system.memory import available_memory, process_rss
from blockmesh.commands import Option, Options, registration
from blockmesh.commands.common import (
    check_folders,
    check_level_options,
    domain_arguments,
    levels_to_add,
    print_json,
    printable,
    resolve_target,
)
from blockmesh.commands.options import (
    JSON_OPTION,
    RenamedOption,
    level_option,
    max_memory_option,
    placement_options,
    plot_option,
)
from blockmesh.commands.solve_adaptive import ADAPTIVE_OPTIONS, check_adaptive, run_adaptive
from blockmesh.domain.domain import Domain
from blockmesh.errors import BlockMeshError, SolverError
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.improve import refine_with_rule
from blockmesh.refinement.sizes import MemoryPrediction, check_fits, solve_command_predictor
from blockmesh.sizing.spec import as_size_spec
from blockmesh.vem import SOLVERS, STABILIZATIONS, solve_elasticity, solve_poisson
from blockmesh.vem.fields import scalar_field, split_pair
from blockmesh.vem.output import SOLUTION_FORMATS, write_solution

__all__ = ["OPTIONS", "register", "run"]

EQUATIONS = ("poisson", "elasticity")

#: The level solved on when none is given (as ``blockmesh mesh`` and ``blockmesh integrate``).
DEFAULT_LEVEL = 2


#: The options of ``blockmesh solve``, in the order of its ``--help``.
OPTIONS: Options = (
    *domain_arguments(),
    level_option(
        f"refinement level: every block becomes 6**L pentagons (default {DEFAULT_LEVEL}; "
        "a mesh file is solved on at its own level, refined further by --level if given; with "
        "--adapt the starting level, default 0; with --size, or a domain file with a [size] "
        "table, 0 unless given)",
    ),
    Option(
        "--size",
        "-s",
        metavar="H",
        help="solve on cells of diameter H (a number, or an expression in x and y) instead of "
        "refined blocks; with --level L too, those cells are refined L times (see blockmesh "
        "mesh --help)",
    ),
    Option("--equation", choices=EQUATIONS, default="poisson", help="the problem"),
    Option(
        "--source",
        action="append",
        default=[],
        metavar="[REGION=]EXPR",
        help="f(x, y) (poisson, default 0) or the body force 'FX, FY' (elasticity, default 0, 0); "
        "REGION=... for one region (repeatable)",
    ),
    Option(
        "--dirichlet",
        action="append",
        default=[],
        metavar="PATCH=EXPR",
        help="the solution on PATCH (repeatable); elasticity: 'UX, UY', a component may be "
        "'free'. PATCH may be a comma list ('left,right=EXPR') or * ('*=EXPR': every boundary "
        "patch no other --dirichlet or --neumann names)",
    ),
    Option(
        "--neumann",
        action="append",
        default=[],
        metavar="PATCH=EXPR",
        help="outward flux kappa du/dn on PATCH (repeatable); elasticity: the traction 'TX, TY'. "
        "PATCH as for --dirichlet (a comma list, or *)",
    ),
    Option(
        "--exact-solution",
        "--exact",
        dest="exact",
        metavar="EXPR",
        action=RenamedOption,
        help="the exact solution ('UX, UY' for elasticity): report the errors against it "
        "(--exact is the earlier spelling)",
    ),
    *(
        Option(
            flag,
            action="append",
            default=[],
            metavar=metavar,
            help=f"{text}; REGION=... for one region of a composite domain (repeatable)",
        )
        for flag, metavar, text in (
            ("--diffusion", "[REGION=]EXPR", "kappa(x, y) (1)"),
            ("--reaction", "[REGION=]EXPR", "c(x, y) (0)"),
            ("--young", "[REGION=]E", "elasticity: E (1)"),
            ("--poisson-ratio", "[REGION=]NU", "elasticity: nu (0.3)"),
        )
    ),
    Option("--plane", choices=("stress", "strain"), default="stress", help="elasticity: the model"),
    Option(
        "--constraint",
        choices=("mean", "rigid"),
        help="pure Neumann problems: zero mean (poisson) or no rigid motion (elasticity)",
    ),
    *placement_options("the mesh"),
    Option("--order", type=int, default=3, metavar="N", help="quadrature order of the loads (3)"),
    Option(
        "--stabilization",
        choices=tuple(STABILIZATIONS),
        help="VEM stabilisation (default trace; identity is for poisson only)",
    ),
    Option("--stabilization-scale", type=float, default=1.0, metavar="A", help="its factor (1)"),
    Option(
        "--solver",
        choices=SOLVERS,
        default="direct",
        help="linear solver: direct (sparse LU; its memory grows as n log n) or amg (algebraic "
        "multigrid, for large problems; needs pyamg)",
    ),
    max_memory_option("problems"),
    Option("-o", "--output", metavar="PATH", help="write the solution (.vtu, or .xdmf with a .h5)"),
    plot_option("the solution"),
    ADAPTIVE_OPTIONS,
    JSON_OPTION,
)


#: One ``--dirichlet`` or ``--neumann`` option: (flag, the option's text, patches, expression);
#: patches is ``"*"`` or the names as written.
Condition = tuple[str, str, str | list[str], str]


def _conditions(args: argparse.Namespace) -> list[Condition]:
    """The boundary-condition options, their syntax checked (the patches are checked later)."""
    found: list[Condition] = []
    for flag, items in (("--dirichlet", args.dirichlet), ("--neumann", args.neumann)):
        for item in items:
            patch, sign, expression = item.partition("=")
            patch, expression = patch.strip(), expression.strip()
            if not sign or not patch or not expression:
                raise BlockMeshError(
                    f"{flag} {item!r}: write PATCH=EXPR, e.g. {flag} left=0 (or "
                    f"{flag} 'left,right=0', or {flag} '*=0' for every other patch)"
                )
            found.append((flag, item, patch, expression))
    return found


def _patch_values(
    conditions: list[Condition],
    patch_names: tuple[str, ...],
    interface_names: tuple[str, ...] = (),
) -> tuple[dict[str, str], dict[str, str]]:
    """The Dirichlet and Neumann values by patch: lists split, ``*`` given the patches left.

    A name that is a patch of the mesh is taken whole (commas and all); otherwise a comma list.
    ``*`` stands for boundary patches only; an interface named is refused (SolverError).
    """
    values: dict[str, dict[str, str]] = {"--dirichlet": {}, "--neumann": {}}
    seen: dict[str, str] = {}
    star: Condition | None = None
    for flag, item, patch, expression in conditions:
        if patch == "*":
            if star is not None:
                raise BlockMeshError(
                    f"'*' is given twice ({star[0]} {star[1]} and {flag} {item}); '*' stands for "
                    "every patch the other options do not name, once"
                )
            star = (flag, item, patch, expression)
            continue
        whole = patch in patch_names or patch in interface_names
        names = [patch] if whole else [n.strip() for n in str(patch).split(",")]
        for name in names:
            if not name:
                raise BlockMeshError(f"{flag} {item!r}: an empty patch name in the list")
            if name in interface_names and name not in patch_names:
                raise SolverError(
                    f"{flag} {item!r}: {name!r} is an interface (an internal patch between two "
                    "regions), not a boundary patch; across an interface u and the flux are "
                    "continuous by themselves. Give conditions on the boundary patches: "
                    f"{', '.join(patch_names)}"
                )
            if name not in patch_names:
                raise BlockMeshError(
                    f"{flag} {item!r}: no patch {name!r}; the patches are {', '.join(patch_names)}"
                )
            if name in seen:
                raise BlockMeshError(
                    f"patch {name!r} is given twice ({seen[name]} and {flag} {item}); give "
                    "each patch one condition"
                )
            seen[name] = f"{flag} {item}"
            values[flag][name] = expression
    if star is not None:
        for name in patch_names:
            if name not in seen:
                values[star[0]][name] = star[3]
    return values["--dirichlet"], values["--neumann"]


#: The value of a per-region option given for no region (and never given).
_DEFAULTS = {"--diffusion": "1", "--reaction": "0", "--young": "1", "--poisson-ratio": "0.3"}
_REGION_ITEM = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_.\-]*)\s*=(.*)$")


def region_option(items: list[str], flag: str, default: str | None) -> Any:
    """A per-region option's value: one text, or a mapping region -> text (``"*"``: the rest).

    ``NAME=VALUE`` gives one region's value, a bare ``VALUE`` every region not named.

    Examples
    --------
    >>> region_option(["fibre=10", "1"], "--diffusion", "1")
    {'fibre': '10', '*': '1'}
    >>> region_option([], "--diffusion", "1")
    '1'
    """
    bare: str | None = None
    named: dict[str, str] = {}
    for item in items:
        match = _REGION_ITEM.match(item)
        if match is None:
            if bare is not None:
                raise BlockMeshError(
                    f"{flag} is given twice for every region ({bare!r} and {item!r}); give one "
                    f"value, and REGION=VALUE for the regions that differ"
                )
            bare = item.strip()
            continue
        region, value = match.group(1), match.group(2).strip()
        if not value:
            raise BlockMeshError(f"{flag} {item!r}: write REGION=VALUE, e.g. {flag} fibre=10")
        if region in named:
            raise BlockMeshError(f"{flag} gives the region {region!r} twice; give it once")
        named[region] = value
    if not named:
        return bare if bare is not None else default
    if bare is not None or default is not None:
        named["*"] = bare if bare is not None else default  # type: ignore[assignment]
    return named


def _numbers(value: Any, flag: str) -> Any:
    """A per-region option's texts as numbers (``--young``, ``--poisson-ratio``)."""

    def number(text: str) -> float:
        try:
            return float(text)
        except ValueError:
            raise BlockMeshError(f"{flag} takes numbers, got {text!r}") from None

    if isinstance(value, dict):
        return {region: number(text) for region, text in value.items()}
    return number(value)


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
    check_adaptive(args)
    check_folders(args.output, args.plot)


def _solve(args: argparse.Namespace, mesh, dirichlet: dict, neumann: dict):
    source = region_option(args.source, "--source", None)
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
            source if source is not None else "0",
            diffusion=region_option(args.diffusion, "--diffusion", _DEFAULTS["--diffusion"]),
            reaction=region_option(args.reaction, "--reaction", _DEFAULTS["--reaction"]),
            dirichlet=dirichlet,
            neumann=neumann,
            **common,
        )
    young = region_option(args.young, "--young", _DEFAULTS["--young"])
    ratio = region_option(args.poisson_ratio, "--poisson-ratio", _DEFAULTS["--poisson-ratio"])
    return solve_elasticity(
        mesh,
        young=_numbers(young, "--young"),
        poisson=_numbers(ratio, "--poisson-ratio"),
        plane=args.plane,
        source=source if source is not None else "0, 0",
        dirichlet=dirichlet,
        neumann=neumann,
        **common,
    )


def _nodal_error(solution, exact: str, equation: str) -> np.ndarray:
    x, y = solution.mesh.points.T
    if equation == "poisson":
        return solution.values - scalar_field(exact, "exact solution")(x, y)
    parts = split_pair(exact, "exact displacement")
    u = np.column_stack([scalar_field(p, "exact displacement")(x, y) for p in parts])
    return np.column_stack([solution.displacement - u, np.zeros(x.size)])


def _check_memory(target, steps: int, args: argparse.Namespace) -> MemoryPrediction:
    """The predicted peak of the whole solve; ResourceError before anything big is allocated."""
    predict = solve_command_predictor(
        target,
        equation=args.equation,
        solver=args.solver,
        smooth=args.smooth,
        plot=bool(args.plot),
    )
    given = args.max_memory
    return check_fits(
        predict,
        steps,
        given if given is not None else available_memory() + process_rss(),
        what=target.name or "the mesh",
        offset=target.level if isinstance(target, Mesh) else 0,
        source="--max-memory" if given is not None else "the memory available now",
    )


def _sized(target: Domain | Mesh | PolygonMesh, size: str | None) -> Domain | Mesh | PolygonMesh:
    """The domain cut into cells of ``--size`` (a number or an expression) when given."""
    if size is None:
        return target
    if not isinstance(target, Domain):
        raise BlockMeshError(
            f"--size cuts a domain into cells of a size; {target.name or 'this'} is a mesh "
            "(refine it with --level, or give the domain it came from)"
        )
    try:
        value: float | str = float(size)
    except ValueError:
        value = size
    return target.with_size(as_size_spec(value, source="--size"))


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh solve`` with the parsed ``args``; returns the exit code."""
    _check(args)
    conditions = _conditions(args)
    domain = _sized(resolve_target(args), args.size)
    dirichlet, neumann = _patch_values(conditions, domain.patch_names, domain.interface_names)
    if args.adapt:
        start = levels_to_add(args.level, domain, 0)
        mesh = refine_with_rule(
            domain, start, rule=args.quality_rule, smooth=args.smooth, max_memory=args.max_memory
        )
        return run_adaptive(args, mesh, lambda m: _solve(args, m, dirichlet, neumann))
    sized = isinstance(domain, Domain) and domain.size_field is not None
    steps = levels_to_add(args.level, domain, 0 if sized else DEFAULT_LEVEL)
    prediction = _check_memory(domain, steps, args)
    started = time.perf_counter()
    mesh = refine_with_rule(
        domain, steps, rule=args.quality_rule, smooth=args.smooth, max_memory=args.max_memory
    )
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
        "placement": args.quality_rule,
        "quality_rule": args.quality_rule,  # the earlier key, kept
        "cells": mesh.n_cells,
        "nodes": mesh.n_points,
        "dof": info.dof,
        "nonzeros": info.nonzeros,
        "solver": info.solver,
        "iterations": info.iterations,
        "residual": info.residual,
        "seconds": seconds,
        "solve_seconds": info.seconds,
        "predicted_peak_bytes": prediction.peak_bytes,
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
        report["output"] = str(write_solution(solution, args.output, extra_point_data=extra))
    if args.plot:
        from blockmesh.vem.plot import plot_solution

        report["plot"] = str(plot_solution(solution, args.plot))
    if args.json:
        print_json(report)
    else:
        _print_report(report, args)
    return 0


register = registration("solve", OPTIONS, run)


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
