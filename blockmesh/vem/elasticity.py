"""Plane linear elasticity with lowest-order virtual elements.

Solves ``-div σ(u) = f`` with ``σ = C ε(u)`` (isotropic, plane stress or plane strain; Young's
modulus E, Poisson's ratio ν), displacements on the Dirichlet patches (each component may be
left free: a roller), tractions ``σ n = t`` on the Neumann patches, and traction-free elsewhere.

Each displacement component lives in the scalar lowest-order space of
:mod:`blockmesh.vem.projections`, so the projection of a displacement is the linear field with
the cell's mean displacement gradient ``W u``. The cell stiffness is the consistency term
``|E| Bᵀ C B`` (B maps the vertex displacements to the mean strain, in Voigt notation with the
engineering shear ``γ_xy``) plus a stabilisation (``"trace"`` by default, see
:mod:`blockmesh.vem.stabilization`). Stresses are constant per cell: ``σ = C B u``.

On a composite domain E, ν and the body force may be given per region (a mapping region ->
value, ``"*"`` for the regions not named): every cell takes its region's C, and the interfaces
carry the natural conditions (the displacement continuous, the traction balanced weakly).

Examples
--------
>>> import blockmesh
>>> from blockmesh.vem import solve_elasticity
>>> mesh = blockmesh.load_domain("square").mesh(1)
>>> sol = solve_elasticity(mesh, young=1.0, poisson=0.3,  # uniaxial tension: exact
...                        dirichlet={"left": "0, free", "bottom": "free, 0"},
...                        neumann={"right": "1, 0"})
>>> bool(abs(sol.stress - [1.0, 0.0, 0.0]).max() < 1e-12)
True
>>> round(float(sol.displacement[:, 0].max()), 10)  # u_x = x / E at x = 1
1.0
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.checks import choice, renamed_keywords
from blockmesh.errors import ArgumentError, SolverError
from blockmesh.vem.assembly import SolveInfo, assemble_system, check_solve_options
from blockmesh.vem.boundary import ProblemData, boundary_conditions
from blockmesh.vem.fields import (
    Field,
    RegionField,
    region_values,
    region_vector_field,
    vector_field,
)
from blockmesh.vem.norms import ErrorNorms, error_norms
from blockmesh.vem.polygons import PolygonMesh, as_polygon_mesh
from blockmesh.vem.projections import Projections, projections
from blockmesh.vem.rules import cell_chunks, cell_rule, check_order, points_per_cell
from blockmesh.vem.stabilization import stabilize

__all__ = ["PLANES", "ElasticitySolution", "elasticity_matrix", "solve_elasticity"]

#: The plane models.
PLANES = ("stress", "strain")

#: Relative size of the net force or moment on a free rigid motion above which loads are rejected.
BALANCE_TOL = 1e-3


def elasticity_matrix(young: float, poisson: float, plane: str = "stress") -> np.ndarray:
    """The 3 x 3 matrix C of ``(σ_xx, σ_yy, σ_xy) = C (ε_xx, ε_yy, γ_xy)``.

    Examples
    --------
    >>> elasticity_matrix(1.0, 0.0).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.5]]
    """
    choice(plane, PLANES, "plane")
    for name, value in (("young", young), ("poisson", poisson)):
        if isinstance(value, bool) or not isinstance(value, int | float | np.floating):
            raise ArgumentError(f"{name} must be a number, got {value!r}")
    e, nu = float(young), float(poisson)
    if not (np.isfinite(e) and e > 0):
        raise ArgumentError(f"young (Young's modulus) must be > 0, got {young!r}")
    if not (np.isfinite(nu) and -1 < nu < 0.5):
        raise ArgumentError(f"poisson (Poisson's ratio) must be in (-1, 0.5), got {poisson!r}")
    if plane == "stress":
        factor = e / (1 - nu * nu)
        return factor * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    factor = e / ((1 + nu) * (1 - 2 * nu))
    return factor * np.array([[1 - nu, nu, 0], [nu, 1 - nu, 0], [0, 0, (1 - 2 * nu) / 2]])


@dataclass(frozen=True, eq=False, repr=False)
class ElasticitySolution:
    """The virtual element solution of a plane elasticity problem.

    Attributes
    ----------
    mesh : PolygonMesh
    displacement : ndarray (N, 2)
        Nodal displacements.
    strain : ndarray (M, 3)
        ``(ε_xx, ε_yy, γ_xy)`` of the projection, constant per cell, in the mesh's cell order.
    stress : ndarray (M, 3)
        ``(σ_xx, σ_yy, σ_xy) = C strain``.
    von_mises : ndarray (M,)
        The von Mises stress (with ``σ_zz = ν (σ_xx + σ_yy)`` in plane strain).
    info : SolveInfo
    seconds : float
    material : ndarray (3, 3), or (R, 3, 3)
        The matrix C of :func:`elasticity_matrix`; one per region (in the order of the mesh's
        region names) when E or ν is given per region.
    """

    mesh: PolygonMesh
    displacement: np.ndarray
    strain: np.ndarray
    stress: np.ndarray
    von_mises: np.ndarray
    info: SolveInfo
    seconds: float
    material: np.ndarray
    _projections: tuple[Projections, ...]
    _order: int
    _data: ProblemData | None = None

    def __repr__(self) -> str:
        """A one-line summary (the arrays are not printed)."""
        return (
            f"ElasticitySolution({self.mesh.n_cells:,} cells, {self.info.dof:,} unknowns, "
            f"largest von Mises stress {self.von_mises.max():.6g})"
        )

    def errors(self, exact: Any, gradient: Any = None, *, order: int | None = None) -> ErrorNorms:
        """L2, H1 and energy errors against an exact displacement.

        Parameters
        ----------
        exact : pair or str, or a mapping of region to one of those
            ``(u_x, u_y)`` as numbers, strings or callables, or ``"UX, UY"``; per region on a
            composite domain.
        gradient : pair of pairs, optional
            ``((∂u_x/∂x, ∂u_x/∂y), (∂u_y/∂x, ∂u_y/∂y))``; finite differences when omitted.
        order : int, optional
            Quadrature order (default: the solve's order + 1).
        """
        fields = region_vector_field(exact, "exact displacement", self.mesh.region_names)
        grad = None
        if gradient is not None:
            if not (isinstance(gradient, tuple | list) and len(gradient) == 2):
                raise ArgumentError("gradient must be ((dux/dx, dux/dy), (duy/dx, duy/dy))")
            grad = [vector_field(row, "exact gradient") for row in gradient]
        c = self.material

        def energy(
            _x: np.ndarray, _y: np.ndarray, _e: np.ndarray, de: np.ndarray, region: np.ndarray
        ) -> np.ndarray:
            strain = np.stack(
                [de[..., 0, 0], de[..., 1, 1], de[..., 0, 1] + de[..., 1, 0]], axis=-1
            )
            if c.ndim == 3:
                return np.einsum("cqa,cab,cqb->cq", strain, c[region], strain)
            return np.einsum("...a,ab,...b->...", strain, c, strain)

        rule_order = check_order(self._order + 1 if order is None else order)
        return error_norms(
            self.mesh, self._projections, self.displacement, fields, grad, energy, rule_order
        )


@renamed_keywords(body_force="source", displacement="dirichlet", traction="neumann")
def solve_elasticity(
    mesh: Any,
    source: Any = (0.0, 0.0),
    *,
    young: float,
    poisson: float,
    plane: str = "stress",
    dirichlet: Mapping[str, Any] | None = None,
    neumann: Mapping[str, Any] | None = None,
    constraint: str | None = None,
    order: int = 3,
    stabilization: str = "trace",
    stabilization_scale: float = 1.0,
    solver: str = "direct",
    tol: float = 1e-10,
) -> ElasticitySolution:
    """Solve plane linear elasticity with lowest-order virtual elements.

    Parameters
    ----------
    mesh : Mesh or PolygonMesh
    young, poisson : float, or a mapping of region to a float
        Young's modulus E > 0 and Poisson's ratio ν in (-1, 0.5); per region on a composite
        domain (``{"steel": 200e3, "rubber": 10}``, ``"*"`` for the regions not named).
    source : pair or str, or a mapping of region to one of those
        The body force ``(f_x, f_y)`` per unit area (numbers, expressions, callables, or
        ``"FX, FY"``); the role ``source`` has in :func:`~blockmesh.vem.solve_poisson` (earlier
        name: ``body_force``).
    plane : {"stress", "strain"}
    dirichlet : mapping of patch name to a pair, optional
        Prescribed displacements ``(u_x, u_y)``; a component ``None`` or ``"free"`` is not
        prescribed (earlier name: ``displacement``).
    neumann : mapping of patch name to a pair, optional
        Tractions ``σ n`` on those patches, force per unit length (earlier name: ``traction``).
    constraint : {"rigid"}, optional
        Remove the rigid motions the displacement conditions leave free (zero mean
        translation and rotation of the nodes); the loads must then balance.
    order : int
        Quadrature order of the loads.
    stabilization : {"trace", "diagonal"}
    stabilization_scale : float
    solver : {"direct", "amg"}
    tol : float

    Raises
    ------
    UnknownNameError
        For a patch the mesh does not have.
    SolverError
        For a patch given both conditions; displacement conditions that leave a rigid motion
        free (without ``constraint="rigid"``); unbalanced loads on a free rigid motion; a failed
        solve.
    ResourceError
        When the direct solver's factorisation runs out of memory (its need is predicted by
        :func:`blockmesh.memory.predict_solve_command`; ``solver="amg"`` needs far less).
    """
    started = time.perf_counter()
    pm = as_polygon_mesh(mesh)
    names = pm.region_names
    cell_region = pm.region
    per_region = isinstance(young, Mapping) or isinstance(poisson, Mapping)
    if per_region:
        e_of = region_values(young, "Young's modulus", names)
        nu_of = region_values(poisson, "Poisson's ratio", names)
        material = np.stack(
            [elasticity_matrix(e, nu, plane) for e, nu in zip(e_of, nu_of, strict=True)]
        )
        nu_cells = nu_of[cell_region]
    else:
        material = elasticity_matrix(young, poisson, plane)
        nu_cells = np.full(pm.n_cells, float(poisson))
    order, recipe, scale = check_solve_options(
        order,
        stabilization,
        stabilization_scale,
        constraint,
        constraints=("rigid",),
        stabilizations=("trace", "diagonal"),
    )
    force = region_vector_field(source, "body force", names)
    bc = boundary_conditions(
        pm,
        dirichlet,
        neumann,
        components=2,
        dirichlet_name="displacement",
        neumann_name="traction",
    )

    dofs, stiffness, load, projs, strains = [], [], [], [], []
    for group in pm.groups:
        proj = projections(pm.points, group.cells)
        strain_map = _strain_matrix(proj.gradient)
        region = cell_region[group.index]
        group_material = material[region] if per_region else material
        k = _stiffness(proj, strain_map, group_material, recipe, scale)
        dofs.append(np.stack([2 * group.cells, 2 * group.cells + 1], axis=2).reshape(k.shape[:2]))
        stiffness.append(k)
        load.append(_body_load(pm, group.cells, region, proj, force, order))
        projs.append(proj)
        strains.append(strain_map)
    system = assemble_system(pm, dofs, stiffness, load, bc, order)
    rigid = _rigid_motions(pm.points)
    constraints = _free_rigid_motions(rigid, system.fixed, system.rhs, constraint)
    u, info = system.solve(solver=solver, tol=tol, constraints=constraints, near_nullspace=rigid)
    strain = np.empty((pm.n_cells, 3))
    for group, d, strain_map in zip(pm.groups, dofs, strains, strict=True):
        strain[group.index] = np.einsum("mak,mk->ma", strain_map, u[d])
    if per_region:
        stress = np.einsum("mab,mb->ma", material[cell_region], strain)
    else:
        stress = strain @ material.T
    mises = _von_mises(stress, nu_cells, plane)
    displacement_values = u.reshape(-1, 2)
    for array in (displacement_values, strain, stress, mises):
        array.setflags(write=False)
    return ElasticitySolution(
        pm,
        displacement_values,
        strain,
        stress,
        mises,
        info,
        time.perf_counter() - started,
        material,
        tuple(projs),
        order,
        ProblemData(tuple(force), bc, recipe, scale),
    )


def _strain_matrix(gradient: np.ndarray) -> np.ndarray:
    """B (M, 3, 2n): mean ``(ε_xx, ε_yy, γ_xy)`` from the vertex displacements (x, y per node)."""
    m, _, n = gradient.shape
    b = np.zeros((m, 3, n, 2))
    b[:, 0, :, 0] = gradient[:, 0]
    b[:, 1, :, 1] = gradient[:, 1]
    b[:, 2, :, 0] = gradient[:, 1]
    b[:, 2, :, 1] = gradient[:, 0]
    return b.reshape(m, 3, 2 * n)


def _stiffness(
    proj: Projections, strain_map: np.ndarray, material: np.ndarray, recipe: str, scale: float
) -> np.ndarray:
    consistency = proj.area[:, None, None] * np.matmul(
        strain_map.transpose(0, 2, 1), np.matmul(material, strain_map)
    )
    m, n = proj.area.shape[0], proj.size
    residual = np.einsum("mij,ab->miajb", proj.residual(), np.eye(2)).reshape(m, 2 * n, 2 * n)
    return consistency + stabilize(consistency, residual, recipe, coefficient=None, scale=scale)


def _body_load(
    pm: PolygonMesh,
    cells: np.ndarray,
    region: np.ndarray,
    proj: Projections,
    force: tuple[Field | RegionField, Field | RegionField],
    order: int,
) -> np.ndarray:
    n_cells, n = cells.shape
    out = np.zeros((n_cells, n, 2))
    if all(f.is_zero for f in force):
        return out.reshape(n_cells, 2 * n)
    coefficients = proj.coefficients
    for part in cell_chunks(n_cells, points_per_cell(n, order)):
        x, y, w = cell_rule(pm.points, cells[part], order)
        monomials = proj.monomials(x, y, part)
        for a, f in enumerate(force):
            if not f.is_zero:
                moments = np.einsum("cq,cqa->ca", w * f.at(x, y, region[part]), monomials)
                out[part, :, a] = np.einsum("ca,can->cn", moments, coefficients[part])
    return out.reshape(n_cells, 2 * n)


def _rigid_motions(points: np.ndarray) -> np.ndarray:
    """The three rigid motions at the nodes (2N, 3): translations x and y, rotation (scaled)."""
    centre = points.mean(axis=0)
    offset = points - centre
    length = max(float(np.abs(offset).max()), 1e-300)
    modes = np.zeros((points.shape[0], 2, 3))
    modes[:, 0, 0] = 1.0
    modes[:, 1, 1] = 1.0
    modes[:, 0, 2] = -offset[:, 1] / length
    modes[:, 1, 2] = offset[:, 0] / length
    return modes.reshape(-1, 3)


def _free_rigid_motions(
    rigid: np.ndarray, fixed: np.ndarray, rhs: np.ndarray, constraint: str | None
) -> np.ndarray | None:
    """The rigid motions the constraints leave free, as constraint columns (or a SolverError)."""
    if fixed.size:
        _, singular, vt = np.linalg.svd(rigid[fixed], full_matrices=True)
        rank = int(np.sum(singular > 1e-9 * max(float(singular[0]), 1e-300)))
    else:
        rank, vt = 0, np.eye(3)
    if rank == 3:
        return None
    free = vt[rank:].T  # (3, r): combinations of the rigid motions nothing holds
    names = _describe(free)
    if constraint is None:
        raise SolverError(
            f"the displacement conditions leave {3 - rank} rigid motion(s) free ({names}): the "
            "solution is not unique; prescribe more displacement components (e.g. a clamped or "
            "roller patch) or give constraint='rigid'"
        )
    columns = rigid @ free
    net = columns.T @ rhs
    scale = float(np.max(np.abs(columns).T @ np.abs(rhs)))
    if np.any(np.abs(net) > BALANCE_TOL * max(scale, 1e-300)):
        raise SolverError(
            f"the loads do not balance on the free rigid motion(s) ({names}): net "
            f"{np.abs(net).max():.6g} against {scale:.6g}; with constraint='rigid' the body "
            "forces and tractions must have zero net force (and moment, if rotation is free)"
        )
    return columns


def _describe(free: np.ndarray) -> str:
    labels = ("translation in x", "translation in y", "rotation")
    parts = []
    for column in free.T:
        big = np.abs(column) > 1e-6
        parts.append(" + ".join(labels[k] for k in np.flatnonzero(big)))
    return "; ".join(parts)


def _von_mises(stress: np.ndarray, poisson: np.ndarray, plane: str) -> np.ndarray:
    sxx, syy, sxy = stress.T
    szz = poisson * (sxx + syy) if plane == "strain" else np.zeros_like(sxx)
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy**2)
