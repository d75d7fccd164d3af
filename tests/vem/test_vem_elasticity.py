"""Plane elasticity: patch tests, P1 equivalence, Cook's membrane, the Kirsch plate, rates."""

from __future__ import annotations

import numpy as np
import pytest

import blockmesh
from blockmesh.domain.catalogue import catalogue_names
from blockmesh.errors import ArgumentError, SolverError, UnknownNameError
from blockmesh.geometry import signed_area
from blockmesh.vem import PolygonMesh, elasticity_matrix, solve_elasticity
from blockmesh.vem.evaluate import boundary_values
from blockmesh.vem.reference import kirsch

skfem = pytest.importorskip("skfem", reason="scikit-fem (the test extra) is the P1 reference")

UX, UY = "0.1 + 0.2*x - 0.3*y", "-0.2 + 0.1*x + 0.4*y"
STRAIN = np.array([0.2, 0.4, -0.3 + 0.1])  # exx, eyy, gamma_xy of (UX, UY)
COOK = [(0, 0), (48, 44), (48, 60), (0, 44)]
#: Vertical displacement of the middle of Cook's loaded edge, (48, 52): 23.96 (Cook 1989;
#: scikit-fem P2 on 64 x 64 mapped quads gives 23.962).
COOK_REFERENCE = 23.96


def _linear(points):
    x, y = points.T
    return np.column_stack([0.1 + 0.2 * x - 0.3 * y, -0.2 + 0.1 * x + 0.4 * y])


# the whole catalogue, curved domains included: their cells are polygons with nodes on the
# curves, so a linear field is still in the virtual element space
@pytest.mark.parametrize("name", catalogue_names())
@pytest.mark.parametrize("plane", ["stress", "strain"])
def test_linear_displacement_is_reproduced_on_every_catalogue_domain(name, plane):
    mesh = blockmesh.load_domain(name).mesh(1)
    sol = solve_elasticity(
        mesh,
        young=3.0,
        poisson=0.3,
        plane=plane,
        dirichlet={p: (UX, UY) for p in mesh.patch_names},
    )
    scale = 1 + np.abs(mesh.points).max()
    assert np.abs(sol.displacement - _linear(mesh.points)).max() < 1e-12 * scale
    assert np.abs(sol.strain - STRAIN).max() < 1e-11 * scale
    stress = elasticity_matrix(3.0, 0.3, plane) @ STRAIN
    assert np.abs(sol.stress - stress).max() < 1e-11 * scale


@pytest.mark.parametrize("recipe", ["trace", "diagonal"])
def test_traction_patch_test_with_rollers(recipe):
    # a stretch plus a rotation, no shear stress: the rollers' free components carry no traction
    mesh = blockmesh.load_domain("square").mesh(2)
    ux, uy = "0.1 + 0.2*x - 0.3*y", "-0.2 + 0.3*x + 0.4*y"
    sxx, syy, sxy = elasticity_matrix(2.0, 0.25) @ [0.2, 0.4, 0.0]
    sol = solve_elasticity(
        mesh,
        young=2.0,
        poisson=0.25,
        dirichlet={"left": (ux, "free"), "bottom": ("free", uy)},
        neumann={"right": (sxx, sxy), "top": (sxy, syy)},  # sigma n on x = 1 and y = 1
        stabilization=recipe,
    )
    x, y = mesh.points.T
    expected = np.column_stack([0.1 + 0.2 * x - 0.3 * y, -0.2 + 0.3 * x + 0.4 * y])
    assert np.abs(sol.displacement - expected).max() < 1e-12
    assert sol.info.dof == 2 * mesh.n_points - 2 * 11  # 11 nodes per side, one component each


