"""The paper's accuracy claim, measured at equal cost (a script, not a test).

The paper says that solutions on its pentagonal refinement "outperform" those on triangle and
quadrilateral refinements. This compares, on the same problems and counting the same things:

* lowest-order virtual elements (``blockmesh.vem``) on the paper's pentagon refinement, on
  pentagons with Laplacian smoothing per level (``smooth=3``), with the paper's inner points
  moved per level (``blockmesh.refinement.improve.inner_point_rule``), with optimised node
  placement per level (``refine(..., placement="optimized")``), and on pentagons converted from
  a uniform triangle mesh (9 pentagons per triangle, the template of ``Domain.from_polygon``);
* P1 triangles and Q1 quadrilaterals of scikit-fem on uniform n x n grids;
* P1 triangles on quality Delaunay meshes (Triangle's ``q30``: no angle below 30 degrees, sizes
  bounded by an area constraint) at the unknowns of the paper's pentagon levels, on the smooth
  problem and Cook's membrane: the fair baseline, as a finite element user would mesh (the
  structured grid is not what one draws for Cook's skewed membrane).

Problems: u = sin(pi x) sin(pi y) on the unit square (smooth); u = r^(2/3) sin(2 phi / 3) on the
L-shape (corner singularity); Cook's membrane (plane stress, E = 1, nu = 1/3, shear load 1: the
vertical displacement of the middle of the loaded edge, (48, 52)); the Kirsch plate (the
catalogue's ``quarter-plate-hole``, plane stress, E = 1, nu = 0.3, the exact infinite-plate stress
of ``blockmesh.vem.reference.kirsch`` as traction on the outer sides, rollers on the symmetry
lines: the energy error against the exact field, and the stress concentration sigma_xx at the top
of the hole, exactly 3, as the area-weighted mean of the cell-mean stresses of the cells there).
The P1/Q1 grids of the Kirsch plate are O-grids: 2n x 2n near-square quadrilaterals (split in
two for P1), uniform along the hole's arc and growing geometrically towards the outer sides.

Counted the same way for every method: ``dof`` = unknowns of the solved system (nodes not on a
Dirichlet patch, times the components), ``nnz`` = stored entries of that reduced matrix,
``seconds`` = assembly + Dirichlet elimination + the same sparse LU solve (SuperLU,
minimum-degree ordering on A + A^T, through ``blockmesh.vem.assembly.solve_system`` for all).
Errors: L2 and the (broken) H1 seminorm against the exact solution with high-order quadrature; for
the virtual elements on the projections ``Π⁰u_h`` and ``∇Π∇u_h`` (the only computable parts of the
virtual solution), for P1/Q1 on the finite element function itself. Errors are compared against
dof, nnz and time, never against level or h.

Run: ``python benchmarks/bench_accuracy.py [--quick] [--plot docs/img/accuracy.png]``; the
tables go to ``docs/benchmarks/accuracy.md`` (``--page-dir DIR`` elsewhere, ``--no-page`` none).
scikit-fem is needed (``pip install -e '.[test]'``), and Triangle for the Delaunay baseline
(``pip install -e '.[bench]'``; without it those rows are left out, and the page says so).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # level-1 BLAS threads only slow this down

import argparse
import json
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np
from _page import Page, add_arguments

import blockmesh
from blockmesh.decompose import decompose_convex_polygon
from blockmesh.mesh import Mesh
from blockmesh.refinement.improve import inner_point_rule, refine_with_rule
from blockmesh.vem import PolygonMesh, elasticity_matrix, solve_elasticity, solve_poisson
from blockmesh.vem.assembly import solve_system
from blockmesh.vem.evaluate import boundary_values
from blockmesh.vem.reference import kirsch
from blockmesh.vem.rules import cell_rule

PI = math.pi
COOK = [(0.0, 0.0), (48.0, 44.0), (48.0, 60.0), (0.0, 44.0)]
COOK_POINT = (48.0, 52.0)
COOK_QUOTED = 23.96
HOLE = 0.5  # the Kirsch plate's hole radius (quarter-plate-hole); E = 1, nu = 0.3, plane stress
KIRSCH = kirsch(radius=HOLE, young=1.0, poisson=0.3)


@dataclass
class Run:
    problem: str
    method: str
    size: int  # level (pentagons) or n (n x n grid)
    dof: int
    nnz: int
    seconds: float
    l2: float = float("nan")
    h1: float = float("nan")
    value: float = float("nan")  # Cook: the displacement; Kirsch: the stress concentration
    energy: float = float("nan")  # Kirsch: the energy norm of the error
    min_angle: float = float("nan")
    h1_floor: float = float("nan")  # the best cell-wise constant gradient on the same cells


# ------------------------------------------------------------------------------ problems
def smooth_u(x, y):
    return np.sin(PI * x) * np.sin(PI * y)


def smooth_grad(x, y):
    return PI * np.cos(PI * x) * np.sin(PI * y), PI * np.sin(PI * x) * np.cos(PI * y)


def smooth_f(x, y):
    return 2 * PI**2 * smooth_u(x, y)


def _corner_polar(x, y):
    """r and the angle phi in [0, 3 pi / 2] of the L-shape's re-entrant corner (1, 1)."""
    dx, dy = x - 1.0, y - 1.0
    r = np.hypot(dx, dy)
    phi = np.arctan2(dx - dy, -(dx + dy)) + 0.75 * PI
    return r, phi, dx, dy


def corner_u(x, y):
    r, phi, _, _ = _corner_polar(x, y)
    return r ** (2 / 3) * np.sin(2 * phi / 3)


def corner_grad(x, y):
    r, phi, dx, dy = _corner_polar(x, y)
    r = np.maximum(r, 1e-300)
    radial = (2 / 3) * r ** (-1 / 3) * np.sin(2 * phi / 3)
    angular = (2 / 3) * r ** (-1 / 3) * np.cos(2 * phi / 3)
    return radial * dx / r - angular * dy / r, radial * dy / r + angular * dx / r


