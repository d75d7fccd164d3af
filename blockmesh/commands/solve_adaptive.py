r"""``blockmesh solve --adapt``: solve, estimate, mark, refine the marked cells; repeat.

The options of the adaptive loop (:func:`blockmesh.vem.adaptive.solve_adaptive`) and its report:
one progress line per step (unknowns, estimator, and with ``--exact-solution`` the errors and the
effectivity), then the final mesh and solution. ``--json`` prints one object whose ``history``
lists every step.

Example, the L-shape's corner singularity::

    blockmesh solve l-shape --adapt --max-unknowns 20000 --source 0 --dirichlet "*=U" \
        --exact-solution U

with ``U = ((x-1)^2+(y-1)^2)^(1/3)*cos(2/3*atan2(x-y, 2-x-y))`` (``r^(2/3) sin(2θ/3)`` about the
re-entrant corner).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from typing import Any

from blockmesh.commands import Group, Option
from blockmesh.commands.common import check_folders, print_json, printable
from blockmesh.commands.options import scheme_option
from blockmesh.errors import BlockMeshError
from blockmesh.io import check_options, format_for_path, write
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.vem.adaptive import DEFAULT_MAX_STEPS, AdaptiveStep, solve_adaptive
from blockmesh.vem.fields import split_pair
from blockmesh.vem.output import write_solution

__all__ = ["ADAPTIVE_OPTIONS", "check_adaptive", "run_adaptive"]


#: The ``--adapt`` options of ``blockmesh solve``, a group of their own in its ``--help``.
ADAPTIVE_OPTIONS = Group(
    "adaptive solving",
    "--adapt: solve, estimate the error of every cell (residual estimator: element "
    "residual, flux jumps, stabilisation term), mark the cells holding THETA of it "
    "(Doerfler), split them (their new edge nodes hang on the coarse neighbours), repeat",
    Option("--adapt", action="store_true", help="solve adaptively"),
    Option("--tol", type=float, metavar="T", help="stop when the estimator is at most T"),
    Option(
        "--max-unknowns",
        type=int,
        metavar="N",
        help="stop before the unknowns would exceed N",
    ),
    Option(
        "--theta",
        type=float,
        default=0.5,
        metavar="THETA",
        help="Doerfler's bulk fraction in (0, 1] (default 0.5)",
    ),
    scheme_option("--scheme"),
    Option(
        "--max-steps",
        type=int,
        default=DEFAULT_MAX_STEPS,
        metavar="K",
        help=f"stop after K solves (default {DEFAULT_MAX_STEPS})",
    ),
    Option(
        "--mesh-output",
        metavar="PATH",
        help="write the final mesh (any mesh format: .vtu .xdmf .msh .mat .npz, OpenFOAM)",
    ),
    Option(
        "--convergence",
        metavar="PNG",
        help="draw the estimator and errors against the unknowns (log-log)",
    ),
)


def check_adaptive(args: argparse.Namespace) -> None:
    """The adaptive options, checked before anything is solved."""
    given = [
        flag
        for flag, value in (
            ("--tol", args.tol),
            ("--max-unknowns", args.max_unknowns),
            ("--mesh-output", args.mesh_output),
            ("--convergence", args.convergence),
        )
        if value is not None
    ]
    if not args.adapt:
        changed = args.theta != 0.5 or args.max_steps != DEFAULT_MAX_STEPS
        if given or changed or args.scheme != "pentagons":
            flag = given[0] if given else "--theta/--max-steps/--scheme"
            raise BlockMeshError(f"{flag} belongs to adaptive solving: add --adapt")
        return
    if args.tol is not None and not args.tol > 0:
        raise BlockMeshError(f"--tol must be > 0, got {args.tol}")
    if args.max_unknowns is not None and args.max_unknowns < 1:
        raise BlockMeshError(f"--max-unknowns must be 1 or more, got {args.max_unknowns}")
    if not 0 < args.theta <= 1:
        raise BlockMeshError(f"--theta must be in (0, 1], got {args.theta}")
    if args.max_steps < 1:
        raise BlockMeshError(f"--max-steps must be 1 or more, got {args.max_steps}")
    if args.tol is None and args.max_unknowns is None and args.max_steps == DEFAULT_MAX_STEPS:
        raise BlockMeshError(
            "--adapt needs a stopping rule: --tol T (estimator), --max-unknowns N or --max-steps K"
        )
    if args.smooth or args.quality_rule != "paper":
        raise BlockMeshError(
            "--adapt refines by the paper's rule; --smooth and --quality-rule apply to uniform "
            "meshes"
        )
    if args.mesh_output:
        check_options(format_for_path(args.mesh_output))
    check_folders(args.mesh_output, args.convergence)


def _line(step: AdaptiveStep) -> str:
    text = (
        f"  step {step.step:>2}: {step.cells:>8,} cells {step.unknowns:>9,} unknowns  "
        f"estimator {step.estimator:.3e}"
    )
    if step.h1_error is not None:
        text += (
            f"  H1 error {step.h1_error:.3e}  L2 error {step.l2_error:.3e}  "
            f"effectivity {step.effectivity:.2f}"
        )
    if step.marked:
        text += f"  marked {step.marked:,}"
    return text


def run_adaptive(
    args: argparse.Namespace, mesh: Mesh | PolygonMesh, solve: Callable[[PolygonMesh], Any]
) -> int:
    """Run the adaptive loop of ``blockmesh solve --adapt`` from ``mesh``; the exit code."""
    started = time.perf_counter()
    exact: Any = args.exact
    if exact is not None and args.equation == "elasticity":
        exact = split_pair(exact, "exact displacement")
    if not args.json:
        print(
            f"{printable(mesh.name)}: adaptive {args.equation} from level {mesh.level} "
            f"({mesh.n_cells:,} cells), theta {args.theta}"
        )
    live = not args.json or sys.stderr.isatty()

    def progress(step: AdaptiveStep) -> None:
        if not live:
            return
        stream = sys.stdout if not args.json else sys.stderr
        print(_line(step), file=stream, flush=True)

    run = solve_adaptive(
        mesh,
        solve,
        tol=args.tol,
        max_unknowns=args.max_unknowns,
        max_steps=args.max_steps,
        theta=args.theta,
        exact=exact,
        progress=progress,
        scheme=args.scheme,
    )
    last = run.history[-1]
    report: dict[str, Any] = {
        "domain": mesh.name,
        "equation": args.equation,
        "adaptive": True,
        "theta": args.theta,
        "scheme": args.scheme,
        "start_level": mesh.level,
        "stopped": run.stopped,
        "steps": len(run.history),
        "cells": last.cells,
        "nodes": last.nodes,
        "dof": last.unknowns,
        "estimator": last.estimator,
        "rates": run.rates(),
        "hanging_nodes": last.hanging_nodes,
        "max_vertices": last.max_vertices,
        "seconds": time.perf_counter() - started,
        "history": [step.as_dict() for step in run.history],
    }
    if last.h1_error is not None:
        report.update(
            {
                "h1_error": last.h1_error,
                "l2_error": last.l2_error,
                "energy_error": last.energy_error,
                "effectivity": last.effectivity,
                "effectivity_range": [
                    min(s.effectivity for s in run.history if s.effectivity is not None),
                    max(s.effectivity for s in run.history if s.effectivity is not None),
                ],
            }
        )
    if args.output:
        report["output"] = str(write_solution(run.solution, args.output))
    if args.mesh_output:
        report["mesh_output"] = str(write(run.mesh, args.mesh_output))
    if args.plot:
        from blockmesh.vem.plot import plot_solution

        report["plot"] = str(plot_solution(run.solution, args.plot))
    if args.convergence:
        from blockmesh.vem.plot import plot_convergence

        report["convergence"] = str(
            plot_convergence(
                run.history, args.convergence, title=f"{mesh.name}: adaptive {args.equation}"
            )
        )
    if args.json:
        print_json(report)
        return 0
    if run.stopped == "tol":
        why = f"the estimator reached --tol {args.tol:g}"
    elif run.stopped == "max_unknowns":
        why = f"the next step would exceed --max-unknowns {args.max_unknowns:,}"
    else:
        why = f"--max-steps {args.max_steps} reached"
    rates = ", ".join(f"{k} {v:.2f}" for k, v in report["rates"].items())
    print(
        f"  stopped: {why}; {last.cells:,} cells of up to {last.max_vertices} vertices, "
        f"{last.hanging_nodes:,} hanging nodes; rate per unknown over the last steps: "
        f"{rates or '-'}; {report['seconds']:.2f} s"
    )
    for key, label in (
        ("output", "solution"),
        ("mesh_output", "mesh"),
        ("plot", "plot"),
        ("convergence", "convergence plot"),
    ):
        if key in report:
            print(f"  wrote {label} {report[key]}")
    return 0
