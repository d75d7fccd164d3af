"""Curved meshes leave through every writer with their nodes on the curves; checkMesh passes."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from helpers import CURVED_CATALOGUE
from helpers_io import find_checkmesh

import blockmesh

CHECKMESH = find_checkmesh()


@pytest.mark.filterwarnings("ignore:.*curved edges, which this format does not keep")
@pytest.mark.parametrize("suffix", [".vtu", ".vtk", ".npz", ".msh", ".mat", ".xdmf", "openfoam"])
def test_nodes_on_curves_survive_a_round_trip(tmp_path, suffix):
    mesh = blockmesh.load_domain("annulus").mesh(2)
    options: dict[str, str] = {"split": "tri3"} if suffix == ".msh" else {}  # no new nodes
    if suffix == "openfoam":  # a case folder
        options, suffix = {"format": "openfoam"}, ""
    again = blockmesh.read(blockmesh.write(mesh, tmp_path / f"annulus{suffix}", **options))
    radius = np.hypot(*again.points.T)
    on_circles = np.isclose(radius, 0.5, rtol=0, atol=1e-15) | np.isclose(
        radius, 1.0, rtol=0, atol=1e-15
    )
    boundary = np.unique(mesh.boundary_edges)
    assert np.array_equal(np.flatnonzero(on_circles), boundary)
    assert np.array_equal(again.points[boundary], mesh.points[boundary])


@pytest.mark.skipif(CHECKMESH is None, reason="OpenFOAM checkMesh is not installed")
@pytest.mark.parametrize("name", CURVED_CATALOGUE)
def test_checkmesh_passes_on_the_curved_catalogue(tmp_path: Path, name: str) -> None:
    assert CHECKMESH is not None
    exe, env = CHECKMESH
    mesh = blockmesh.load_domain(name).mesh(3)
    blockmesh.write(mesh, tmp_path / "case", format="openfoam")
    run = subprocess.run(
        [exe], cwd=tmp_path / "case", env=env, capture_output=True, text=True, timeout=300
    )
    out = run.stdout + run.stderr
    assert run.returncode == 0, out
    assert "Mesh OK." in out, out
    assert re.search(rf"^\s*cells:\s+{mesh.n_cells}$", out, re.M), out
    assert "***" not in out, out


#: The formats that keep a mesh's curves (and the others, which say they cannot).
KEEPS_CURVES = [".npz", ".xdmf", ".vtu"]
LOSES_CURVES = [".vtk", ".msh", ".mat"]


@pytest.mark.parametrize("suffix", KEEPS_CURVES)
@pytest.mark.parametrize("name", ["annulus", "plate-hole"])
def test_a_saved_curved_mesh_refines_onto_its_curves(tmp_path, suffix, name):
    """Refining a saved mesh dropped its curves silently (issue 22): the new nodes went onto
    the straight edges. Read back, the mesh has the same curves, and refining it gives the
    mesh the domain gives at that level."""
    domain = blockmesh.load_domain(name)
    mesh = domain.mesh(1)
    back = blockmesh.read(blockmesh.write(mesh, tmp_path / f"m{suffix}"))
    assert back.curves is not None and len(back.curves) == len(mesh.curves)
    for key in ("edges", "curve", "start", "stop"):
        assert np.array_equal(getattr(back.curves, key), getattr(mesh.curves, key)), key
    assert back.curves.curves == mesh.curves.curves
    refined, direct = blockmesh.refine(back, 2), domain.mesh(3)
    assert np.array_equal(refined.points, direct.points)
    assert np.array_equal(refined.cells, direct.cells)
    assert refined.curves is not None and refined.curves.distances(refined.points).max() == 0


@pytest.mark.parametrize("suffix", LOSES_CURVES)
def test_a_format_without_the_curves_warns_that_refining_it_is_straight(tmp_path, suffix):
    mesh = blockmesh.load_domain("annulus").mesh(1)
    path = blockmesh.write(mesh, tmp_path / f"m{suffix}")
    with pytest.warns(blockmesh.BlockMeshWarning, match=r"curved edges.*straight"):
        back = blockmesh.read(path)
    assert back.curves is None


def test_a_straight_mesh_reads_back_without_a_warning(tmp_path, recwarn):
    for suffix in (*KEEPS_CURVES, *LOSES_CURVES):
        path = blockmesh.write(blockmesh.load_domain("l-shape").mesh(1), tmp_path / f"m{suffix}")
        assert blockmesh.read(path).curves is None
    assert not [w for w in recwarn if issubclass(w.category, blockmesh.BlockMeshWarning)]


def test_the_command_line_prints_the_straight_refinement_warning(tmp_path, capsys):
    from helpers import run_cli

    path = blockmesh.write(blockmesh.load_domain("annulus").mesh(1), tmp_path / "m.msh")
    code, out, err = run_cli(capsys, "mesh", str(path), "--level", "1")
    assert code == 0, err
    assert "blockmesh: warning:" in err and "straight" in err and ".npz" in err


def test_a_curved_vtu_stays_readable_by_meshio_and_the_fast_reader(tmp_path):
    import meshio

    from blockmesh.io.vtu.stream import read_stream

    mesh = blockmesh.load_domain("annulus").mesh(2)
    path = blockmesh.write(mesh, tmp_path / "m.vtu")
    parts = read_stream(path)
    assert parts is not None and parts.fields["curve_edges"].size == 2 * len(mesh.curves)
    read = meshio.read(path)
    assert read.cells_dict["polygon"].shape == (mesh.n_cells, 5)
    assert np.array_equal(read.field_data["curve_start"], mesh.curves.start)
