"""The composite rules: exactness degree, the paper's program, API behaviour, the CLI."""

from __future__ import annotations

import argparse
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh.commands import integrate as integrate_command
from blockmesh.errors import BlockMeshError, ExpressionError, ResourceError
from blockmesh.exact import exact_integral
from blockmesh.gauss import gauss_legendre
from blockmesh.mesh import Mesh
from blockmesh.quadrature import (
    RULES,
    integrate,
    integrate_to_tolerance,
    quadrature_points,
    rule_info,
)
from blockmesh.refinement import refine
from blockmesh.tables import PENTAGONS

SP = np.array(PENTAGONS["SP"], dtype=float)
USP = np.array(PENTAGONS["USP"], dtype=float)


def _pentagon(points) -> Mesh:
    return Mesh.from_cells(np.asarray(points, dtype=float), [[0, 1, 2, 3, 4]])


# --------------------------------------------------------------------------- exactness
@st.composite
def convex_pentagons(draw):
    """Five points on an ellipse at sorted angles (gaps < pi), mapped by a random affine map."""
    gaps = draw(st.lists(st.floats(0.15, 2.0), min_size=5, max_size=5))
    total = sum(gaps)
    gaps = [g * 2 * math.pi / total for g in gaps]
    if max(gaps) >= math.pi * 0.97:
        gaps = [2 * math.pi / 5] * 5
    start = draw(st.floats(0, 2 * math.pi))
    angles = start + np.cumsum([0.0, *gaps[:4]])
    unit = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    a, b, c, d = (draw(st.floats(-1.5, 1.5)) for _ in range(4))
    matrix = np.array([[1.0 + abs(a), b * 0.5], [c * 0.5, 0.4 + abs(d)]])
    shift = np.array([draw(st.floats(-1, 1)), draw(st.floats(-1, 1))])
    if np.linalg.det(matrix) < 0:  # a reflection: keep the corners counter-clockwise
        unit = unit[::-1]
    return unit @ matrix.T + shift


def _monomial_errors(points, rule: str, n: int, degree: int):
    """Largest |rule - exact| / round-off scale over monomials of total degree ``degree``."""
    mesh = _pentagon(points)
    x, y, w = quadrature_points(mesh, order=n, rule=rule)
    worst = 0.0
    for a in range(degree + 1):
        b = degree - a
        values = x**a * y**b
        exact = float(exact_integral(points, {(a, b): 1}))
        scale = float(np.sum(np.abs(w * values))) + 1e-300
        worst = max(worst, abs(float(np.dot(w, values)) - exact) / scale)
    return worst


@settings(max_examples=20, deadline=None)
@given(convex_pentagons(), st.sampled_from(tuple(RULES)))
def test_every_monomial_up_to_degree_2n_minus_1_is_exact(points, rule):
    for n in range(1, 9):
        for degree in range(2 * n):
            assert _monomial_errors(points, rule, n, degree) < 1e-13, (rule, n, degree)


@pytest.mark.parametrize("rule", tuple(RULES))
@pytest.mark.parametrize("n", [1, 2, 3, 5, 8])
def test_degree_2n_is_not_exact(rule, n):
    """The degree is sharp: some monomial of degree 2n is off by far more than round-off."""
    assert _monomial_errors(USP * 0.7 + 0.1, rule, n, 2 * n) > 1e-11


def test_rule_info_counts_and_degrees():
    assert rule_info("paper", 5).points_per_cell == 150
    assert rule_info("jacobi", 5).points_per_cell == 125
    assert rule_info("fan", 5).points_per_cell == 75
    assert {rule_info(r, 7).degree for r in RULES} == {13}
    x, _, _ = quadrature_points(_pentagon(SP), order=4, level=1, rule="jacobi")
    assert x.size == 6 * rule_info("jacobi", 4).points_per_cell


