"""``blockmesh tables`` through the command line's main()."""

from __future__ import annotations

import pytest
from helpers import run_cli


def test_cli_tables(tmp_path, capsys):
    csv_path, png = tmp_path / "all.csv", tmp_path / "all.png"
    code, out, _ = run_cli(
        capsys,
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
    )
    assert code == 0
    assert out.count("Table 1, ") == 2 and out.count("Table 7, ") == 2
    assert f"wrote 16 rows to {csv_path}" in out and png.read_bytes()[:4] == b"\x89PNG"
    code, out, _ = run_cli(
        capsys, "tables", "--table", "2", "--pentagon", "USP", "--levels", "1", "--rule", "fan"
    )
    assert code == 0 and "rule       fan" in out and out.count("\n  10  ") == 2


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (("--levels", "one"), "is not a list of whole numbers"),
        (("--table", "1-100000000000"), "names more than 1000 numbers"),
    ],
)
def test_cli_tables_bad_lists(capsys, argv, message):
    with pytest.raises(SystemExit):
        run_cli(capsys, "tables", *argv)
    assert message in capsys.readouterr().err


def test_cli_tables_bad_numbers(capsys):
    code, _, err = run_cli(capsys, "tables", "--table", "12")
    assert code == 2 and "no table 12" in err
    code, _, err = run_cli(capsys, "tables", "--table", "1", "--orders", "0")
    assert code == 2 and "order must be" in err
