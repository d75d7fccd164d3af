"""Polygon meshes of composite domains: interfaces kept by conversion, local refinement, files.

A :class:`~blockmesh.mesh.polygons.PolygonMesh` carries interfaces as a Mesh does: converting
either way keeps them, ``refine(mesh, cells=...)`` splits an interface edge into two interface
edges (the first region still on the left), every writer and reader of polygon meshes carries
them, and ``blockmesh solve --adapt`` refines a composite domain with per-region coefficients
and stays exact on a piecewise linear solution.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import run_cli
from test_composite_solve import BAR, BAR_EXACT

import blockmesh
from blockmesh.geometry.topology import cell_neighbours
from blockmesh.io.names import FOAM_WORD
from blockmesh.mesh.polygons import PolygonMesh

#: Composite catalogue domains and the level they are refined locally from.
DOMAINS = [("layered-plate", 1), ("inclusion", 0), ("heat-sink", 0)]


def _region_edges(mesh: PolygonMesh) -> set[tuple[int, int]]:
    """Every edge between two cells of different regions, as (lower id, higher id)."""
    cells = mesh.polygon_cells()
    across = cell_neighbours(cells, mesh.n_points)
    owner = cells.slot_cell()
    inner = across >= 0
    apart = inner & (mesh.region[owner] != mesh.region[owner[np.maximum(across, 0)]])
    a, b = mesh.nodes[apart], cells.following()[apart]
    return set(zip(np.minimum(a, b).tolist(), np.maximum(a, b).tolist(), strict=True))


def _check_interfaces(mesh: PolygonMesh) -> None:
    """Every edge between regions is an interface edge and the other way round; the first
    region of each interface is on the left of every one of its edges."""
    edges = mesh.interface_edges
    listed = {(min(a, b), max(a, b)) for a, b in edges.tolist()}
    assert len(listed) == edges.shape[0]  # no edge twice
    assert listed == _region_edges(mesh)
    sides = mesh.region[mesh.interface_cells()]  # checks every edge is between two cells
    for k, name in enumerate(mesh.interface_names):
        first, second = name.split("|")
        mine = sides[mesh.interface_patch == k]
        assert mine.size
        assert set(mine[:, 0].tolist()) == {mesh.region_names.index(first)}
        assert set(mine[:, 1].tolist()) == {mesh.region_names.index(second)}


def _interface_lengths(mesh) -> dict[str, float]:
    d = mesh.points[mesh.interface_edges[:, 1]] - mesh.points[mesh.interface_edges[:, 0]]
    length = np.hypot(d[:, 0], d[:, 1])
    return {
        name: float(length[mesh.interface_patch == k].sum())
        for k, name in enumerate(mesh.interface_names)
    }


@pytest.mark.parametrize(("name", "level"), DOMAINS)
def test_conversion_both_ways_keeps_the_interfaces(name, level):
    mesh = blockmesh.load_domain(name).mesh(level)
    poly = PolygonMesh.from_mesh(mesh)
    assert poly.interface_names == mesh.interface_names
    assert np.array_equal(poly.interface_edges, mesh.interface_edges)
    assert np.array_equal(poly.interface_patch, mesh.interface_patch)
    assert np.array_equal(poly.interface_cells(), mesh.interface_cells())
    _check_interfaces(poly)
    rebuilt = PolygonMesh(**{f: getattr(poly, f) for f in _FIELDS})  # the full checks
    back = rebuilt.to_mesh()
    assert back.interface_names == mesh.interface_names
    assert np.array_equal(back.interface_edges, mesh.interface_edges)
    assert "interfaces " in repr(poly)


_FIELDS = (
    "points", "offsets", "nodes", "block_id", "parent", "boundary_edges", "boundary_patch",
    "patch_names", "region", "region_names", "cell_level", "level", "name", "curves",
    "interface_edges", "interface_patch", "interface_names",
)  # fmt: skip


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize(("name", "level"), DOMAINS)
def test_local_refinement_carries_the_interfaces(name, level, seed):
    domain = blockmesh.load_domain(name)
    mesh = PolygonMesh.from_mesh(domain.mesh(level))
    lengths = _interface_lengths(mesh)
    rng = np.random.default_rng(seed)
    for _ in range(3):  # several rounds: hanging nodes on interfaces, split again
        near = np.zeros(mesh.n_cells, dtype=bool)
        near[mesh.interface_cells().ravel()] = True
        pick = rng.random(mesh.n_cells) < np.where(near, 0.4, 0.1)
        pick[rng.integers(mesh.n_cells)] = True
        before = mesh
        mesh = blockmesh.refine(mesh, cells=np.flatnonzero(pick))
        _check_interfaces(mesh)
        # Each interface edge either stays or becomes two, end to end, the new node between.
        assert mesh.interface_edges.shape[0] >= before.interface_edges.shape[0]
        assert mesh.interface_names == before.interface_names
    if name == "layered-plate":  # straight interfaces: their length is kept exactly
        assert _interface_lengths(mesh) == pytest.approx(lengths, rel=1e-14)
    if name == "inclusion":  # every interface node on the circle (radius 0.5 about (0, 0))
        radius = np.hypot(*mesh.points[np.unique(mesh.interface_edges)].T)
        assert np.abs(radius - 0.5).max() < 1e-12
    assert mesh.check_geometry() is None  # convex cells, hanging nodes straight


@pytest.fixture(scope="module")
def refined_composite():
    """A locally refined fibre-free composite with hanging nodes on its interfaces."""
    mesh = PolygonMesh.from_mesh(blockmesh.load_domain("layered-plate").mesh(1))
    near = np.unique(mesh.interface_cells()[::2].ravel())
    refined = blockmesh.refine(mesh, cells=near)
    assert refined.hanging_nodes().size and len(refined.interface_names) == 2
    return refined


def _signature(mesh) -> dict[str, list]:
    """Each interface's edges by their end coordinates, in order, and the first side's region."""
    out = {}
    sides = mesh.region[mesh.interface_cells()]
    for k, name in enumerate(mesh.interface_names):
        mine = mesh.interface_patch == k
        ends = mesh.points[mesh.interface_edges[mine]].round(12).reshape(-1, 4).tolist()
        left = {mesh.region_names[r] for r in sides[mine, 0].tolist()}
        out[name] = [sorted(map(tuple, ends)), left]
    return out


@pytest.mark.parametrize("suffix", [".vtu", ".vtk", ".xdmf", ".msh", ".mat", ".npz", "openfoam"])
def test_every_polygon_writer_and_reader_carries_the_interfaces(
    refined_composite, suffix, tmp_path
):
    mesh = refined_composite
    target = tmp_path / ("case" if suffix == "openfoam" else f"m{suffix}")
    options = {"format": "openfoam"} if suffix == "openfoam" else {}
    blockmesh.write(mesh, target, **options)
    back = blockmesh.read(target)
    assert isinstance(back, PolygonMesh)
    if suffix == "openfoam":  # zone names are OpenFOAM words: 'bottom|core' is 'bottom_core'
        assert list(back.interface_names) == list(FOAM_WORD.unique(mesh.interface_names))
        back = back.with_interfaces(
            back.interface_edges, back.interface_patch, mesh.interface_names
        )
    assert back.interface_names == mesh.interface_names
    _check_interfaces(back)
    assert _signature(back) == _signature(mesh)
    assert back.n_cells == mesh.n_cells and back.hanging_nodes().size == mesh.hanging_nodes().size


def test_solve_adapt_on_a_composite_bar_stays_exact_with_its_interface(capsys, tmp_path):
    path = tmp_path / "bar.geojson"
    path.write_text(json.dumps(BAR))
    final = tmp_path / "final.npz"
    code, stdout, stderr = run_cli(
        capsys, "solve", str(path), "--adapt", "--max-unknowns", "1500",
        "--diffusion", "a=1", "--diffusion", "b=10", "--dirichlet", f"*={BAR_EXACT}",
        "--exact", BAR_EXACT, "--mesh-output", str(final), "--json",
    )  # fmt: skip
    assert code == 0, stderr
    report = json.loads(stdout)
    history = report["history"]
    assert len(history) >= 3 and history[-1]["hanging_nodes"] > 0
    for step in history:  # exact to round-off at every step; the estimator sees no error
        assert step["l2_error"] < 1e-13 and step["h1_error"] < 1e-10
        assert step["estimator"] < 1e-10
    mesh = blockmesh.read(final)
    assert isinstance(mesh, PolygonMesh) and mesh.interface_names == ("a|b",)
    _check_interfaces(mesh)
    ends = mesh.points[mesh.interface_edges]
    assert np.abs(ends[..., 0] - 1.0).max() == 0.0  # on the line x = 1, from y = 0 to 1
    assert np.abs(ends[:, 1, 1] - ends[:, 0, 1]).sum() == pytest.approx(1.0, rel=1e-14)
    assert mesh.interface_edges.shape[0] > 3  # refined along the interface (3 edges at first)
    code, stdout, _ = run_cli(capsys, "check", str(final))
    count = mesh.interface_edges.shape[0]
    assert code == 0 and f"interface a|b: {count} edges between a and b (internal)" in stdout