PROBLEMS: dict[str, tuple[Callable, Callable, Callable]] = {
    "smooth": (smooth_u, smooth_grad, smooth_f),
    "corner": (corner_u, corner_grad, lambda x, _y: np.zeros_like(x)),
}


# ------------------------------------------------------------------------------ meshes
def triangles_to_pentagons(points: np.ndarray, triangles: np.ndarray) -> Mesh:
    """Every triangle as the 9 pentagons of its template, merged by topology (not coordinates).

    The template's two nodes per side sit at symmetric fractions, so neighbours agree on each
    shared side; a side node is identified by (side, position from the side's lower vertex id).
    """
    ref = decompose_convex_polygon(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    bary = np.column_stack([1 - ref.vertices.sum(axis=1), ref.vertices])  # (19, 3)
    n_t, n_p = triangles.shape[0], points.shape[0]
    local_ids = np.full((n_t, bary.shape[0]), -1, dtype=np.int64)
    local_ids[:, :3] = triangles
    next_id = n_p
    side_nodes: dict[tuple[int, int, int], int] = {}
    for t in range(n_t):  # the merge is bookkeeping only; the geometry below is vectorised
        for side, chain in enumerate(ref.edge_chains):
            a, b = int(triangles[t, side]), int(triangles[t, (side + 1) % 3])
            inner = chain[1:-1] if a < b else chain[1:-1][::-1]
            for k, node in enumerate(inner):
                key = (min(a, b), max(a, b), k)
                if key not in side_nodes:
                    side_nodes[key] = next_id
                    next_id += 1
                local_ids[t, node] = side_nodes[key]
        for node in range(bary.shape[0]):
            if local_ids[t, node] < 0:
                local_ids[t, node] = next_id
                next_id += 1
    xy = np.empty((next_id, 2))
    xy[:n_p] = points
    placed = np.einsum("vk,tkd->tvd", bary, points[triangles]).reshape(-1, 2)
    ids, first = np.unique(local_ids.ravel(), return_index=True)  # a shared node: its first
    xy[ids] = placed[first]
    xy[:n_p] = points  # the triangles' corners exactly
    cells = np.take_along_axis(local_ids, np.tile(ref.blocks.ravel(), (n_t, 1)), axis=1)
    return Mesh.from_cells(xy, cells.reshape(-1, 5))


#: The method name of P1 on quality Delaunay meshes (the fair baseline).
DELAUNAY = "P1 Delaunay (Triangle q30)"


def have_triangle() -> bool:
    """Whether the ``triangle`` package (Shewchuk's Triangle) is installed."""
    import importlib.util

    return importlib.util.find_spec("triangle") is not None


def delaunay_mesh(corners: np.ndarray, max_area: float):
    """A quality Delaunay mesh of the polygon ``corners`` (Triangle ``pq30a<max_area>``)."""
    import skfem
    import triangle

    segments = np.column_stack([np.arange(len(corners)), np.roll(np.arange(len(corners)), -1)])
    made = triangle.triangulate(
        {"vertices": np.asarray(corners, float), "segments": segments},
        f"pq30a{np.format_float_positional(max_area, trim='-')}",  # Triangle reads no exponent
    )
    points = made["vertices"]
    triangles = _ccw(points, made["triangles"])
    return skfem.MeshTri(np.ascontiguousarray(points.T), np.ascontiguousarray(triangles.T))


def matched_delaunay(corners: np.ndarray, dof_of: Callable, target: int, tol: float = 0.02):
    """The Delaunay mesh whose unknowns (``dof_of(mesh)``) are within ``tol`` of ``target``.

    The unknowns go as 1/area: the area constraint is rescaled by the ratio got/target until they
    match (a few Triangle runs of milliseconds each); the closest mesh is returned.
    """
    area = float(abs(_shoelace(np.asarray(corners, float))))
    max_area = area / target  # about 2 triangles per node, half of them inside: a first guess
    best, best_gap = None, math.inf
    for _ in range(12):
        mesh = delaunay_mesh(corners, max_area)
        got = dof_of(mesh)
        gap = abs(got / target - 1)
        if gap < best_gap:
            best, best_gap = mesh, gap
        if gap <= tol:
            break
        max_area *= got / target
    return best


def _shoelace(xy: np.ndarray) -> float:
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _interior_nodes(mesh) -> int:
    return mesh.p.shape[1] - mesh.boundary_nodes().size


def _cook_unknowns(mesh) -> int:
    return 2 * int(np.count_nonzero(~np.isclose(mesh.p[0], 0.0)))


#: Cook's membrane with the middle of the loaded edge, where the displacement is read, a vertex.
COOK_WITH_POINT = np.array([(0.0, 0.0), (48.0, 44.0), (48.0, 52.0), (48.0, 60.0), (0.0, 44.0)])


def square_triangles(n: int):
    import skfem

    t = np.linspace(0, 1, n + 1)
    return skfem.MeshTri.init_tensor(t, t)


def optimized_levels(domain, level: int) -> Mesh:
    """The mesh of ``blockmesh mesh --placement optimized`` (node placement after each level)."""
    return refine_with_rule(domain, level, rule="optimized")


def lshape_grid(n: int, quads: bool):
    """Uniform n-per-unit grid on [0,2]x[0,1] u [0,1]x[1,2]."""
    import skfem

    t = np.linspace(0, 2, 2 * n + 1)
    full = skfem.MeshQuad.init_tensor(t, t) if quads else skfem.MeshTri.init_tensor(t, t)
    centres = full.p[:, full.t].mean(axis=1)
    return full.remove_elements(np.flatnonzero((centres[0] > 1) & (centres[1] > 1)))


def cook_grid(n: int, quads: bool):
    import skfem

    t = np.linspace(0, 1, n + 1)
    unit = skfem.MeshQuad.init_tensor(t, t) if quads else skfem.MeshTri.init_tensor(t, t)
    xi, eta = unit.p
    return type(unit)(np.array([48 * xi, 44 * xi + eta * (44 - 28 * xi)]), unit.t)


def kirsch_grid(n: int, quads: bool):
    """The quarter plate [0, 2]^2 minus the hole: an O-grid of 2n x 2n near-square cells.

    Angles are uniform on the arc (2n cells); each ray from the arc to the side x = 2 (angles up
    to 45 degrees) or y = 2 carries 2n cells growing geometrically, so that every cell's radial
    length is about its width (the grid a finite element user would draw around a hole).
    """
    import skfem

    theta = np.linspace(0, PI / 2, 2 * n + 1)
    ray = np.column_stack([np.cos(theta), np.sin(theta)])
    reach = 2.0 / np.maximum(ray[:, 0], ray[:, 1])  # from the centre to the outer side
    radius = HOLE * (reach[:, None] / HOLE) ** np.linspace(0, 1, 2 * n + 1)[None, :]
    p = radius[:, :, None] * ray[:, None, :]  # (angle, radius, xy)
    ids = np.arange(p.shape[0] * p.shape[1]).reshape(p.shape[:2])
    a, b = ids[:-1, :-1].ravel(), ids[:-1, 1:].ravel()  # counter-clockwise: out, round, in
    c, d = ids[1:, 1:].ravel(), ids[1:, :-1].ravel()
    points = p.reshape(-1, 2).T
    if quads:
        return skfem.MeshQuad(points, np.array([a, b, c, d]))
    return skfem.MeshTri(points, np.hstack([np.array([a, b, c]), np.array([a, c, d])]))


# ------------------------------------------------------------------------------ VEM runs
def timed(solve: Callable[[], tuple], small: bool) -> tuple[tuple, float]:
    """The result of ``solve()`` and its best time of 3 runs (1 run for big systems)."""
    best = math.inf
    result: tuple = ()
    for _ in range(3 if small else 1):
        started = time.perf_counter()
        result = solve()
        best = min(best, time.perf_counter() - started)
    return result, best


def vem_poisson(problem: str, method: str, size: int, mesh) -> Run:
    u, grad, f = PROBLEMS[problem]
    (sol,), seconds = timed(
        lambda: (solve_poisson(mesh, f, dirichlet={p: u for p in mesh.patch_names}, order=4),),
        mesh.n_points < 50_000,
    )
    e = sol.errors(u, grad, order=6)
    angle = mesh.quality().min_angle if isinstance(mesh, Mesh) else float("nan")
    return Run(
        problem,
        method,
        size,
        sol.info.dof,
        sol.info.nonzeros,
        seconds,
        e.l2,
        e.h1,
        min_angle=angle,
        h1_floor=constant_gradient_floor(mesh, grad),
    )


def constant_gradient_floor(mesh, grad: Callable) -> float:
    """``(Σ_E ‖∇u - mean_E ∇u‖²)^(1/2)``: no constant gradient per cell does better."""
    pm = mesh if isinstance(mesh, PolygonMesh) else PolygonMesh.from_mesh(mesh)
    total = 0.0
    for group in pm.groups:
        x, y, w = cell_rule(pm.points, group.cells, 6)
        gx, gy = grad(x, y)
        area = w.sum(axis=1, keepdims=True)
        mx, my = (w * gx).sum(1, keepdims=True) / area, (w * gy).sum(1, keepdims=True) / area
        total += float(np.sum(w * ((gx - mx) ** 2 + (gy - my) ** 2)))
    return math.sqrt(total)


def vem_cook(method: str, size: int, mesh, **options) -> Run:
    def solve() -> tuple:
        return (
            solve_elasticity(
                mesh,
                young=1.0,
                poisson=1 / 3,
                dirichlet={"clamped": (0, 0)},
                neumann={"loaded": (0, 1 / 16)},
                **options,
            ),
        )

    (sol,), seconds = timed(solve, mesh.n_points < 25_000)
    value = float(boundary_values(sol.mesh, sol.displacement, [COOK_POINT])[0, 1])
    return Run(
        "cook",
        method,
        size,
        sol.info.dof,
        sol.info.nonzeros,
        seconds,
        value=value,
        min_angle=mesh.quality().min_angle,
    )


def vem_kirsch(method: str, size: int, mesh) -> Run:
    sxx, syy, sxy = KIRSCH.stress

    def solve() -> tuple:
        return (
            solve_elasticity(
                mesh,
                young=1.0,
                poisson=0.3,
                dirichlet={"left": (0, "free"), "down": ("free", 0)},
                neumann={"right": (sxx, sxy), "up": (sxy, syy)},
                order=4,
            ),
        )

    (sol,), seconds = timed(solve, mesh.n_points < 25_000)
    e = sol.errors(KIRSCH.displacement, order=6)
    top = np.flatnonzero(np.hypot(mesh.points[:, 0], mesh.points[:, 1] - HOLE) < 1e-9)
    cells = np.flatnonzero(np.any(mesh.cells == top[0], axis=1))
    area = mesh.cell_areas()[cells]
    peak = float(area @ sol.stress[cells, 0] / area.sum())
    return Run(
        "kirsch",
        method,
        size,
        sol.info.dof,
        sol.info.nonzeros,
        seconds,
        l2=e.l2,
        value=peak,
        energy=e.energy,
        min_angle=mesh.quality().min_angle,
    )


# ------------------------------------------------------------------------------ FEM runs
def fem_poisson(problem: str, method: str, size: int, mesh) -> Run:
    import skfem
    from skfem.helpers import dot, grad

    u, du, f = PROBLEMS[problem]
    element = skfem.ElementQuad1() if isinstance(mesh, skfem.MeshQuad) else skfem.ElementTriP1()

    def solve() -> tuple:
        basis = skfem.Basis(mesh, element, intorder=6)
        a = skfem.asm(skfem.BilinearForm(lambda v, w, _: dot(grad(v), grad(w))), basis)
        b = skfem.asm(skfem.LinearForm(lambda v, w: f(*w.x) * v), basis)
        fixed = mesh.boundary_nodes()
        return solve_system(a.tocsr(), b, fixed, u(*mesh.p[:, fixed]))

    (uh, info), seconds = timed(solve, mesh.p.shape[1] < 50_000)

    @skfem.Functional
    def l2(w):
        return (w["uh"] - u(*w.x)) ** 2

    @skfem.Functional
    def h1(w):
        gx, gy = du(*w.x)
        return (w["uh"].grad[0] - gx) ** 2 + (w["uh"].grad[1] - gy) ** 2

    fine = skfem.Basis(mesh, element, intorder=10)
    field = fine.interpolate(uh)
    return Run(
        problem,
        method,
        size,
        info.dof,
        info.nonzeros,
        seconds,
        math.sqrt(l2.assemble(fine, uh=field)),
        math.sqrt(h1.assemble(fine, uh=field)),
    )


def fem_cook(method: str, size: int, mesh, order: int = 1) -> Run:
    import skfem
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    lam, mu = lame_parameters(1.0, 1 / 3)
    lam = 2 * lam * mu / (lam + 2 * mu)  # plane stress
    if isinstance(mesh, skfem.MeshQuad):
        scalar = skfem.ElementQuad1()
    else:
        scalar = skfem.ElementTriP1() if order == 1 else skfem.ElementTriP2()
    element = skfem.ElementVector(scalar)
    basis = skfem.Basis(mesh, element)

    def solve() -> tuple:
        a = skfem.asm(linear_elasticity(lam, mu), skfem.Basis(mesh, element))
        loaded = mesh.facets_satisfying(lambda x: np.isclose(x[0], 48.0))
        fb = skfem.FacetBasis(mesh, element, facets=loaded)
        b = skfem.asm(skfem.LinearForm(lambda v, _w: v[1] / 16), fb)
        fixed = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
        return solve_system(a.tocsr(), b, fixed, np.zeros(fixed.size))

    (uh, info), seconds = timed(solve, mesh.p.shape[1] < 25_000)
    node = np.flatnonzero(np.isclose(mesh.p[0], 48) & np.isclose(mesh.p[1], 52))
    if node.size:
        value = float(uh[basis.nodal_dofs[1, node[0]]])
    else:  # the point is inside an edge: interpolate along it (the trace is linear there)
        value = float(basis.probes(np.array([[48.0 - 1e-12], [52.0]])) @ uh)
    return Run("cook", method, size, info.dof, info.nonzeros, seconds, value=value)


def fem_kirsch(method: str, size: int, mesh) -> Run:
    import skfem
    from skfem.helpers import sym_grad
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    lam, mu = lame_parameters(1.0, 0.3)
    lam = 2 * lam * mu / (lam + 2 * mu)  # plane stress
    quads = isinstance(mesh, skfem.MeshQuad)
    element = skfem.ElementVector(skfem.ElementQuad1() if quads else skfem.ElementTriP1())
    basis = skfem.Basis(mesh, element, intorder=4)
    (ux, uy), (sxx, syy, sxy) = KIRSCH.displacement, KIRSCH.stress

    def solve() -> tuple:
        a = skfem.asm(linear_elasticity(lam, mu), skfem.Basis(mesh, element, intorder=4))
        right = mesh.facets_satisfying(lambda x: np.isclose(x[0], 2.0))
        up = mesh.facets_satisfying(lambda x: np.isclose(x[1], 2.0))
        fr = skfem.FacetBasis(mesh, element, facets=right, intorder=6)
        fu = skfem.FacetBasis(mesh, element, facets=up, intorder=6)
        b = skfem.asm(skfem.LinearForm(lambda v, w: sxx(*w.x) * v[0] + sxy(*w.x) * v[1]), fr)
        b += skfem.asm(skfem.LinearForm(lambda v, w: sxy(*w.x) * v[0] + syy(*w.x) * v[1]), fu)
        fixed = np.concatenate(
            [
                basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).nodal["u^1"],
                basis.get_dofs(lambda x: np.isclose(x[1], 0.0)).nodal["u^2"],
            ]
        )
        return solve_system(a.tocsr(), b, fixed, np.zeros(fixed.size))

    (uh, info), seconds = timed(solve, mesh.p.shape[1] < 25_000)
    compliance = np.linalg.inv(elasticity_matrix(1.0, 0.3))

    def strain_error(w):  # (exx, eyy, gamma_xy) of the exact field minus the discrete one
        exact = np.einsum("ij,j...->i...", compliance, np.array([f(*w.x) for f in KIRSCH.stress]))
        e = sym_grad(w["uh"])
        return exact - np.array([e[0, 0], e[1, 1], 2 * e[0, 1]])

    @skfem.Functional
    def l2(w):
        return (w["uh"][0] - ux(*w.x)) ** 2 + (w["uh"][1] - uy(*w.x)) ** 2

    @skfem.Functional
    def energy(w):
        d = strain_error(w)
        return np.einsum("i...,ij,j...->...", d, elasticity_matrix(1.0, 0.3), d)

    @skfem.Functional
    def mean_sxx(w):  # the cell integral of sigma_xx(u_h)
        e = sym_grad(w["uh"])
        c = elasticity_matrix(1.0, 0.3)
        return c[0, 0] * e[0, 0] + c[0, 1] * e[1, 1]

    fine = skfem.Basis(mesh, element, intorder=8)
    field = fine.interpolate(uh)
    top = np.flatnonzero(np.hypot(mesh.p[0], mesh.p[1] - HOLE) < 1e-9)[0]
    cells = np.flatnonzero(np.any(mesh.t == top, axis=0))
    integral = mean_sxx.elemental(fine, uh=field)[cells]
    area = skfem.Functional(lambda w: 1.0 + 0 * w.x[0]).elemental(fine)[cells]
    return Run(
        "kirsch",
        method,
        size,
        info.dof,
        info.nonzeros,
        seconds,
        l2=math.sqrt(l2.assemble(fine, uh=field)),
        value=float(integral.sum() / area.sum()),
        energy=math.sqrt(energy.assemble(fine, uh=field)),
    )


