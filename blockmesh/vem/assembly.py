"""Global matrices from cell matrices, Dirichlet elimination, and the linear solve.

Cell matrices come in groups of equal size (one array ``(M, d, d)`` per group) and are summed into
one ``scipy.sparse`` CSR matrix. Constrained degrees of freedom are eliminated (their columns move
to the right-hand side); the remaining symmetric positive definite system is solved

* ``solver="direct"`` (default): a sparse LU factorisation (SuperLU, minimum-degree ordering on
  ``A + Aᵀ`` for uniformly refined meshes, column approximate minimum degree for locally refined
  ones, see :func:`ordering_for`); exact to round-off, fine up to a few hundred thousand
  unknowns;
* ``solver="amg"``: smoothed-aggregation algebraic multigrid as a preconditioner for conjugate
  gradients (``pyamg``, an optional dependency: ``pip install 'blockmesh[vem]'``), to a relative
  residual ``tol``; for large systems. For elasticity the rigid motions are given to the
  aggregation as its near-null space.

A singular system (no boundary condition fixes a constant or a rigid motion) is detected before
the solve by the callers; a failed solve raises :class:`~blockmesh.errors.SolverError`, and a
factorisation that runs out of memory :class:`~blockmesh.errors.ResourceError` (SuperLU reports
a failed allocation as a ``RuntimeError`` "Malloc fails for ..." or as ``MemoryError``). The
memory a direct solve needs is predicted by :func:`blockmesh.memory.predict_solve_command`.

Examples
--------
>>> import numpy as np
>>> k = np.array([[[1.0, -1.0], [-1.0, 1.0]]] * 2)  # two 1-D bars 0-1-2
>>> a = assemble_matrix([np.array([[0, 1], [1, 2]])], [k], 3)
>>> a.toarray().tolist()
[[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]
>>> u, info = solve_system(a, np.zeros(3), np.array([0, 2]), np.array([0.0, 1.0]))
>>> u.tolist(), info.dof, info.nonzeros
([0.0, 0.5, 1.0], 1, 1)
"""

from __future__ import annotations

import re
import time
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse import linalg as sparse_linalg

from blockmesh.checks import choice
from blockmesh.errors import ArgumentError, ResourceError, SolverError
from blockmesh.vem.boundary import BoundaryConditions
from blockmesh.vem.polygons import PolygonMesh
from blockmesh.vem.rules import check_order
from blockmesh.vem.stabilization import STABILIZATIONS, check_scale, check_stabilization

__all__ = [
    "SOLVERS",
    "LinearSystem",
    "SolveInfo",
    "assemble_matrix",
    "assemble_system",
    "assemble_vector",
    "check_solve_options",
    "check_tolerance",
    "ordering_for",
    "solve_system",
]

#: The linear solvers, by name.
SOLVERS = ("direct", "amg")

_AMG_MAX_ITERATIONS = 500


@dataclass(frozen=True)
class SolveInfo:
    """What the linear solve did.

    Attributes
    ----------
    dof : int
        Unknowns of the solved system: degrees of freedom that are not constrained by Dirichlet
        data (plus nothing else: Lagrange multipliers of a constraint are not counted).
    nonzeros : int
        Stored entries of the reduced matrix (free rows and columns).
    solver : str
    iterations : int or None
        Conjugate-gradient iterations (``"amg"``), None for the direct solver.
    residual : float
        ``‖b - A u‖ / ‖b‖`` of the reduced system (0 when ``b = 0``).
    seconds : float
        Time of the solve (factorisation or setup included).
    """

    dof: int
    nonzeros: int
    solver: str
    iterations: int | None
    residual: float
    seconds: float


def check_tolerance(tol: object) -> float:
    """``tol`` as a float in (0, 1) (ArgumentError otherwise)."""
    if isinstance(tol, bool) or not isinstance(tol, int | float | np.floating):
        raise ArgumentError(f"tol must be a number in (0, 1), got {tol!r}")
    if not 0 < float(tol) < 1:
        raise ArgumentError(f"tol must be a number in (0, 1), got {tol!r}")
    return float(tol)


def assemble_matrix(
    dofs: list[np.ndarray], blocks: list[np.ndarray], size: int
) -> sparse.csr_matrix:
    """Sum the cell matrices ``blocks[g][m]`` (d x d) at rows and columns ``dofs[g][m]`` (d,).

    O(total entries) memory for the triplets; duplicates are summed by the CSR conversion.
    """
    rows = [np.repeat(d, d.shape[1], axis=1).ravel() for d in dofs]
    cols = [np.tile(d, (1, d.shape[1])).ravel() for d in dofs]
    values = [b.reshape(b.shape[0], -1).ravel() for b in blocks]
    matrix = sparse.coo_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
        shape=(size, size),
    ).tocsr()
    matrix.sum_duplicates()
    return matrix


