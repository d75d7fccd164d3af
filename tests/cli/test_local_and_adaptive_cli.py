"""``blockmesh mesh --refine-*`` and ``blockmesh solve --adapt`` from the command line."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers import run_cli

import blockmesh
from blockmesh.mesh.polygons import PolygonMesh

#: The L-shape's corner solution r^(2/3) sin(2θ/3) about its re-entrant corner (1, 1).
U = "((x-1)^2+(y-1)^2)^(1/3)*cos(2/3*atan2(x-y, 2-x-y))"


def test_the_exact_line_of_the_issue(capsys):
    code, out, _ = run_cli(
        capsys,
        "solve",
        "l-shape",
        "--adapt",
        "--max-unknowns",
        "20000",
        "--source",
        "0",
        "--dirichlet",
        f"*={U}",
        "--exact",
        U,
        "--json",
    )
    assert code == 0
    report = json.loads(out)
    history = report["history"]
    assert len(history) >= 8
    for step in history:
        assert {"unknowns", "estimator", "h1_error", "l2_error", "effectivity"} <= set(step)
        assert 1.0 <= step["effectivity"] <= 4.0
    unknowns = [s["unknowns"] for s in history]
    assert unknowns == sorted(unknowns) and unknowns[-1] <= 20000
    assert report["stopped"] == "max_unknowns"
    assert report["rates"]["h1_error"] >= 0.45
    assert history[-1]["h1_error"] < history[0]["h1_error"] / 10
    assert report["max_vertices"] > 5 and report["hanging_nodes"] > 0


def test_adaptive_solve_writes_mesh_solution_and_convergence(capsys, tmp_path: Path):
    code, out, _ = run_cli(
        capsys,
        "solve",
        "l-shape",
        "--adapt",
        "--max-unknowns",
        "1500",
        "--theta",
        "0.4",
        "--dirichlet",
        f"*={U}",
        "--exact",
        U,
        "-o",
        str(tmp_path / "u.vtu"),
        "--mesh-output",
        str(tmp_path / "mesh.npz"),
        "--convergence",
        str(tmp_path / "conv.png"),
    )
    assert code == 0, out
    steps = [line for line in out.splitlines() if line.strip().startswith("step")]
    assert len(steps) >= 5 and all("effectivity" in line for line in steps)
    assert "stopped: the next step would exceed --max-unknowns 1,500" in out
    mesh = blockmesh.read(tmp_path / "mesh.npz")
    assert isinstance(mesh, PolygonMesh) and mesh.hanging_nodes().size
    assert (tmp_path / "conv.png").stat().st_size > 0
    assert (tmp_path / "u.vtu").stat().st_size > 0


def test_adaptive_elasticity_with_a_tolerance(capsys):
    code, out, _ = run_cli(
        capsys,
        "solve",
        "quarter-plate-hole",
        "--equation",
        "elasticity",
        "--adapt",
        "--tol",
        "0.2",
        "--dirichlet",
        "left=0, free",
        "--dirichlet",
        "down=free, 0",
        "--neumann",
        "right=1, 0",
        "--json",
    )
    assert code == 0
    report = json.loads(out)
    assert report["stopped"] == "tol" and report["estimator"] <= 0.2
    assert report["history"][0]["estimator"] > 0.2


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--adapt"], "needs a stopping rule"),
        (["--tol", "0.1"], "--tol belongs to adaptive solving: add --adapt"),
        (["--adapt", "--max-unknowns", "100", "--theta", "1.5"], "--theta must be in (0, 1]"),
        (["--adapt", "--max-unknowns", "100", "--smooth", "1"], "--adapt refines by the paper"),
        (["--adapt", "--max-unknowns", "100", "--dirichlet", "nope=0"], "no patch 'nope'"),
    ],
)
def test_adaptive_options_are_checked(capsys, argv, message):
    code, _, err = run_cli(capsys, "solve", "l-shape", "--dirichlet", "*=0", *argv)
    assert code != 0
    assert message in err


def test_mesh_refines_where_asked_and_reports_it(capsys, tmp_path: Path):
    code, out, _ = run_cli(
        capsys,
        "mesh",
        "l-shape",
        "-l",
        "1",
        "--refine-where",
        "0.3 - sqrt((x-1)^2+(y-1)^2)",
        "--refine-near",
        "inlet:0.05",
        "--refine-rounds",
        "2",
        "-o",
        str(tmp_path / "m.vtu"),
        "--json",
    )
    assert code == 0
    report = json.loads(out)
    local = report["local_refinement"]
    assert local["rounds"] == 2 and len(local["marked"]) == 2 and local["hanging_nodes"] > 0
    mesh = blockmesh.read(tmp_path / "m.vtu")
    assert isinstance(mesh, PolygonMesh)
    assert mesh.n_cells == report["cells"] and report["quality"]["not_strictly_convex"] == 0
    near_corner = np.hypot(*(mesh.vertex_means() - 1).T) < 0.2
    assert mesh.cell_level[near_corner].min() == 3  # level 1, two local rounds


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--refine-where", "-1"], "marks none of the 144 cells"),
        (["--refine-region", "nope"], "no region 'nope'; the regions are corner, arm-right"),
        (["--refine-near", "nope:0.1"], "no patch 'nope'"),
        (["--refine-near", "inlet"], "write PATCH:DISTANCE"),
        (["--refine-rounds", "2"], "--refine-rounds counts rounds of local refinement"),
        (["--refine-region", "corner", "--numbering", "rcm"], "keeps the nested numbering"),
    ],
)
def test_bad_markings_are_located(capsys, argv, message):
    code, _, err = run_cli(capsys, "mesh", "l-shape", "-l", "1", *argv)
    assert code != 0
    assert message in err


def test_check_and_show_take_a_polygon_mesh(capsys, tmp_path: Path):
    mesh = blockmesh.refine(blockmesh.load_domain("l-shape").mesh(1), cells=[0, 5, 9])
    path = blockmesh.write(mesh, tmp_path / "m.npz")
    code, out, _ = run_cli(capsys, "check", str(path), "--json")
    assert code == 0
    report = json.loads(out)
    assert report["valid"] and report["kind"] == "polygons"
    assert report["cells"] == mesh.n_cells and report["most_hanging_nodes_per_side"] == 1
    assert report["euler_characteristic"] == 1
    code, out, _ = run_cli(capsys, "show", str(path), "-o", str(tmp_path / "m.png"))
    assert code == 0 and (tmp_path / "m.png").stat().st_size > 0
    code, out, _ = run_cli(capsys, "integrate", str(path), "-f", "x*y", "--json")
    assert code == 0 and abs(json.loads(out)["value"] - 1.75) < 1e-12


def test_dask_pieces_refuse_a_polygon_mesh_with_the_reason(capsys, tmp_path: Path):
    pytest.importorskip("dask")
    from blockmesh.distributed.partition import partition
    from blockmesh.errors import ArgumentTypeError

    mesh = blockmesh.refine(blockmesh.load_domain("sp").mesh(1), cells=[0])
    with pytest.raises(ArgumentTypeError, match="refine pentagon blocks uniformly"):
        partition(mesh, 1, 2)
    path = blockmesh.write(mesh, tmp_path / "m.npz")
    code, _, err = run_cli(
        capsys, "mesh", str(path), "-l", "1", "--partitions", "2", "-o", str(tmp_path / "o.pvtu")
    )
    assert code != 0 and "in one process" in err