# ------------------------------------------------------------------------------ the study
def smooth_runs(quick: bool) -> list[Run]:
    import skfem

    runs = []
    square = blockmesh.load_domain("square")
    top = 4 if quick else 5
    for level in range(1, top + 1):
        runs.append(vem_poisson("smooth", "pentagons (paper)", level, square.mesh(level)))
        runs.append(
            vem_poisson("smooth", "pentagons, smooth=3", level, square.mesh(level, smooth=3))
        )
        runs.append(
            vem_poisson(
                "smooth", "pentagons, inner-point rule", level, inner_point_rule(square, level)
            )
        )
        if level <= top - (1 if quick else 0):
            runs.append(
                vem_poisson(
                    "smooth", "pentagons, optimized", level, optimized_levels(square, level)
                )
            )
        print(f"  smooth: level {level} done", flush=True)
    for n in (2, 4, 8, 16, 32) if not quick else (2, 4, 8):
        tri = square_triangles(n)
        converted = triangles_to_pentagons(tri.p.T, _ccw(tri.p.T, tri.t.T))
        runs.append(vem_poisson("smooth", "pentagons from triangles", n, converted))
    for n in (8, 16, 32, 64, 128, 256) if not quick else (8, 16, 32, 64):
        t = np.linspace(0, 1, n + 1)
        runs.append(fem_poisson("smooth", "P1 triangles", n, skfem.MeshTri.init_tensor(t, t)))
        runs.append(fem_poisson("smooth", "Q1 quads", n, skfem.MeshQuad.init_tensor(t, t)))
    if have_triangle():
        unit = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
        for run in [r for r in runs if r.method == "pentagons (paper)"]:
            mesh = matched_delaunay(unit, _interior_nodes, run.dof)
            runs.append(fem_poisson("smooth", DELAUNAY, run.size, mesh))
    check = square_triangles(16)  # VEM on the same triangles reproduces P1 (a sanity row)
    runs.append(
        vem_poisson(
            "smooth",
            "VEM on the P1 triangles",
            16,
            PolygonMesh.from_cells(check.p.T, _ccw(check.p.T, check.t.T)),
        )
    )
    return runs


