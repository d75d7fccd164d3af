"""Mesh files read within bounds: each reproducer of issue 26, run as an attacker would.

Each test makes its hostile file in a temporary folder, runs ``python -m blockmesh`` on it in a
child process and checks what the issue asks: one located message (naming the file and what is
wrong), exit code 1 or 2, nothing written, the child's peak memory under 500 MB, and an end
(a child still running after 10 s is killed and the test fails: it hung).
"""

from __future__ import annotations

import base64
import os
import re
import struct
import warnings
import zlib
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.io
from helpers import slow_except
from helpers_hostile import (
    assert_refused,
    deflate_zeros,
    listing,
    run_blockmesh,
    xz_zeros,
    zlib_zeros,
)

import blockmesh

GB = 1 << 30
FILE_FORMATS = [".vtu", ".vtk", ".xdmf", ".msh", ".mat", ".npz"]


def _mesh(level: int = 1) -> blockmesh.Mesh:
    return blockmesh.load_domain("sp").mesh(level)


def _check_refused(folder: Path, *argv: str, names: tuple[str, ...] = ()) -> None:
    before = listing(folder)
    run = run_blockmesh(*argv, cwd=folder)
    assert_refused(run, names=names)
    assert listing(folder) == before


# ------------------------------------------------------------------ only ordinary files
@pytest.mark.parametrize("suffix", slow_except(FILE_FORMATS, ".msh", ".npz"))
def test_a_fifo_named_like_a_mesh_is_refused_without_blocking(tmp_path, suffix):
    os.mkfifo(tmp_path / f"m{suffix}")
    _check_refused(tmp_path, "check", f"m{suffix}", names=(f"m{suffix}", "FIFO"))


@pytest.mark.parametrize("command", [("check",), ("mesh",), ("convert", "-o", "x.toml")])
def test_a_link_to_dev_zero_is_refused_before_it_is_read(tmp_path, command):
    (tmp_path / "z.vtu").symlink_to("/dev/zero")
    argv = (command[0], "z.vtu", *command[1:])
    _check_refused(tmp_path, *argv, names=("z.vtu", "character device"))


def test_an_openfoam_owner_fifo_is_refused(tmp_path):
    poly = blockmesh.write(_mesh(), tmp_path / "case", format="openfoam")
    (poly / "owner").unlink()
    os.mkfifo(poly / "owner")
    _check_refused(tmp_path, "check", "case", names=("owner", "FIFO"))


def test_an_xdmf_whose_hdf5_file_is_a_fifo_is_refused(tmp_path):
    light = blockmesh.write(_mesh(), tmp_path / "m.xdmf")
    (h5,) = tmp_path.glob("*.h5")
    h5.unlink()
    os.mkfifo(h5)
    _check_refused(tmp_path, "check", light.name, names=(h5.name, "not a regular file"))


# ------------------------------------------------------------------ XDMF's HDF5 reference
def _point_xdmf_at(light: Path, reference: str) -> None:
    text = light.read_text()
    text = re.sub(r">[^<>]*\.h5:/mesh/points<", f">{reference}:/mesh/points<", text)
    light.write_text(text)


@pytest.mark.parametrize(
    "reference",
    slow_except(
        ["/etc/passwd", "../../../../../../etc/passwd", "/proc/self/mem", "link-out", "/no/such/f"],
        "../../../../../../etc/passwd",
        "link-out",
    ),
)
def test_the_hdf5_reference_stays_in_the_xdmf_folder(tmp_path, reference):
    folder = tmp_path / "in"
    folder.mkdir()
    light = blockmesh.write(_mesh(), folder / "m.xdmf")
    (folder / "link-out").symlink_to("/etc/passwd")
    _point_xdmf_at(light, reference)
    before = listing(tmp_path)
    run = run_blockmesh("check", "in/m.xdmf", cwd=tmp_path)
    assert_refused(run, names=("not a regular file in the folder of m.xdmf",))
    assert listing(tmp_path) == before
    # the same words whether the file exists or not: the light file cannot probe for files
    assert run.error_lines[0].replace(reference, "R") == _refusal_for(tmp_path, "/no/such/f")


