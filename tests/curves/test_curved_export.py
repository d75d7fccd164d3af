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
