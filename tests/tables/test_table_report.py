"""The regenerated tables as text, CSV and a picture."""

from __future__ import annotations

import csv

from blockmesh.tables import PENTAGONS, compute_table, format_table, write_csv
from blockmesh.tables.plot import plot_convergence


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
    assert plot_convergence(results, str(png)) == png
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
