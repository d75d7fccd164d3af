"""Builders, comparisons and external-tool finders shared by the export tests (``tests/io``)."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from helpers import TWO_BLOCKS, TWO_VERTICES

import blockmesh._system.atomic as atomic
import blockmesh.io as bio
from blockmesh.io import Format
from blockmesh.mesh import Mesh
from blockmesh.refinement import refine

SP_ARRAY = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0]], dtype=float)


def sp_mesh(level: int) -> Mesh:
    """The paper's symmetric pentagon refined ``level`` times (one block, one patch)."""
    return refine(Mesh.from_cells(SP_ARRAY, [[0, 1, 2, 3, 4]]), level)


def _two_block(level: int) -> Mesh:
    return refine(Mesh.from_cells(np.array(TWO_VERTICES, float), TWO_BLOCKS), level)


def tagged(level: int) -> Mesh:
    """The two-block mesh with three patches and two regions (names with a space and a word)."""
    base = _two_block(level)
    xy = base.points[base.boundary_edges]
    on_left = np.all(xy[:, :, 0] < 1e-12, axis=1)
    on_right = np.all(xy[:, :, 0] > 3.9, axis=1)
    patch = np.where(on_left, 1, np.where(on_right, 2, 0))
    return (
        base.with_patches(patch, ("outer wall", "inlet", "outlet"))
        .with_regions(base.block_id, ("left", "right"))
        .with_name("two-block")
    )


def two_block(level: int) -> Mesh:
    """The two-block example with patches ``outer wall``, ``inlet`` and two regions."""
    base = _two_block(level)
    xy = base.points[base.boundary_edges]
    inlet = np.all(xy[:, :, 0] < 1e-12, axis=1)
    return (
        base.with_patches(inlet.astype(np.int64), ("outer wall", "inlet"))
        .with_regions(base.block_id, ("left", "right"))
        .with_name("two-block")
    )


def edges_by_patch(m: Mesh) -> dict[str, set[tuple[int, int]]]:
    return {name: set(map(tuple, m.patch_edges(name).tolist())) for name in m.patch_names}


def assert_same(a: Mesh, b: Mesh, *, parent: bool = True, block: bool = True) -> None:
    """Equal meshes: points, cells, regions, names, boundary per patch (and ids if asked)."""
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.cells, b.cells)
    np.testing.assert_array_equal(a.region, b.region)
    assert a.region_names == b.region_names
    assert a.patch_names == b.patch_names
    assert edges_by_patch(a) == edges_by_patch(b)
    if block:
        np.testing.assert_array_equal(a.block_id, b.block_id)
    if parent:
        np.testing.assert_array_equal(a.parent, b.parent)


