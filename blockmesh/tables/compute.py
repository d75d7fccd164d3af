"""Regenerating the paper's tables: the refined pentagons and the paper's rule over them.

Examples
--------
>>> result = compute_table(1, "USP", levels=(1, 2), orders=(10,))
>>> bool(result.errors.max() < 1e-13 * result.case.abs_integral)
True
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

import numpy as np

from blockmesh.checks import whole_number
from blockmesh.errors import ArgumentTypeError
from blockmesh.mesh.mesh import Mesh
from blockmesh.numerics.expr import parse_expression
from blockmesh.quadrature.arguments import check_chunk, check_max_points
from blockmesh.quadrature.kernel import DEFAULT_CHUNK, cell_sums, total_of
from blockmesh.quadrature.registry import get_rule, order_of
from blockmesh.quadrature.targets import DEFAULT_MAX_POINTS, check_work, plan_mesh
from blockmesh.refinement.pipeline import refine
from blockmesh.tables.data import PENTAGONS, PaperCase, _check_pentagon, paper_case, table_orders

__all__ = ["PaperTable", "compute_table", "pentagon_mesh"]


@lru_cache(maxsize=16)
def pentagon_mesh(pentagon: str, level: int) -> Mesh:
    """The paper's pentagon refined ``level`` times (6**level cells), cached.

    Examples
    --------
    >>> pentagon_mesh("SP", 2).n_cells
    36
    """
    key = _check_pentagon(pentagon)
    steps = whole_number(level, "level")
    base = Mesh.from_cells(
        np.array(PENTAGONS[key], dtype=np.float64), np.array([[0, 1, 2, 3, 4]]), name=key
    )
    return refine(base, steps)


@dataclass(frozen=True, eq=False)
class PaperTable:
    """One regenerated table for one pentagon.

    Attributes
    ----------
    case : PaperCase
    orders, levels : tuple of int
        Rows (OGLR) and columns (NPMR = 6**level).
    values : ndarray (len(orders), len(levels))
    rule : str
    """

    case: PaperCase
    orders: tuple[int, ...]
    levels: tuple[int, ...]
    values: np.ndarray
    rule: str = "paper"

    @property
    def errors(self) -> np.ndarray:
        """``|value - reference|`` of every entry (the reference subtracted exactly)."""
        ref = self.case.exact
        return np.array(
            [[float(abs(Fraction(float(v)) - ref)) for v in row] for row in self.values]
        ).reshape(self.values.shape)

    @property
    def scaled_errors(self) -> np.ndarray:
        """``|value - reference| / ∫|f|``, comparable with the round-off floor 1e-13."""
        return self.errors / self.case.abs_integral


def _whole_numbers(values: object, name: str) -> tuple[int, ...]:
    if isinstance(values, str) or not hasattr(values, "__iter__"):
        raise ArgumentTypeError(f"{name} must be a sequence of whole numbers, got {values!r}")
    return tuple(whole_number(v, name) for v in values)


def compute_table(
    table: int,
    pentagon: str,
    *,
    levels: tuple[int, ...] = (1, 2, 3, 4),
    orders: tuple[int, ...] | None = None,
    rule: str = "paper",
    chunk: int = DEFAULT_CHUNK,
    max_points: int = DEFAULT_MAX_POINTS,
) -> PaperTable:
    """Regenerate ``table`` for ``pentagon`` at the given levels and orders.

    The entries are plain values of the rule (low orders on coarse meshes are meant to be
    inaccurate: no error estimate is made and nothing is warned about).

    Parameters
    ----------
    table : int
        1..11.
    pentagon : {"SP", "USP"}
    levels : tuple of int
        Refinement levels (columns NPMR = 6**level), default the paper's 1..4.
    orders : tuple of int, optional
        Rows; default :func:`~blockmesh.tables.data.table_orders`.
    rule : str
        Quadrature rule, default the paper's.
    chunk, max_points : int
        As in :func:`blockmesh.quadrature.integrate`; every entry is checked against the budget
        before anything is computed.

    Raises
    ------
    ArgumentError, ArgumentTypeError, UnknownNameError
        For a table, pentagon, level, order or rule that does not exist.
    ResourceError
        When an entry would pass ``max_points``.

    Examples
    --------
    >>> t = compute_table(6, "SP", levels=(1,), orders=(10, 11))
    >>> t.values.shape, bool(t.errors[1, 0] < 1e-14)  # degree 20 is exact from order 11 on
    ((2, 1), True)
    """
    case = paper_case(table, pentagon)
    found = get_rule(rule)
    rows = table_orders(table) if orders is None else _whole_numbers(orders, "orders")
    rows = tuple(order_of(found, n) for n in rows)
    columns = _whole_numbers(levels, "levels")
    chunk = check_chunk(chunk)
    budget = check_max_points(max_points)
    base = pentagon_mesh(case.pentagon, 0)
    for level in columns:
        plan = plan_mesh(base, level)
        for n in rows:
            check_work(plan, found.info(n).points_per_cell, budget, f"order {n}")
    function = parse_expression(case.integrand)
    values = np.empty((len(rows), len(columns)))
    for j, level in enumerate(columns):
        mesh = pentagon_mesh(case.pentagon, level)
        for i, n in enumerate(rows):
            values[i, j] = total_of(cell_sums(mesh, function, found, n, chunk))
    values.setflags(write=False)
    return PaperTable(case, rows, columns, values, found.name)