# --------------------------------------------------------------------------- the paper's program
def _fifth_program(mesh: Mesh, f, n: int) -> float:
    """A literal transcription of the paper's FIFTH program (loops, scalar arithmetic)."""
    ss, ww = gauss_legendre(n)
    sss, www = gauss_legendre(n + 1)
    X, Y = mesh.points[:, 0], mesh.points[:, 1]
    total = 0.0
    for cell in mesh.cells:
        elm = [*cell.tolist(), int(cell[0])]
        xcc = ycc = 0.0
        for k in range(5):
            xcc += X[elm[k]]
            ycc += Y[elm[k]]
        xcc, ycc = xcc / 5, ycc / 5
        ii = 0.0
        for N in range(5):
            xi, yi = X[elm[N + 1]], Y[elm[N + 1]]
            xk, yk = X[elm[N]], Y[elm[N]]
            d = (xcc - xi) * (yk - yi) - (xk - xi) * (ycc - yi)
            II = 0.0
            if d != 0:
                for jj in range(n + 1):
                    for kk in range(n):
                        ps = (1 + sss[jj]) / 2
                        qs = (1 - sss[jj]) / 2
                        t = ss[kk]
                        wt = ww[kk] * www[jj] / 4
                        xs = xcc * qs + ps * ((xi + xk) / 2 + (xk - xi) * t / 2)
                        ys = ycc * qs + ps * ((yi + yk) / 2 + (yk - yi) * t / 2)
                        II += ps * wt * f(xs, ys)
            ii += II * d
        total += ii
    return total


@pytest.mark.parametrize(
    ("text", "f"),
    [
        ("(x^4 + y^3) / (1 + x^2)", lambda x, y: (x**4 + y**3) / (1 + x**2)),
        ("cos(30*(x + y))", lambda x, y: math.cos(30 * (x + y))),
        (
            "sqrt((x - 0.5)^2 + (y - 0.5)^2)",
            lambda x, y: math.sqrt((x - 0.5) ** 2 + (y - 0.5) ** 2),
        ),
    ],
)
@pytest.mark.parametrize("pentagon", ["SP", "USP"])
def test_paper_rule_is_the_fifth_program(text, f, pentagon):
    for level, n in ((1, 3), (2, 6)):
        mesh = refine(_pentagon(PENTAGONS[pentagon]), level)
        expected = _fifth_program(mesh, f, n)
        scale = integrate(mesh, f"abs({text})", order=n)
        assert abs(integrate(mesh, text, order=n) - expected) <= 1e-15 * scale


def test_degenerate_triangles_are_skipped_like_the_paper():
    """A pentagon with a 180-degree corner: the flat triangle contributes nothing, even NaN."""
    square = Mesh.from_cells([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)], [[0, 1, 2, 3, 4]])
    assert integrate(square, "1", order=1, rule="fan") == pytest.approx(4.0, rel=1e-15)
    assert integrate(square, "1", order=1) == pytest.approx(4.0, rel=1e-15)


# --------------------------------------------------------------------------- API
def test_domain_mesh_and_level_agree():
    domain = blockmesh.load_domain("usp")
    mesh1 = domain.mesh(1)
    by_domain = integrate(domain, "exp(x - y)", order=4, level=2)
    assert integrate(mesh1, "exp(x - y)", order=4, level=2) == pytest.approx(by_domain, rel=1e-15)
    assert integrate(domain.mesh(2), "exp(x - y)", order=4) == pytest.approx(by_domain, rel=1e-15)
    assert integrate(domain, "exp(x - y)", order=4) == pytest.approx(
        integrate(domain.block_mesh(), "exp(x - y)", order=4), rel=1e-15
    )
    with pytest.raises(BlockMeshError, match="below the mesh's own level 1"):
        integrate(mesh1, "1", order=1, level=0)