def test_vem_on_triangles_is_p1_finite_elements_to_round_off():
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    t = np.linspace(0, 1, 7)
    tri = skfem.MeshTri.init_tensor(t, 0.5 * t)
    rng = np.random.default_rng(3)
    p = tri.p.copy()
    inner = (p[0] > 0) & (p[0] < 1) & (p[1] > 0) & (p[1] < 0.5)
    p[:, inner] += rng.uniform(-0.03, 0.03, (2, int(inner.sum())))
    tri = skfem.MeshTri(p, tri.t)
    points = tri.p.T
    cells = tri.t.T.copy()
    clockwise = signed_area(points[cells]) < 0
    cells[clockwise] = cells[clockwise][:, [0, 2, 1]]
    left = set(np.flatnonzero(np.isclose(points[:, 0], 0)).tolist())
    right = set(np.flatnonzero(np.isclose(points[:, 0], 1)).tolist())
    patches = {
        "left": [e for e in tri.facets.T.tolist() if set(e) <= left],
        "right": [e for e in tri.facets.T.tolist() if set(e) <= right],
    }
    mesh = PolygonMesh.from_cells(points, cells, patches=patches)
    young, nu = 5.0, 0.3
    sol = solve_elasticity(
        mesh,
        young=young,
        poisson=nu,
        plane="strain",
        source=("x*y", "-1 + x"),
        dirichlet={"left": ("0", "0.01*y")},
        neumann={"right": ("1 + y", "0.5")},
        order=3,
    )
    element = skfem.ElementVector(skfem.ElementTriP1())
    basis = skfem.Basis(tri, element, intorder=4)
    lam, mu = lame_parameters(young, nu)  # plane strain: the 2-D Lamé parameters as they are
    a = skfem.asm(linear_elasticity(lam, mu), basis)

    @skfem.LinearForm
    def body(v, w):
        x, y = w.x
        return x * y * v[0] + (-1 + x) * v[1]

    @skfem.LinearForm
    def pull(v, w):
        return (1 + w.x[1]) * v[0] + 0.5 * v[1]

    facets = tri.facets_satisfying(lambda x: np.isclose(x[0], 1.0))
    fb = skfem.FacetBasis(tri, element, facets=facets, intorder=4)
    b = skfem.asm(body, basis) + skfem.asm(pull, fb)
    clamped = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    prescribed = np.zeros(basis.N)
    nodes = basis.nodal_dofs  # (2, N): the x and y dof of every node
    left_nodes = np.flatnonzero(np.isclose(points[:, 0], 0))
    prescribed[nodes[1, left_nodes]] = 0.01 * points[left_nodes, 1]
    reference = skfem.solve(*skfem.condense(a, b, x=prescribed, D=clamped))
    ours = np.empty(basis.N)
    ours[nodes[0]] = sol.displacement[:, 0]
    ours[nodes[1]] = sol.displacement[:, 1]
    assert np.abs(ours - reference).max() < 1e-12 * np.abs(reference).max()


def test_cooks_membrane_converges_to_the_reference_from_below():
    domain = blockmesh.Domain.from_polygon(COOK, patches={"clamped": [3], "loaded": [1]})
    tips = []
    for level in (2, 3, 4):
        sol = solve_elasticity(
            domain.mesh(level),
            young=1.0,
            poisson=1 / 3,
            dirichlet={"clamped": (0, 0)},
            neumann={"loaded": (0, 1 / 16)},  # a shear load of 1 spread over the 16-long edge
        )
        tips.append(boundary_values(sol.mesh, sol.displacement, [(48, 52)])[0, 1])
    assert tips[0] < tips[1] < tips[2] < COOK_REFERENCE
    assert abs(tips[2] - COOK_REFERENCE) < 0.005 * COOK_REFERENCE  # level 4: 23.87
    assert COOK_REFERENCE - tips[2] < 0.4 * (COOK_REFERENCE - tips[1])


def test_manufactured_displacement_converges_at_the_expected_rates():
    sympy = pytest.importorskip("sympy")
    x, y = sympy.symbols("x y")
    young, nu = 1.0, 0.25
    c = elasticity_matrix(young, nu)
    u = [sympy.sin(sympy.pi * x) * sympy.sin(sympy.pi * y), x * y * (1 - x) * (1 - y)]
    exx, eyy = sympy.diff(u[0], x), sympy.diff(u[1], y)
    gxy = sympy.diff(u[0], y) + sympy.diff(u[1], x)
    sxx, syy, sxy = (c[k, 0] * exx + c[k, 1] * eyy + c[k, 2] * gxy for k in range(3))
    force = [-(sympy.diff(sxx, x) + sympy.diff(sxy, y)), -(sympy.diff(sxy, x) + sympy.diff(syy, y))]
    as_function = [sympy.lambdify((x, y), f, "numpy") for f in force]
    exact = [sympy.lambdify((x, y), f, "numpy") for f in u]
    gradient = [[sympy.lambdify((x, y), sympy.diff(f, v), "numpy") for v in (x, y)] for f in u]
    domain = blockmesh.load_domain("square")
    dof, l2, h1, energy = [], [], [], []
    for level in (1, 2, 3):
        mesh = domain.mesh(level)
        sol = solve_elasticity(
            mesh,
            young=young,
            poisson=nu,
            source=tuple(as_function),
            dirichlet={p: (0, 0) for p in mesh.patch_names},
        )
        e = sol.errors(tuple(exact), tuple(tuple(g) for g in gradient))
        dof.append(sol.info.dof)
        l2.append(e.l2)
        h1.append(e.h1)
        energy.append(e.energy)
    h = np.asarray(dof, dtype=float) ** -0.5
    rate = lambda errors: np.log(errors[-2] / errors[-1]) / np.log(h[-2] / h[-1])  # noqa: E731
    assert 1.8 < rate(l2) < 2.2, rate(l2)
    assert 0.9 < rate(h1) < 1.1, rate(h1)
    assert 0.9 < rate(energy) < 1.1, rate(energy)