def assemble_vector(dofs: list[np.ndarray], blocks: list[np.ndarray], size: int) -> np.ndarray:
    """Sum the cell vectors ``blocks[g][m]`` (d,) at ``dofs[g][m]``."""
    out = np.zeros(size)
    for d, b in zip(dofs, blocks, strict=True):
        out += np.bincount(d.ravel(), weights=b.ravel(), minlength=size)
    return out


#: SuperLU's column orderings by name (see :func:`ordering_for`).
ORDERINGS = ("MMD_AT_PLUS_A", "COLAMD")


def ordering_for(cell_level: np.ndarray) -> str:
    """The SuperLU ordering for a mesh whose cells have the levels ``cell_level``.

    Measured on 7-15k unknowns: on uniformly refined meshes (the paper's nested numbering)
    ``MMD_AT_PLUS_A`` factors 1.2-1.8x faster than ``COLAMD``; on locally refined ones (new nodes
    numbered after the old) it is 8x slower (3.2 s against 0.39 s at 13k unknowns).

    Examples
    --------
    >>> ordering_for(np.array([2, 2, 2])), ordering_for(np.array([2, 3, 2]))
    ('MMD_AT_PLUS_A', 'COLAMD')
    """
    levels = np.asarray(cell_level)
    uniform = levels.size == 0 or bool(np.all(levels == levels[0]))
    return ORDERINGS[0] if uniform else ORDERINGS[1]


def solve_system(
    matrix: sparse.csr_matrix,
    rhs: np.ndarray,
    fixed: np.ndarray,
    values: np.ndarray,
    *,
    solver: str = "direct",
    tol: float = 1e-10,
    constraints: np.ndarray | None = None,
    near_nullspace: np.ndarray | None = None,
    ordering: str = ORDERINGS[0],
) -> tuple[np.ndarray, SolveInfo]:
    """Solve ``matrix u = rhs`` with ``u[fixed] = values``.

    Parameters
    ----------
    ordering : {"MMD_AT_PLUS_A", "COLAMD"}
        The direct solver's column ordering (:func:`ordering_for`).
    constraints : ndarray (n, k), optional
        Extra linear constraints ``constraintsᵀ u = 0`` (Lagrange multipliers; direct solver only):
        the mean-value condition of a pure Neumann problem.
    near_nullspace : ndarray (n, k), optional
        Candidate vectors for the multigrid aggregation (rigid motions for elasticity).
    """
    choice(solver, SOLVERS, "solver")
    tol = check_tolerance(tol)
    size = matrix.shape[0]
    u = np.zeros(size)
    u[fixed] = values
    free = np.ones(size, dtype=bool)
    free[fixed] = False
    free_ids = np.flatnonzero(free)
    reduced = matrix[free_ids][:, free_ids].tocsr()
    b = rhs[free_ids] - matrix[free_ids][:, fixed] @ values
    started = time.perf_counter()
    iterations: int | None = None
    if free_ids.size == 0:
        solution = np.empty(0)
    elif constraints is not None:
        if solver != "direct":
            raise ArgumentError(
                "a mean-value constraint needs solver='direct' (the augmented system is not "
                "positive definite)"
            )
        solution = _solve_constrained(reduced, b, constraints[free_ids], ordering)
    elif solver == "direct":
        solution = _solve_direct(reduced, b, ordering)
    else:
        candidates = None if near_nullspace is None else near_nullspace[free_ids]
        solution, iterations = _solve_amg(reduced, b, tol, candidates)
    seconds = time.perf_counter() - started
    norm = float(np.linalg.norm(b))
    residual = float(np.linalg.norm(b - reduced @ solution)) / norm if norm > 0 else 0.0
    if constraints is None and not residual <= max(1e-6, 10 * tol):
        raise SolverError(
            f"the linear solve failed: relative residual {residual:.2g} (the system may be "
            "singular or badly conditioned)"
        )
    u[free_ids] = solution
    info = SolveInfo(int(free_ids.size), int(reduced.nnz), solver, iterations, residual, seconds)
    return u, info


#: How SuperLU words a failed allocation (its ABORT becomes a RuntimeError in scipy).
_NO_MEMORY = re.compile(r"malloc|memory", re.IGNORECASE)


def check_solve_options(
    order: object,
    stabilization: object,
    stabilization_scale: object,
    constraint: str | None,
    *,
    constraints: tuple[str, ...],
    stabilizations: tuple[str, ...] = tuple(STABILIZATIONS),
) -> tuple[int, str, float]:
    """The options every solver takes, checked: the order, the stabilisation and its scale.

    ``constraint`` must be None or one of ``constraints``. Returns the order, the stabilisation
    and its scale; ArgumentError naming the option otherwise.

    Examples
    --------
    >>> check_solve_options(3, "trace", 1, None, constraints=("mean",))
    (3, 'trace', 1.0)
    """
    checked = check_order(order), check_stabilization(stabilization, stabilizations)
    scale = check_scale(stabilization_scale)
    if constraint is not None and constraint not in constraints:
        raise ArgumentError(
            f"unknown constraint {constraint!r}; choose one of: {', '.join(constraints)}"
        )
    return checked[0], checked[1], scale