def _refusal_for(tmp_path: Path, reference: str) -> str:
    folder = tmp_path / "other"
    folder.mkdir(exist_ok=True)
    light = blockmesh.write(_mesh(), folder / "m.xdmf")
    _point_xdmf_at(light, reference)
    run = run_blockmesh("check", "other/m.xdmf", cwd=tmp_path)
    return run.error_lines[0].replace(reference, "R").replace("other/", "in/")


# ------------------------------------------------------------------ VTU parsing
def _vtu(tmp_path: Path, compression: str = "zlib") -> tuple[Path, bytes]:
    path = blockmesh.write(_mesh(), tmp_path / "m.vtu", compression=compression)
    return path, path.read_bytes()


def test_a_long_start_tag_is_parsed_in_linear_time(tmp_path):
    path, data = _vtu(tmp_path)
    junk = b" " + b"a" * 32_000  # an attribute name without "=": quadratic for the old regex
    path.write_bytes(data.replace(b"<VTKFile ", b"<VTKFile" + junk + b" ", 1))
    _check_refused(tmp_path, "check", "m.vtu", names=("m.vtu",))


def test_a_tag_of_megabytes_ends_quickly_either_way(tmp_path):
    path, data = _vtu(tmp_path)
    big = b' comment="' + b"x" * (4 << 20) + b'"'
    path.write_bytes(data.replace(b"<VTKFile ", b"<VTKFile" + big + b" ", 1))
    run = run_blockmesh("check", "m.vtu", cwd=tmp_path)
    assert not run.killed and run.code in (0, 1, 2), run.describe()
    assert "internal error" not in run.err and run.peak_bytes < 500 * 2**20, run.describe()


def test_a_foreign_vtu_of_many_appended_arrays_is_refused_before_meshio(tmp_path):
    # meshio copies the whole appended text for every array: quadratic; 20,000 arrays of 4 MB
    arrays = "".join(
        f'<DataArray type="Float64" Name="a{k}" format="appended" offset="0"/>'
        for k in range(20_000)
    )
    text = (
        '<?xml version="1.0"?><VTKFile type="UnstructuredGrid" version="0.1" '
        'byte_order="LittleEndian"><UnstructuredGrid><Piece NumberOfPoints="3" '
        f'NumberOfCells="1"><PointData>{arrays}</PointData></Piece></UnstructuredGrid>'
        '<AppendedData encoding="base64">_' + "A" * (4 << 20) + "</AppendedData></VTKFile>"
    )
    (tmp_path / "f.vtu").write_text(text)
    _check_refused(tmp_path, "check", "f.vtu", names=("f.vtu",))


def _array_text(data: bytes, name: bytes) -> tuple[int, int]:
    """Where the base64 text of the DataArray ``name`` starts and ends in ``data``."""
    at = data.index(b'Name="' + name + b'"')
    start = data.index(b">", at) + 1
    while data[start : start + 1].isspace():
        start += 1
    return start, data.index(b"<", start)


def test_a_data_length_past_the_end_of_the_file_is_refused(tmp_path):
    path, data = _vtu(tmp_path, "none")
    start, stop = _array_text(data, b"connectivity")
    raw = base64.b64decode(data[start:stop])
    fake = struct.pack("<Q", 10 * len(raw)) + raw[8:]
    path.write_bytes(data[:start] + base64.b64encode(fake) + data[stop:])
    _check_refused(tmp_path, "check", "m.vtu", names=("m.vtu", "connectivity", "file are left"))


