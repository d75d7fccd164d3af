"""Diffusion-reaction problems with lowest-order virtual elements.

Solves ``-∇·(κ ∇u) + c u = f`` in the domain, ``u = g_D`` on the Dirichlet patches and
``κ ∂u/∂n = g_N`` (outward flux) on the Neumann patches; patches named by neither have zero flux.
The discrete problem on every cell E:

* stiffness ``κ̄_E |E| Wᵀ W + s_E``: the consistency term ``∫_E κ ∇Π∇φ_i · ∇Π∇φ_j`` (the
  projected gradients are constant, so only the cell integral ``κ̄_E |E|`` of κ is needed) plus the
  stabilisation of :mod:`blockmesh.vem.stabilization`;
* mass ``∫_E c Π⁰φ_i Π⁰φ_j + s_E``: by quadrature, plus the same recipe on the mass;
* load ``∫_E f Π⁰φ_i``: by quadrature (blockmesh's composite Gauss rule, exact to degree
  ``2 order - 1``), not f at a centroid, so the L2 error keeps its second order;
* flux ``∫_e g_N φ_i``: Gauss-Legendre on every Neumann edge.

On triangles every projection is exact and the method is the P1 finite element method.

On a composite domain (several regions) the source, the diffusion and the reaction may be given
per region, as a mapping region -> value or expression (``{"fibre": 10, "matrix": 1}``; ``"*"``
for the regions not named). Every cell lies in one region, so the interface conditions are the
natural ones: u is continuous (the nodes on an interface are shared) and so is the normal flux
``κ ∂u/∂n`` (weakly, as in any conforming method). An interface is not a boundary patch: a
Dirichlet or Neumann condition on one is refused, naming it.

Examples
--------
>>> import blockmesh
>>> from blockmesh.vem import solve_poisson
>>> mesh = blockmesh.load_domain("square").mesh(2)
>>> sol = solve_poisson(mesh, "2*pi^2*sin(pi*x)*sin(pi*y)",
...                     dirichlet={p: 0 for p in mesh.patch_names})
>>> sol.info.dof, round(float(sol.values.max()), 2)
(413, 1.0)
>>> e = sol.errors("sin(pi*x)*sin(pi*y)")
>>> e.l2 < 5e-3, e.h1 < 0.2
(True, True)
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.sparse import csgraph

from blockmesh.errors import SolverError
from blockmesh.vem.assembly import (
    SolveInfo,
    assemble_system,
    assemble_vector,
    check_solve_options,
)
from blockmesh.vem.boundary import ProblemData, boundary_conditions
from blockmesh.vem.fields import Field, RegionField, region_field, region_vector_field
from blockmesh.vem.norms import ErrorNorms, error_norms
from blockmesh.vem.polygons import PolygonMesh, as_polygon_mesh
from blockmesh.vem.projections import Projections, projections
from blockmesh.vem.rules import cell_chunks, cell_rule, check_order, points_per_cell
from blockmesh.vem.stabilization import stabilize

__all__ = ["CONSTRAINTS", "PoissonSolution", "solve_poisson"]

#: Constraints that make a pure Neumann problem well posed.
CONSTRAINTS = ("mean",)

#: Relative size of ``∫f + ∫g_N`` above which pure Neumann data are rejected as incompatible.
COMPATIBILITY_TOL = 1e-3


@dataclass(frozen=True, eq=False, repr=False)
class PoissonSolution:
    """The virtual element solution of a diffusion-reaction problem.

    Attributes
    ----------
    mesh : PolygonMesh
    values : ndarray (N,)
        u_h at the nodes (its degrees of freedom).
    cell_gradient : ndarray (M, 2)
        ``∇Π∇u_h`` on every cell (constant per cell), in the mesh's cell order.
    cell_value : ndarray (M,)
        ``Π∇u_h`` at every cell's vertex mean (the mean of its vertex values), so that on cell m
        ``Π⁰u_h(x) = cell_value[m] + cell_gradient[m] · (x - centre_m)``.
    info : SolveInfo
        Unknowns, non-zeros, solver, residual, time of the linear solve.
    seconds : float
        Total time: assembly and solve.
    """

    mesh: PolygonMesh
    values: np.ndarray
    cell_gradient: np.ndarray
    cell_value: np.ndarray
    info: SolveInfo
    seconds: float
    _projections: tuple[Projections, ...]
    _diffusion: Field | RegionField
    _reaction: Field | RegionField
    _order: int
    _data: ProblemData | None = None

    def __repr__(self) -> str:
        """A one-line summary (the arrays are not printed)."""
        return (
            f"PoissonSolution({self.mesh.n_cells:,} cells, {self.info.dof:,} unknowns, "
            f"u in [{self.values.min():.6g}, {self.values.max():.6g}])"
        )

    def errors(
        self,
        exact: Any,
        gradient: Any = None,
        *,
        order: int | None = None,
    ) -> ErrorNorms:
        """L2, H1 and energy errors against an exact solution.

        Parameters
        ----------
        exact : number, str or callable, or a mapping of region to one of those
            u(x, y); per region on a composite domain (each cell against its region's piece).
        gradient : pair, optional
            ``(∂u/∂x, ∂u/∂y)`` as numbers, strings or callables (or ``"UX, UY"``). Without it the
            gradient is taken by finite differences (see :mod:`blockmesh.vem.norms`).
        order : int, optional
            Quadrature order (default: the solve's order + 1).
        """
        names = self.mesh.region_names
        u = region_field(exact, "exact solution", names)
        grad = (
            None if gradient is None else [region_vector_field(gradient, "exact gradient", names)]
        )
        kappa, c = self._diffusion, self._reaction

        def energy(
            x: np.ndarray, y: np.ndarray, e: np.ndarray, de: np.ndarray, region: np.ndarray
        ) -> np.ndarray:
            density = kappa.at(x, y, region) * np.sum(de[..., 0, :] ** 2, axis=-1)
            if not c.is_zero:
                density = density + c.at(x, y, region) * e[..., 0] ** 2
            return density

        rule_order = check_order(self._order + 1 if order is None else order)
        return error_norms(
            self.mesh,
            self._projections,
            self.values[:, None],
            [u],
            grad,
            energy,
            rule_order,
        )


def solve_poisson(
    mesh: Any,
    source: Any = 0.0,
    *,
    diffusion: Any = 1.0,
    reaction: Any = 0.0,
    dirichlet: Mapping[str, Any] | None = None,
    neumann: Mapping[str, Any] | None = None,
    constraint: str | None = None,
    order: int = 3,
    stabilization: str = "trace",
    stabilization_scale: float = 1.0,
    solver: str = "direct",
    tol: float = 1e-10,
) -> PoissonSolution:
    """Solve ``-∇·(κ∇u) + c u = f`` with lowest-order virtual elements.

    Parameters
    ----------
    mesh : Mesh or PolygonMesh
        A blockmesh mesh (pentagons) or any polygon mesh.
    source : number, str or callable, or a mapping of region to one of those
        f(x, y).
    diffusion, reaction : number, str or callable, or a mapping of region to one of those
        κ(x, y) > 0 and c(x, y) >= 0; per region on a composite domain
        (``{"fibre": 10, "matrix": 1}``, ``"*"`` for the regions not named).
    dirichlet : mapping of patch name to value, optional
        ``u`` on those patches (number, expression or callable of x, y).
    neumann : mapping of patch name to flux, optional
        Outward flux ``κ ∂u/∂n`` on those patches. Unnamed patches have zero flux.
    constraint : {"mean"}, optional
        For a problem with no Dirichlet patch and no reaction: fix the solution's mean to zero
        (the data must then be compatible, ``∫f + ∫g_N = 0``).
    order : int
        Quadrature order of the load, the mass and the fluxes (exact to degree ``2 order - 1``).
    stabilization : {"trace", "identity", "diagonal"}
        See :mod:`blockmesh.vem.stabilization` (default ``"trace"``).
    stabilization_scale : float
        Factor on the stabilisation (default 1).
    solver : {"direct", "amg"}
        See :mod:`blockmesh.vem.assembly`.
    tol : float
        Relative residual of the iterative solver.

    Returns
    -------
    PoissonSolution

    Raises
    ------
    UnknownNameError
        For a patch or a region the mesh does not have.
    SolverError
        For a patch given both conditions, a condition on an interface, a region without a
        value, a problem without anything fixing the constant (no
        Dirichlet patch, no reaction, no constraint), incompatible pure Neumann data, or a failed
        solve.
    ResourceError
        When the direct solver's factorisation runs out of memory (its need is predicted by
        :func:`blockmesh.memory.predict_solve_command`; ``solver="amg"`` needs far less).
    """
    started = time.perf_counter()
    pm = as_polygon_mesh(mesh)
    order, recipe, scale = check_solve_options(
        order, stabilization, stabilization_scale, constraint, constraints=CONSTRAINTS
    )
    names = pm.region_names
    f = region_field(source, "source", names)
    kappa = region_field(diffusion, "diffusion", names)
    c = region_field(reaction, "reaction", names)
    bc = boundary_conditions(pm, dirichlet, neumann, components=1)
    cell_region = pm.region

    dofs, stiffness, load, means, projs = [], [], [], [], []
    for group in pm.groups:
        proj = projections(pm.points, group.cells)
        region = cell_region[group.index]
        k, m, b, mean = _cell_matrices(
            pm, group.cells, region, proj, f, kappa, c, order, recipe, scale
        )
        dofs.append(group.cells)
        stiffness.append(k if m is None else k + m)
        load.append(b)
        means.append(mean)
        projs.append(proj)
    system = assemble_system(pm, dofs, stiffness, load, bc, order)
    constraints = _constraints(
        pm, system.matrix, system.fixed, c, constraint, system.rhs, dofs, means
    )
    u, info = system.solve(solver=solver, tol=tol, constraints=constraints)
    gradient = np.empty((pm.n_cells, 2))
    value = np.empty(pm.n_cells)
    for group, proj in zip(pm.groups, projs, strict=True):
        local = u[group.cells]
        gradient[group.index] = np.einsum("mdn,mn->md", proj.gradient, local)
        value[group.index] = local.mean(axis=1)
    for array in (u, gradient, value):
        array.setflags(write=False)
    return PoissonSolution(
        pm,
        u,
        gradient,
        value,
        info,
        time.perf_counter() - started,
        tuple(projs),
        kappa,
        c,
        order,
        ProblemData((f,), bc, recipe, scale),
    )


def _cell_matrices(
    pm: PolygonMesh,
    cells: np.ndarray,
    region: np.ndarray,
    proj: Projections,
    f: Field | RegionField,
    kappa: Field | RegionField,
    c: Field | RegionField,
    order: int,
    recipe: str,
    scale: float,
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, np.ndarray]:
    """Stiffness, mass (None without reaction), load and ``∫Πφ_i`` of one group's cells."""
    n_cells, n = cells.shape
    kappa_mean = np.empty(n_cells)
    load = np.zeros((n_cells, n))
    basis_mean = np.empty((n_cells, n))
    mass = None if c.is_zero else np.empty((n_cells, n, n))
    reaction_mean = np.empty(n_cells)
    coefficients = proj.coefficients  # Π∇φ_j = (1, x - c_x, y - c_y) @ coefficients[:, :, j]
    for part in cell_chunks(n_cells, points_per_cell(n, order)):
        x, y, w = cell_rule(pm.points, cells[part], order)
        monomials = proj.monomials(x, y, part)  # (C, Q, 3)
        local = coefficients[part]
        basis_mean[part] = np.einsum("ca,can->cn", np.einsum("cq,cqa->ca", w, monomials), local)
        kappa_mean[part] = np.sum(w * kappa.at(x, y, region[part]), axis=1) / proj.area[part]
        if not f.is_zero:
            moments = np.einsum("cq,cqa->ca", w * f.at(x, y, region[part]), monomials)
            load[part] = np.einsum("ca,can->cn", moments, local)
        if mass is not None:
            cw = w * c.at(x, y, region[part])
            second = np.matmul(monomials.transpose(0, 2, 1), cw[:, :, None] * monomials)
            mass[part] = np.matmul(local.transpose(0, 2, 1), np.matmul(second, local))
            reaction_mean[part] = np.sum(cw, axis=1) / proj.area[part]
    if np.any(kappa_mean <= 0):
        bad = int(np.flatnonzero(kappa_mean <= 0)[0])
        raise SolverError(
            f"diffusion {kappa.text} has mean {kappa_mean[bad]:.3g} <= 0 on a cell with corners "
            f"{pm.points[cells[bad]].round(6).tolist()}; the diffusion must be positive"
        )
    residual = proj.residual()
    consistency = (kappa_mean * proj.area)[:, None, None] * np.matmul(
        proj.gradient.transpose(0, 2, 1), proj.gradient
    )
    stiffness = consistency + stabilize(
        consistency, residual, recipe, coefficient=kappa_mean, scale=scale
    )
    if mass is not None:
        mass = mass + stabilize(
            mass, residual, recipe, coefficient=reaction_mean * proj.area / n, scale=scale
        )
    return stiffness, mass, load, basis_mean


def _constraints(
    pm: PolygonMesh,
    matrix,
    fixed: np.ndarray,
    c: Field | RegionField,
    constraint: str | None,
    rhs: np.ndarray,
    dofs: list[np.ndarray],
    means: list[np.ndarray],
) -> np.ndarray | None:
    """The mean-value constraints of the pieces that nothing else anchors, or a SolverError."""
    if not c.is_zero:
        return None
    pieces, label = csgraph.connected_components(matrix, directed=False)
    anchored = np.zeros(pieces, dtype=bool)
    anchored[label[fixed]] = True
    loose = np.flatnonzero(~anchored)
    if loose.size == 0:
        return None
    if constraint is None:
        where = "" if pieces == 1 else f" (on {loose.size} of the mesh's {pieces} pieces)"
        raise SolverError(
            "no Dirichlet data: with only Neumann (or natural) patches and no reaction, u is "
            f"determined up to a constant{where}; give a Dirichlet patch, a reaction > 0, or "
            "constraint='mean' (zero mean)"
        )
    weight = assemble_vector(dofs, means, pm.n_points)  # ∫ Π⁰φ_i over the domain
    columns = np.zeros((pm.n_points, loose.size))
    for k, piece in enumerate(loose):
        inside = label == piece
        columns[inside, k] = weight[inside]
        total = float(np.sum(rhs[inside]))
        scale = float(np.sum(np.abs(rhs[inside])))
        if abs(total) > COMPATIBILITY_TOL * scale:
            raise SolverError(
                f"the data of a pure Neumann problem must balance, ∫f + ∫g_N = 0; here it is "
                f"{total:.6g} (against {scale:.6g} in absolute value), so there is no solution"
            )
    return columns