def _ccw(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a, b, c = (points[triangles[:, k]] for k in range(3))
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    out = triangles.copy()
    out[area < 0] = out[area < 0][:, [0, 2, 1]]
    return out


def corner_runs(quick: bool) -> list[Run]:
    runs = []
    lshape = blockmesh.load_domain("l-shape")
    for level in range(1, (3 if quick else 4) + 1):
        runs.append(vem_poisson("corner", "pentagons (paper)", level, lshape.mesh(level)))
        runs.append(
            vem_poisson("corner", "pentagons, optimized", level, optimized_levels(lshape, level))
        )
    for n in (4, 8, 16, 32, 64, 128) if not quick else (4, 8, 16, 32):
        runs.append(fem_poisson("corner", "P1 triangles", n, lshape_grid(n, quads=False)))
        runs.append(fem_poisson("corner", "Q1 quads", n, lshape_grid(n, quads=True)))
    return runs


def cook_runs(quick: bool) -> tuple[list[Run], float]:
    runs = []
    cook = blockmesh.Domain.from_polygon(COOK, patches={"clamped": [3], "loaded": [1]}, name="cook")
    for level in range(0, (3 if quick else 5) + 1):
        runs.append(vem_cook("pentagons (paper)", level, cook.mesh(level)))
        runs.append(vem_cook("pentagons, optimized", level, optimized_levels(cook, level)))
    for n in (4, 8, 16, 32, 64, 128) if not quick else (4, 8, 16, 32):
        runs.append(fem_cook("P1 triangles", n, cook_grid(n, quads=False)))
        runs.append(fem_cook("Q1 quads", n, cook_grid(n, quads=True)))
    if have_triangle():
        for run in [r for r in runs if r.method == "pentagons (paper)"]:
            mesh = matched_delaunay(COOK_WITH_POINT, _cook_unknowns, run.dof)
            runs.append(fem_cook(DELAUNAY, run.size, mesh))
    reference = [
        fem_cook("P2 triangles (reference)", n, cook_grid(n, quads=False), order=2)
        for n in ((16, 32, 64) if quick else (32, 64, 128))
    ]
    runs += reference
    v = [r.value for r in reference]
    ratio = (v[1] - v[0]) / (v[2] - v[1])  # Richardson with the observed rate
    extrapolated = v[2] + (v[2] - v[1]) / (ratio - 1)
    return runs, extrapolated


def kirsch_runs(quick: bool) -> list[Run]:
    runs = []
    plate = blockmesh.load_domain("quarter-plate-hole")
    for level in range(1, (3 if quick else 4) + 1):
        runs.append(vem_kirsch("pentagons (paper)", level, plate.mesh(level)))
        runs.append(vem_kirsch("pentagons, optimized", level, optimized_levels(plate, level)))
    for n in (2, 4, 8, 16) if quick else (2, 4, 8, 16, 32, 64):
        runs.append(fem_kirsch("P1 triangles", n, kirsch_grid(n, quads=False)))
        runs.append(fem_kirsch("Q1 quads", n, kirsch_grid(n, quads=True)))
    return runs


def stabilization_runs() -> list[Run]:
    runs = []
    mesh = blockmesh.load_domain("square").mesh(4)
    u, grad, f = PROBLEMS["smooth"]
    for recipe in ("identity", "trace", "diagonal"):
        for scale in (0.1, 0.3, 1.0, 3.0, 10.0):
            started = time.perf_counter()
            sol = solve_poisson(
                mesh,
                f,
                dirichlet={p: 0 for p in mesh.patch_names},
                stabilization=recipe,
                stabilization_scale=scale,
                order=4,
            )
            seconds = time.perf_counter() - started
            e = sol.errors(u, grad, order=6)
            runs.append(
                Run(
                    "stabilization",
                    f"{recipe} x {scale:g}",
                    4,
                    sol.info.dof,
                    sol.info.nonzeros,
                    seconds,
                    e.l2,
                    e.h1,
                )
            )
    cook = blockmesh.Domain.from_polygon(COOK, patches={"clamped": [3], "loaded": [1]})
    for recipe in ("trace", "diagonal"):
        for scale in (0.1, 0.3, 1.0, 3.0, 10.0):
            run = vem_cook(
                f"{recipe} x {scale:g}",
                3,
                cook.mesh(3),
                stabilization=recipe,
                stabilization_scale=scale,
            )
            run.problem = "stabilization-cook"
            runs.append(run)
    return runs


# ------------------------------------------------------------------------------ reporting
def at_dof(runs: list[Run], method: str, attribute: str, dof: float) -> float:
    """The error of ``method`` at ``dof`` unknowns, by log-log interpolation between runs."""
    points = sorted((r.dof, getattr(r, attribute)) for r in runs if r.method == method)
    x = np.log([p[0] for p in points])
    y = np.log([p[1] for p in points])
    if not x[0] <= math.log(dof) <= x[-1]:
        return float("nan")
    return float(np.exp(np.interp(math.log(dof), x, y)))


def print_runs(runs: list[Run], title: str, columns: tuple[str, ...]) -> None:
    print(f"\n{title}")
    head = f"{'method':<30} {'size':>5} {'dof':>9} {'nnz':>10} {'seconds':>8}"
    print(head + "".join(f" {c:>11}" for c in columns) + f" {'min angle':>9}")
    for r in runs:
        values = "".join(f" {getattr(r, c):11.4e}" for c in columns)
        print(
            f"{r.method:<30} {r.size:>5} {r.dof:>9,} {r.nnz:>10,} {r.seconds:>8.3f}{values}"
            f" {r.min_angle:>9.1f}"
        )


def summary(runs: list[Run], problem: str, dof: float, attributes: tuple[str, ...]) -> list[dict]:
    chosen = [r for r in runs if r.problem == problem]
    methods = list(dict.fromkeys(r.method for r in chosen))
    rows = []
    for method in methods:
        row = {"method": method}
        for a in attributes:
            row[a] = at_dof(chosen, method, a, dof)
            row[f"{a}_vs_P1"] = row[a] / at_dof(chosen, "P1 triangles", a, dof)
            fair = (
                at_dof(chosen, DELAUNAY, a, dof)
                if any(r.method == DELAUNAY for r in chosen)
                else math.nan
            )
            row[f"{a}_vs_delaunay"] = row[a] / fair
        rows.append(row)
    return rows


def print_summary(rows: list[dict], title: str, attributes: tuple[str, ...]) -> None:
    print(f"\n{title}")
    print(f"{'method':<30}" + "".join(f" {a:>11} {'x P1':>6} {'x Del':>6}" for a in attributes))
    for row in rows:
        print(
            f"{row['method']:<30}"
            + "".join(
                f" {row[a]:11.3e} {row[a + '_vs_P1']:6.2f} {row[a + '_vs_delaunay']:6.2f}"
                for a in attributes
            )
        )


def corner_cell_growth(levels: range = range(6)) -> list[tuple[int, int, float, float]]:
    """The L-shape's cells at its re-entrant corner (1, 1): (level, cells, area / mean, max / mean).

    A child at a parent's corner keeps 1/4 of its area where the mean child has 1/6, so the cells
    at a block vertex grow against the mean by 1.5x per level: the paper's refinement coarsens
    exactly where a corner singularity needs small cells.
    """
    lshape = blockmesh.load_domain("l-shape")
    rows = []
    for level in levels:
        mesh = lshape.mesh(level)
        node = np.flatnonzero(np.hypot(mesh.points[:, 0] - 1, mesh.points[:, 1] - 1) < 1e-12)[0]
        cells = np.flatnonzero(np.any(mesh.cells == node, axis=1))
        area = mesh.cell_areas()
        mean = area.mean()
        rows.append(
            (level, mesh.n_cells, float(area[cells].max() / mean), float(area.max() / mean))
        )
    return rows


def matched(runs: list[Run], problem: str, attribute: str) -> list[list[str]]:
    """Each pentagon level beside the Delaunay P1 mesh of (about) its unknowns."""
    chosen = [r for r in runs if r.problem == problem]
    by = {(r.method, r.size): r for r in chosen}
    rows = []
    for paper in (r for r in chosen if r.method == "pentagons (paper)"):
        fair = by.get((DELAUNAY, paper.size))
        optimized = by.get(("pentagons, optimized", paper.size))
        if fair is None:
            continue
        p, d = getattr(paper, attribute), getattr(fair, attribute)
        o = getattr(optimized, attribute) if optimized else math.nan
        rows.append(
            [
                str(paper.size),
                f"{paper.dof:,}",
                f"{fair.dof:,}",
                f"{p:.3e}",
                f"{o:.3e}" if optimized else "",
                f"{d:.3e}",
                f"{p / d:.2f}",
                f"{o / d:.2f}" if optimized else "",
            ]
        )
    return rows


MATCHED_COLUMNS = [
    "level",
    "unknowns, pentagons",
    "unknowns, Delaunay",
    "paper",
    "optimized",
    "P1 Delaunay",
    "paper / Delaunay",
    "optimized / Delaunay",
]


def markdown_table(columns: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(columns) + " |", "|" + " --- |" * len(columns)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def summary_markdown(rows: list[dict], attributes: tuple[str, ...], names: dict[str, str]) -> str:
    columns = ["method"]
    for a in attributes:
        columns += [names[a], "x P1 grid", "x P1 Delaunay"]
    body = []
    for row in rows:
        cells = [row["method"]]
        for a in attributes:  # blank where the method has no runs about that many unknowns
            cells += [
                _shown(row[a], ".3e"),
                _shown(row[a + "_vs_P1"], ".2f"),
                _shown(row[a + "_vs_delaunay"], ".2f"),
            ]
        body.append(cells)
    return markdown_table(columns, body)


def _shown(value: float, spec: str) -> str:
    return "" if math.isnan(value) else format(value, spec)


STYLE = {
    "pentagons (paper)": ("C3", "o", "-"),
    "pentagons, smooth=3": ("C1", "s", "--"),
    "pentagons, inner-point rule": ("C4", "v", ":"),
    "pentagons, optimized": ("C2", "D", "-"),
    "pentagons from triangles": ("C5", "p", "-."),
    "P1 triangles": ("C0", "^", "-"),
    DELAUNAY: ("C9", "<", "--"),
    "Q1 quads": ("k", "x", "-"),
    "P2 triangles (reference)": ("0.6", ".", ":"),
}


def plot(runs: list[Run], cook_reference: float, path: str) -> None:
    from blockmesh.plot import pyplot, save_figure

    plt = pyplot()
    fig, axes = plt.subplots(2, 4, figsize=(21, 10))
    panels = [
        (axes[0, 0], "smooth", "dof", "l2", "smooth: L2 error against unknowns"),
        (axes[0, 1], "smooth", "dof", "h1", "smooth: H1 error against unknowns"),
        (axes[0, 2], "smooth", "nnz", "h1", "smooth: H1 error against matrix non-zeros"),
        (axes[1, 0], "smooth", "seconds", "h1", "smooth: H1 error against assembly + solve time"),
        (axes[1, 1], "corner", "dof", "h1", "L-shape corner singularity: H1 error"),
        (axes[1, 2], "cook", "dof", "cook", "Cook's membrane: |v(48, 52) - reference|"),
        (axes[0, 3], "kirsch", "dof", "energy", "Kirsch plate: energy error"),
        (axes[1, 3], "kirsch", "dof", "peak", "Kirsch plate: |sigma_xx(0, a) - 3|"),
    ]
    for ax, problem, xkey, ykey, title in panels:
        chosen = [r for r in runs if r.problem == problem]
        for method in dict.fromkeys(r.method for r in chosen):
            if method not in STYLE or method.startswith("P2"):
                continue
            mine = sorted((r for r in chosen if r.method == method), key=lambda r: r.dof)
            x = [getattr(r, xkey) for r in mine]
            if ykey == "cook":
                y = [abs(r.value - cook_reference) for r in mine]
            elif ykey == "peak":
                y = [abs(r.value - KIRSCH.peak) for r in mine]
            else:
                y = [getattr(r, ykey) for r in mine]
            colour, marker, line = STYLE[method]
            ax.loglog(x, y, color=colour, marker=marker, linestyle=line, label=method, ms=5)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel({"dof": "unknowns", "nnz": "non-zeros", "seconds": "seconds"}[xkey])
        ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    axes[1, 2].legend(fontsize=8)
    fig.suptitle("Error at equal cost: virtual elements on pentagons vs P1 / Q1 (scikit-fem)")
    save_figure(fig, path)


#: The summaries: problem, attributes, and what each attribute is on that problem.
SUMMARIES = (
    ("smooth", ("l2", "h1"), {"l2": "L2 error", "h1": "H1 error"}),
    ("corner", ("l2", "h1"), {"l2": "L2 error", "h1": "H1 error"}),
    ("cook", ("h1",), {"h1": "abs(v(48, 52) - reference)"}),
    ("kirsch", ("energy", "h1"), {"energy": "energy error", "h1": "abs(sigma_xx(0, a) - 3)"}),
)
TITLES = {
    "smooth": "Smooth: u = sin(pi x) sin(pi y) on the unit square",
    "corner": "Corner singularity: u = r^(2/3) sin(2 phi / 3) on the L-shape",
    "cook": "Cook's membrane: the vertical displacement at (48, 52)",
    "kirsch": "Kirsch plate: energy error and the stress concentration at the hole",
}
EVERY_RUN = (
    ("smooth", ("l2", "h1", "h1_floor")),
    ("corner", ("l2", "h1", "h1_floor")),
    ("cook", ("value",)),
    ("kirsch", ("l2", "energy", "value")),
    ("stabilization", ("l2", "h1")),
    ("stabilization-cook", ("value",)),
)


def page_text(
    runs: list[Run], summaries: dict[str, list[dict]], dof: float, reference: float, quick: bool
) -> str:
    """The Markdown page of one measurement: summaries, matched unknowns, corner cells, runs."""
    out = [
        "(--quick: fewer levels, errors at 2,000 unknowns.)" if quick else "",
        "",
        "Lowest-order virtual elements (VEM) on the paper's pentagons and on variants of them "
        "(Laplacian smoothing, the inner-point rule, optimised node placement, pentagons converted "
        "from triangles) against P1 triangles and Q1 quadrilaterals of scikit-fem on uniform grids "
        "and P1 on quality Delaunay meshes (Triangle's `q30`: no angle below 30 degrees, at the "
        "unknowns of each pentagon level), on the same problems, counting the same unknowns; "
        "errors against unknowns, never against level. The summaries interpolate each method "
        f'log-log at {dof:,.0f} unknowns; "x P1 grid" and "x P1 Delaunay" are the error over '
        "that baseline's (below 1 wins). The structured grid is the easy baseline to beat; the "
        "Delaunay mesh is the one a finite element user would make.",
        "",
    ]
    if not any(r.method == DELAUNAY for r in runs):
        out += ["*Triangle is not installed here: the Delaunay rows are missing.*", ""]
    out += [f"## Errors at {dof:,.0f} unknowns", ""]
    for problem, attributes, names in SUMMARIES:
        out += [
            f"### {TITLES[problem]}",
            "",
            summary_markdown(summaries[problem], attributes, names),
        ]
        chosen = [r for r in runs if r.problem == problem]
        if problem in ("smooth", "cook") and any(r.method == DELAUNAY for r in chosen):
            grid, fair = (at_dof(chosen, m, attributes[0], dof) for m in ("P1 triangles", DELAUNAY))
            out += [
                "",
                f"P1 on the Delaunay meshes: {grid / fair:.2f} times more accurate than P1 on the "
                f"grid ({names[attributes[0]]}).",
            ]
        out.append("")
    out += [
        "## Pentagon levels beside P1 on Delaunay meshes of the same unknowns",
        "",
        "Each level of the paper's refinement (and of the optimised placement, same cells) beside "
        "P1 on a Triangle `q30` mesh whose area bound was tuned to the same number of unknowns "
        "(within 2 %). Ratios above 1: the pentagons' error is larger.",
        "",
    ]
    for problem, attribute, what in (
        ("smooth", "l2", "smooth problem, L2 error"),
        ("smooth", "h1", "smooth problem, H1 error"),
        ("cook", "h1", "Cook's membrane, abs(v(48, 52) - reference)"),
    ):
        rows = matched(runs, problem, attribute)
        if rows:
            out += [f"### {what}", "", markdown_table(MATCHED_COLUMNS, rows), ""]
    out += [
        "## The paper's refinement coarsens the cells at block corners",
        "",
        "A child at a parent's corner keeps 1/4 of the parent's area, the mean child 1/6: the "
        "cells at a block vertex grow against the mean cell by 1.5x per level. At the L-shape's "
        "re-entrant corner, where the corner singularity wants the smallest cells:",
        "",
        markdown_table(
            ["level", "cells", "corner cell / mean cell area", "largest cell / mean"],
            [[str(a), f"{b:,}", f"{c:.2f}", f"{d:.2f}"] for a, b, c, d in corner_cell_growth()],
        ),
        "",
        "## Reproducible node placement",
        "",
        "The inner-point rule picks its `t` per level by the worst angle; candidates whose worst "
        "angles agree within `blockmesh.refinement.improve.ANGLE_TIE` (1e-9 degrees) are a tie, "
        "which goes to the `t` nearest the paper's 1/2 (on the square every `t` ties, so its rows "
        "are the paper's mesh). The optimised placement sums its inner products in one fixed "
        "order, so it gives the same bits whatever the number of BLAS threads (a test runs it with "
        "`OPENBLAS_NUM_THREADS=1` and `2` and compares).",
        "",
        "## Every run",
        "",
        f"Cook reference: P2 Richardson {reference:.4f} (quoted {COOK_QUOTED}). `seconds`: "
        "assembly + Dirichlet elimination + the sparse LU solve, best of 3 below 50,000 nodes.",
        "",
    ]
    for problem, columns in EVERY_RUN:
        chosen = [r for r in runs if r.problem == problem]
        rows = [
            [r.method, str(r.size), f"{r.dof:,}", f"{r.nnz:,}", f"{r.seconds:.3f}"]
            + [f"{getattr(r, c):.4e}" for c in columns]
            + [f"{r.min_angle:.1f}"]
            for r in chosen
        ]
        heads = ["method", "size", "dof", "nnz", "seconds", *columns, "min angle"]
        out += [f"### {problem}", "", markdown_table(heads, rows), ""]
    return "\n".join(out).rstrip() + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer levels (a smoke run)")
    parser.add_argument("--plot", metavar="PNG", help="write the figure")
    parser.add_argument("--json", metavar="FILE", help="write every run as JSON")
    add_arguments(parser)
    args = parser.parse_args()
    started = time.perf_counter()
    runs = smooth_runs(args.quick)
    runs += corner_runs(args.quick)
    print("  corner done", flush=True)
    cook, reference = cook_runs(args.quick)
    runs += cook
    print("  cook done", flush=True)
    runs += kirsch_runs(args.quick)
    print("  kirsch done", flush=True)
    runs += stabilization_runs()
    for problem, columns in EVERY_RUN:
        print_runs([r for r in runs if r.problem == problem], problem, columns)
    print(f"\nCook reference: P2 Richardson {reference:.4f} (quoted {COOK_QUOTED})")
    for r in runs:
        if r.problem == "cook":
            r.h1 = abs(r.value - reference)  # the error, for the summary
        if r.problem == "kirsch":
            r.h1 = abs(r.value - KIRSCH.peak)  # the stress concentration's error
    dof = 2000.0 if args.quick else 16000.0  # within the runs of each mode
    summaries = {}
    for problem, attributes, _ in SUMMARIES:
        label = {
            "cook": " (h1 = |v - reference|)",
            "kirsch": " (h1 = |sigma_xx(0, a) - 3|)",
        }.get(problem, "")
        summaries[problem] = summary(runs, problem, dof, attributes)
        print_summary(
            summaries[problem],
            f"{problem}: errors at {dof:,.0f} unknowns (log-log interpolation){label}",
            attributes,
        )
    if args.plot:
        plot(runs, reference, args.plot)
        print(f"\nwrote {args.plot}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump([asdict(r) for r in runs] + [{"cook_reference": reference}], f, indent=1)
    page = Page("accuracy", "Accuracy at equal cost")
    page.text(page_text(runs, summaries, dof, reference, args.quick))
    page.write(args)
    print(f"\n{time.perf_counter() - started:.0f} s in all")


if __name__ == "__main__":
    main()