def test_per_cell_values_sum_to_the_total():
    mesh = refine(_pentagon(SP), 2)
    cells = integrate(mesh, "x^2 + y", order=3, per_cell=True)
    assert cells.shape == (36,) and not cells.flags.writeable
    assert float(np.sum(cells)) == integrate(mesh, "x^2 + y", order=3)
    np.testing.assert_allclose(
        integrate(mesh, "1", order=1, per_cell=True), mesh.cell_areas(), rtol=1e-14
    )


@pytest.mark.parametrize("chunk", [1, 7, 150, 1000, 10**7])
def test_chunking_does_not_change_the_result(chunk):
    mesh = refine(_pentagon(USP), 2)
    reference = integrate(mesh, "sin(3*x*y)", order=5, per_cell=True)
    np.testing.assert_allclose(
        integrate(mesh, "sin(3*x*y)", order=5, per_cell=True, chunk=chunk),
        reference,
        rtol=1e-14,
        atol=1e-16,
    )


def test_f_sees_at_most_a_chunk_of_points():
    sizes = []

    def f(x, y):
        sizes.append(x.size)
        return x * y

    integrate(refine(_pentagon(SP), 3), f, order=4, chunk=5000)
    assert max(sizes) <= 5000 and sum(sizes) == 216 * rule_info("paper", 4).points_per_cell


def test_callables_constants_and_bad_callables():
    mesh = _pentagon(USP)
    assert integrate(mesh, lambda x, y: 2.0, order=1) == pytest.approx(12.0, rel=1e-15)
    with pytest.raises(ExpressionError, match="vectorised"):
        integrate(mesh, lambda x, y: np.zeros(3), order=2)
    with pytest.raises(ExpressionError, match="complex"):
        integrate(mesh, lambda x, y: x + 1j * y, order=2)
    with pytest.raises(ExpressionError, match="callable"):
        integrate(mesh, 3.0, order=2)  # type: ignore[arg-type]


def test_non_finite_integrands_name_the_point_and_cell():
    with pytest.raises(BlockMeshError, match=r"f is not finite \(nan\) at \(x, y\) = .*cell \d+"):
        integrate(refine(_pentagon(SP), 1), "log(x + 1)", order=3)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"order": 0}, "order must be a whole number"),
        ({"order": 2.5}, "order must be a whole number"),
        (
            {"order": 2, "rule": "simpson"},
            "unknown rule 'simpson'; choose one of: paper, jacobi, fan",
        ),
        ({"order": 2, "chunk": 0}, "chunk must be"),
        ({"order": 2, "level": -1}, "level must be"),
    ],
)
def test_bad_arguments(kwargs, message):
    with pytest.raises(BlockMeshError, match=message):
        integrate(_pentagon(SP), "x", **kwargs)


def test_bad_target():
    with pytest.raises(BlockMeshError, match="Domain or a Mesh"):
        integrate([(0, 0), (1, 0), (0, 1)], "x", order=2)


def test_quadrature_points_reproduce_integrate():
    mesh = refine(_pentagon(SP), 1)
    x, y, w = quadrature_points(mesh, order=6, rule="paper")
    assert float(np.sum(w)) == pytest.approx(5.0, rel=1e-14)
    assert float(np.dot(w, np.cos(x * y))) == pytest.approx(
        integrate(mesh, "cos(x*y)", order=6), rel=1e-14
    )


# --------------------------------------------------------------------------- to a tolerance
@pytest.mark.parametrize("rule", tuple(RULES))
def test_integrate_to_tolerance_smooth(rule):
    result = integrate_to_tolerance(
        _pentagon(SP), "exp(-((x - 1/2)^2 + (y - 1/2)^2))", 1e-12, rule=rule
    )
    assert result.converged and result.error_estimate <= 1e-12
    assert abs(result.value - 1.729175291842216445410886742214897) <= 1e-12
    assert result.points > 0 and len(result.history) >= 3 and float(result) == result.value
    assert "converged" in result.message


