"""Real readers see the regions and interfaces of a composite export (issue 23).

OpenFOAM's checkMesh lists the cellZones and faceZones; ParaView's own reader (pvpython) shows
the region and interface names and the interface lines of the .vtu; the gmsh API lists the
physical groups of the .msh; meshio reads the .vtu and the .msh.
"""

from __future__ import annotations

import re
import subprocess
from collections import Counter

import meshio
import numpy as np
import pytest
from helpers_io import find_checkmesh, run_pvpython

import blockmesh
import blockmesh.io as bio

CHECKMESH = find_checkmesh()


@pytest.fixture(scope="module")
def mesh() -> blockmesh.Mesh:
    return blockmesh.load_domain("layered-plate").mesh(1)


@pytest.mark.skipif(CHECKMESH is None, reason="OpenFOAM checkMesh is not installed")
def test_checkmesh_lists_cell_and_face_zones(tmp_path, mesh):
    assert CHECKMESH is not None
    exe, env = CHECKMESH
    bio.write(mesh, tmp_path / "case", format="openfoam")
    run = subprocess.run(
        [exe], cwd=tmp_path / "case", env=env, capture_output=True, text=True, timeout=300
    )
    out = run.stdout + run.stderr
    assert run.returncode == 0 and "Mesh OK." in out, out
    assert re.search(r"face zones:\s+2", out) and re.search(r"cell zones:\s+3", out), out
    for zone in ("bottom_core", "core_top"):  # 24 faces each, an open singly connected sheet
        assert re.search(rf"{zone}\s+24\s+\d+\s+ok \(non-closed singly connected\)", out), out
    for zone in ("bottom", "core", "top"):
        assert re.search(rf"^\s+{zone}\s+288\s", out, re.M), out


PARAVIEW = """
from collections import Counter
from paraview.simple import OpenDataFile
from paraview import servermanager
reader = OpenDataFile("{path}")
reader.UpdatePipeline()
grid = servermanager.Fetch(reader)
fields = grid.GetFieldData()
for i in range(fields.GetNumberOfArrays()):
    a = fields.GetArray(i)
    if a.GetName().startswith(("region:", "interface:")):
        print("NAME", a.GetName(), "=", int(a.GetTuple1(0)))
interface = grid.GetCellData().GetArray("interface")
lines = Counter(
    int(interface.GetTuple1(c)) for c in range(grid.GetNumberOfCells()) if grid.GetCellType(c) == 3
)
for k, n in sorted(lines.items()):
    print("LINES", k, "=", n)
"""


def test_paraview_shows_region_names_and_interface_lines(tmp_path, mesh):
    path = bio.write(mesh, tmp_path / "plate.vtu")
    run = run_pvpython(PARAVIEW.format(path=path), tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    lines = run.stdout.splitlines()
    names = {
        line[5:].rsplit(" = ")[0]: int(line.rsplit(" = ")[1]) for line in lines if "NAME" in line
    }
    assert names == {
        "region:bottom": 0, "region:core": 1, "region:top": 2,
        "interface:bottom|core": 0, "interface:core|top": 1,
    }  # fmt: skip
    counts = {int(line.split()[1]): int(line.split()[-1]) for line in lines if "LINES" in line}
    assert counts == {-1: mesh.boundary_edges.shape[0], 0: 24, 1: 24}


def test_gmsh_lists_the_physical_groups(tmp_path, mesh):
    gmsh = pytest.importorskip("gmsh")
    path = bio.write(mesh, tmp_path / "plate.msh")
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(str(path))
        groups = {
            (dim, gmsh.model.getPhysicalName(dim, tag)): tag
            for dim, tag in gmsh.model.getPhysicalGroups()
        }
        lines = {
            name: len(
                gmsh.model.mesh.getElements(1, gmsh.model.getEntitiesForPhysicalGroup(1, tag)[0])[
                    1
                ][0]
            )
            for (dim, name), tag in groups.items()
            if dim == 1
        }
    finally:
        gmsh.finalize()
    assert {name for dim, name in groups if dim == 2} == {"bottom", "core", "top"}
    assert {name for dim, name in groups if dim == 1} == {
        *mesh.patch_names,
        "bottom|core",
        "core|top",
    }
    assert lines["bottom|core"] == 24 and lines["core|top"] == 24  # tri5 keeps the edges


def test_meshio_reads_vtu_and_msh(tmp_path, mesh):
    vtu = meshio.read(bio.write(mesh, tmp_path / "plate.vtu"))
    interface = np.concatenate(vtu.cell_data["interface"])
    assert Counter(interface.tolist()) == {
        -1: mesh.n_cells + mesh.boundary_edges.shape[0],
        0: 24,
        1: 24,
    }
    msh = meshio.read(bio.write(mesh, tmp_path / "plate.msh"))
    assert {"bottom|core", "core|top", "bottom", "core", "top"} <= set(msh.field_data)