def _vtu_bomb(tmp_path: Path, compression: str, stream: bytes) -> None:
    """The mesh's points as one compressed block declared small that inflates to gigabytes."""
    path, data = _vtu(tmp_path, compression)
    start, stop = _array_text(data, b"Points")
    text = data[start:stop]
    kind = "<u8" if b'header_type="UInt64"' in data else "<u4"
    size = np.dtype(kind).itemsize
    head = np.frombuffer(base64.b64decode(text[: 4 * -(-4 * size // 3)])[: 4 * size], kind)
    blocks, block, last = (int(v) for v in head[:3])
    assert blocks == 1
    header = np.array([1, block, last, len(stream)], dtype=kind).tobytes()
    bomb = base64.b64encode(header) + base64.b64encode(stream)
    path.write_bytes(data[:start] + bomb + data[stop:])


def test_a_vtu_zlib_block_inflating_to_2_gb_is_refused(tmp_path):
    _vtu_bomb(tmp_path, "zlib", zlib_zeros(2 * GB))
    _check_refused(tmp_path, "check", "m.vtu", names=("m.vtu", "Points", "declared"))


def test_an_lzma_vtu_inflating_to_3_gb_is_refused(tmp_path):
    _vtu_bomb(tmp_path, "lzma", xz_zeros(3 * GB))
    _check_refused(tmp_path, "check", "m.vtu", names=("m.vtu", "Points", "declared"))


def _zip_member(name: str, header: bytes, n_zeros: int) -> tuple[bytes, bytes]:
    """A deflated zip member: ``header`` then ``n_zeros`` zeros (local entry, central entry)."""
    compressor = zlib.compressobj(9, zlib.DEFLATED, -15)
    data = compressor.compress(header) + compressor.flush(zlib.Z_FULL_FLUSH)
    data += deflate_zeros(n_zeros)
    size = len(header) + n_zeros
    fields = struct.pack("<HHHHHIII", 20, 0, 8, 0, 0, 0, len(data), size)  # CRC left 0
    local = b"PK\x03\x04" + fields + struct.pack("<HH", len(name), 0) + name.encode() + data
    central = (
        b"PK\x01\x02"
        + struct.pack("<H", 20)
        + fields
        + struct.pack("<HHHHHII", len(name), 0, 0, 0, 0, 0, 0)
        + name.encode()
    )
    return local, central


def test_an_npz_zip_bomb_of_3_gb_is_refused(tmp_path):
    good = tmp_path / "good.npz"
    blockmesh.write(_mesh(), good)
    n = (3 * GB) // 16
    header = bytearray()
    dictionary = f"{{'descr': '<f8', 'fortran_order': False, 'shape': ({n}, 2), }}"
    header += b"\x93NUMPY\x01\x00"
    padded = dictionary + " " * (-(10 + len(dictionary) + 1) % 64) + "\n"
    header += struct.pack("<H", len(padded)) + padded.encode()
    with np.load(good) as arrays:
        others = {k: arrays[k] for k in arrays.files if k != "points"}
    entries = [_zip_member("points.npy", bytes(header), 16 * n)]
    for key, value in others.items():
        buffer = _npy_bytes(value)
        entries.append(_zip_member(f"{key}.npy", buffer, 0))
    out, central, offsets = b"", b"", []
    for local, entry in entries:
        offsets.append(len(out))
        out += local
        central += entry
    central = b"".join(
        entry[:42] + struct.pack("<I", offset) + entry[46:]
        for (_, entry), offset in zip(entries, offsets, strict=True)
    )
    end = struct.pack("<4sHHHHIIH", b"PK\x05\x06", 0, 0, len(entries), len(entries),
                      len(central), len(out), 0)  # fmt: skip
    good.unlink()
    (tmp_path / "bomb.npz").write_bytes(out + central + end)
    _check_refused(tmp_path, "check", "bomb.npz", names=("bomb.npz", "points"))


def _npy_bytes(value: np.ndarray) -> bytes:
    import io

    buffer = io.BytesIO()
    np.save(buffer, value)
    return buffer.getvalue()


def test_a_zlib_mat_bomb_is_refused(tmp_path):
    path = tmp_path / "m.mat"
    blockmesh.write(_mesh(), path)
    n = (3 * GB) // 16  # a Node of n x 2 doubles: 3 GB declared and inflated
    flags = struct.pack("<IIII", 6, 8, 6, 0)  # miUINT32 array flags: mxDOUBLE_CLASS
    dims = struct.pack("<IIii", 5, 8, n, 2)
    name = struct.pack("<II", 1, 4) + b"Node" + bytes(4)
    data = struct.pack("<II", 9, 16 * n)
    body = flags + dims + name + data
    prefix = struct.pack("<II", 14, len(body) + 16 * n) + body
    compressor = zlib.compressobj(9, zlib.DEFLATED, -15)
    raw = compressor.compress(prefix) + compressor.flush(zlib.Z_FULL_FLUSH) + deflate_zeros(16 * n)
    a = zlib.adler32(prefix)
    low, high = a & 0xFFFF, a >> 16
    adler = (((high + (16 * n % 65521) * low) % 65521) << 16) | low
    stream = b"\x78\xda" + raw + adler.to_bytes(4, "big")
    element = struct.pack("<II", 15, len(stream)) + stream
    path.write_bytes(path.read_bytes()[:128] + element)
    _check_refused(tmp_path, "check", "m.mat", names=("m.mat",))


@pytest.mark.parametrize("chunked", [False, True])
def test_an_hdf5_dataset_claiming_3_gb_is_refused(tmp_path, chunked):
    light = blockmesh.write(_mesh(), tmp_path / "m.xdmf")
    (h5,) = tmp_path.glob("*.h5")
    n = (3 * GB) // 16
    with h5py.File(h5, "r+") as f:
        del f["mesh/points"]
        options = {"chunks": (1 << 20, 2), "compression": "gzip"} if chunked else {}
        f["mesh"].create_dataset("points", shape=(n, 2), dtype="f8", **options)
    text = light.read_text().replace('Dimensions="15 2"', f'Dimensions="{n} 2"')
    light.write_text(text)
    _check_refused(tmp_path, "check", "m.xdmf", names=("m.xdmf", "/mesh/points", "declares"))


# ------------------------------------------------------------------ malformed files
def test_a_mat_whose_node_holds_strings_is_located(tmp_path):
    cells = np.empty((1, 1), dtype=object)
    cells[0, 0] = np.array([[1.0, 2, 3, 4, 5]])
    nodes = np.array(["a", "b", "c", "d", "e"])
    scipy.io.savemat(tmp_path / "m.mat", {"Node": nodes, "Element": cells})
    _check_refused(tmp_path, "check", "m.mat", names=("m.mat", "Node"))


def test_non_integer_physical_names_tags_are_located(tmp_path):
    path = blockmesh.write(_mesh(), tmp_path / "m.msh")
    text = path.read_text()
    at = text.index("$PhysicalNames")
    line_start = text.index("\n", text.index("\n", at) + 1) + 1
    line_end = text.index("\n", line_start)
    path.write_text(text[:line_start] + 'x y "boundary"' + text[line_end:])
    _check_refused(tmp_path, "check", "m.msh", names=("m.msh", "physical name"))


def test_negative_element_data_components_are_located(tmp_path):
    path = blockmesh.write(_mesh(), tmp_path / "m.msh")
    lines = path.read_text().split("\n")
    at = lines.index("$ElementData")
    n_str = int(lines[at + 1])
    n_real = int(lines[at + 2 + n_str])
    ints_at = at + 3 + n_str + n_real  # the count of integer tags, then the tags
    lines[ints_at + 2] = "-3"  # the number of components
    path.write_text("\n".join(lines))
    _check_refused(tmp_path, "check", "m.msh", names=("m.msh", "components"))


def test_element_data_announcing_10_12_strings_is_refused_at_once(tmp_path):
    path = blockmesh.write(_mesh(), tmp_path / "m.msh")
    text = path.read_text()
    at = text.index("$ElementData\n") + len("$ElementData\n")
    end = text.index("\n", at)
    path.write_text(text[:at] + "1000000000000" + text[end:])
    _check_refused(tmp_path, "check", "m.msh", names=("m.msh", "string tags"))


def _owner_file(poly: Path) -> tuple[list[str], int]:
    lines = (poly / "owner").read_text().split("\n")
    count_at = next(k for k, line in enumerate(lines) if line.strip().isdigit())
    return lines, count_at


def test_an_openfoam_owner_of_minus_one_is_located(tmp_path):
    poly = blockmesh.write(_mesh(), tmp_path / "case", format="openfoam")
    lines, count_at = _owner_file(poly)
    count = int(lines[count_at])
    lines[count_at + 1 + count] = "-1"  # the last face: a boundary face
    (poly / "owner").write_text("\n".join(lines))
    _check_refused(tmp_path, "check", "case", names=("case", "owner"))


def test_an_openfoam_boundary_of_40000_patches_is_read_in_linear_time(tmp_path):
    poly = blockmesh.write(_mesh(2), tmp_path / "case", format="openfoam")
    boundary = poly / "boundary"
    text = boundary.read_text()
    count = re.search(r"^(\d+)\s*$", text, flags=re.M)
    assert count is not None
    opening = text.index("(", count.end()) + 1
    extra = "".join(f"extra{k} {{ type patch; nFaces 0; startFace 0; }}\n" for k in range(40_000))
    total = str(int(count[1]) + 40_000)
    boundary.write_text(
        text[: count.start()] + total + text[count.end() : opening] + "\n" + extra + text[opening:]
    )
    run = run_blockmesh("mesh", "case", "--level", "0", "--json", cwd=tmp_path)
    assert not run.killed and run.code in (0, 1, 2), run.describe()
    assert "internal error" not in run.err and run.peak_bytes < 500 * 2**20, run.describe()


@pytest.mark.parametrize("level", [2e62, -7])
def test_an_npz_of_an_impossible_level_is_refused(tmp_path, level):
    path = blockmesh.write(_mesh(), tmp_path / "m.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["level"] = np.array(level)
    np.savez(path, **arrays)
    _check_refused(tmp_path, "check", "m.npz", names=("m.npz", "level"))


def test_nan_and_infinite_nodes_given_to_convert_are_located(tmp_path):
    import meshio

    for k, bad in enumerate([np.nan, np.inf]):
        points = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
        points[3, 0] = bad
        meshio.write(
            tmp_path / f"t{k}.vtu", meshio.Mesh(points, [("triangle", [[0, 1, 2], [1, 3, 2]])])
        )
        _check_refused(
            tmp_path, "convert", f"t{k}.vtu", "-o", "out.toml", names=(f"t{k}.vtu", "point 3")
        )


@pytest.mark.parametrize("suffix", [".vtu", ".npz", ".msh", ".xdmf"])
def test_reads_honour_max_memory(tmp_path, suffix):
    blockmesh.write(blockmesh.load_domain("joined-8").mesh(4), tmp_path / f"m{suffix}")
    _check_refused(
        tmp_path, "mesh", f"m{suffix}", "--level", "0", "--max-memory", "300K",
        names=(f"m{suffix}", "--max-memory"),
    )  # fmt: skip


# ------------------------------------------------------------------ polygon meshes (issue 25)
def _polygons() -> blockmesh.PolygonMesh:
    return blockmesh.refine(_mesh(), cells=[0, 3])


@pytest.mark.parametrize("level", [2e62, -7])
def test_a_polygon_npz_of_an_impossible_level_is_refused(tmp_path, level):
    path = blockmesh.write(_polygons(), tmp_path / "p.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["level"] = np.array(level)
    np.savez(path, **arrays)
    _check_refused(tmp_path, "check", "p.npz", names=("p.npz", "level"))


def test_a_polygon_npz_of_infinite_points_is_located(tmp_path):
    path = blockmesh.write(_polygons(), tmp_path / "p.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["points"] = arrays["points"].copy()
    arrays["points"][4, 1] = np.inf
    np.savez(path, **arrays)
    _check_refused(tmp_path, "check", "p.npz", names=("p.npz", "point 4"))


def test_an_xdmf_polygon_of_negative_size_ends_with_a_message(tmp_path):
    # A foreign Mixed topology (no offsets beside it) walked record by record: a size of -2
    # once sent the walk back to where it was, for ever.
    (tmp_path / "p.xdmf").write_text(
        '<?xml version="1.0"?><Xdmf Version="3.0"><Domain><Grid Name="m">'
        '<Topology TopologyType="Mixed" NumberOfElements="1">'
        '<DataItem Format="XML" NumberType="Int" Dimensions="6">3 -2 0 1 2 3</DataItem>'
        "</Topology>"
        '<Geometry GeometryType="XY"><DataItem Format="XML" Dimensions="4 2">'
        "0 0 1 0 1 1 0 1</DataItem></Geometry></Grid></Domain></Xdmf>"
    )
    _check_refused(tmp_path, "check", "p.xdmf", names=("p.xdmf", "-2 nodes"))


def test_an_openfoam_polygon_case_naming_a_missing_point_is_located(tmp_path):
    blockmesh.write(_polygons(), tmp_path / "case", format="openfoam")
    faces = tmp_path / "case" / "constant" / "polyMesh" / "faces"
    text = faces.read_text()
    at = text.rindex("6(")  # a hexagon (a split cell's centre): a face of the empty patch
    faces.write_text(text[:at] + "6(999999 " + text[at + 2 :].split(" ", 1)[1])
    _check_refused(tmp_path, "check", "case", names=("faces", "999999"))


def test_a_polygon_mat_element_holding_text_is_located(tmp_path):
    blockmesh.write(_polygons(), tmp_path / "p.mat")
    data = scipy.io.loadmat(tmp_path / "p.mat")
    data["Element"][0, 0] = np.array(["abc"])  # main's polygon path: a ValueError, exit 3
    scipy.io.savemat(tmp_path / "p.mat", {k: v for k, v in data.items() if k[:2] != "__"})
    _check_refused(tmp_path, "check", "p.mat", names=("p.mat", "Element"))


def test_a_msh_entity_tag_beyond_int64_is_located(tmp_path):
    # Found by the ten-minute fuzz: the tag reached numpy as a Python int (OverflowError, exit 3).
    path = blockmesh.write(_mesh(), tmp_path / "m.msh")
    lines = path.read_bytes().split(b"\n")
    header = lines.index(b"$Elements") + 2  # after the section's counts: the first block's header
    dim, _tag, kind, count = lines[header].split()
    lines[header] = b" ".join([dim, b"9223372036854775808", kind, count])
    path.write_bytes(b"\n".join(lines))
    _check_refused(tmp_path, "check", "m.msh", names=("m.msh", "9223372036854775808"))


def test_non_finite_nodes_are_located_before_the_elements_are_merged():
    # Found by the ten-minute fuzz of .msh: an infinite node reached the corner test of elements
    # merged by their outlines (a RuntimeWarning, then a message about the wrong thing).
    from blockmesh.io.pentagons import merge_elements
    from blockmesh.io.split import split_cells

    split = split_cells(_mesh(0), "quad5")
    points = split.points.copy()
    points[7] = [np.inf, 0.0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(blockmesh.ExportError, match="m.msh: point 7 .* not finite"):
            merge_elements(split.cells, split.parent, points, where="m.msh")


@pytest.mark.parametrize("encoding", ["utfinf", "shift_jis"])
def test_an_xdmf_declaring_an_unusable_encoding_is_located(tmp_path, encoding):
    # Found by the ten-minute XDMF fuzz: expat raised LookupError for an unknown encoding.
    path = blockmesh.write(_mesh(), tmp_path / "m.xdmf")
    text = path.read_bytes().replace(b'encoding="utf-8"', f'encoding="{encoding}"'.encode(), 1)
    path.write_bytes(text)
    _check_refused(tmp_path, "check", "m.xdmf", names=("m.xdmf", "encoding"))


@pytest.mark.parametrize("mesh", ["pentagons", "polygons"])
def test_openfoam_points_that_are_not_finite_are_located(tmp_path, mesh):
    # Found by the ten-minute OpenFOAM fuzz: an infinite point reached the search for the
    # bottom plane (RuntimeWarnings printed as warnings before the located message).
    blockmesh.write(
        _mesh() if mesh == "pentagons" else _polygons(), tmp_path / "case", format="openfoam"
    )
    points = tmp_path / "case" / "constant" / "polyMesh" / "points"
    text = points.read_text()
    first = re.search(r"\n\((\S+) (\S+) (\S+)\)", text[text.index("}") :])
    assert first is not None
    at = text.index("}") + first.start(3)  # the first point's z: the planes are found from z
    points.write_text(text[:at] + "inf" + text[at + len(first[3]) :])
    _check_refused(tmp_path, "check", "case", names=("points", "inf"))


def test_a_mat_interface_holding_text_is_located(tmp_path):
    # The interfaces of composite domains (issue 23): on main's reader a ValueError, exit 3.
    blockmesh.write(blockmesh.load_domain("layered-plate").mesh(1), tmp_path / "c.mat")
    data = scipy.io.loadmat(tmp_path / "c.mat")
    field = data["InterfaceEdges"].dtype.names[0]
    data["InterfaceEdges"][0, 0][field] = np.array(["ab"])
    scipy.io.savemat(tmp_path / "c.mat", {k: v for k, v in data.items() if k[:2] != "__"})
    _check_refused(tmp_path, "check", "c.mat", names=("c.mat", "InterfaceEdges"))
