"""``blockmesh solve``: the README commands, JSON, outputs read back, and bad input."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np
import pytest
from helpers import run_cli

SOURCE = "2*pi^2*sin(pi*x)*sin(pi*y)"
EXACT = "sin(pi*x)*sin(pi*y)"
WALLS = ["--dirichlet", "left=0", "--dirichlet", "right=0", "--dirichlet", "top=0",
         "--dirichlet", "bottom=0"]  # fmt: skip


def test_readme_poisson_example_writes_vtu_point_data(capsys, tmp_path):
    out = tmp_path / "solution.vtu"
    code, stdout, stderr = run_cli(
        capsys, "solve", "square", "--level", "3", "--source", SOURCE, *WALLS,
        "--exact", EXACT, "-o", str(out), "--json",
    )  # fmt: skip
    assert code == 0, stderr
    report = json.loads(stdout)
    assert report["dof"] == 2553 and report["nonzeros"] > report["dof"]
    assert report["l2_error"] < 1e-3 and report["h1_error"] < 0.1
    assert report["l2_relative"] == pytest.approx(report["l2_error"] / 0.5, rel=1e-9)
    assert set(report) >= {"seconds", "cells", "nodes", "solver", "residual", "output"}
    back = meshio.read(out)
    assert back.points.shape[0] == report["nodes"]
    # the solution, the error, and (issue 23) the region of every cell and patch of every node
    assert set(back.point_data) == {"u", "error", "patch"}
    assert set(back.cell_data) == {"gradient", "region"}
    assert np.abs(back.point_data["u"]).max() == pytest.approx(report["u_max"])
    assert np.abs(back.point_data["error"]).max() < 2e-3


def test_relative_errors_against_a_zero_solution_are_valid_json(capsys):
    # u = 0 has no norm to divide by: the relative errors are infinite, written "inf" (JSON has
    # no infinity), and the report is still one valid object (it was an internal error)
    code, stdout, stderr = run_cli(
        capsys, "solve", "square", "--level", "1", "--source", "1", "--dirichlet", "*=0",
        "--exact-solution", "0", "--json",
    )  # fmt: skip
    assert code == 0, stderr
    report = json.loads(stdout)
    assert report["l2_error"] > 0
    assert report["l2_relative"] == report["h1_relative"] == "inf"


def test_text_report(capsys):
    code, stdout, _ = run_cli(capsys, "solve", "square", "--level", "2", "--source", "1",
                              "--dirichlet", "left=0", "--exact", "x*(2 - x)/2")  # fmt: skip
    assert code == 0
    assert "square: poisson on level 2, 288 cells, 453 nodes" in stdout
    assert "unknowns 440" in stdout and "errors against x*(2 - x)/2: L2" in stdout


def test_elasticity_writes_displacements_and_stresses(capsys, tmp_path):
    out, picture = tmp_path / "bracket.xdmf", tmp_path / "bracket.png"
    code, stdout, stderr = run_cli(
        capsys, "solve", "l-shape", "--level", "2", "--equation", "elasticity",
        "--young", "200", "--poisson-ratio", "0.3", "--dirichlet", "inlet=0, 0",
        "--neumann", "outlet=0, -1", "-o", str(out), "--plot", str(picture), "--json",
    )  # fmt: skip
    assert code == 0, stderr
    report = json.loads(stdout)
    assert report["dof"] == 2 * report["nodes"] - 2 * 9  # the inlet's 9 nodes are clamped
    assert picture.stat().st_size > 0
    tree = ET.parse(out)
    names = {a.get("Name"): a.get("Center") for a in tree.iter("Attribute")}
    assert names == {
        "displacement": "Node",
        "stress": "Cell",
        "von_mises": "Cell",
        "region": "Cell",  # issue 23: the region of every cell, the patch of every node
        "patch": "Node",
    }
    data = {item.text.split(":")[0] for item in tree.iter("DataItem")}
    assert len(data) == 1 and sorted(p.name for p in tmp_path.glob("*.h5")) == sorted(data)
    with h5py.File(tmp_path / data.pop()) as f:
        displacement = f["point/displacement"][()]
        assert displacement.shape == (report["nodes"], 3)
        assert np.hypot(*displacement[:, :2].T).max() == pytest.approx(report["max_displacement"])
        assert f["cell/von_mises"][()].max() == pytest.approx(report["max_von_mises"])


def test_pure_neumann_with_constraint(capsys):
    code, stdout, stderr = run_cli(
        capsys, "solve", "square", "--level", "2", "--source", "2*pi^2*cos(pi*x)*cos(pi*y)",
        "--constraint", "mean", "--exact", "cos(pi*x)*cos(pi*y)", "--json",
    )  # fmt: skip
    assert code == 0, stderr
    assert json.loads(stdout)["l2_relative"] < 0.02


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--dirichlet", "inlet=0"], "no patch 'inlet'; the patches are bottom, right, top, left"),
        (["--dirichlet", "left=0", "--neumann", "left=1"], "patch 'left' is given twice"),
        (["--dirichlet", "left=0", "--dirichlet", "left=1"], "patch 'left' is given twice"),
        (["--neumann", "left=1"], "no Dirichlet data"),
        (["--neumann", "left=1"], "or --constraint mean (zero mean)"),  # the flag, not Python
        (["--dirichlet", "left"], "--dirichlet 'left': write PATCH=EXPR"),
        (["--dirichlet", "left=0", "-o", "{tmp}/u.msh"], "a solution is written to .vtu"),
        (["--neumann", "left=1", "-o", "{tmp}/u.vtu"], "no Dirichlet data"),
        (["--dirichlet", "left=0", "--constraint", "rigid"], "--constraint rigid is for the other"),
        (["--dirichlet", "left=__import__('os')"], "unknown function '__import__'"),
    ],
)
def test_bad_input_is_one_clear_line(capsys, tmp_path, arguments, message):
    arguments = [a.replace("{tmp}", str(tmp_path)) for a in arguments]
    code, stdout, stderr = run_cli(
        capsys, "solve", "square", "--level", "1", "--source", "1", *arguments
    )
    assert code == 2 and stdout == ""
    assert message in stderr
    assert "Traceback" not in stderr
    assert not list(tmp_path.iterdir())


def test_quality_rule_optimized_in_mesh_and_solve(capsys):
    code, stdout, _ = run_cli(capsys, "mesh", "square", "--level", "3", "--json")
    paper = json.loads(stdout)
    code, stdout, _ = run_cli(
        capsys, "mesh", "square", "--level", "3", "--quality-rule", "optimized", "--json"
    )
    better = json.loads(stdout)
    assert code == 0 and better["quality_rule"] == "optimized" and paper["quality_rule"] == "paper"
    assert better["cells"] == paper["cells"] and better["nodes"] == paper["nodes"]
    assert better["quality"]["min_angle"] > paper["quality"]["min_angle"]
    errors = {}
    for rule in ("paper", "optimized"):
        code, stdout, _ = run_cli(
            capsys, "solve", "square", "--level", "3", "--source", SOURCE, *WALLS,
            "--exact", EXACT, "--quality-rule", rule, "--json",
        )  # fmt: skip
        errors[rule] = json.loads(stdout)
    assert errors["optimized"]["dof"] == errors["paper"]["dof"]
    assert errors["optimized"]["l2_error"] < errors["paper"]["l2_error"]
    assert errors["optimized"]["h1_error"] < errors["paper"]["h1_error"]


def test_elasticity_on_a_curved_catalogue_domain(capsys, tmp_path):
    # the quarter Kirsch plate under uniform tension: the stress concentration at the hole
    out = tmp_path / "plate.vtu"
    code, stdout, stderr = run_cli(
        capsys, "solve", "quarter-plate-hole", "--level", "2", "--equation", "elasticity",
        "--dirichlet", "left=0, free", "--dirichlet", "down=free, 0", "--neumann", "right=1, 0",
        "-o", str(out), "--json",
    )  # fmt: skip
    assert code == 0, stderr
    report = json.loads(stdout)
    back = meshio.read(out)
    stress = np.concatenate(back.cell_data["stress"])
    assert back.point_data["displacement"].shape == (report["nodes"], 3)
    assert 2.2 < stress[:, 0].max() < 3.5  # σ_xx peaks at the top of the hole (3.14 on level 3)
    assert np.abs(back.point_data["displacement"][back.points[:, 0] < 1e-12, 0]).max() < 1e-14


# ----------------------------------------------------------------- mesh files (issue 22)
def test_solve_takes_a_mesh_file_at_its_own_level(capsys, tmp_path):
    """`solve --help` said DOMAIN may be a mesh file; the command refused one."""
    import blockmesh

    path = blockmesh.write(blockmesh.load_domain("square").mesh(2), tmp_path / "sq.npz")
    direct = json.loads(run_cli(capsys, "solve", "square", "--level", "3", "--source", SOURCE,
                                *WALLS, "--exact", EXACT, "--json")[1])  # fmt: skip
    for extra, level in (([], 2), (["--level", "1"], 3)):
        code, stdout, stderr = run_cli(
            capsys, "solve", str(path), "--source", SOURCE, *WALLS, "--exact", EXACT, "--json",
            *extra,
        )  # fmt: skip
        assert code == 0, stderr
        report = json.loads(stdout)
        assert report["level"] == level and report["cells"] == 8 * 6**level
    assert report["l2_error"] == pytest.approx(direct["l2_error"], rel=1e-12)


def test_solve_help_and_errors_name_every_domain_kind(capsys):
    with pytest.raises(SystemExit):
        run_cli(capsys, "solve", "--help")
    text = " ".join(capsys.readouterr().out.split())
    assert ".wkt" in text and ".geojson" in text and "mesh file" in text
    assert "refined further by --level" in text


# -------------------------------------------------------------- memory (issue 22, item 4)
def test_solve_refuses_early_what_the_factorisation_cannot_hold(capsys):
    """Out of memory in the factorisation was reported as "the system matrix is singular"."""
    import blockmesh
    from blockmesh.refinement.sizes import solve_command_predictor

    predict = solve_command_predictor(blockmesh.load_domain("square"))
    between = (predict(4).peak_bytes + predict(5).peak_bytes) // 2  # ~100 MB from either
    code, stdout, stderr = run_cli(capsys, "solve", "square", "--level", "6", "--source", "1",
                                   *WALLS, "--max-memory", str(between))  # fmt: skip
    assert code == 2 and stdout == ""
    assert "largest level that fits is 4" in stderr and "factorisation" in stderr
    assert "--max-memory" in stderr and "singular" not in stderr


def test_solve_reports_the_predicted_peak(capsys):
    code, stdout, stderr = run_cli(capsys, "solve", "square", "--level", "2", "--source", "1",
                                   *WALLS, "--json")  # fmt: skip
    report = json.loads(stdout)
    assert code == 0 and report["predicted_peak_bytes"] > 0


@pytest.mark.parametrize(
    "failure",
    [MemoryError(), RuntimeError("Malloc fails for dgstrf"), RuntimeError("not enough memory")],
)
def test_running_out_of_memory_in_the_factorisation_says_so(capsys, monkeypatch, failure):
    from scipy.sparse import linalg

    def no_memory(*_args, **_kwargs):
        raise failure

    monkeypatch.setattr(linalg, "splu", no_memory)
    code, stdout, stderr = run_cli(capsys, "solve", "square", "--level", "1", "--source", "1",
                                   *WALLS)  # fmt: skip
    assert code == 2 and "ran out of memory" in stderr and "singular" not in stderr


def test_a_singular_factorisation_is_still_called_singular(monkeypatch):
    from scipy.sparse import linalg

    import blockmesh
    from blockmesh.errors import SolverError
    from blockmesh.vem import solve_poisson

    def singular(*_args, **_kwargs):
        raise RuntimeError("Factor is exactly singular")

    monkeypatch.setattr(linalg, "splu", singular)
    with pytest.raises(SolverError, match="singular"):
        solve_poisson(blockmesh.load_domain("square").mesh(1), 1, dirichlet={"left": 0})
