"""Virtual elements on locally refined meshes: patch tests, the estimator, the adaptive loop."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh.errors import ArgumentError
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.local import refine_marked
from blockmesh.vem import solve_elasticity, solve_poisson
from blockmesh.vem.adaptive import dorfler_marking, solve_adaptive
from blockmesh.vem.estimate import estimate_error
from blockmesh.vem.reference import kirsch

#: The L-shape's corner solution r^(2/3) sin(2θ/3), θ from the edge x = 1, y > 1.
CORNER = "((x-1)^2+(y-1)^2)^(1/3)*cos(2/3*atan2(x-y, 2-x-y))"


def _hanging_mesh(name: str, seed: int, rounds: int = 3) -> PolygonMesh:
    mesh = PolygonMesh.from_mesh(blockmesh.load_domain(name).mesh(1))
    rng = np.random.default_rng(seed)
    for _ in range(rounds):
        marked = rng.random(mesh.n_cells) < 0.2
        marked[rng.integers(mesh.n_cells)] = True
        mesh = refine_marked(mesh, marked)
    assert mesh.hanging_nodes().size > 0
    return mesh


@given(st.sampled_from(["l-shape", "square-cut", "comb", "hexagon"]), st.integers(0, 10**6))
@settings(max_examples=examples(12), deadline=None)
def test_poisson_patch_test_with_hanging_nodes(name, seed):
    mesh = _hanging_mesh(name, seed)
    exact = "1 + 2*x - 3*y"
    sol = solve_poisson(mesh, 0, dirichlet={p: exact for p in mesh.patch_names})
    x, y = mesh.points.T
    assert np.max(np.abs(sol.values - (1 + 2 * x - 3 * y))) < 1e-11
    assert np.max(np.abs(sol.cell_gradient - [2.0, -3.0])) < 1e-10
    estimate = estimate_error(sol)  # nothing to estimate: the solution is exact
    assert estimate.estimator < 1e-9


@given(st.integers(0, 10**6))
@settings(max_examples=examples(8), deadline=None)
def test_poisson_patch_test_with_neumann_data(seed):
    mesh = _hanging_mesh("square", seed)
    flux = {"right": 2.0, "bottom": 3.0, "top": -3.0}  # (2, -3) . n on each side
    sol = solve_poisson(mesh, 0, dirichlet={"left": "1 + 2*x - 3*y"}, neumann=flux)
    x, y = mesh.points.T
    assert np.max(np.abs(sol.values - (1 + 2 * x - 3 * y))) < 1e-11
    assert estimate_error(sol).estimator < 1e-9


@given(st.integers(0, 10**6))
@settings(max_examples=examples(8), deadline=None)
def test_elasticity_patch_test_with_hanging_nodes(seed):
    mesh = _hanging_mesh("square-cut", seed)
    ux, uy = "0.1 + 0.2*x - 0.3*y", "-0.2 + 0.05*x + 0.4*y"
    sol = solve_elasticity(
        mesh, young=2.0, poisson=0.3, dirichlet={p: (ux, uy) for p in mesh.patch_names}
    )
    x, y = mesh.points.T
    expected = np.column_stack([0.1 + 0.2 * x - 0.3 * y, -0.2 + 0.05 * x + 0.4 * y])
    assert np.max(np.abs(sol.displacement - expected)) < 1e-11
    assert np.max(np.abs(sol.strain - [0.2, 0.4, -0.25])) < 1e-10
    assert estimate_error(sol).estimator < 1e-9


def test_dorfler_marks_the_fewest_cells_holding_theta():
    rng = np.random.default_rng(3)
    values = rng.random(500) ** 4
    for theta in (0.1, 0.3, 0.5, 0.9, 1.0):
        mask = dorfler_marking(values, theta)
        assert values[mask].sum() >= theta * values.sum() * (1 - 1e-12)
        smallest = values[mask].min()
        assert values[mask].sum() - smallest < theta * values.sum()  # none could be left out
        assert np.all(values[~mask] <= smallest)
    with pytest.raises(ArgumentError, match="theta"):
        dorfler_marking(values, 0.0)


def test_adaptive_l_shape_converges_at_the_optimal_rate_with_bounded_effectivity():
    mesh = blockmesh.load_domain("l-shape").mesh(0)

    def solve(m):
        return solve_poisson(m, 0, dirichlet={p: CORNER for p in m.patch_names})

    run = solve_adaptive(mesh, solve, max_unknowns=6000, exact=CORNER)
    assert run.stopped == "max_unknowns"
    unknowns = [s.unknowns for s in run.history]
    assert unknowns == sorted(unknowns) and unknowns[-1] <= 6000
    assert all(1.0 <= s.effectivity <= 4.0 for s in run.history)
    assert run.rates()["h1_error"] > 0.45  # uniform refinement: 1/3 at best
    assert run.history[-1].max_vertices > 5  # hanging nodes were used as they are
    run.mesh.check_geometry()


def test_adaptive_tolerance_and_elasticity():
    radius = 0.5
    mesh = blockmesh.load_domain("quarter-plate-hole").mesh(0)
    field = kirsch(radius=radius, young=1.0, poisson=0.3)
    sxx, syy, sxy = field.stress

    def solve(m):
        return solve_elasticity(
            m,
            young=1.0,
            poisson=0.3,
            dirichlet={"left": (0, "free"), "down": ("free", 0)},
            neumann={"right": (sxx, sxy), "up": (sxy, syy)},
        )

    run = solve_adaptive(mesh, solve, tol=0.05, max_steps=12, exact=field.displacement)
    assert run.stopped in ("tol", "max_steps")
    estimators = [s.estimator for s in run.history]
    assert estimators[-1] < estimators[0] / 2
    assert all(1.0 <= s.effectivity <= 4.0 for s in run.history)
