"""Gmsh .msh: read by the gmsh API and by meshio (every split), read back losslessly."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers_io import assert_same, gmsh_summary, sp_mesh, tagged

import blockmesh.io as bio
import blockmesh.io.msh.reader as msh_reader
from blockmesh.errors import ExportError
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


@pytest.mark.parametrize(
    ("split", "gmsh_type", "per_cell", "new_nodes", "lines_per_edge"),
    [("tri5", 2, 5, "cells", 1), ("tri3", 2, 3, "none", 1), ("quad5", 3, 5, "edges+cells", 2)],
)
def test_msh_through_gmsh(
    mesh: Mesh,
    tmp_path: Path,
    split: str,
    gmsh_type: int,
    per_cell: int,
    new_nodes: str,
    lines_per_edge: int,
) -> None:
    path = bio.write(mesh, tmp_path / "m.msh", split=split)
    info = gmsh_summary(path)
    m = mesh.n_cells
    extra = {"cells": m, "none": 0, "edges+cells": mesh.n_edges + m}[new_nodes]
    assert info["nodes"] == mesh.n_points + extra
    assert info["types"] == [gmsh_type] and info["elements"] == [per_cell * m]
    for k, name in enumerate(mesh.patch_names):
        edges = int(np.count_nonzero(mesh.boundary_patch == k))
        assert info["groups"][(1, name)] == lines_per_edge * edges
    for k, name in enumerate(mesh.region_names):
        assert info["groups"][(2, name)] == per_cell * int(np.count_nonzero(mesh.region == k))
    # the "pentagon" view: every element's pentagon, each pentagon with per_cell children
    assert set(info["views"]) == {"pentagon", "parent"}
    tags = info["element_tags"].tolist()
    pentagon = np.array([info["views"]["pentagon"][t] for t in tags], dtype=int)
    np.testing.assert_array_equal(np.bincount(pentagon, minlength=m), np.full(m, per_cell))
    parent = np.array([info["views"]["parent"][t] for t in tags], dtype=int)
    np.testing.assert_array_equal(parent, mesh.parent[pentagon])  # the cell one level up
    lines = set(info["views"]["pentagon"]) - set(tags)  # the boundary lines: -1
    assert lines and {info["views"]["pentagon"][t] for t in lines} == {-1}
    assert_same(bio.read(path), mesh)  # lossless: parent and block ids too


@pytest.mark.parametrize("split", ["tri5", "tri3", "quad5"])
def test_msh_through_meshio(mesh: Mesh, tmp_path: Path, split: str) -> None:
    """meshio reads every split: the element data covers the boundary lines too."""
    import meshio

    vm = meshio.read(bio.write(mesh, tmp_path / "m.msh", split=split))
    kinds = {c.type for c in vm.cells}
    assert kinds == {"line", "quad" if split == "quad5" else "triangle"}
    per = 3 if split == "tri3" else 5
    surface = [k for k, c in enumerate(vm.cells) if c.type != "line"]
    pentagon = np.concatenate([vm.cell_data["pentagon"][k] for k in surface]).astype(int)
    np.testing.assert_array_equal(np.bincount(pentagon), np.full(mesh.n_cells, per))
    for k, c in enumerate(vm.cells):
        assert len(vm.cell_data["pentagon"][k]) == len(c.data)
        if c.type == "line":
            assert set(vm.cell_data["parent"][k].tolist()) == {-1}
    names = {name for name, (_, dim) in vm.field_data.items()}
    assert names == set(mesh.patch_names) | set(mesh.region_names)


def test_msh_blocks_spanning_regions(mesh: Mesh, tmp_path: Path) -> None:
    """A block whose cells lie in two regions gets one surface entity per (block, region)."""
    mixed = mesh.with_regions(np.arange(mesh.n_cells) % 2, ("even", "odd"))
    path = bio.write(mixed, tmp_path / "m.msh", split="tri3")
    info = gmsh_summary(path)
    assert info["groups"][(2, "even")] == 3 * ((mesh.n_cells + 1) // 2)
    assert_same(bio.read(path), mixed)


def test_names_gmsh_cannot_hold(tmp_path: Path) -> None:
    """A double quote becomes _ in the physical name; blockmesh reads the real name back."""
    m = sp_mesh(1).with_patches(np.zeros(10, dtype=np.int64), ('the "wall"',))
    path = bio.write(m, tmp_path / "m.msh")
    assert gmsh_summary(path)["groups"][(1, "the _wall_")] == 10
    assert bio.read(path).patch_names == ('the "wall"',)


def test_elements_in_another_order_are_merged_by_their_outlines(mesh: Mesh, tmp_path: Path) -> None:
    """A file whose elements are not in blockmesh's order (another tool saved it) still reads."""
    path = bio.write(mesh, tmp_path / "m.msh", split="quad5")
    text = path.read_text().split("\n")
    start = text.index("$Elements")
    header = text[start + 1].split()
    blocks, at = int(header[0]), start + 2
    for _ in range(blocks):
        n = int(text[at].split()[3])
        text[at + 1 : at + 1 + n] = text[at + 1 : at + 1 + n][::-1]  # reversed in each block
        at += 1 + n
    (tmp_path / "r.msh").write_text("\n".join(text))
    assert_same(bio.read(tmp_path / "r.msh"), mesh)


