"""The paper's data shipped in the package: complete, consistent, and true to the mathematics."""

from __future__ import annotations

from fractions import Fraction

import pytest

from blockmesh.errors import ArgumentError, ArgumentTypeError, UnknownNameError
from blockmesh.quadrature import integrate
from blockmesh.quadrature.exact import exact_integral
from blockmesh.tables import (
    CASES,
    ERRATA,
    PENTAGONS,
    TABLES,
    paper_case,
    pentagon_mesh,
    table_orders,
)


def test_the_data_covers_every_table_and_pentagon():
    assert tuple(range(1, 12)) == TABLES
    assert {(c.table, c.pentagon) for c in CASES} == {(t, p) for t in TABLES for p in PENTAGONS}
    assert sum(len(c.entries) for c in CASES) == 313
    for case in CASES:
        rows = {1, 2, 5, 10} if case.table <= 6 else {5, 10, 20}
        assert {e.level for e in case.entries} == {1, 2, 3, 4}
        assert {e.order for e in case.entries} - {45} == rows
        assert all(e.order in table_orders(case.table) for e in case.entries)


def test_reference_values_have_34_digits_and_match_the_exact_fractions():
    for case in CASES:
        digits = case.reference.lstrip("-0.").split("e")[0].replace(".", "")
        assert len(digits) >= 34, case
        if case.exact_fraction is None:
            assert case.exact == Fraction(case.reference)
        else:  # the decimal is the fraction rounded to its 34 digits
            gap = abs(Fraction(case.reference) - Fraction(case.exact_fraction))
            assert gap <= Fraction(1, 10**33) * abs(case.exact)
            assert gap < abs(case.exact) / 10**30


def test_exact_fractions_are_the_exact_integrals():
    for case in CASES:
        if case.exact_fraction:
            assert exact_integral(PENTAGONS[case.pentagon], case.integrand) == case.exact


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c.table}-{c.pentagon}")
def test_abs_integrals_are_the_integrals_of_abs_f(case):
    """∫|f| >= |∫f|, and the stored ∫|f| is what the rule gives for abs(f) on a fine mesh.

    The stored values are scales, good to about 8 digits (Table 8's cone converges slowly: its
    ∫|f| = ∫f is stored up to 1.1e-9 below the reference).
    """
    assert case.abs_integral >= abs(float(case.exact)) * (1 - 1e-8)
    value = integrate(
        pentagon_mesh(case.pentagon, 4), f"abs({case.integrand})", order=12, warn_rtol=None
    )
    assert value == pytest.approx(case.abs_integral, rel=3e-5)  # |f| has kinks: slow


def test_every_erratum_is_about_a_case_and_every_correction_has_one():
    keys = {(c.table, c.pentagon) for c in CASES}
    assert all((e.table, e.pentagon) in keys for e in ERRATA)
    corrected = {
        (c.table, c.pentagon, e.order, e.level) for c in CASES for e in c.entries if e.corrected
    }
    located = {(e.table, e.pentagon, e.order, e.level) for e in ERRATA if e.order is not None}
    assert corrected == located == {(3, "SP", 1, 1), (8, "USP", 5, 3), (8, "USP", 45, 1)}


def test_orders_and_lookups():
    assert table_orders(6) == tuple(range(1, 11))
    assert table_orders(11) == (5, 10, 15, 20, 25, 30, 35, 40, 45)
    with pytest.raises(ArgumentError, match="no table 12"):
        table_orders(12)
    with pytest.raises(ArgumentTypeError, match="table must be a whole number"):
        table_orders("1")  # type: ignore[arg-type]
    with pytest.raises(UnknownNameError, match="unknown pentagon 'XP'; choose one of: SP, USP"):
        paper_case(1, "XP")
    with pytest.raises(ArgumentTypeError, match="pentagon must be a name"):
        paper_case(1, 5)  # type: ignore[arg-type]
    assert pentagon_mesh("sp", 1).n_cells == 6
