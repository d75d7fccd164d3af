"""Solving on composite domains: per-region data, exactness across interfaces, convergence.

- a two-material bar whose exact solution is piecewise linear (kappa 1 and 10, flux continuous)
  is reproduced to round-off by ``blockmesh solve`` (the Done-when command, GeoJSON input);
- the circular inclusion in a uniform far field (closed form, conductivity contrast 10)
  converges at the optimal rates of the refinement: the L2 error falls 4x and the H1 error 2x
  per level (h halves), as for a smooth one-material problem on the same meshes;
- a bimaterial elasticity patch test (E and nu per layer, piecewise linear displacement) passes.
"""

from __future__ import annotations

import json

import meshio
import numpy as np
import pytest
from helpers import run_cli

import blockmesh
from blockmesh import SolverError, UnknownNameError
from blockmesh.vem import solve_elasticity, solve_poisson

BAR = {
    "type": "FeatureCollection",
    "features": [
        {
            "type": "Feature",
            "properties": {"region": region},
            "geometry": {"type": "Polygon", "coordinates": [ring]},
        }
        for region, ring in (
            ("a", [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]),
            ("b", [[1, 0], [2, 0], [2, 1], [1, 1], [1, 0]]),
        )
    ],
}
#: kappa 1 in a (x < 1), 10 in b: the flux -kappa u' = -1 on both sides.
BAR_EXACT = "min(x, 0.9 + 0.1*x)"


def test_layered_bar_is_reproduced_to_round_off_by_the_command(capsys, tmp_path):
    path = tmp_path / "bar.geojson"
    path.write_text(json.dumps(BAR))
    out = tmp_path / "bar.vtu"
    code, stdout, stderr = run_cli(
        capsys, "solve", str(path), "--level", "2", "--diffusion", "a=1", "--diffusion", "b=10",
        "--dirichlet", f"*={BAR_EXACT}", "--exact", BAR_EXACT, "-o", str(out), "--json",
    )  # fmt: skip
    assert code == 0, stderr
    report = json.loads(stdout)
    assert report["l2_error"] < 1e-13 and report["h1_error"] < 1e-10
    # The solution file carries the region of every cell and the patch of every node.
    back = meshio.read(out)
    region = np.concatenate(back.cell_data["region"])
    centres = back.points[np.concatenate([c.data for c in back.cells])][:, :, 0].mean(axis=1)
    assert np.array_equal(region, (centres > 1).astype(int))
    patch = back.point_data["patch"]
    on_boundary = np.isclose(back.points[:, 0] % 2, 0) | np.isclose(back.points[:, 1] % 1, 0)
    assert np.array_equal(patch >= 0, on_boundary)
    # A bare value means everywhere; a region value overrides it.
    code, stdout, _ = run_cli(
        capsys, "solve", str(path), "--level", "1", "--diffusion", "1", "--diffusion", "b=10",
        "--dirichlet", f"*={BAR_EXACT}", "--exact", BAR_EXACT, "--json",
    )  # fmt: skip
    assert code == 0 and json.loads(stdout)["l2_error"] < 1e-13


def test_a_wkt_multipolygon_passes_check(capsys, tmp_path):
    path = tmp_path / "two.wkt"
    path.write_text("MULTIPOLYGON (((0 0, 1 0, 1 1, 0 1, 0 0)), ((1 0, 2 0, 2 1, 1 1, 1 0)))\n")
    code, stdout, _ = run_cli(capsys, "check", str(path))
    assert code == 0 and "interface part0|part1: 3 edges" in stdout


def test_layered_plate_piecewise_linear_in_python():
    mesh = blockmesh.load_domain("layered-plate").mesh(2)
    kappa = {"bottom": 1.0, "core": 10.0, "top": 2.0}
    # -kappa u' = -1 in every layer: u' = 1/kappa, continuous u.
    exact = {"bottom": "y", "core": "1 + (y - 1)/10", "top": "1.1 + (y - 2)/2"}
    sol = solve_poisson(mesh, 0, diffusion=kappa, dirichlet={"floor": 0, "ceiling": 1.6})
    errors = sol.errors(exact)
    assert errors.l2 < 1e-12 and errors.h1 < 1e-10
    flux = sol.cell_gradient[:, 1] * np.array([kappa[n] for n in mesh.region_names])[mesh.region]
    assert np.abs(flux - 1.0).max() < 1e-10  # the flux is continuous across both interfaces