# ------------------------------------------------------------------------------ rigid motions
def test_free_rigid_motions_are_named():
    mesh = blockmesh.load_domain("square").mesh(1)
    with pytest.raises(SolverError, match=r"leave 3 rigid motion\(s\) free"):
        solve_elasticity(mesh, young=1, poisson=0.3, neumann={"right": (1, 0)})
    with pytest.raises(SolverError, match=r"leave 1 rigid motion\(s\) free \(translation in x\)"):
        solve_elasticity(mesh, young=1, poisson=0.3, dirichlet={"bottom": ("free", 0)})


def test_rigid_constraint_with_balanced_loads():
    mesh = blockmesh.load_domain("square").mesh(2)
    sol = solve_elasticity(
        mesh,
        young=2.0,
        poisson=0.3,
        neumann={"right": (1, 0), "left": (-1, 0)},
        constraint="rigid",
    )
    assert np.abs(sol.stress - [1.0, 0.0, 0.0]).max() < 1e-12
    assert np.abs(sol.displacement.mean(axis=0)).max() < 1e-14
    with pytest.raises(SolverError, match="the loads do not balance"):
        solve_elasticity(
            mesh, young=2.0, poisson=0.3, neumann={"right": (1, 0)}, constraint="rigid"
        )


# ------------------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    ("options", "error", "match"),
    [
        ({"young": 0.0}, ArgumentError, r"young \(Young's modulus\) must be > 0"),
        ({"poisson": 0.5}, ArgumentError, r"poisson \(Poisson's ratio\) must be in \(-1, 0.5\)"),
        ({"plane": "membrane"}, ArgumentError, "unknown plane 'membrane'; choose one of"),
        ({"stabilization": "identity"}, ArgumentError, "choose one of: trace, diagonal"),
        ({"constraint": "mean"}, ArgumentError, "unknown constraint 'mean'; choose one of: rigid"),
        ({"dirichlet": {"inlet": (0, 0)}}, UnknownNameError, "no patch 'inlet'"),
        ({"neumann": {"left": (0, 1)}}, SolverError, "patch 'left' is given both"),
        ({"neumann": {"right": "1"}}, Exception, "must be two expressions separated by a comma"),
        ({"dirichlet": {"left": "free, free"}}, SolverError, "both components are free"),
        ({"displacement": {"left": (0, 0)}}, ArgumentError, "both dirichlet and its earlier name"),
    ],
)
def test_bad_input_is_rejected_clearly(options, error, match):
    mesh = blockmesh.load_domain("square").mesh(1)
    arguments = {"young": 1.0, "poisson": 0.3, "dirichlet": {"left": (0, 0)}, **options}
    with pytest.raises(error, match=match):
        solve_elasticity(mesh, **arguments)


def test_boundary_values_reject_interior_points():
    mesh = PolygonMesh.from_mesh(blockmesh.load_domain("square").mesh(1))
    with pytest.raises(ArgumentError, match=r"point 0 \(0.5, 0.5\) is not on the boundary"):
        boundary_values(mesh, np.zeros(mesh.n_points), [(0.5, 0.5)])


