"""A residual a-posteriori error estimator for the lowest-order virtual elements.

For a solution ``u_h`` of :func:`~blockmesh.vem.solve_poisson` the indicator of a cell E is
(Cangiani, Georgoulis, Pryer and Sutton, "A posteriori error estimates for the virtual element
method", Numer. Math. 137, 2017; Beirão da Veiga and Manzini, IMA J. Numer. Anal. 35, 2015)

``η_E² = (h_E/π)² ‖f - c Π⁰u_h + ∇·(κ ∇Π∇u_h)‖²_E``         (element residual)
``     + ½ Σ_{e ⊂ ∂E inside} h_e ‖[κ ∇Π∇u_h · n]‖²_e``           (flux jumps)
``     + Σ_{e ⊂ ∂E on Neumann or natural patches} h_e ‖g_N - κ ∇Π∇u_h · n‖²_e``
``     + S_E((I - Π∇) u_h, (I - Π∇) u_h)``                        (stabilisation term)

with ``h_E`` the cell's diameter and ``h_e`` the edge's length (``h_E/π`` is the Payne-Weinberger
constant of a convex cell, ``‖v - v̄‖_E <= (h_E/π) ‖∇v‖_E``: the sharp weight of the element
residual, which with ``h_E`` alone made the estimator ten times the error while a sharp peak was
not yet resolved); the estimator is
``η = (Σ_E η_E²)^(1/2)``, an upper bound of the energy error up to a constant and, up to
data oscillation, a lower one (so it follows the error on any mesh, hanging nodes included: an
edge of a coarse cell halved by a hanging node is two edges, each with the one fine cell across).
For :func:`~blockmesh.vem.solve_elasticity` the same with the stress: ``f + div σ(Πu_h)`` (zero
divergence, the stress being constant per cell), the traction jumps ``[σ(Πu_h) n]``, the
traction residual ``t - σ n`` on traction and free patches, and the elasticity stabilisation.

``∇·(κ ∇Π∇u_h) = ∇κ · ∇Π∇u_h`` (the projected gradient is constant per cell); a κ that is not
constant is differentiated by central differences. On a composite domain the data may be given
per region (:class:`~blockmesh.vem.fields.RegionField`): each cell takes its region's f, κ, c (or
C), and the flux jump across an edge is ``κ_1 ∇Π∇u_1 · n - κ_2 ∇Π∇u_2 · n`` with each side's own
κ, so that across an interface, where κ jumps and the exact flux does not, it measures the
flux's discontinuity. Integrals use the composite rule of
:mod:`blockmesh.vem.rules` on cells and Gauss-Legendre on edges, at the solve's order.

Examples
--------
>>> import blockmesh
>>> from blockmesh.vem import solve_poisson
>>> mesh = blockmesh.load_domain("square").mesh(2)
>>> walls = {p: 0 for p in mesh.patch_names}
>>> sol = solve_poisson(mesh, "2*pi^2*sin(pi*x)*sin(pi*y)", dirichlet=walls)
>>> est = estimate_error(sol)
>>> est.indicators.shape == (mesh.n_cells,), est.estimator > sol.errors("sin(pi*x)*sin(pi*y)").h1
(True, True)
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from blockmesh.errors import ArgumentTypeError
from blockmesh.geometry.topology import boundary_slots, cell_neighbours
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.vem.boundary import ProblemData
from blockmesh.vem.elasticity import ElasticitySolution, _strain_matrix
from blockmesh.vem.fields import Field, RegionField
from blockmesh.vem.norms import GRADIENT_STEP, _numerical_gradient
from blockmesh.vem.poisson import PoissonSolution
from blockmesh.vem.rules import cell_chunks, cell_rule, edge_rule, points_per_cell
from blockmesh.vem.stabilization import stabilize

__all__ = ["ErrorEstimate", "estimate_error"]


@dataclass(frozen=True, eq=False)
class ErrorEstimate:
    """The error indicators of every cell, and their parts.

    Attributes
    ----------
    indicators : ndarray (M,)
        ``η_E²`` of every cell, in the mesh's cell order.
    residual, jump, stabilization : ndarray (M,)
        The parts of ``η_E²``: the element residual, the flux (traction) jumps and boundary
        residuals, and the stabilisation term.
    """

    indicators: np.ndarray
    residual: np.ndarray
    jump: np.ndarray
    stabilization: np.ndarray

    @property
    def estimator(self) -> float:
        """``η = (Σ η_E²)^(1/2)``."""
        return float(np.sqrt(np.sum(self.indicators)))

    def parts(self) -> dict[str, float]:
        """The square roots of the summed parts (JSON-ready)."""
        return {
            "residual": float(np.sqrt(self.residual.sum())),
            "jump": float(np.sqrt(self.jump.sum())),
            "stabilization": float(np.sqrt(self.stabilization.sum())),
        }


def estimate_error(solution: PoissonSolution | ElasticitySolution) -> ErrorEstimate:
    """The residual estimator of a virtual element solution (see the module notes).

    O(M) whole-array work plus the quadrature of the solve.
    """
    if isinstance(solution, PoissonSolution):
        return _poisson(solution)
    if isinstance(solution, ElasticitySolution):
        return _elasticity(solution)
    raise ArgumentTypeError(
        f"estimate_error takes a PoissonSolution or ElasticitySolution, not "
        f"{type(solution).__name__}"
    )


class _Edges:
    """The edges of a mesh, slot by slot: interior pairs once, boundary edges with patches."""

    def __init__(self, mesh: PolygonMesh) -> None:
        cells = mesh.polygon_cells()
        neighbour = cell_neighbours(cells, mesh.n_points)
        owner = cells.slot_cell()
        following = cells.following()
        slots = np.arange(mesh.nodes.size)
        inner = slots[neighbour > slots]
        self.inner = np.stack([mesh.nodes[inner], following[inner]], axis=1)
        self.inner_cells = np.stack([owner[inner], owner[neighbour[inner]]], axis=1)
        bslots = boundary_slots(cells, neighbour, mesh.boundary_edges, mesh.n_points)
        self.boundary = mesh.boundary_edges
        self.boundary_cell = owner[bslots]
        self.boundary_patch = mesh.boundary_patch
        self.points = mesh.points

    def share(self, jump: np.ndarray, term: np.ndarray) -> None:
        """Half of every inner edge's ``term`` to each of its two cells."""
        np.add.at(jump, self.inner_cells[:, 0], 0.5 * term)
        np.add.at(jump, self.inner_cells[:, 1], 0.5 * term)

    def flux_patches(self, data: ProblemData, names: tuple[str, ...], order: int) -> Iterator:
        """Per Neumann or natural patch: ``(fields, cell, normal, length, x, y, w)`` of its edges.

        ``fields`` per component as :func:`_neumann_data` gives them; ``x, y, w`` the
        Gauss-Legendre points of the edges.
        """
        for patch, fields in _neumann_data(data, names).items():
            mine = np.flatnonzero(self.boundary_patch == patch)
            if mine.size == 0:
                continue
            e = self.boundary[mine]
            normal, length = self.normals(self.points, e)
            x, y, w, _ = edge_rule(self.points, e, order)
            yield fields, self.boundary_cell[mine], normal, length, x, y, w

    @staticmethod
    def normals(points: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Unit normals to the right of each edge (outward for a CCW cell) and lengths."""
        d = points[edges[:, 1]] - points[edges[:, 0]]
        length = np.hypot(d[:, 0], d[:, 1])
        return np.stack([d[:, 1], -d[:, 0]], axis=1) / length[:, None], length


def _cell_diameters(mesh: PolygonMesh) -> np.ndarray:
    return mesh.cell_diameters()


def _gradient_of(
    field: Field | RegionField, x: np.ndarray, y: np.ndarray, step: np.ndarray, region: np.ndarray
) -> np.ndarray:
    """∇field at the points (C, Q, 2) of cells of ``region`` (C,), by central differences.

    Zero for a constant, or a constant in every region; a region's field is differentiated as
    the smooth function it is inside that region.
    """
    if _piecewise_constant(field):
        return np.zeros((*np.shape(x), 2))
    gx, gy = _numerical_gradient(field, x, y, step, region)
    return np.stack([gx, gy], axis=-1)


def _piecewise_constant(field: Field | RegionField) -> bool:
    """Whether ``field`` is a constant, or a constant in every region."""
    if isinstance(field, RegionField):
        return all(piece.constant is not None for piece in field.pieces)
    return field.constant is not None


#: A displacement component held by a Dirichlet condition (no traction residual there).
_HELD = "held"


def _neumann_data(data: ProblemData, patch_names: tuple[str, ...]) -> dict[int, tuple]:
    """Per patch index, per component: the Neumann field, None (natural: zero), or held.

    A component prescribed by a Dirichlet condition is held (no flux residual); a free
    component of a displacement condition (a roller) is natural.
    """
    components = data.conditions.components
    given = {c.patch: c.fields for c in data.conditions.neumann}
    held = {c.patch: c.fields for c in data.conditions.dirichlet}
    out: dict[int, tuple] = {}
    for k, name in enumerate(patch_names):
        if name in held:
            parts = tuple(_HELD if f is not None else None for f in held[name])
            if all(part == _HELD for part in parts):
                continue
            out[k] = parts
        else:
            out[k] = given.get(name, (None,) * components)
    return out


def _stabilization_term(
    consistency: np.ndarray,
    residual: np.ndarray,
    local: np.ndarray,
    data: ProblemData,
    coefficient: np.ndarray | None,
) -> np.ndarray:
    """``S_E((I - Π)u, (I - Π)u) = Σ_i T_ii r_i²`` with ``r = (I - Π) u`` (M,), never negative.

    ``r`` is formed first: the quadratic form of the full vector would cancel to round-off of
    the size of ``u`` itself (a linear ``u`` has ``r = 0`` exactly up to round-off of ``r``).
    """
    d = consistency.shape[1]
    identity = np.broadcast_to(np.eye(d), consistency.shape)
    weights = stabilize(
        consistency, identity, data.recipe, coefficient=coefficient, scale=data.scale
    )
    r = np.einsum("mij,mj->mi", residual, local)
    return np.einsum("mii,mi->m", weights, r * r)


def _poisson(solution: PoissonSolution) -> ErrorEstimate:
    mesh = solution.mesh
    data = solution._data
    if data is None:
        raise ArgumentTypeError("this solution does not carry its data; solve it again")
    f, kappa, c = data.load[0], solution._diffusion, solution._reaction
    order = solution._order
    diameter = _cell_diameters(mesh)
    gradient = solution.cell_gradient
    residual = np.zeros(mesh.n_cells)
    stab = np.zeros(mesh.n_cells)
    for group, proj in zip(mesh.groups, solution._projections, strict=True):
        local = solution.values[group.cells]
        kappa_mean = np.empty(group.n_cells)
        for part in cell_chunks(group.n_cells, points_per_cell(group.size, order)):
            cells = group.cells[part]
            index = group.index[part]
            x, y, w = cell_rule(mesh.points, cells, order)
            region = mesh.region[index]
            value = f.at(x, y, region)
            kappa_at = kappa.at(x, y, region)
            kappa_mean[part] = np.sum(w * kappa_at, axis=1) / proj.area[part]
            g = gradient[index]
            if not c.is_zero:
                dx = x - proj.centre[part, 0:1]
                dy = y - proj.centre[part, 1:2]
                uh = local[part].mean(axis=1)[:, None] + dx * g[:, None, 0] + dy * g[:, None, 1]
                value = value - c.at(x, y, region) * uh
            if not _piecewise_constant(kappa):
                step = GRADIENT_STEP * diameter[index][:, None]
                grad_kappa = _gradient_of(kappa, x, y, step, region)
                value = value + np.einsum("cqd,cd->cq", grad_kappa, g)
            weight = (diameter[index] / np.pi) ** 2
            residual[index] = weight * np.sum(w * value * value, axis=1)
        consistency = (kappa_mean * proj.area)[:, None, None] * np.matmul(
            proj.gradient.transpose(0, 2, 1), proj.gradient
        )
        stab[group.index] = _stabilization_term(
            consistency, proj.residual(), local, data, kappa_mean
        )
    edges = _Edges(mesh)
    jump = np.zeros(mesh.n_cells)
    # interior edges: the jump of the normal flux, half to each side (each side with its own
    # region's κ: across an interface of a composite domain κ jumps, the flux does not)
    normal, length = edges.normals(mesh.points, edges.inner)
    x, y, w, _ = edge_rule(mesh.points, edges.inner, order)
    flux = np.zeros(x.shape)
    for side, sign in ((0, 1.0), (1, -1.0)):
        cell = edges.inner_cells[:, side]
        normal_gradient = np.einsum("ed,ed->e", gradient[cell], normal)[:, None]
        flux += sign * kappa.at(x, y, mesh.region[cell]) * normal_gradient
    edges.share(jump, length * np.sum(w * flux * flux, axis=1))
    # boundary edges on Neumann and natural patches: the flux residual
    for fields, cell, normal, length, x, y, w in edges.flux_patches(data, mesh.patch_names, order):
        given = 0.0 if fields[0] is None else fields[0](x, y)
        kappa_at = kappa.at(x, y, mesh.region[cell])
        miss = given - kappa_at * np.einsum("ed,ed->e", gradient[cell], normal)[:, None]
        np.add.at(jump, cell, length * np.sum(w * miss * miss, axis=1))
    total = residual + jump + stab
    return ErrorEstimate(total, residual, jump, stab)


def _elasticity(solution: ElasticitySolution) -> ErrorEstimate:
    mesh = solution.mesh
    data = solution._data
    if data is None:
        raise ArgumentTypeError("this solution does not carry its data; solve it again")
    order = solution._order
    diameter = _cell_diameters(mesh)
    residual = np.zeros(mesh.n_cells)
    stab = np.zeros(mesh.n_cells)
    material = solution.material
    for group, proj in zip(mesh.groups, solution._projections, strict=True):
        d = np.stack([2 * group.cells, 2 * group.cells + 1], axis=2).reshape(group.n_cells, -1)
        local = solution.displacement.reshape(-1)[d]
        if not all(f.is_zero for f in data.load):
            for part in cell_chunks(group.n_cells, points_per_cell(group.size, order)):
                index = group.index[part]
                x, y, w = cell_rule(mesh.points, group.cells[part], order)
                region = mesh.region[index]
                square = sum(f.at(x, y, region) ** 2 for f in data.load if not f.is_zero)
                weight = (diameter[index] / np.pi) ** 2
                residual[index] = weight * np.sum(w * square, axis=1)
        strain_map = _strain_matrix(proj.gradient)
        cell_material = material[mesh.region[group.index]] if material.ndim == 3 else material
        consistency = proj.area[:, None, None] * np.matmul(
            strain_map.transpose(0, 2, 1), np.matmul(cell_material, strain_map)
        )
        m, n = proj.area.shape[0], proj.size
        rest = np.einsum("mij,ab->miajb", proj.residual(), np.eye(2)).reshape(m, 2 * n, 2 * n)
        stab[group.index] = _stabilization_term(consistency, rest, local, data, None)
    sxx, syy, sxy = solution.stress.T
    tensor = np.stack([np.stack([sxx, sxy], -1), np.stack([sxy, syy], -1)], -2)  # (M, 2, 2)
    edges = _Edges(mesh)
    jump = np.zeros(mesh.n_cells)
    normal, length = edges.normals(mesh.points, edges.inner)
    difference = tensor[edges.inner_cells[:, 0]] - tensor[edges.inner_cells[:, 1]]
    traction = np.einsum("eij,ej->ei", difference, normal)
    edges.share(jump, length * length * np.sum(traction * traction, axis=1))
    for fields, cell, normal, length, x, y, w in edges.flux_patches(data, mesh.patch_names, order):
        own = np.einsum("eij,ej->ei", tensor[cell], normal)  # (E, 2)
        miss = np.zeros(x.shape)
        for a in range(2):
            field = fields[a]
            if isinstance(field, str):  # held by a displacement condition
                continue
            given = 0.0 if field is None else field(x, y)
            miss = miss + (given - own[:, a : a + 1]) ** 2
        np.add.at(jump, cell, length * np.sum(w * miss, axis=1))
    total = residual + jump + stab
    return ErrorEstimate(total, residual, jump, stab)
