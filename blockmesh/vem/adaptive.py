"""Adaptive solving: solve, estimate, mark (Dörfler), refine the marked cells, repeat.

:func:`solve_adaptive` runs the loop of an adaptive finite element code on blockmesh's polygon
meshes. Every step solves the problem with the lowest-order virtual elements, computes the
residual indicators of :mod:`blockmesh.vem.estimate`, marks the fewest cells whose indicators
hold the fraction ``theta`` of the estimator's square (Dörfler's bulk criterion), and splits them
by local refinement (:func:`blockmesh.refine` with ``cells=``; marked pentagons into the paper's
six, other polygons into corner pentagons and a central polygon; new edge nodes hang on the
coarse neighbours, at most one per side). The virtual element method takes the resulting cells of
6 to 11 vertices as they are.

The loop stops when the estimator reaches ``tol``, when the next refinement would take the
unknowns above ``max_unknowns`` (predicted from the marked set before anything is built), or
after ``max_steps`` solves. Each step's record (:class:`AdaptiveStep`) holds the unknowns, the
estimator and its parts and, with an exact solution, the errors and the effectivity
``estimator / error`` (in the energy norm, which for ``-Δu = f`` is the H1 seminorm).

Examples
--------
>>> import blockmesh
>>> from blockmesh.vem import solve_poisson
>>> mesh = blockmesh.load_domain("l-shape").mesh(0)
>>> corner = "((x-1)^2+(y-1)^2)^(1/3)*cos(2/3*atan2(x-y, 2-x-y))"
>>> def solve(m):
...     return solve_poisson(m, 0, dirichlet={p: corner for p in m.patch_names})
>>> run = solve_adaptive(mesh, solve, max_unknowns=800, exact=corner)
>>> [s.unknowns for s in run.history][:3]
[27, 45, 71]
>>> run.history[-1].h1_error < run.history[0].h1_error / 3
True
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from blockmesh.checks import whole_number
from blockmesh.errors import ArgumentError
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh, as_polygon_mesh
from blockmesh.refinement.local import (
    check_scheme,
    close_marking,
    predict_local_size,
    refine_marked,
)
from blockmesh.vem.elasticity import ElasticitySolution
from blockmesh.vem.estimate import ErrorEstimate, estimate_error
from blockmesh.vem.poisson import PoissonSolution

__all__ = ["AdaptiveResult", "AdaptiveStep", "dorfler_marking", "solve_adaptive"]

Solution = PoissonSolution | ElasticitySolution

#: Steps (solves) of the loop when neither a tolerance nor an unknown count stops it sooner.
DEFAULT_MAX_STEPS = 40


@dataclass(frozen=True)
class AdaptiveStep:
    """One step of the adaptive loop.

    Attributes
    ----------
    step : int
        0 for the first solve.
    cells, nodes, unknowns : int
        The mesh's cells and nodes, and the unknowns of the solve.
    estimator : float
        ``η = (Σ η_E²)^(1/2)``.
    residual, jump, stabilization : float
        The parts of the estimator (square roots of their sums).
    marked : int
        Cells marked for the next step (0 on the last).
    hanging_nodes : int
        Nodes that are straight vertices of a coarser cell.
    max_vertices : int
        The most vertices of a cell.
    seconds : float
        Time of the step (solve, estimate, marking, refinement).
    h1_error, l2_error, energy_error, effectivity : float or None
        With an exact solution: ``|u - Π∇u_h|_1``, ``‖u - Π⁰u_h‖``, the energy error and
        ``estimator / energy_error``.
    """

    step: int
    cells: int
    nodes: int
    unknowns: int
    estimator: float
    residual: float
    jump: float
    stabilization: float
    marked: int
    hanging_nodes: int
    max_vertices: int
    seconds: float
    h1_error: float | None = None
    l2_error: float | None = None
    energy_error: float | None = None
    effectivity: float | None = None

    def as_dict(self) -> dict[str, Any]:
        """Plain dictionary (JSON-ready); the errors only when they were measured."""
        return {k: v for k, v in asdict(self).items() if v is not None}


@dataclass(frozen=True, eq=False)
class AdaptiveResult:
    """What :func:`solve_adaptive` returns.

    Attributes
    ----------
    history : tuple of AdaptiveStep
    solution : PoissonSolution or ElasticitySolution
        The last step's solution (on :attr:`mesh`).
    mesh : PolygonMesh
        The last mesh.
    estimate : ErrorEstimate
        The last step's indicators.
    stopped : str
        Why the loop ended: ``"tol"``, ``"max_unknowns"`` or ``"max_steps"``.
    """

    history: tuple[AdaptiveStep, ...]
    solution: Solution
    mesh: PolygonMesh
    estimate: ErrorEstimate
    stopped: str

    def rates(self, last: int = 4) -> dict[str, float]:
        """Convergence rates per unknown over the last ``last`` steps: ``-d log e / d log N``.

        Least-squares slopes of the estimator and (when measured) the H1 error against the
        unknowns; 1/2 is optimal for lowest-order elements in 2-D.
        """
        steps = self.history[-last:]
        if len(steps) < 2:
            return {}
        n = np.log([s.unknowns for s in steps])
        out = {"estimator": float(-np.polyfit(n, np.log([s.estimator for s in steps]), 1)[0])}
        h1 = [s.h1_error for s in steps if s.h1_error]
        if len(h1) == len(steps):
            errors = np.log(np.array(h1, dtype=float))
            out["h1_error"] = float(-np.polyfit(n, errors, 1)[0])
        return out


def dorfler_marking(indicators: np.ndarray, theta: float) -> np.ndarray:
    """The fewest cells whose indicators ``η_E²`` add up to ``theta`` of their sum (a mask).

    Cells are taken by decreasing indicator; equal indicators at the threshold are all taken
    (so symmetric meshes are marked symmetrically). ``theta`` in (0, 1]. O(M log M).

    Examples
    --------
    >>> dorfler_marking(np.array([1.0, 4.0, 2.0, 3.0]), 0.5).tolist()
    [False, True, False, True]
    """
    theta = _check_theta(theta)
    values = np.asarray(indicators, dtype=np.float64)
    order = np.argsort(-values, kind="stable")
    total = float(values.sum())
    if not total > 0:
        return np.ones(values.size, dtype=bool)
    running = np.cumsum(values[order])
    count = int(np.searchsorted(running, theta * total * (1 - 1e-12))) + 1
    threshold = values[order[min(count, values.size) - 1]]
    return values >= threshold * (1 - 1e-12)


def _check_theta(theta: object) -> float:
    if isinstance(theta, bool) or not isinstance(theta, int | float | np.floating):
        raise ArgumentError(f"theta must be a number in (0, 1], got {theta!r}")
    value = float(theta)
    if not 0 < value <= 1:
        raise ArgumentError(f"theta must be a number in (0, 1], got {theta!r}")
    return value


def solve_adaptive(
    mesh: Mesh | PolygonMesh,
    solve: Callable[[PolygonMesh], Solution],
    *,
    tol: float | None = None,
    max_unknowns: int | None = None,
    max_steps: int = DEFAULT_MAX_STEPS,
    theta: float = 0.5,
    exact: Any = None,
    gradient: Any = None,
    progress: Callable[[AdaptiveStep], None] | None = None,
    max_memory: int | None = None,
    scheme: str = "pentagons",
) -> AdaptiveResult:
    """Solve, estimate, mark and refine until the estimator or the unknowns say stop.

    Parameters
    ----------
    mesh : Mesh or PolygonMesh
        The starting mesh (a Domain's ``mesh(level)``, or any polygon mesh).
    solve : callable
        ``solve(mesh) -> solution``: the problem, e.g. a closure over
        :func:`~blockmesh.vem.solve_poisson` with its data.
    tol : float, optional
        Stop when the estimator is at most this.
    max_unknowns : int, optional
        Stop before a refinement that would take the unknowns above this.
    max_steps : int
        Stop after this many solves (default 40).
    theta : float
        Dörfler's bulk fraction in (0, 1] (default 0.5; 1 refines every cell).
    exact : number, str, callable or pair, optional
        The exact solution (a pair for elasticity): every step then measures the errors and
        the effectivity.
    gradient : optional
        Its gradient (see :meth:`PoissonSolution.errors`); finite differences without it.
    progress : callable, optional
        Called with every step's :class:`AdaptiveStep` as soon as it is done.
    max_memory : int, optional
        The memory bound of each refinement (default: the memory available).
    scheme : {"pentagons", "quads"}
        How marked cells are split (:data:`blockmesh.refinement.local.SCHEMES`).

    Raises
    ------
    ArgumentError
        For a bad ``theta``, ``tol``, ``max_unknowns`` or ``max_steps``.
    """
    theta = _check_theta(theta)
    scheme = check_scheme(scheme)
    if tol is not None and (isinstance(tol, bool) or not float(tol) > 0):
        raise ArgumentError(f"tol must be a number > 0, got {tol!r}")
    if max_unknowns is not None:
        max_unknowns = whole_number(max_unknowns, "max_unknowns", minimum=1)
    max_steps = whole_number(max_steps, "max_steps", minimum=1)
    current = as_polygon_mesh(mesh)
    history: list[AdaptiveStep] = []
    step = 0
    while True:
        started = time.perf_counter()
        solution = solve(current)
        estimate = estimate_error(solution)
        eta = estimate.estimator
        errors = None if exact is None else solution.errors(exact, gradient)
        components = 1 if isinstance(solution, PoissonSolution) else 2
        stop = None
        if tol is not None and eta <= float(tol):
            stop = "tol"
        elif step + 1 >= max_steps:
            stop = "max_steps"
        marked = None
        if stop is None:
            marked = close_marking(current, dorfler_marking(estimate.indicators, theta))
            if max_unknowns is not None:
                size = predict_local_size(current, marked, scheme)
                fixed = components * current.n_points - solution.info.dof
                if components * size.nodes - fixed > max_unknowns:
                    stop = "max_unknowns"
        record = AdaptiveStep(
            step=step,
            cells=current.n_cells,
            nodes=current.n_points,
            unknowns=solution.info.dof,
            estimator=eta,
            **estimate.parts(),
            marked=0 if stop or marked is None else int(np.count_nonzero(marked)),
            hanging_nodes=int(current.hanging_nodes().size),
            max_vertices=int(current.cell_sizes().max()),
            seconds=0.0,
            **_errors(errors, eta),
        )
        if stop is None:
            current = refine_marked(current, marked, max_memory=max_memory, scheme=scheme)
        record = _with_seconds(record, time.perf_counter() - started)
        history.append(record)
        if progress is not None:
            progress(record)
        if stop is not None:
            return AdaptiveResult(tuple(history), solution, solution.mesh, estimate, stop)
        step += 1


def _errors(errors: Any, eta: float) -> dict[str, Any]:
    if errors is None:
        return {}
    energy = float(errors.energy)
    return {
        "h1_error": float(errors.h1),
        "l2_error": float(errors.l2),
        "energy_error": energy,
        "effectivity": eta / energy if energy > 0 else math.inf,
    }


def _with_seconds(record: AdaptiveStep, seconds: float) -> AdaptiveStep:
    values = asdict(record)
    values["seconds"] = seconds
    return AdaptiveStep(**values)
