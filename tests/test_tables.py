"""The paper's Tables 1-11 reproduced entry by entry, and the ``tables`` command."""

from __future__ import annotations

import argparse
import csv
import json
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from blockmesh.commands import tables as tables_command
from blockmesh.errors import BlockMeshError
from blockmesh.exact import exact_integral
from blockmesh.tables import (
    CASES,
    ERRATA,
    PENTAGONS,
    TABLES,
    compute_table,
    format_table,
    paper_case,
    pentagon_mesh,
    plot_convergence,
    table_orders,
    write_csv,
)

DATA = json.loads((Path(__file__).parent / "data" / "paper_printed_values.json").read_text())
#: |a - b| <= TOLERANCE * ∫|f| (MATH.md section 5).
TOLERANCE = 1e-13


def _case_id(case: dict) -> str:
    return f"table{case['table']}-{case['pentagon']}"


@pytest.mark.parametrize("level", [1, 2, 3, pytest.param(4, marks=pytest.mark.slow)])
@pytest.mark.parametrize("case", DATA["cases"], ids=_case_id)
def test_printed_entries_are_reproduced(case, level):
    """Every printed entry (rows 1, 2, 5, 10 or 5, 10, 20) within 1e-13 ∫|f|; errata corrected."""
    entries = [e for e in case["entries"] if e["level"] == level]
    orders = tuple(e["order"] for e in entries)
    result = compute_table(case["table"], case["pentagon"], levels=(level,), orders=orders)
    for entry, value in zip(entries, result.values[:, 0], strict=True):
        expected = float(entry.get("corrected", entry["printed"]))
        error = abs(value - expected) / case["abs_integral"]
        assert error <= TOLERANCE, (entry, value)
        if "corrected" in entry:  # the misprint itself is far off
            assert abs(value - float(entry["printed"])) / case["abs_integral"] > 1e-12


def test_the_data_covers_every_table_and_pentagon():
    assert {(c["table"], c["pentagon"]) for c in DATA["cases"]} == {
        (t, p) for t in TABLES for p in PENTAGONS
    }
    assert sum(len(c["entries"]) for c in DATA["cases"]) == 312
    assert {(c.table, c.pentagon) for c in CASES} == {(t, p) for t in TABLES for p in PENTAGONS}


def test_reference_values_and_abs_integrals_match_the_data():
    for case in DATA["cases"]:
        ours = paper_case(case["table"], case["pentagon"])
        assert ours.exact == Fraction(case["reference"]) or ours.exact_fraction
        assert ours.abs_integral == case["abs_integral"]


def test_exact_fractions_are_the_exact_integrals():
    for case in CASES:
        if case.exact_fraction:
            assert exact_integral(PENTAGONS[case.pentagon], case.integrand) == case.exact
            assert abs(float(case.exact) - float(Fraction(case.reference))) <= 1e-30 + 1e-30 * abs(
                float(case.exact)
            )


def test_converged_entries_meet_the_high_precision_reference():
    """High orders on fine meshes agree with the reference to round-off (Tables 1, 7, 9)."""
    for table, order in ((1, 10), (7, 20), (9, 20)):
        for pentagon in PENTAGONS:
            result = compute_table(table, pentagon, levels=(3,), orders=(order,))
            assert result.scaled_errors[0, 0] <= TOLERANCE


def test_orders_and_errata():
    assert table_orders(6) == tuple(range(1, 11))
    assert table_orders(11) == (5, 10, 15, 20, 25, 30, 35, 40, 45)
    assert any(e.table == 3 and e.order == 1 for e in ERRATA)
    with pytest.raises(BlockMeshError, match="no table 12"):
        table_orders(12)
    with pytest.raises(BlockMeshError, match="choose SP or USP"):
        paper_case(1, "XP")
    assert pentagon_mesh("sp", 1).n_cells == 6


def test_table_8_usp_erratum_at_order_45():
    """The erratum beyond the test data: printed 7.80061835888679, correct 7.800618358888683."""
    value = compute_table(8, "USP", levels=(1,), orders=(45,)).values[0, 0]
    assert abs(value - 7.800618358888683) <= TOLERANCE * 7.8
    assert abs(value - 7.80061835888679) > 1e-12


def test_format_table_has_the_paper_layout():
    result = compute_table(3, "SP", levels=(1, 2), orders=(1, 2))
    text = format_table(result)
    lines = text.splitlines()
    assert lines[0].startswith("Table 3, [I] P = SP, symmetrical pentagon <1(-1,-1), 2(1,-1)")
    assert lines[3].split() == ["OGLR", "NPMR=6", "NPMR=6^2"]
    assert lines[4].split()[0] == "1" and float(lines[4].split()[1]) == result.values[0, 0]
    assert "paper erratum: OGLR 1, NPMR=6^1: printed +3.247407437070757e-008" in text
    assert "round-off floor" in text


def test_csv_and_plot(tmp_path):
    results = [compute_table(9, p, levels=(1, 2), orders=(5, 10)) for p in PENTAGONS]
    path = tmp_path / "t.csv"
    with path.open("w", encoding="utf-8", newline="") as handle:
        assert write_csv(results, handle) == 8
    rows = list(csv.DictReader(path.open(encoding="utf-8")))
    assert len(rows) == 8 and rows[0]["table"] == "9" and rows[0]["npmr"] == "6"
    assert float(rows[0]["value"]) == results[0].values[0, 0]
    png = tmp_path / "t.png"
    plot_convergence(results, str(png))
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _run(argv: list[str], capsys) -> tuple[int, str]:
    parser = argparse.ArgumentParser(prog="blockmesh")
    tables_command.register(parser.add_subparsers(dest="command"))
    args = parser.parse_args(argv)
    code = args.run(args)
    return code, capsys.readouterr().out


def test_cli_tables(tmp_path, capsys):
    csv_path, png = tmp_path / "all.csv", tmp_path / "all.png"
    code, out = _run(
        [
            "tables",
            "--table",
            "1,7",
            "--levels",
            "1-2",
            "--orders",
            "5,10",
            "--csv",
            str(csv_path),
            "--plot",
            str(png),
        ],
        capsys,
    )
    assert code == 0
    assert out.count("Table 1, ") == 2 and out.count("Table 7, ") == 2
    assert f"wrote 16 rows to {csv_path}" in out and png.exists()
    code, out = _run(
        ["tables", "--table", "2", "--pentagon", "USP", "--levels", "1", "--rule", "fan"], capsys
    )
    assert code == 0 and "rule       fan" in out and out.count("\n  10  ") == 2


def test_cli_tables_bad_lists(capsys):
    parser = argparse.ArgumentParser(prog="blockmesh")
    tables_command.register(parser.add_subparsers(dest="command"))
    with pytest.raises(SystemExit):
        parser.parse_args(["tables", "--levels", "one"])
    assert "is not a list of whole numbers" in capsys.readouterr().err


def test_values_are_read_only():
    result = compute_table(1, "SP", levels=(1,), orders=(1,))
    with pytest.raises(ValueError):
        result.values[0, 0] = 0.0
    assert np.isfinite(result.errors).all()
