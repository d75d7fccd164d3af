"""``blockmesh mesh --size``: sizes by number or expression, with --level, from a [size] table."""

from __future__ import annotations

import json

from helpers import run_cli

from blockmesh.decompose.sized import SIZE_TOLERANCE


def test_size_number_json(capsys):
    code, out, _ = run_cli(capsys, "mesh", "square", "--size", "0.1", "--json")
    assert code == 0
    report = json.loads(out)
    assert report["level"] == 0
    assert report["size_asked"] == 0.1
    sizes = report["sizes"]
    assert sizes["worst_ratio"] <= SIZE_TOLERANCE
    assert 0.5 <= sizes["count_ratio"] <= 2.0
    assert sizes["neighbour_ratio"] >= 1.0


def test_size_expression_and_level(capsys):
    code, out, _ = run_cli(
        capsys, "mesh", "l-outline", "--size", "0.05 + 0.1*sqrt((x-1)^2 + (y-1)^2)", "--json"
    )
    assert code == 0
    blocks = json.loads(out)["cells"]
    code, out, _ = run_cli(
        capsys, "mesh", "l-outline", "--level", "1", "--json",
        "--size", "0.05 + 0.1*sqrt((x-1)^2 + (y-1)^2)",
    )  # fmt: skip
    report = json.loads(out)
    assert code == 0 and report["level"] == 1 and report["cells"] == 6 * blocks
    # Refined further, every cell is smaller still than the size asked.
    assert report["sizes"]["worst_ratio"] <= SIZE_TOLERANCE


def test_size_report_lines_and_plot(capsys, tmp_path):
    picture = tmp_path / "sizes.png"
    code, out, _ = run_cli(
        capsys, "mesh", "plate-hole", "--size", "0.3", "--size-plot", str(picture)
    )
    assert code == 0
    assert "size got / size asked: worst" in out and "largest neighbour size ratio" in out
    assert picture.stat().st_size > 0
    # Without a size, the neighbour ratio is reported still.
    code, out, _ = run_cli(capsys, "mesh", "l-shape", "--level", "2")
    assert "largest neighbour size ratio" in out and "size got" not in out


def test_size_table_in_a_domain_file(capsys, tmp_path):
    path = tmp_path / "hole.toml"
    path.write_text(
        "polygon = [[0, 0], [4, 0], [4, 2], [0, 2]]\n"
        "holes = [[[1.5, 0.5], [2.5, 0.5], [2.5, 1.5], [1.5, 1.5]]]\n"
        '[patches]\nhole = ["hole 0"]\n'
        "[size]\ndefault = 0.3\n"
        '[[size.near]]\npatch = "hole"\nsize = 0.05\ndistance = [0.1, 1.0]\n'
    )
    code, out, _ = run_cli(capsys, "mesh", str(path), "--json")
    report = json.loads(out)
    assert code == 0 and report["level"] == 0
    assert report["sizes"]["worst_ratio"] <= SIZE_TOLERANCE


def test_bad_sizes_are_one_located_line(capsys, tmp_path):
    code, _, err = run_cli(capsys, "mesh", "square", "--size", "0")
    assert code != 0 and "--size must be a finite number > 0, got 0" in err
    code, _, err = run_cli(capsys, "mesh", "square", "--size", "1/x")
    assert code != 0 and "--size '1/x' gives inf at (0," in err
    code, _, err = run_cli(capsys, "mesh", "square", "--size", "0.1 + (x")
    assert code != 0 and "column" in err
    code, _, err = run_cli(capsys, "mesh", "square", "--gradation", "1.2")
    assert code != 0 and "--gradation goes with --size" in err
    code, _, err = run_cli(capsys, "mesh", "square", "--size", "0.1", "--gradation", "0.9")
    assert code != 0 and "gradation must be > 1" in err
    code, _, err = run_cli(capsys, "mesh", "square", "--size", "1e-5", "--max-memory", "100M")
    assert code != 0 and "the largest size that fits is about" in err
    code, _, err = run_cli(capsys, "mesh", "square", "--size", "0.1*abs(x-0.30017)")
    assert code != 0 and "'0.1*abs(x-0.30017)' gets ever smaller near (0.30017, " in err
    mesh = tmp_path / "square.npz"
    assert run_cli(capsys, "mesh", "square", "--level", "1", "-o", str(mesh))[0] == 0
    code, _, err = run_cli(capsys, "mesh", str(mesh), "--size", "0.1")
    assert code != 0 and "is a mesh" in err


def test_solve_on_sized_cells(capsys):
    patches = ["--dirichlet", "bottom=0", "--dirichlet", "right=0", "--dirichlet", "top=0",
               "--dirichlet", "left=0"]  # fmt: skip
    code, out, err = run_cli(
        capsys, "solve", "square", "--size", "0.1", "--source", "2*pi^2*sin(pi*x)*sin(pi*y)",
        *patches, "--exact", "sin(pi*x)*sin(pi*y)",
    )  # fmt: skip
    assert code == 0, err
    assert "on level 0" in out and "errors against" in out


def test_sized_then_refined_locally_reports_its_sizes(capsys, tmp_path):
    # --size with --refine-near makes a polygon mesh (hanging nodes): its size report and
    # picture cover every cell, the refined ones smaller than the size asked.
    picture = tmp_path / "sizes.png"
    code, out, _ = run_cli(
        capsys, "mesh", "plate-hole", "--size", "0.4", "--refine-near", "hole:0.3",
        "--size-plot", str(picture), "--json",
    )  # fmt: skip
    assert code == 0
    report = json.loads(out)
    sizes = report["sizes"]
    assert report["local_refinement"]["hanging_nodes"] > 0
    assert sizes["cells"] == report["cells"]
    assert sizes["worst_ratio"] <= SIZE_TOLERANCE
    assert sizes["mean_ratio"] < 1.0
    assert sizes["count_ratio"] > 1.0  # the refined cells are smaller than asked
    assert picture.stat().st_size > 0