def test_per_region_data_errors():
    mesh = blockmesh.load_domain("layered-plate").mesh(0)
    with pytest.raises(SolverError, match="diffusion is given for the region bottom but not for"):
        solve_poisson(mesh, 0, diffusion={"bottom": 1}, dirichlet={"floor": 0})
    with pytest.raises(UnknownNameError, match="diffusion names the region 'mantle'"):
        solve_poisson(mesh, 0, diffusion={"mantle": 1, "*": 2}, dirichlet={"floor": 0})
    with pytest.raises(SolverError, match="diffusion .* has mean -1 <= 0"):
        solve_poisson(mesh, 0, diffusion={"core": -1, "*": 1}, dirichlet={"floor": 0})


def _inclusion_errors(levels):
    """L2 and H1 errors of the circular inclusion (radius a = 0.5, kappa 10 in 1, field E = 1)."""
    domain = blockmesh.load_domain("inclusion")
    k, a = 10.0, 0.5
    inside, b = 2 / (k + 1), (1 - k) / (k + 1)
    exact = {"matrix": f"x*(1 + ({b})*{a * a}/(x*x + y*y))", "inclusion": f"{inside}*x"}
    out = []
    for level in levels:
        mesh = domain.mesh(level)
        sol = solve_poisson(
            mesh,
            0,
            diffusion={"matrix": 1, "inclusion": k},
            dirichlet={"boundary": exact["matrix"]},
        )
        errors = sol.errors(exact)
        out.append((sol.info.dof, errors.l2, errors.h1))
    return np.array(out)


def _assert_optimal(table):
    # h halves at every level: O(h^2) in L2 and O(h) in H1 are factors 4 and 2.
    l2_factor = table[:-1, 1] / table[1:, 1]
    h1_factor = table[:-1, 2] / table[1:, 2]
    assert np.all(l2_factor > 3.9), l2_factor
    assert np.all(h1_factor > 1.95), h1_factor
    # Against the unknowns (about 6x per level): N^-0.84 and N^-0.48 (see docs/composite.md).
    rates = np.diff(np.log(table[:, 1:]), axis=0) / np.diff(np.log(table[:, :1]), axis=0)
    assert np.all(rates[:, 0] < -0.8) and np.all(rates[:, 1] < -0.45), rates


def test_circular_inclusion_converges_at_optimal_rates():
    _assert_optimal(_inclusion_errors([0, 1, 2]))


@pytest.mark.slow
def test_circular_inclusion_converges_at_optimal_rates_to_level_3():
    _assert_optimal(_inclusion_errors([0, 1, 2, 3]))


def test_bimaterial_elasticity_patch_test():
    """Stretching along the layers: u_x = e x, u_y piecewise linear with each layer's nu.

    The traction across every interface is zero on both sides (sigma_yy = sigma_xy = 0), the
    displacement continuous: an exact solution the lowest-order space holds cell by cell.
    """
    mesh = blockmesh.load_domain("layered-plate").mesh(2)
    e = 1e-3
    young = {"bottom": 200.0, "core": 3.0, "top": 70.0}
    nu = {"bottom": 0.3, "core": 0.45, "top": 0.33}
    exact = {
        "bottom": f"{e}*x, -{nu['bottom'] * e}*y",
        "core": f"{e}*x, -{nu['bottom'] * e} - {nu['core'] * e}*(y - 1)",
        "top": f"{e}*x, -{(nu['bottom'] + nu['core']) * e} - {nu['top'] * e}*(y - 2)",
    }
    # Every boundary patch gets the exact displacement: the floor and the ceiling their layer's.
    displacement = {"floor": exact["bottom"], "ceiling": exact["top"]}
    # The side patches span all layers: one expression with each layer's slope.
    side = (
        f"{e}*x, -{e}*({nu['bottom']}*min(y, 1) + {nu['core']}*max(min(y, 2) - 1, 0) "
        f"+ {nu['top']}*max(y - 2, 0))"
    )
    displacement.update({"left": side, "right": side})
    sol = solve_elasticity(mesh, young=young, poisson=nu, dirichlet=displacement)
    errors = sol.errors(exact)
    assert errors.l2 < 1e-15 and errors.h1 < 1e-12
    for k, name in enumerate(mesh.region_names):
        stress = sol.stress[mesh.region == k]
        expected = young[name] * e  # plane stress, sigma_yy = 0: sigma_xx = E e
        assert np.abs(stress - [expected, 0.0, 0.0]).max() < 1e-10 * expected
