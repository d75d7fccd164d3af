"""Integration over the true curved domains: exact geometry, exact integrals along curves."""

from __future__ import annotations

import itertools
import json
import math
from fractions import Fraction

import numpy as np
import pytest
from curved_references import AREAS, moment
from helpers import run_cli

import blockmesh
from blockmesh import Domain
from blockmesh.curves import Arc, Polyline, Spline
from blockmesh.errors import ArgumentTypeError, ExpressionError
from blockmesh.quadrature import RULES, integrate_cells
from blockmesh.quadrature.curved import along_points, curved_cells

MONOMIALS = [(a, b) for a in range(9) for b in range(9 - a)]  # every degree up to 8
EXACT_DOMAINS = ["plate-hole", "disc", "annulus"]


@pytest.fixture(scope="module")
def domains():
    return {name: blockmesh.load_domain(name) for name in EXACT_DOMAINS}


def _close(value: float, name: str, a: int, b: int, rel: float) -> bool:
    exact, scale = moment(name, a, b), moment(name, a, b, absolute=True)
    return abs(value - exact) <= rel * (abs(exact) if exact else scale)


@pytest.mark.parametrize("level", [0, 3])
@pytest.mark.parametrize("name", EXACT_DOMAINS)
def test_exact_geometry_integrates_monomials_to_degree_8(domains, name, level):
    mesh = domains[name].mesh(level)
    bad = []
    for a, b in MONOMIALS:
        value = blockmesh.integrate(
            mesh, lambda x, y, a=a, b=b: x**a * y**b, order=5, exact_geometry=True, warn_rtol=None
        )
        if not _close(value, name, a, b, 1e-13):
            bad.append((a, b, value, moment(name, a, b)))
    assert not bad


@pytest.mark.parametrize("rule", ["jacobi", "fan"])
def test_every_rule_integrates_the_curved_cells(domains, rule):
    disc = domains["disc"]
    for a, b in [(0, 0), (2, 4), (6, 2)]:
        value = blockmesh.integrate(
            disc, f"x^{a} * y^{b}", order=5, rule=rule, level=1, exact_geometry=True
        )
        assert _close(value, "disc", a, b, 1e-13)


@pytest.mark.parametrize("name", EXACT_DOMAINS)
def test_one_integrates_to_the_true_area_at_level_0(domains, name):
    value = blockmesh.integrate(domains[name], "1", order=1, exact_geometry=True)
    assert value == pytest.approx(AREAS[name], rel=1e-15)
    assert blockmesh.integrate(domains[name], "1", order=1) == pytest.approx(
        domains[name].block_mesh().area, rel=1e-15
    )


def test_straight_cells_converge_at_second_order_and_exact_geometry_does_not_need_to(domains):
    exact = moment("disc", 2, 2)
    straight = [
        blockmesh.integrate(domains["disc"], "x^2*y^2", order=5, level=level)
        for level in range(1, 6)
    ]
    errors = [abs(v - exact) for v in straight]
    ratios = [a / b for a, b in itertools.pairwise(errors)]
    assert all(3.5 < r < 4.5 for r in ratios[1:]), ratios
    curved = blockmesh.integrate(domains["disc"], "x^2*y^2", order=5, exact_geometry=True)
    assert abs(curved - exact) < 1e-15


@pytest.mark.parametrize("name", EXACT_DOMAINS)
def test_exact_integrals_along_arcs_match_the_closed_forms(domains, name):
    for a, b in MONOMIALS:
        value = blockmesh.exact_integral(domains[name], {(a, b): 1})
        assert isinstance(value, float)
        assert _close(value, name, a, b, 1e-14), (a, b)


def _spline_domain() -> Domain:
    pentagon = [(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)]
    edges = {(0, 1): Spline(points=[(0.7, -0.15), (1.4, -0.1)]),
             (2, 3): Polyline(points=[(2.2, 2.1)])}  # fmt: skip
    return Domain.from_blocks(pentagon, [(0, 1, 2, 3, 4)], edges=edges)


