"""Pentagonal conversion of existing meshes (gmsh triangle, quadrilateral and mixed meshes)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely
from helpers import assert_blocks_tile, run_cli

import blockmesh
from blockmesh import BlockMeshWarning, Domain, DomainError
from blockmesh.geometry import is_strictly_convex, signed_area

meshio = pytest.importorskip("meshio")

#: The channel of :func:`_gmsh_mesh`, with its obstacle.
CHANNEL = shapely.Polygon(
    [(0, 0), (3, 0), (3, 1), (0, 1)], [[(0.5, 0.4), (0.8, 0.4), (0.8, 0.6), (0.5, 0.6)]]
)


def _gmsh_mesh(path, kind: str) -> None:
    """A 3 x 1 channel with a square obstacle; physical curves and surfaces named.

    ``kind``: "triangles", "quads" (recombined) or "mixed" (left half quads, right triangles).
    """
    gmsh = pytest.importorskip("gmsh", reason="gmsh makes the reference meshes")
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(kind)
        geo = gmsh.model.geo
        size = 0.25
        corners = [(0, 0), (1.5, 0), (3, 0), (3, 1), (1.5, 1), (0, 1)]
        p = [geo.addPoint(x, y, 0, size) for x, y in corners]
        hole = [
            geo.addPoint(x, y, 0, size / 2)
            for x, y in [(0.5, 0.4), (0.8, 0.4), (0.8, 0.6), (0.5, 0.6)]
        ]
        lines = [geo.addLine(p[i], p[(i + 1) % 6]) for i in range(6)]
        middle = geo.addLine(p[1], p[4])
        square = [geo.addLine(hole[i], hole[(i + 1) % 4]) for i in range(4)]
        left = geo.addCurveLoop([lines[0], middle, lines[4], lines[5]])
        right = geo.addCurveLoop([lines[1], lines[2], lines[3], -middle])
        obstacle = geo.addCurveLoop(square)
        s_left = geo.addPlaneSurface([left, obstacle])
        s_right = geo.addPlaneSurface([right])
        geo.synchronize()
        gmsh.model.addPhysicalGroup(1, [lines[5]], name="inlet")
        gmsh.model.addPhysicalGroup(1, [lines[2]], name="outlet")
        gmsh.model.addPhysicalGroup(1, [lines[0], lines[1], lines[3], lines[4]], name="walls")
        gmsh.model.addPhysicalGroup(1, square, name="obstacle")
        gmsh.model.addPhysicalGroup(2, [s_left], name="upstream")
        gmsh.model.addPhysicalGroup(2, [s_right], name="downstream")
        if kind in ("quads", "mixed"):
            gmsh.model.mesh.setRecombine(2, s_left)
        if kind == "quads":
            gmsh.model.mesh.setRecombine(2, s_right)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


@pytest.fixture(scope="module", params=["triangles", "quads", "mixed"])
def gmsh_file(request, tmp_path_factory):
    path = tmp_path_factory.mktemp("gmsh") / f"{request.param}.msh"
    _gmsh_mesh(path, request.param)
    return request.param, path


def _element_area(mesh) -> float:
    total = 0.0
    for cells in mesh.cells:
        if cells.type in ("triangle", "quad"):
            total += float(np.abs(signed_area(mesh.points[cells.data][:, :, :2])).sum())
    return total


def test_gmsh_meshes_convert_conformingly(gmsh_file):
    kind, path = gmsh_file
    source = meshio.read(path)
    domain = Domain.from_mesh(path)
    assert domain.layout == "conversion" and domain.name == kind
    assert np.all(is_strictly_convex(domain.vertices[domain.blocks] - domain.vertices.mean(0)))
    assert domain.area == pytest.approx(_element_area(source), rel=1e-12)
    assert domain.area == pytest.approx(3.0 - 0.06, rel=1e-12)
    # Edge to edge, no hanging node, the union is the channel (checked independently).
    assert_blocks_tile(domain, CHANNEL)
    assert set(domain.patch_names) == {"inlet", "outlet", "walls", "obstacle"}
    assert set(domain.region_names) == {"upstream", "downstream"}
    # Each block knows its element: triangles became 9 blocks, quadrilaterals 12.
    counts = np.bincount(domain.block_source)
    types = [
        c.type for c in source.cells for _ in range(len(c.data)) if c.type in ("triangle", "quad")
    ]
    assert counts.tolist() == [9 if t == "triangle" else 12 for t in types]
    if kind == "quads":
        assert set(counts.tolist()) == {12}
    if kind == "mixed":
        assert set(counts.tolist()) == {9, 12}
    # Patches lie where their groups are: the inlet on x = 0, the outlet on x = 3.
    inlet = domain.vertices[domain.patches["inlet"]]
    outlet = domain.vertices[domain.patches["outlet"]]
    assert np.all(inlet[:, :, 0] == 0.0) and np.all(outlet[:, :, 0] == 3.0)
    upstream = domain.vertices[domain.blocks[domain.regions["upstream"]]]
    assert np.all(upstream[:, :, 0] <= 1.5 + 1e-12)
    # A converted domain refines like any other.
    mesh = domain.mesh(2)
    assert mesh.n_cells == domain.n_blocks * 36
    assert mesh.area == pytest.approx(domain.area, rel=1e-12)


def test_meshio_round_trip(gmsh_file, tmp_path):
    _, path = gmsh_file
    source = meshio.read(path)
    planar = meshio.Mesh(
        source.points[:, :2], [c for c in source.cells if c.type in ("triangle", "quad")]
    )
    for suffix in (".vtu", ".vtk", ".xdmf"):
        target = tmp_path / f"m{suffix}"
        meshio.write(target, planar)
        domain = Domain.from_mesh(target)
        assert domain.area == pytest.approx(_element_area(source), rel=1e-12)
        assert domain.patch_names == ("boundary",)
        assert_blocks_tile(domain, CHANNEL)
    # blockmesh's own output, read back: its cells are the blocks, patches kept.
    domain = Domain.from_mesh(path)
    written = blockmesh.write(domain.mesh(1), tmp_path / "again.vtu")
    again = Domain.from_mesh(written)
    assert again.layout == "mesh" and again.n_blocks == domain.n_blocks * 6
    assert set(again.patch_names) == set(domain.patch_names)
    assert again.area == pytest.approx(domain.area, rel=1e-12)


def test_all_pentagon_input_keeps_its_elements_as_blocks():
    sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
    domain = Domain.from_mesh(meshio.Mesh(sp, [("polygon", np.array([[0, 1, 2, 3, 4]]))]))
    assert domain.layout == "mesh" and domain.blocks.tolist() == [[0, 1, 2, 3, 4]]


def test_clockwise_meshes_are_reversed_and_non_convex_quads_split():
    points = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.8, 0.3]], dtype=float)
    # A dart: (0, 1, 4, 3) has a reflex corner at 4; the triangle (1, 2, 3, 4) fills the rest.
    mesh = meshio.Mesh(
        points, [("quad", np.array([[0, 1, 4, 3]])), ("triangle", np.array([[1, 2, 4], [4, 2, 3]]))]
    )
    domain = Domain.from_mesh(mesh)
    assert domain.area == pytest.approx(1.0, rel=1e-12)
    assert set(domain.block_source.tolist()) == {0, 1, 2}
    flipped = meshio.Mesh(
        points, [("triangle", np.array([[0, 4, 1], [1, 4, 2], [4, 3, 2], [0, 3, 4]]))]
    )
    with pytest.warns(BlockMeshWarning, match="all run clockwise; they were reversed"):
        assert Domain.from_mesh(flipped).area == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize(
    ("mesh", "message"),
    [
        (
            meshio.Mesh(
                np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float),
                [("tetra", np.array([[0, 1, 2, 3]]))],
            ),
            "1 tetra elements: blockmesh converts 2-D meshes",
        ),
        (
            meshio.Mesh(
                np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.5]], dtype=float),
                [("triangle", np.array([[0, 1, 2]]))],
            ),
            "not planar: point 2 has z = 0.5",
        ),
        (
            meshio.Mesh(
                np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0.5]], dtype=float),
                [("triangle", np.array([[0, 1, 2], [0, 2, 3], [1, 2, 4]]))],
            ),
            r"1 element is inverted .* 2 \(triangle\)",
        ),
        (
            meshio.Mesh(
                np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1, 0], [1, -1]], dtype=float),
                [("triangle", np.array([[0, 1, 2], [0, 2, 3], [0, 5, 4]]))],
            ),
            r"node 4 \(1.0, 0.0\) lies on edge \(0, 1\) of element 0 .* not conforming",
        ),
        (
            meshio.Mesh(
                np.array([[0, 0], [1, 0], [0.5, 1], [0.5, -1], [0.5, 0.5]], dtype=float),
                [("triangle", np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]]))],
            ),
            "belongs to 3 elements",
        ),
        (
            meshio.Mesh(
                np.array([[0, 0], [1, 0], [2, 0]], dtype=float),
                [("triangle", np.array([[0, 1, 2]]))],
            ),
            "has zero area",
        ),
        (meshio.Mesh(np.zeros((2, 2)), [("line", np.array([[0, 1]]))]), "no triangles"),
    ],
)
def test_bad_meshes_are_rejected_with_the_element_named(mesh, message):
    with pytest.raises(DomainError, match=message):
        Domain.from_mesh(mesh)


def test_unreadable_files(tmp_path):
    bad = tmp_path / "bad.vtu"
    bad.write_text("not a mesh")
    with pytest.raises(blockmesh.DomainFormatError, match="bad.vtu: cannot read it as a mesh"):
        Domain.from_mesh(bad)
    with pytest.raises(blockmesh.DomainFormatError, match="no such file"):
        Domain.from_mesh(tmp_path / "missing.msh")


def test_convert_command(gmsh_file, tmp_path, capsys):
    kind, path = gmsh_file
    out = tmp_path / "channel.toml"
    code, stdout, err = run_cli(capsys, "convert", str(path), "-o", str(out))
    assert code == 0, err
    assert "pentagonal blocks (conversion)" in stdout and "patch inlet" in stdout
    converted = blockmesh.load_domain(out)
    assert converted.area == pytest.approx(3.0 - 0.06, rel=1e-12)
    assert {"inlet", "outlet", "walls", "obstacle"} <= set(converted.patch_names)
    code, stdout, _ = run_cli(
        capsys, "convert", str(path), "-o", str(tmp_path / "c.vtu"), "--level", "1", "--json"
    )
    report = json.loads(stdout)
    assert (
        code == 0 and report["cells"] == 6 * report["blocks"] and report["layout"] == "conversion"
    )
    assert set(report["regions"]) == {"upstream", "downstream"}
    assert blockmesh.read(tmp_path / "c.vtu").n_cells == report["cells"]
    # In Python, load_domain converts a mesh file as well.
    assert blockmesh.load_domain(path).layout == "conversion"