@dataclass(frozen=True)
class LinearSystem:
    """A problem's global system: its matrix and right-hand side, and the Dirichlet values."""

    matrix: sparse.csr_matrix
    rhs: np.ndarray
    fixed: np.ndarray
    values: np.ndarray
    ordering: str

    def solve(
        self,
        *,
        solver: str,
        tol: float,
        constraints: np.ndarray | None = None,
        near_nullspace: np.ndarray | None = None,
    ) -> tuple[np.ndarray, SolveInfo]:
        """:func:`solve_system` of this system."""
        return solve_system(
            self.matrix,
            self.rhs,
            self.fixed,
            self.values,
            solver=solver,
            tol=tol,
            constraints=constraints,
            near_nullspace=near_nullspace,
            ordering=self.ordering,
        )


def assemble_system(
    mesh: PolygonMesh,
    dofs: list[np.ndarray],
    matrices: list[np.ndarray],
    loads: list[np.ndarray],
    bc: BoundaryConditions,
    order: int,
) -> LinearSystem:
    """The global system of ``mesh`` from its cell matrices and loads and the conditions ``bc``.

    ``bc.components`` unknowns per node; the Neumann loads integrated to ``order``.
    """
    size = bc.components * mesh.n_points
    return LinearSystem(
        assemble_matrix(dofs, matrices, size),
        assemble_vector(dofs, loads, size) + bc.load(mesh, order),
        *bc.fixed(mesh),
        ordering_for(mesh.cell_level),
    )


def _out_of_memory(matrix: sparse.csr_matrix) -> ResourceError:
    return ResourceError(
        f"ran out of memory factorising the system of {matrix.shape[0]:,} unknowns "
        f"({matrix.nnz:,} non-zeros) with the direct solver; try a lower level, "
        "solver='amg', or free memory"
    )


def _solve_direct(
    matrix: sparse.csr_matrix, b: np.ndarray, ordering: str = ORDERINGS[0]
) -> np.ndarray:
    choice(ordering, ORDERINGS, "ordering")
    with warnings.catch_warnings():
        warnings.simplefilter("error", sparse_linalg.MatrixRankWarning)
        try:
            lu = sparse_linalg.splu(matrix.tocsc(), permc_spec=ordering)
        except MemoryError:
            raise _out_of_memory(matrix) from None
        except (RuntimeError, sparse_linalg.MatrixRankWarning) as error:
            if isinstance(error, RuntimeError) and _NO_MEMORY.search(str(error)):
                raise _out_of_memory(matrix) from None
            raise SolverError(
                f"the system matrix is singular ({error}); the boundary conditions do not "
                "determine the solution"
            ) from None
    solution = lu.solve(b)
    if not np.all(np.isfinite(solution)):
        raise SolverError("the linear solve produced non-finite values (singular system)")
    return solution


def _solve_constrained(
    matrix: sparse.csr_matrix, b: np.ndarray, constraints: np.ndarray, ordering: str
) -> np.ndarray:
    k = constraints.shape[1]
    block = sparse.csr_matrix(constraints)
    augmented = sparse.bmat([[matrix, block], [block.T, None]], format="csc")
    full = _solve_direct(augmented.tocsr(), np.concatenate([b, np.zeros(k)]), ordering)
    return full[: matrix.shape[0]]


def _solve_amg(
    matrix: sparse.csr_matrix, b: np.ndarray, tol: float, candidates: np.ndarray | None
) -> tuple[np.ndarray, int]:
    try:
        import pyamg
    except ImportError:
        raise SolverError(
            "solver='amg' needs the optional package pyamg: pip install 'blockmesh[vem]' "
            "(or use solver='direct')"
        ) from None
    hierarchy = pyamg.smoothed_aggregation_solver(
        matrix, B=candidates, symmetry="symmetric", max_coarse=500
    )
    residuals: list[float] = []
    solution = hierarchy.solve(
        b, tol=tol, accel="cg", maxiter=_AMG_MAX_ITERATIONS, residuals=residuals
    )
    norm = float(np.linalg.norm(b))
    reached = residuals[-1] / norm if residuals and norm > 0 else 0.0
    if reached > 10 * tol:
        raise SolverError(
            f"algebraic multigrid did not converge: relative residual {reached:.2g} after "
            f"{len(residuals) - 1} iterations (tol {tol:g}); try solver='direct'"
        )
    return np.asarray(solution, dtype=np.float64), max(len(residuals) - 1, 0)