def test_files_of_blockmesh_0_1(mesh: Mesh, tmp_path: Path) -> None:
    """Before layout 2, the view "parent" named each element's pentagon (lines not covered)."""
    path = bio.write(mesh, tmp_path / "m.msh", split="tri5")
    text = path.read_text()
    head, _, rest = text.partition("$ElementData\n")
    views = [v for v in ("$ElementData\n" + rest).split("$EndElementData\n") if v.strip()]
    pentagon_view = views[0]
    assert '"pentagon"' in pentagon_view
    lines = pentagon_view.split("\n")
    n_lines = mesh.boundary_edges.shape[0]
    body = lines[9 + n_lines :]  # drop the boundary lines' rows
    old_view = "\n".join([*lines[:1], "1", '"parent"', *lines[3:8], str(len(body) - 1), *body])
    meta_line = next(line for line in text.split("\n") if line.startswith("{"))
    meta = json.loads(meta_line)
    del meta["layout"]
    old = head + old_view + "$EndElementData\n$BlockMesh\n" + json.dumps(meta) + "\n$EndBlockMesh\n"
    (tmp_path / "old.msh").write_text(old)
    back = bio.read(tmp_path / "old.msh")
    assert_same(back, mesh, parent=False)
    assert np.all(back.parent == -1)


def test_missing_pentagon_view_is_explained(mesh: Mesh, tmp_path: Path) -> None:
    path = bio.write(mesh, tmp_path / "m.msh")
    text = path.read_text().replace('"pentagon"', '"other"')
    (tmp_path / "x.msh").write_text(text)
    with pytest.raises(ExportError, match='no "pentagon" element data'):
        bio.read(tmp_path / "x.msh")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda t: t.replace("$EndNodes", "$EndNoodles"), "no \\$EndNodes|expected a \\$Section"),
        (lambda t: t.replace("$Nodes\n1 ", "$Nodes\nx "), "malformed \\$Nodes header"),
        (lambda t: t[: t.index("$Elements") + 200], "ends at line|no \\$End|malformed"),
        (lambda t: t.replace("$Entities\n0 ", "$Entities\nzero "), "line 13: malformed \\$Ent"),
        (lambda t: t.replace(" 0\n$EndNodes", " zero\n$EndNodes"), "lines .*: malformed numbers"),
    ],
)
def test_broken_files_give_located_errors(
    mesh: Mesh, tmp_path: Path, change: object, message: str
) -> None:
    path = bio.write(mesh, tmp_path / "m.msh")
    (tmp_path / "b.msh").write_text(change(path.read_text()))  # type: ignore[operator]
    with pytest.raises(ExportError, match=message):
        msh_reader.read_msh(tmp_path / "b.msh")