def listing(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


def snapshot(directory: Path) -> dict[str, bytes]:
    """Every file under ``directory`` (relative path -> bytes)."""
    return {
        str(p.relative_to(directory)): p.read_bytes()
        for p in sorted(directory.rglob("*"))
        if p.is_file()
    }


def target(fmt: Format, folder: Path) -> Path:
    """A path in ``folder`` that :func:`blockmesh.io.write` writes in ``fmt``."""
    return folder / ("case" if fmt.directory else "m" + fmt.extensions[0])


def lossless(fmt: Format) -> dict[str, bool]:
    """What ``fmt`` keeps: ``parent`` and ``block`` ids (OpenFOAM keeps neither)."""
    kept = fmt.name != "openfoam"
    return {"parent": kept, "block": kept}


class _OsProxy:
    """The :mod:`os` module with some functions replaced (for :func:`patch_atomic_os`)."""

    def __init__(self, **overrides: object) -> None:
        self.__dict__.update(overrides)

    def __getattr__(self, name: str) -> object:
        return getattr(os, name)


def patch_atomic_os(monkeypatch: pytest.MonkeyPatch, **overrides: object) -> None:
    """Replace :mod:`os` functions as :mod:`blockmesh._system.atomic` sees them (faults)."""
    monkeypatch.setattr(atomic, "os", _OsProxy(**overrides))


# ------------------------------------------------------------------------- external tools
def gmsh_summary(path: Path) -> dict:
    """What the gmsh Python API reads from ``path``: groups, element types and counts, views."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        groups = {}
        for dim, tag in gmsh.model.getPhysicalGroups():
            count = 0
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                count += sum(len(t) for t in gmsh.model.mesh.getElements(dim, ent)[1])
            groups[(dim, gmsh.model.getPhysicalName(dim, tag))] = count
        types, elem_tags, _ = gmsh.model.mesh.getElements(2)
        views = {}
        for v in gmsh.view.getTags():
            name = gmsh.option.getString(f"View[{gmsh.view.getIndex(v)}].Name")
            _, data_tags, data, _, _ = gmsh.view.getModelData(v, 0)
            views[name] = dict(
                zip(np.asarray(data_tags).tolist(), np.ravel(data).tolist(), strict=True)
            )
        return {
            "groups": groups,
            "types": list(types),
            "elements": [len(t) for t in elem_tags],
            "element_tags": np.concatenate(elem_tags),
            "nodes": len(gmsh.model.mesh.getNodes()[0]),
            "views": views,
        }
    finally:
        gmsh.finalize()


def foam_tool(name: str) -> tuple[str, dict[str, str]] | None:
    """An OpenFOAM executable (``checkMesh``, ``laplacianFoam``) and its environment, or None.

    Distribution packages (Debian's ``openfoam``) put the tools on the PATH but need
    ``WM_PROJECT_DIR`` to find ``etc/controlDict``; it is set here when the shell has not.
    """
    exe = shutil.which(name)
    if exe is None:
        found = sorted(Path("/usr/lib/openfoam").glob(f"*/bin/{name}"))
        exe = str(found[-1]) if found else None
    if exe is None:
        return None
    env = dict(os.environ)
    if not env.get("WM_PROJECT_DIR"):
        roots = [Path("/usr/share/openfoam"), *sorted(Path("/usr/lib/openfoam").glob("*"))]
        root = next((r for r in roots if (r / "etc" / "controlDict").exists()), None)
        if root is not None:
            env["WM_PROJECT_DIR"] = str(root)
    return exe, env


def find_checkmesh() -> tuple[str, dict[str, str]] | None:
    """OpenFOAM's ``checkMesh`` and the environment it needs, or None if absent."""
    return foam_tool("checkMesh")


def run_pvpython(script: str, cwd: Path, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run ``script`` in ParaView's ``pvpython`` (under ``xvfb-run`` when there is no display).

    Skips the test when ``pvpython`` is not installed.
    """
    exe = shutil.which("pvpython")
    if exe is None:
        pytest.skip("ParaView's pvpython is not installed (apt-get install paraview)")
    argv = [exe, "-c", script]
    if not os.environ.get("DISPLAY") and shutil.which("xvfb-run"):
        argv = ["xvfb-run", "-a", *argv]
    return subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=timeout)


def write_all_formats(mesh: Mesh, folder: Path) -> dict[str, Path]:
    """``mesh`` written in every registry format into ``folder``; format name -> path."""
    return {
        name: bio.write(mesh, target(fmt, folder), format=name) for name, fmt in bio.FORMATS.items()
    }


def vtk_connectivity(grid: object) -> list[list[int]]:
    from vtkmodules.vtkCommonCore import vtkIdList

    ids = vtkIdList()
    rows = []
    for c in range(grid.GetNumberOfCells()):
        grid.GetCellPoints(c, ids)
        rows.append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
    return rows


PARAVIEW_NAMES = """
import sys
from paraview.simple import OpenDataFile
from paraview import servermanager
reader = OpenDataFile(sys.argv[1] if len(sys.argv) > 1 else "{path}")
reader.UpdatePipeline()
grid = servermanager.Fetch(reader)
fields = grid.GetFieldData()
print("CELLS", grid.GetNumberOfCells())
for i in range(fields.GetNumberOfArrays()):
    a = fields.GetArray(i)
    if a.GetName().startswith(("patch:", "region:")):
        print("NAME", a.GetName(), "=", int(a.GetTuple1(0)))
"""


def paraview_names(path: Path) -> tuple[int, dict[str, int]]:
    """What ParaView's own reader shows for ``path``: cell count and the name lookups."""
    run = run_pvpython(PARAVIEW_NAMES.format(path=path), path.parent)
    assert run.returncode == 0, run.stdout + run.stderr
    lines = run.stdout.splitlines()
    cells = next(int(line.split()[1]) for line in lines if line.startswith("CELLS"))
    names = {
        line[5:].rsplit(" = ", 1)[0]: int(line.rsplit(" = ", 1)[1])
        for line in lines
        if line.startswith("NAME ")
    }
    return cells, names


def expected_names(mesh: Mesh) -> dict[str, int]:
    names = {f"patch:{n}": k for k, n in enumerate(mesh.patch_names)}
    names.update({f"region:{n}": k for k, n in enumerate(mesh.region_names)})
    return names
