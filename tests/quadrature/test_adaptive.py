"""Integration to a tolerance: convergence, limits, arguments."""

from __future__ import annotations

import math

import numpy as np
import pytest

import blockmesh
from blockmesh.errors import ArgumentError, ArgumentTypeError, ResourceError
from blockmesh.mesh import Mesh
from blockmesh.quadrature import RULES, integrate_to_tolerance
from blockmesh.quadrature.exact import exact_integral
from blockmesh.tables import PENTAGONS

SP = np.array(PENTAGONS["SP"], dtype=float)
USP = np.array(PENTAGONS["USP"], dtype=float)


def _pentagon(points) -> Mesh:
    return Mesh.from_cells(np.asarray(points, dtype=float), np.array([[0, 1, 2, 3, 4]]))


@pytest.mark.parametrize("rule", tuple(RULES))
def test_integrate_to_tolerance_smooth(rule):
    result = integrate_to_tolerance(
        _pentagon(SP), "exp(-((x - 1/2)^2 + (y - 1/2)^2))", 1e-12, rule=rule
    )
    assert result.converged and result.error_estimate <= 1e-12
    assert abs(result.value - 1.729175291842216445410886742214897) <= 1e-12
    assert result.points > 0 and len(result.history) >= 3 and float(result) == result.value
    assert "converged" in result.message and result.worst_cell is None


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
    with pytest.raises(ArgumentError, match="tol must be"):
        integrate_to_tolerance(_pentagon(SP), "x", -1.0)
    with pytest.raises(ArgumentTypeError, match="tol must be"):
        integrate_to_tolerance(_pentagon(SP), "x", "small")  # type: ignore[arg-type]
    with pytest.raises(ArgumentError, match="give a tolerance"):
        integrate_to_tolerance(_pentagon(SP), "x", 0.0)
    with pytest.raises(ArgumentError, match="max_order must be|order must be"):
        integrate_to_tolerance(_pentagon(SP), "x", 1e-9, max_order=0)
    with pytest.raises(ArgumentTypeError, match="the target must be a Domain or a Mesh"):
        integrate_to_tolerance("sp", "x", 1e-9)


def test_integrate_to_tolerance_without_room_for_one_step():
    with pytest.raises(ResourceError, match="nothing computed"):
        integrate_to_tolerance(_pentagon(SP), "x", 1e-9, max_points=5)
    with pytest.raises(ResourceError, match="nothing computed"):  # before refining to level 9
        integrate_to_tolerance(_pentagon(SP), "x", 1e-9, level=9)
    one = integrate_to_tolerance(_pentagon(SP), "x", 1e-9, max_points=30)
    assert not one.converged and one.cells == 1 and len(one.history) == 1
    assert one.error_estimate == math.inf
