"""The same role has the same keyword name in every function that takes it (issue 21, item 4).

Paired functions (a solver and its sibling, an entry point and its distributed twin, a fixed rule
and its adaptive variant) must spell their shared roles alike; each pair lists the roles it
shares, so a rename in one of them fails here until the other follows.
"""

from __future__ import annotations

import inspect

import pytest

import blockmesh
from blockmesh import vem

PAIRS = [
    (
        vem.solve_poisson,
        vem.solve_elasticity,
        {"mesh", "source", "dirichlet", "neumann", "constraint", "order", "stabilization",
         "stabilization_scale", "solver", "tol"},
    ),
    (
        blockmesh.integrate,
        blockmesh.integrate_to_tolerance,
        {"target", "f", "level", "rule", "max_points", "chunk", "exact_geometry"},
    ),
    (blockmesh.integrate, blockmesh.quadrature_points, {"target", "order", "level", "rule"}),
]  # fmt: skip


def keywords(function) -> set[str]:
    return set(inspect.signature(function).parameters)


@pytest.mark.parametrize(
    ("one", "other", "shared"), PAIRS, ids=lambda x: getattr(x, "__name__", "")
)
def test_shared_roles_have_one_name(one, other, shared):
    assert shared <= keywords(one), shared - keywords(one)
    assert shared <= keywords(other), shared - keywords(other)
