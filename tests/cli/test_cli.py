"""The command line: every subcommand through main(argv), JSON output, errors without tracebacks."""

from __future__ import annotations

import json

import pytest
from helpers import CATALOGUE, run_cli

from blockmesh.cli import main


def run(capsys, *argv: str) -> tuple[int, str, str]:
    return run_cli(capsys, *argv)


def test_catalogue_json_lists_every_domain(capsys):
    code, out, _ = run(capsys, "catalogue", "--json")
    assert code == 0
    rows = json.loads(out)["domains"]
    names = {row["name"] for row in rows}
    assert {"sp", "usp", "square-cut", "ring", "l-shape"} <= names
    for row in rows:
        assert row["blocks"] >= 1 and row["area"] > 0 and row["patches"] and row["description"]


def test_catalogue_table(capsys):
    code, out, _ = run(capsys, "catalogue")
    assert code == 0 and "square-cut" in out and "description" in out


def test_check_certificate(capsys):
    code, out, _ = run(capsys, "check", "ring", "--json")
    report = json.loads(out)
    assert code == 0 and report["valid"] is True
    assert report["blocks"] == 6 and report["shared_edges"] == 6
    assert report["patches"] == {"inner": 6, "outer": 12}
    assert report["euler_characteristic"] == 0 and report["holes"] == 1
    assert all(b["counter_clockwise"] and b["strictly_convex"] for b in report["block_details"])
    code, out, _ = run(capsys, "check", "square-cut")
    assert code == 0 and "Euler characteristic 1" in out


def test_check_reports_located_errors(capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("polygon = [[0, 0], [2, 0], [0, 2], [2, 2]]\n")
    code, out, err = run(capsys, "check", str(bad))
    assert code == 1 and out == ""
    assert "edges 1 (2, 0)->(0, 2) and 3 (2, 2)->(0, 0) cross at (1, 1)" in err
    assert "Traceback" not in err
    code, out, _ = run(capsys, "check", str(bad), "--json")
    report = json.loads(out)
    assert code == 1 and report["valid"] is False and report["error"]["type"] == "DomainError"
    assert "cross at (1, 1)" in report["problems"][0]


def test_check_polygon_option_and_warnings(capsys):
    code, out, _ = run(capsys, "check", "--polygon", "0,0 0,1 1,1 1,0", "--json")
    report = json.loads(out)
    assert code == 0 and report["blocks"] == 8
    assert any("clockwise" in w for w in report["warnings"])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["check", "nosuchdomain"],
            "'nosuchdomain' is neither a catalogue domain nor a .toml file",
        ),
        (["check", "--polygon", "0,0 1,x 0,1"], "token 2 '1,x' is not a pair"),
        (["check"], "no domain"),
        (["mesh", "sp", "--level", "-1"], "--level must be 0 or more"),
        (["mesh", "sp", "--level", "20"], "largest level that fits"),
        (["mesh", "sp", "square", "--level", "1", "-o", "out.vtu"], "must contain {name}"),
    ],
)
def test_errors_are_one_readable_line(capsys, argv, message):
    code = main(argv)
    err = capsys.readouterr().err
    assert code != 0
    assert message in err
    assert "Traceback" not in err


def test_show_draws_a_picture(capsys, tmp_path):
    picture = tmp_path / "ring.png"
    code, _, _ = run(capsys, "show", "ring", "-o", str(picture))
    assert code == 0 and picture.stat().st_size > 10_000
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_input_never_leaves_a_file(capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        "vertices = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 2]]\nblocks = [[0, 1, 2, 3]]\n"
    )
    picture = tmp_path / "bad.png"
    code, _, err = run(capsys, "show", str(bad), "-o", str(picture))
    assert code == 2 and "block 0 is [0, 1, 2, 3]" in err
    assert not picture.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_mesh_json_report(capsys):
    code, out, _ = run(capsys, "mesh", "sp", "--level", "2", "--json")
    report = json.loads(out)
    assert code == 0
    assert (report["cells"], report["nodes"], report["edges"]) == (36, 65, 100)
    assert report["boundary_edges"] == 20 and report["area"] == pytest.approx(5.0)
    for key in ("min_angle", "max_angle", "max_aspect_ratio", "area_ratio", "not_strictly_convex"):
        assert key in report["quality"]
    assert report["bandwidth"]["nested"] > 0


def test_mesh_rcm_reports_bandwidth_before_and_after(capsys):
    code, out, _ = run(capsys, "mesh", "square-cut", "--level", "3", "--numbering", "rcm", "--json")
    bandwidth = json.loads(out)["bandwidth"]
    assert code == 0 and bandwidth["rcm"] < bandwidth["nested"]


def test_mesh_plots(capsys, tmp_path):
    plot, quality = tmp_path / "m.png", tmp_path / "q.png"
    code, out, _ = run(
        capsys,
        "mesh",
        "hexagon",
        "--level",
        "1",
        "--plot",
        str(plot),
        "--quality-plot",
        str(quality),
    )
    assert code == 0 and plot.stat().st_size > 10_000 and quality.stat().st_size > 10_000
    assert "hexagon: level 1, 12 cells" in out


def test_mesh_batch_keeps_going_after_a_failure(capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("polygon = [[0, 0], [1, 0]]\n")
    plots = str(tmp_path / "{name}.png")
    code, out, err = run(
        capsys, "mesh", "sp", str(bad), "usp", "--level", "2", "--plot", plots, "--json"
    )
    report = json.loads(out)
    assert code == 1 and report["failed"] == 1
    assert [r["domain"] for r in report["domains"]] == ["sp", str(bad), "usp"]
    assert [r["ok"] for r in report["domains"]] == [True, False, True]
    assert "at least 3 vertices" in err
    assert (tmp_path / "sp.png").exists() and (tmp_path / "usp.png").exists()


@pytest.mark.parametrize("name", CATALOGUE)
def test_every_catalogue_entry_passes_check(capsys, name):
    code, out, _ = run(capsys, "check", name, "--json")
    report = json.loads(out)
    assert code == 0 and report["valid"] is True and report["warnings"] == []
    assert report["connected_components"] == 1
    assert all(b["strictly_convex"] and b["counter_clockwise"] for b in report["block_details"])
    assert report["euler_characteristic"] == 1 - report["holes"]


@pytest.mark.parametrize(
    "argv",
    [
        ["mesh", "sp", "--level", "1", "-o", "{missing}/m.vtu"],
        ["mesh", "sp", "--level", "1", "--plot", "{missing}/m.png"],
        ["tables", "--table", "1", "--levels", "1", "--csv", "{missing}/t.csv"],
        ["tables", "--table", "1", "--levels", "1", "--plot", "{missing}/t.png"],
    ],
)
def test_missing_output_folder_fails_before_the_work(capsys, tmp_path, argv):
    missing = tmp_path / "no" / "such"
    argv = [a.replace("{missing}", str(missing)) for a in argv]
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert f"the directory {missing} does not exist" in err
    assert not (tmp_path / "no").exists()