# ------------------------------------------------------------------------------ Kirsch plate
@pytest.mark.parametrize("plane", ["stress", "strain"])
def test_kirsch_field_is_an_elastic_equilibrium_with_a_free_hole(plane):
    k = kirsch(radius=0.5, young=2.0, poisson=0.3, plane=plane, tension=1.5)
    rng = np.random.default_rng(5)
    r, th = rng.uniform(0.6, 3.0, 50), rng.uniform(0, 2 * np.pi, 50)
    x, y, d = r * np.cos(th), r * np.sin(th), 1e-5

    def diff(f, dx, dy):  # central difference
        return (f(x + dx, y + dy) - f(x - dx, y - dy)) / (2 * d)

    (ux, uy), (sxx, syy, sxy) = k.displacement, k.stress
    strain = np.array([diff(ux, d, 0), diff(uy, 0, d), diff(ux, 0, d) + diff(uy, d, 0)])
    stress = elasticity_matrix(2.0, 0.3, plane) @ strain  # Hooke's law
    assert np.abs(stress - [sxx(x, y), syy(x, y), sxy(x, y)]).max() < 1e-8
    assert np.abs(diff(sxx, d, 0) + diff(sxy, 0, d)).max() < 1e-8  # div σ = 0
    assert np.abs(diff(sxy, d, 0) + diff(syy, 0, d)).max() < 1e-8
    c, s = np.cos(th), np.sin(th)  # σ n = 0 on the hole, n = (cos θ, sin θ)
    xa, ya = 0.5 * c, 0.5 * s
    assert np.abs(sxx(xa, ya) * c + sxy(xa, ya) * s).max() < 1e-14
    assert np.abs(sxy(xa, ya) * c + syy(xa, ya) * s).max() < 1e-14
    assert sxx(0.0, 0.5) == pytest.approx(k.peak) == 4.5
    assert np.abs(ux(0 * r, r)).max() < 1e-14 and np.abs(uy(r, 0 * r)).max() < 1e-14  # symmetry


def test_kirsch_plate_converges_to_the_exact_field_and_stress_concentration():
    # the quarter plate with the exact stress as traction on its outer sides, rollers on the
    # symmetry lines, a free hole: the Kirsch field is exact, σ_xx(0, a) = 3
    k = kirsch(radius=0.5, young=1.0, poisson=0.3)
    (sxx, syy, sxy), domain = k.stress, blockmesh.load_domain("quarter-plate-hole")
    dof, l2, energy, peak = [], [], [], []
    for level in (1, 2, 3):
        mesh = domain.mesh(level)
        sol = solve_elasticity(
            mesh,
            young=1.0,
            poisson=0.3,
            dirichlet={"left": (0, "free"), "down": ("free", 0)},
            neumann={"right": (sxx, sxy), "up": (sxy, syy)},
        )
        e = sol.errors(k.displacement)
        top = np.flatnonzero(np.all(np.isclose(mesh.points, [0.0, 0.5], atol=1e-12), axis=1))
        (cell,) = np.flatnonzero(np.any(mesh.cells == top[0], axis=1))  # the one cell there
        dof.append(sol.info.dof)
        l2.append(e.l2)
        energy.append(e.energy)
        peak.append(sol.stress[cell, 0])
    h = np.asarray(dof, dtype=float) ** -0.5
    rate = lambda errors: np.log(errors[-2] / errors[-1]) / np.log(h[-2] / h[-1])  # noqa: E731
    assert 1.5 < rate(l2) < 2.2, rate(l2)  # the polygonal hole costs a little (1.67 measured)
    assert 0.8 < rate(energy) < 1.1, rate(energy)
    assert energy[-1] < 0.03 * e.energy_exact  # level 3: 2.3 %
    # the cell stress at the top of the hole rises to 3 at first order: the error halves with h
    gaps = 3.0 - np.asarray(peak)  # 1.08, 0.61, 0.32
    ratios = gaps[1:] / gaps[:-1]
    assert np.all(gaps > 0) and np.all((ratios > 0.45) & (ratios < 0.6)), ratios
    assert abs(2 * peak[-1] - peak[-2] - k.peak) < 0.05 * k.peak  # Richardson, rate 1: 2.965


def test_earlier_keyword_names_still_work_with_a_warning():
    mesh = blockmesh.load_domain("square").mesh(1)
    new = solve_elasticity(
        mesh,
        ("0", "-1"),
        young=1.0,
        poisson=0.3,
        dirichlet={"left": (0, 0)},
        neumann={"right": (1, 0)},
    )
    with pytest.warns(DeprecationWarning, match="displacement= is now dirichlet="):
        old = solve_elasticity(
            mesh,
            young=1.0,
            poisson=0.3,
            body_force=("0", "-1"),
            displacement={"left": (0, 0)},
            traction={"right": (1, 0)},
        )
    assert np.array_equal(new.displacement, old.displacement)
