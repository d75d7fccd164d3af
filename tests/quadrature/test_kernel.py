"""The kernel: the paper's program reproduced, chunking, the integrand's checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from blockmesh.errors import ArgumentTypeError, ExpressionError
from blockmesh.mesh import Mesh
from blockmesh.numerics.gauss import gauss_legendre
from blockmesh.quadrature import integrate, integrate_cells, rule_info
from blockmesh.refinement import refine
from blockmesh.tables import PENTAGONS

SP = np.array(PENTAGONS["SP"], dtype=float)
USP = np.array(PENTAGONS["USP"], dtype=float)


def _pentagon(points) -> Mesh:
    return Mesh.from_cells(np.asarray(points, dtype=float), np.array([[0, 1, 2, 3, 4]]))


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
        scale = integrate(mesh, f"abs({text})", order=n, warn_rtol=None)
        assert abs(integrate(mesh, text, order=n, warn_rtol=None) - expected) <= 1e-15 * scale


def test_degenerate_triangles_are_skipped_like_the_paper():
    """A pentagon with a 180-degree corner: the flat triangle contributes nothing, even NaN."""
    square = Mesh.from_cells([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)], np.array([[0, 1, 2, 3, 4]]))
    assert integrate(square, "1", order=1, rule="fan") == pytest.approx(4.0, rel=1e-15)
    assert integrate(square, "1", order=1) == pytest.approx(4.0, rel=1e-15)


@pytest.mark.parametrize("chunk", [1, 7, 150, 1000, 10**7])
def test_chunking_does_not_change_the_result(chunk):
    mesh = refine(_pentagon(USP), 2)
    reference = integrate_cells(mesh, "sin(3*x*y)", order=5)
    np.testing.assert_allclose(
        integrate_cells(mesh, "sin(3*x*y)", order=5, chunk=chunk), reference, rtol=1e-14, atol=1e-16
    )


def test_f_sees_at_most_a_chunk_of_points():
    sizes = []

    def f(x, y):
        sizes.append(x.size)
        return x * y

    integrate(refine(_pentagon(SP), 3), f, order=4, chunk=5000, warn_rtol=None)
    assert max(sizes) <= 5000 and sum(sizes) == 216 * rule_info("paper", 4).points_per_cell


def test_callables_constants_and_bad_callables():
    mesh = _pentagon(USP)
    assert integrate(mesh, lambda x, y: 2.0, order=1) == pytest.approx(12.0, rel=1e-15)
    with pytest.raises(ExpressionError, match="vectorised"):
        integrate(mesh, lambda x, y: np.zeros(3), order=2)
    with pytest.raises(ExpressionError, match="complex"):
        integrate(mesh, lambda x, y: x + 1j * y, order=2)
    with pytest.raises(ExpressionError, match="not numbers"):
        integrate(mesh, lambda x, y: np.full(x.shape, "a"), order=2)
    with pytest.raises(ArgumentTypeError, match="callable"):
        integrate(mesh, 3.0, order=2)  # type: ignore[arg-type]


def test_non_finite_integrands_name_the_point_and_cell():
    with pytest.raises(ExpressionError, match=r"f is not finite \(nan\) at \(x, y\) = .*cell \d+"):
        integrate(refine(_pentagon(SP), 1), "log(x + 1)", order=3)
    with pytest.raises(ExpressionError, match=r"f is not finite \(inf\) .* of cell"):
        integrate(refine(_pentagon(USP), 2), "1e308 * y", order=3)


def test_a_sum_that_overflows_is_an_error_not_inf():
    """Every value and cell integral finite, the total beyond float64: an error (issue 14)."""
    strip = Mesh.from_cells([(0, 0), (5, 0), (10, 0), (10, 1), (0, 1)], np.array([[0, 1, 2, 3, 4]]))
    with pytest.raises(ExpressionError, match="the integral overflows: every cell integral is fin"):
        integrate(refine(strip, 2), "1e308 * y", order=10)
    with pytest.raises(ExpressionError, match="the integral over cell 0 overflows"):
        integrate(strip, lambda x, y: np.full(x.shape, 1.7e308), order=2)
