"""The diffusion-reaction solver: patch tests, P1 equivalence, rates, boundary data, bad input."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import blockmesh
from blockmesh.domain.catalogue import catalogue_names
from blockmesh.errors import ArgumentError, SolverError, TopologyError, UnknownNameError
from blockmesh.vem import PolygonMesh, solve_poisson
from blockmesh.vem.rules import cell_rule, fan_rule

skfem = pytest.importorskip("skfem", reason="scikit-fem (the test extra) is the P1 reference")

LINEAR = "1 + 2*x - 3*y"
SMOOTH = "sin(pi*x)*sin(pi*y)"
SMOOTH_SOURCE = "2*pi^2*sin(pi*x)*sin(pi*y)"


def _linear(points: np.ndarray) -> np.ndarray:
    return 1 + 2 * points[:, 0] - 3 * points[:, 1]


def _all_dirichlet(mesh, value):
    return {patch: value for patch in mesh.patch_names}


# ---------------------------------------------------------------------------------- patch test
# the whole catalogue, curved domains included: their cells are polygons with nodes on the
# curves, so a linear field is still in the virtual element space
@pytest.mark.parametrize("name", catalogue_names())
@pytest.mark.parametrize("level", [1, 2])
def test_linear_solution_is_reproduced_on_every_catalogue_domain(name, level):
    mesh = blockmesh.load_domain(name).mesh(level)
    sol = solve_poisson(mesh, 0.0, dirichlet=_all_dirichlet(mesh, LINEAR))
    scale = 1 + np.abs(mesh.points).max()
    assert np.abs(sol.values - _linear(mesh.points)).max() < 1e-12 * scale
    assert np.abs(sol.cell_gradient - [2.0, -3.0]).max() < 1e-11 * scale


@pytest.mark.parametrize("recipe", ["identity", "trace", "diagonal"])
def test_patch_test_holds_for_every_stabilization_with_reaction(recipe):
    mesh = blockmesh.load_domain("usp").mesh(2)
    sol = solve_poisson(
        mesh,
        f"2.5*({LINEAR})",
        reaction=2.5,
        dirichlet=_all_dirichlet(mesh, LINEAR),
        stabilization=recipe,
        stabilization_scale=3.0,
    )
    assert np.abs(sol.values - _linear(mesh.points)).max() < 1e-12


def test_patch_test_with_neumann_patches_on_the_square_and_the_l_shape():
    square = blockmesh.load_domain("square").mesh(2)  # flux = grad u . n on each side
    sol = solve_poisson(
        square,
        0,
        dirichlet={"left": LINEAR, "right": LINEAR},
        neumann={"bottom": 3.0, "top": -3.0},
    )
    assert np.abs(sol.values - _linear(square.points)).max() < 1e-12
    lshape = blockmesh.load_domain("l-shape").mesh(2)  # inlet: top (y = 2), outlet: x = 2
    sol = solve_poisson(
        lshape, 0, dirichlet={"boundary": LINEAR}, neumann={"inlet": -3.0, "outlet": 2.0}
    )
    assert np.abs(sol.values - _linear(lshape.points)).max() < 1e-12


def test_patch_test_on_a_mixed_polygon_mesh():
    # a 2x2 block: a triangle pair, a quadrilateral and a pentagon, conforming
    points = [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1), (0, 2), (1, 2), (2, 2), (1.5, 1.6)]
    cells = [[0, 1, 4], [0, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 9], [4, 9, 8, 7]]
    mesh = PolygonMesh.from_cells(points, cells)
    assert [g.size for g in mesh.groups] == [3, 4]
    sol = solve_poisson(mesh, 0, dirichlet={"boundary": LINEAR})
    assert np.abs(sol.values - _linear(mesh.points)).max() < 1e-13


# ---------------------------------------------------------------------------------- VEM = P1
def _perturbed_triangles(n: int, seed: int):
    t = np.linspace(0, 1, n + 1)
    tri = skfem.MeshTri.init_tensor(t, t)
    rng = np.random.default_rng(seed)
    p = tri.p.copy()
    inner = (p[0] > 0) & (p[0] < 1) & (p[1] > 0) & (p[1] < 1)
    p[:, inner] += rng.uniform(-0.25, 0.25, (2, int(inner.sum()))) / n
    tri = skfem.MeshTri(p, tri.t)
    cells = tri.t.T.copy()
    x = p[:, cells]  # make every triangle counter-clockwise
    area = (x[0, :, 1] - x[0, :, 0]) * (x[1, :, 2] - x[1, :, 0]) - (x[0, :, 2] - x[0, :, 0]) * (
        x[1, :, 1] - x[1, :, 0]
    )
    cells[area < 0] = cells[area < 0][:, [0, 2, 1]]
    return tri, cells


def test_vem_on_triangles_is_p1_finite_elements_to_round_off():
    from skfem.helpers import dot, grad

    tri, cells = _perturbed_triangles(6, seed=1)
    points = tri.p.T
    right = np.flatnonzero(np.isclose(points[:, 0], 1.0))
    on_right = set(right.tolist())
    edges = [(a, b) for a, b in tri.facets.T if a in on_right and b in on_right]  # Neumann side
    mesh = PolygonMesh.from_cells(points, cells, patches={"right": edges})

    def f(x, y):
        return 1 + x * y - 2 * x**2

    kappa, c = 1.7, 0.6
    sol = solve_poisson(
        mesh,
        f,
        diffusion=kappa,
        reaction=c,
        dirichlet={"boundary": "x - y^2"},
        neumann={"right": "1 + y"},
        order=3,
    )

    basis = skfem.Basis(tri, skfem.ElementTriP1(), intorder=6)

    @skfem.BilinearForm
    def form(u, v, w):
        return kappa * dot(grad(u), grad(v)) + c * u * v

    @skfem.LinearForm
    def load(v, w):
        x, y = w.x
        return f(x, y) * v

    @skfem.LinearForm
    def flux(v, w):
        return (1 + w.x[1]) * v

    facets = tri.facets_satisfying(lambda x: np.isclose(x[0], 1.0))
    fb = skfem.FacetBasis(tri, skfem.ElementTriP1(), facets=facets, intorder=4)
    a = skfem.asm(form, basis)
    b = skfem.asm(load, basis) + skfem.asm(flux, fb)
    right_inside = right[(points[right, 1] > 0) & (points[right, 1] < 1)]
    dirichlet = np.setdiff1d(tri.boundary_nodes(), right_inside)  # the corners stay Dirichlet
    x_d = points[dirichlet]
    u_d = np.zeros(len(points))
    u_d[dirichlet] = x_d[:, 0] - x_d[:, 1] ** 2
    reference = skfem.solve(*skfem.condense(a, b, x=u_d, D=dirichlet))
    assert sol.info.dof == len(points) - dirichlet.size
    assert np.abs(sol.values - reference).max() < 1e-13 * np.abs(reference).max()


# ---------------------------------------------------------------------------------- rates
def test_convergence_rates_against_dof_on_pentagons():
    domain = blockmesh.load_domain("square")
    dof, l2, h1 = [], [], []
    for level in (1, 2, 3, 4):
        mesh = domain.mesh(level)
        sol = solve_poisson(mesh, SMOOTH_SOURCE, dirichlet=_all_dirichlet(mesh, 0))
        e = sol.errors(SMOOTH, ("pi*cos(pi*x)*sin(pi*y)", "pi*sin(pi*x)*cos(pi*y)"))
        dof.append(sol.info.dof)
        l2.append(e.l2)
        h1.append(e.h1)
    # rates in h ~ dof^(-1/2), between the last two levels
    h = np.asarray(dof, dtype=float) ** -0.5
    rate_l2 = np.log(l2[-2] / l2[-1]) / np.log(h[-2] / h[-1])
    rate_h1 = np.log(h1[-2] / h1[-1]) / np.log(h[-2] / h[-1])
    assert 1.8 < rate_l2 < 2.2, rate_l2
    assert 0.9 < rate_h1 < 1.1, rate_h1
    assert l2[-1] < 2e-4 and h1[-1] < 4e-2  # level 4: 15,473 unknowns


def test_numerical_gradient_matches_the_exact_one():
    mesh = blockmesh.load_domain("square").mesh(2)
    sol = solve_poisson(mesh, SMOOTH_SOURCE, dirichlet=_all_dirichlet(mesh, 0))
    exact = sol.errors(SMOOTH, ("pi*cos(pi*x)*sin(pi*y)", "pi*sin(pi*x)*cos(pi*y)"))
    numerical = sol.errors(SMOOTH)
    assert abs(exact.h1 - numerical.h1) < 1e-9 * exact.h1
    assert abs(exact.h1_exact - np.pi / np.sqrt(2)) < 1e-9
    assert abs(exact.l2_exact - 0.5) < 1e-12
    assert exact.energy == pytest.approx(exact.h1, rel=1e-14)  # kappa = 1, c = 0


# ---------------------------------------------------------------------------------- data
def test_pure_neumann_with_mean_constraint():
    mesh = blockmesh.load_domain("square").mesh(3)
    u = "cos(pi*x)*cos(pi*y)"  # zero normal derivative on the square, zero mean
    sol = solve_poisson(mesh, f"2*pi^2*{u}", constraint="mean")
    assert sol.errors(u).l2 < 2e-3
    assert abs(sol.cell_value @ mesh.cell_areas()) < 1e-12  # ∫ Π⁰u_h = 0


def test_variable_coefficients_converge():
    domain = blockmesh.load_domain("square")
    u, kappa = "x*(1-x)*y*(1-y)*exp(x)", "1 + x^2"
    grad = ("(1-2*x + x*(1-x))*y*(1-y)*exp(x)", "x*(1-x)*(1-2*y)*exp(x)")
    # f = -div((1 + x^2) grad u) + u for the exact u above (c = 1), derived by hand
    f = (
        "-(2*x*(1-2*x + x*(1-x))*y*(1-y)*exp(x)"
        " + (1 + x^2)*((-2 + 2*(1-2*x) + x*(1-x))*y*(1-y)*exp(x))"
        " + (1 + x^2)*(-2*x*(1-x)*exp(x)))"
        f" + {u}"
    )
    errors = []
    for level in (2, 3):
        mesh = domain.mesh(level)
        sol = solve_poisson(
            mesh, f, diffusion=kappa, reaction=1.0, dirichlet=_all_dirichlet(mesh, 0)
        )
        errors.append(sol.errors(u, grad))
    rate = np.log(errors[0].l2 / errors[1].l2) / np.log(6**0.5)
    assert rate > 1.7, rate
    assert errors[1].energy > errors[1].h1  # kappa >= 1 and c > 0 weigh the error more


def test_amg_agrees_with_the_direct_solve():
    mesh = blockmesh.load_domain("l-shape").mesh(3)
    direct = solve_poisson(mesh, 1.0, dirichlet={"boundary": 0})
    amg = solve_poisson(mesh, 1.0, dirichlet={"boundary": 0}, solver="amg", tol=1e-12)
    assert amg.info.iterations is not None and amg.info.iterations > 0
    assert np.abs(amg.values - direct.values).max() < 1e-9 * np.abs(direct.values).max()
    assert amg.info.dof == direct.info.dof and amg.info.nonzeros == direct.info.nonzeros


def test_amg_without_pyamg_is_a_clean_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "pyamg", None)
    mesh = blockmesh.load_domain("sp").mesh(1)
    with pytest.raises(SolverError, match=r"pip install 'blockmesh\[vem\]'"):
        solve_poisson(mesh, 1.0, dirichlet={"boundary": 0}, solver="amg")


# ---------------------------------------------------------------------------------- bad input
def test_unknown_patch_is_named_with_the_choices():
    mesh = blockmesh.load_domain("square").mesh(1)
    with pytest.raises(UnknownNameError, match="no patch 'inlet'; the patches are bottom, right"):
        solve_poisson(mesh, 1.0, dirichlet={"inlet": 0})
    with pytest.raises(UnknownNameError, match="no patch 'wall'"):
        solve_poisson(mesh, 1.0, dirichlet={"left": 0}, neumann={"wall": 1})


def test_a_patch_given_twice_is_rejected():
    mesh = blockmesh.load_domain("square").mesh(1)
    with pytest.raises(SolverError, match="patch 'left' is given both a Dirichlet and a Neumann"):
        solve_poisson(mesh, 1.0, dirichlet={"left": 0}, neumann={"left": 1})


def test_pure_neumann_without_constraint_is_rejected():
    mesh = blockmesh.load_domain("square").mesh(1)
    with pytest.raises(SolverError, match="no Dirichlet data.*constraint='mean'"):
        solve_poisson(mesh, 1.0, neumann={"left": 1.0})
    with pytest.raises(SolverError, match="must balance"):
        solve_poisson(mesh, 1.0, constraint="mean")  # ∫f = 1, no flux: no solution
    sol = solve_poisson(mesh, 1.0, reaction=1.0)  # a reaction fixes the constant
    assert np.abs(sol.values - 1.0).max() < 1e-12


@pytest.mark.parametrize(
    ("options", "error", "match"),
    [
        ({"stabilization": "dofi"}, ArgumentError, "unknown stabilization 'dofi'; choose one"),
        ({"stabilization_scale": 0}, ArgumentError, "stabilization_scale must be a number > 0"),
        ({"order": 0}, ArgumentError, "order must be a whole number in 1..30"),
        ({"solver": "cg"}, ArgumentError, "unknown solver 'cg'; choose one of: direct, amg"),
        ({"constraint": "zero"}, ArgumentError, "unknown constraint 'zero'"),
        ({"diffusion": "-1"}, SolverError, "diffusion -1 has mean -1 <= 0"),
        ({"source": "log(x - 2)"}, SolverError, r"source log\(x - 2\) is not finite \(nan\) at"),
        ({"reaction": "1/(x - x)"}, SolverError, r"reaction 1/\(x - x\) is not finite"),
    ],
)
def test_bad_options_are_rejected_clearly(options, error, match):
    mesh = blockmesh.load_domain("square").mesh(1)
    arguments = {"source": 1.0, "dirichlet": {"left": 0}, **options}
    source = arguments.pop("source")
    with pytest.raises(error, match=match):
        solve_poisson(mesh, source, **arguments)


# ---------------------------------------------------------------------------------- quadrature
def test_pentagon_quadrature_is_blockmesh_quadrature_points():
    mesh = blockmesh.load_domain("usp").mesh(2)
    x, y, w = cell_rule(mesh.points, mesh.cells, 4)
    bx, _, bw = blockmesh.quadrature_points(mesh, order=4, rule="jacobi")
    assert np.array_equal(x.ravel(), bx) and np.array_equal(w.ravel(), bw)
    fx, fy, fw = fan_rule(mesh.points, mesh.cells, 4)  # the construction used for other sizes

    def f(a, b):
        return np.exp(a) * np.cos(3 * b)

    per_cell = (w * f(x, y)).sum(axis=1)
    assert np.abs(per_cell - (fw * f(fx, fy)).sum(axis=1)).max() < 1e-14 * np.abs(per_cell).max()
    assert np.abs(np.sort(x, axis=1) - np.sort(fx, axis=1)).max() < 1e-14


@pytest.mark.parametrize(
    ("points", "cells", "error", "match"),
    [
        ([(0, 0), (1, 0), (0, 1)], [[0, 2, 1]], ArgumentError, "is clockwise"),
        ([(0, 0), (1, 0), (0, 1)], [[0, 1, 3]], ArgumentError, "outside 0..2"),
        ([(0, 0), (1, 0), (0, 1)], [[0, 1, 1]], ArgumentError, "repeats a node"),
        (  # a dart: not star-shaped from its vertex mean
            [(0, 0), (4, 0), (0.2, 0.2), (0, 4)],
            [[0, 1, 2, 3]],
            ArgumentError,
            "not star-shaped",
        ),
        (  # node 4 halves the edge (1, 2) of the left square: a hanging node
            [(0, 0), (1, 0), (1, 1), (0, 1), (1, 0.5), (2, 0), (2, 1)],
            [[0, 1, 2, 3], [1, 5, 4], [4, 5, 6, 2]],
            TopologyError,
            r"node 4 \[1.0, 0.5\] lies inside the edge \(1, 2\)",
        ),
    ],
)
def test_bad_polygon_meshes_are_rejected(points, cells, error, match):
    with pytest.raises(error, match=match):
        PolygonMesh.from_cells(points, cells)


def test_patch_edges_must_be_boundary_edges():
    points = [(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5)]
    cells = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    with pytest.raises(ArgumentError, match=r"patch 'wall': edge \(0, 4\) is not a boundary"):
        PolygonMesh.from_cells(points, cells, patches={"wall": [(0, 4)]})
    with pytest.raises(ArgumentError, match="already in another patch"):
        PolygonMesh.from_cells(points, cells, patches={"a": [(0, 1)], "b": [(1, 0)]})