def test_splines_and_polylines_have_rational_exact_integrals_and_quadrature_meets_them():
    d = _spline_domain()
    for monomial in ["1", "x^3*y^2", "x^7*y", "y^8"]:
        exact = blockmesh.exact_integral(d, monomial)
        assert isinstance(exact, Fraction)
        for level in (0, 2):
            value = blockmesh.integrate(d, monomial, order=5, level=level, exact_geometry=True)
            assert value == pytest.approx(float(exact), rel=2e-15)
    assert float(blockmesh.exact_integral(d, "1")) == pytest.approx(d.area, rel=1e-15)


def test_cell_integrals_cover_the_curved_cells_only(domains):
    mesh = domains["annulus"].mesh(1)
    straight = integrate_cells(mesh, "x^2", order=3)
    curved = integrate_cells(mesh, "x^2", order=3, exact_geometry=True)
    on_curve = curved_cells(mesh, lambda x, y: x * x, RULES["paper"], 3).cells
    untouched = np.setdiff1d(np.arange(mesh.n_cells), on_curve)
    assert np.array_equal(straight[untouched], curved[untouched])
    assert not np.allclose(straight[on_curve], curved[on_curve])
    areas = integrate_cells(mesh, "1", order=1, exact_geometry=True)
    assert np.allclose(areas, mesh.curved_cell_areas(), rtol=1e-14)


def test_integration_to_a_tolerance_over_the_curved_disc(domains):
    # e^x cos y is harmonic: its mean over the disc is its value at the centre.
    result = blockmesh.integrate_to_tolerance(
        domains["disc"], "exp(x) * cos(y)", 1e-12, exact_geometry=True
    )
    assert result.converged and abs(result.value - math.pi) < 1e-12


def test_along_points_grow_with_the_arcs_turn_and_the_order():
    arc = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
    assert 3 <= along_points(arc, 3, 1 / 1024) <= 4
    assert along_points(arc, 3, 1.0) > along_points(arc, 3, 0.25) >= 3
    assert along_points(arc, 10, 1.0) > along_points(arc, 3, 1.0)
    line = Polyline(points=[(1, 1)]).with_ends((0, 0), (2, 0))
    assert along_points(line, 4, 1.0) == 4


def test_bad_arguments_and_integrands_are_located(domains):
    with pytest.raises(ArgumentTypeError, match="exact_geometry must be True or False"):
        blockmesh.integrate(domains["disc"], "x", order=2, exact_geometry="yes")
    with pytest.raises(ExpressionError, match="a quadrature point of cell"):
        blockmesh.integrate(domains["disc"], "sqrt(0.5 - x^2 - y^2)", order=3, exact_geometry=True)
    nowhere = lambda x, y: np.where(x * x + y * y > 0.5, np.nan, 1.0)  # noqa: E731
    with pytest.raises(ExpressionError, match=r"f is not finite \(nan\) at \(x, y\) = "):
        curved_cells(domains["disc"].block_mesh(), nowhere, RULES["paper"], 3)


def test_cli_integrates_over_the_exact_geometry(capsys):
    code, out, _ = run_cli(
        capsys, "integrate", "plate-hole", "-f", "x^2*y^2", "--level", "1", "--order", "5",
        "--exact", "--exact-geometry", "--json",
    )  # fmt: skip
    report = json.loads(out)
    assert code == 0 and report["exact_error"] < 1e-13 * 28.44
    code, out, _ = run_cli(capsys, "integrate", "disc", "-f", "1", "--level", "2")
    assert code == 0 and "--exact-geometry: the curved cells" in out


def test_cli_says_when_there_is_no_curve_to_follow(capsys, tmp_path):
    path = blockmesh.write(blockmesh.load_domain("disc").mesh(1), tmp_path / "disc.msh")
    code, out, err = run_cli(capsys, "integrate", str(path), "-f", "1", "--exact-geometry")
    assert code == 0 and "no curved edges here" in out and ".npz" in out
    assert "refining it further puts the new nodes on straight edges" in err


def test_a_saved_npz_keeps_its_curves_for_exact_geometry(capsys, tmp_path):
    path = blockmesh.write(blockmesh.load_domain("disc").mesh(1), tmp_path / "disc.npz")
    code, out, err = run_cli(capsys, "integrate", str(path), "-f", "1", "--exact-geometry")
    assert code == 0 and "the curved cells (exact geometry)" in out, err
    assert abs(float(out.split("value")[1].split()[0]) - np.pi) < 1e-12