def test_integrate_to_tolerance_refines_when_the_order_stalls():
    result = integrate_to_tolerance(
        blockmesh.load_domain("sp"), "exp(-100*((x - 1/2)^2 + (y - 1/2)^2))", 1e-10
    )
    assert result.converged
    assert abs(result.value - 0.03139133725472966396367968598186081) <= 1e-10


def test_integrate_to_tolerance_reports_limits():
    result = integrate_to_tolerance(
        _pentagon(USP), "sqrt((x - 0.5)^2 + (y - 0.5)^2)", 1e-14, max_points=200_000
    )
    assert not result.converged
    assert "not reached" in result.message and "max_points=200,000" in result.message
    assert result.points <= 200_000
    floor = integrate_to_tolerance(_pentagon(USP), "x^2", 1e-30)
    assert not floor.converged and "round-off" in floor.message
    assert floor.value == pytest.approx(float(exact_integral(USP, "x^2")), rel=1e-14)


def test_integrate_to_tolerance_bad_arguments():
    with pytest.raises(BlockMeshError, match="tol must be"):
        integrate_to_tolerance(_pentagon(SP), "x", -1.0)
    with pytest.raises(BlockMeshError, match="give a tolerance"):
        integrate_to_tolerance(_pentagon(SP), "x", 0.0)


# --------------------------------------------------------------------------- CLI
def _run(argv: list[str], capsys) -> tuple[int, str, str]:
    parser = argparse.ArgumentParser(prog="blockmesh")
    integrate_command.register(parser.add_subparsers(dest="command"))
    args = parser.parse_args(argv)
    code = args.run(args)
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_json(capsys):
    code, out, _ = _run(
        [
            "integrate",
            "usp",
            "--function",
            "(0.2*x+0.3*y)^19",
            "--level",
            "1",
            "--order",
            "10",
            "--exact",
            "--json",
        ],
        capsys,
    )
    payload = json.loads(out)
    assert code == 0
    assert set(payload) == {
        "value",
        "level",
        "order",
        "rule",
        "cells",
        "points",
        "error_estimate",
        "exact",
    }
    assert payload["exact"] == "5832661838294956841/8400000000000000000"
    assert payload["cells"] == 6 and payload["points"] == 6 * 550 and payload["rule"] == "paper"
    assert abs(payload["value"] - 0.6943645045589234) < 1e-15


def test_cli_tolerance_and_text(capsys):
    code, out, _ = _run(
        ["integrate", "sp", "-f", "cos(30*(x + y))", "--tol", "1e-11", "--json"], capsys
    )
    payload = json.loads(out)
    assert code == 0 and payload["converged"] and payload["error_estimate"] <= 1e-11
    assert abs(payload["value"] + 0.007436177299024373) <= 1e-11
    code, out, _ = _run(
        ["integrate", "--polygon", "0,0 2,0 3,1 1,3 0,2", "-f", "x*y", "--exact"], capsys
    )
    assert code == 0 and "exact" in out and "value" in out
    code, out, err = _run(
        [
            "integrate",
            "usp",
            "-f",
            "sqrt((x-0.5)^2+(y-0.5)^2)",
            "--tol",
            "1e-15",
            "--max-level",
            "1",
        ],
        capsys,
    )
    assert code == 1 and "not reached" in err


def test_cli_errors_are_typed(capsys):
    with pytest.raises(ExpressionError, match="unknown name 'os'"):
        _run(["integrate", "sp", "-f", "x + os"], capsys)
    with pytest.raises(ExpressionError, match="not a polynomial"):
        _run(["integrate", "sp", "-f", "sin(x)", "--exact"], capsys)


def test_integrate_to_tolerance_without_room_for_one_step():
    with pytest.raises(ResourceError, match="nothing computed"):
        integrate_to_tolerance(_pentagon(SP), "x", 1e-9, max_points=5)
    one = integrate_to_tolerance(_pentagon(SP), "x", 1e-9, max_points=30)
    assert not one.converged and one.cells == 1 and len(one.history) == 1
    assert one.error_estimate == math.inf
