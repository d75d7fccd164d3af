"""Every format of the registry :data:`blockmesh.io.FORMATS`: lookup, options, round trips,
atomic writes and operating-system failures.

A new format module registered in ``blockmesh.io`` is tested here without a line added (its
own reader-specific tests go to ``tests/io/test_<format>.py``).
"""

from __future__ import annotations

import errno
import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from helpers import slow_except
from helpers_io import (
    assert_same,
    listing,
    lossless,
    patch_atomic_os,
    snapshot,
    sp_mesh,
    tagged,
    target,
)

import blockmesh._system.atomic as atomic
import blockmesh.io as bio
import blockmesh.io.text as text
from blockmesh.errors import BlockMeshError, ExportError
from blockmesh.mesh import Mesh

FORMAT_NAMES = list(bio.FORMATS)
#: The formats whose damaged copies are tried by default (XDMF's and VTU's take seconds: slow set).
CHEAP_TO_DAMAGE = slow_except(FORMAT_NAMES, *(n for n in FORMAT_NAMES if n not in ("xdmf", "vtu")))


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


# ----------------------------------------------------------------------------- registry
def test_registry_lists_every_format() -> None:
    assert set(bio.FORMATS) == {"vtu", "vtk", "xdmf", "msh", "mat", "openfoam", "npz"}
    for name, fmt in bio.FORMATS.items():
        assert fmt.name == name and fmt.description and fmt.can_read
        assert fmt.default_compression in fmt.compressions
        assert (fmt.default_split in fmt.splits) if fmt.splits else fmt.default_split is None
    assert bio.FORMATS["msh"].needs_split and bio.FORMATS["msh"].default_split == "tri5"
    assert not any(f.needs_split for n, f in bio.FORMATS.items() if n != "msh")
    assert bio.FORMATS["openfoam"].directory and "dz" in bio.FORMATS["openfoam"].options


@pytest.mark.parametrize(
    ("path", "name"),
    [
        ("a.vtu", "vtu"),
        ("A.VTU", "vtu"),
        ("a.vtk", "vtk"),
        ("a.xdmf", "xdmf"),
        ("a.msh", "msh"),
        ("a.mat", "mat"),
        ("a.npz", "npz"),
        ("case/constant/polyMesh", "openfoam"),
    ],
)
def test_format_for_path(path: str, name: str) -> None:
    assert bio.format_for_path(path).name == name


def test_format_for_existing_directory_is_openfoam(tmp_path: Path) -> None:
    assert bio.format_for_path(tmp_path).name == "openfoam"
    assert bio.format_for_path("x.dat", "VTU").name == "vtu"
    assert bio.format_for_path("x.dat", ".msh").name == "msh"


def test_unknown_extension_lists_formats(mesh: Mesh, tmp_path: Path) -> None:
    with pytest.raises(ExportError) as info:
        bio.write(mesh, tmp_path / "mesh.stl")
    msg = str(info.value)
    assert "'.stl'" in msg
    for ext in (".vtu", ".vtk", ".xdmf", ".msh", ".mat", ".npz", "polyMesh"):
        assert ext in msg
    assert "format= (vtu|vtk|xdmf|msh|mat|openfoam|npz)" in msg
    assert "--format" not in msg  # the library speaks of its arguments, the CLI of its flags
    assert not any(tmp_path.iterdir())
    assert isinstance(info.value, BlockMeshError)


def test_unknown_format_name(mesh: Mesh, tmp_path: Path) -> None:
    with pytest.raises(ExportError, match=r"unknown format 'stl'; format= takes vtu\|vtk\|xdmf"):
        bio.write(mesh, tmp_path / "x", format="stl")


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_missing_directory_is_named(mesh: Mesh, tmp_path: Path, name: str) -> None:
    missing = tmp_path / "no" / "such"
    with pytest.raises(ExportError, match=f"the directory {missing} does not exist"):
        bio.write(mesh, target(bio.FORMATS[name], missing), format=name)
    assert listing(tmp_path) == []


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_a_file_in_the_path_is_named(mesh: Mesh, tmp_path: Path, name: str) -> None:
    (tmp_path / "file").write_text("not a folder")
    with pytest.raises(ExportError, match=f"{tmp_path / 'file'} is a file, not a directory"):
        bio.write(mesh, target(bio.FORMATS[name], tmp_path / "file" / "sub"), format=name)
    assert listing(tmp_path) == ["file"]


def test_options_are_checked(mesh: Mesh, tmp_path: Path) -> None:
    default = bio.write(mesh, tmp_path / "m.msh")  # the default split, tri5
    assert bio.read(default).n_cells == mesh.n_cells
    assert bio.FORMATS["msh"].default_split == "tri5"
    default.unlink()
    with pytest.raises(ExportError, match="split 'tri4' is not available.*tri5, tri3, quad5"):
        bio.write(mesh, tmp_path / "m.msh", split="tri4")
    with pytest.raises(ExportError, match="applies to msh only"):
        bio.write(mesh, tmp_path / "m.vtu", split="tri5")
    with pytest.raises(
        ExportError, match="compression 'lzma' is not available for xdmf.*none, zlib"
    ):
        bio.write(mesh, tmp_path / "m.xdmf", compression="lzma")
    with pytest.raises(ExportError, match="option dz is not known to the vtu writer"):
        bio.write(mesh, tmp_path / "m.vtu", dz=1.0)
    with pytest.raises(ExportError, match="takes a blockmesh Mesh"):
        bio.write("not a mesh", tmp_path / "m.vtu")
    with pytest.raises(ExportError, match="it is a directory"):
        bio.write(mesh, tmp_path, format="vtu")
    assert listing(tmp_path) == []


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_options_a_format_does_not_take_name_its_options(
    mesh: Mesh, tmp_path: Path, name: str
) -> None:
    """Every option a format does not take is an error listing the options it takes."""
    fmt = bio.FORMATS[name]
    path = target(fmt, tmp_path)
    options = fmt.describe_options()
    assert "--" not in options
    for value in ("lzma", "zlib", "bzip2"):
        if value in fmt.compressions:
            continue
        with pytest.raises(ExportError) as info:
            bio.write(mesh, path, format=name, compression=value)
        assert name in str(info.value)
        if len(fmt.compressions) > 1:
            assert ", ".join(fmt.compressions) in str(info.value)
        else:
            assert f"its options: {options}" in str(info.value)
    if not fmt.splits:
        with pytest.raises(ExportError, match=f"its options: {re.escape(options)}"):
            bio.write(mesh, path, format=name, split="tri3")
    with pytest.raises(ExportError, match=r"option colour is not known .*its options: "):
        bio.write(mesh, path, format=name, colour="red")
    bio.write(mesh, path, format=name, compression="none")  # every format takes "none"
    assert bio.read(path, format=name).n_cells == mesh.n_cells


def test_read_errors(tmp_path: Path) -> None:
    with pytest.raises(ExportError, match="does not exist"):
        bio.read(tmp_path / "none.vtu")
    bad = tmp_path / "bad.msh"
    bad.write_text("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n")
    with pytest.raises(ExportError, match="binary"):
        bio.read(bad)


# -------------------------------------------------------------------------- round trips
@pytest.mark.parametrize("level", [0, 1, 3])
@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_round_trip_levels(tmp_path: Path, level: int, name: str) -> None:
    fmt = bio.FORMATS[name]
    m = sp_mesh(level)
    path = bio.write(m, target(fmt, tmp_path), format=name)
    back = bio.read(path, format=name)
    assert_same(back, m, **lossless(fmt))
    assert back.level == (m.level if name != "openfoam" else 0)


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_names_and_ids_survive(mesh: Mesh, tmp_path: Path, name: str) -> None:
    """Three patches (one with a space), two regions, block ids and parents, mesh name."""
    fmt = bio.FORMATS[name]
    back = bio.read(bio.write(mesh, target(fmt, tmp_path), format=name), format=name)
    if name == "openfoam":  # OpenFOAM words: the space becomes "_"
        assert back.patch_names == ("outer_wall", "inlet", "outlet")
        back = back.with_patches(back.boundary_patch, mesh.patch_names)
    else:
        assert (back.name, back.level) == (mesh.name, mesh.level)
    assert_same(back, mesh, **lossless(fmt))


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_every_file_ends_up_in_place(mesh: Mesh, tmp_path: Path, name: str) -> None:
    """No temporary is left beside the output, and writing again replaces it whole."""
    fmt = bio.FORMATS[name]
    path = target(fmt, tmp_path)
    bio.write(sp_mesh(1), path, format=name)
    first = listing(tmp_path)
    bio.write(mesh, path, format=name)
    assert len(listing(tmp_path)) == len(first)
    assert not [p for p in tmp_path.rglob(".*")]
    assert bio.read(path, format=name).n_cells == mesh.n_cells


# ---------------------------------------------------------------- failures keep the old
def _commit_fails(monkeypatch: pytest.MonkeyPatch, error: BaseException) -> None:
    """Make every rename of the atomic module raise ``error`` (the commit fails)."""

    def boom(*args: object, **kw: object) -> None:
        raise error

    patch_atomic_os(monkeypatch, replace=boom, rename=boom)
    monkeypatch.setattr(atomic, "_exchange", lambda a, b: boom())


@pytest.mark.parametrize("error", [KeyboardInterrupt("simulated"), OSError(errno.EIO, "I/O")])
@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_failed_commit_keeps_old_output(
    mesh: Mesh,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    name: str,
    error: BaseException,
) -> None:
    fmt = bio.FORMATS[name]
    path = target(fmt, tmp_path)
    bio.write(sp_mesh(1), path, format=name)
    before = snapshot(tmp_path)
    _commit_fails(monkeypatch, error)
    with pytest.raises((KeyboardInterrupt, ExportError)):
        bio.write(mesh, path, format=name)
    monkeypatch.undo()
    assert snapshot(tmp_path) == before  # old files intact, no temporary left
    assert bio.read(path, format=name).n_cells == 6


def _breaking_points() -> list[tuple[str, str, str]]:
    """(format, object to break, attribute) per file format: a failure in the middle."""
    return [
        ("vtu", "blockmesh.io.vtu.writer", "_write_raw"),
        ("vtk", "blockmesh.io.vtk.format", "_field_block"),
        ("xdmf", "blockmesh.io.xdmf.writer", "_xdmf_tree"),
        ("msh", "blockmesh.io.msh.writer", "_write_blocks"),
        ("mat", "scipy.io", "savemat"),
        ("npz", "numpy", "savez"),
        ("openfoam", "blockmesh.io.openfoam.writer", "_write_polymesh"),
    ]


@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
@pytest.mark.parametrize(("name", "module", "attr"), _breaking_points())
def test_failed_write_keeps_old_file(
    mesh: Mesh,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    name: str,
    module: str,
    attr: str,
    error: type[BaseException],
) -> None:
    import importlib

    assert set(FORMAT_NAMES) == {n for n, _, _ in _breaking_points()}
    path = target(bio.FORMATS[name], tmp_path)
    old = bio.write(sp_mesh(1), path, format=name)
    before = snapshot(tmp_path)

    def boom(*args: object, **kw: object) -> None:
        raise error("simulated failure mid-write")

    monkeypatch.setattr(importlib.import_module(module), attr, boom)
    with pytest.raises(error, match="simulated"):
        bio.write(mesh, path, format=name)
    assert snapshot(tmp_path) == before  # old file(s) intact, no temporary left
    monkeypatch.undo()
    assert bio.read(old, format=name).n_cells == 6


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_failed_first_write_leaves_nothing(
    mesh: Mesh, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str
) -> None:
    def boom(*args: object, **kw: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(text, "_as_matrix", boom)  # the text formats (msh, openfoam)
    patch_atomic_os(monkeypatch, replace=boom, rename=boom)  # and the commit of every format
    monkeypatch.setattr(atomic, "_exchange", lambda a, b: boom())
    with pytest.raises(ExportError, match="disk full"):
        bio.write(mesh, target(bio.FORMATS[name], tmp_path), format=name)
    assert listing(tmp_path) == []


# ------------------------------------------------------------------- operating-system errors
@pytest.mark.parametrize(
    ("code", "words"),
    [
        (errno.EROFS, "Read-only file system (EROFS); write to a folder on a writable"),
        (errno.EACCES, "Permission denied (EACCES); check the folder's permissions"),
        (errno.ENOSPC, "No space left on device (ENOSPC); free some space"),
        (errno.EDQUOT, "(EDQUOT)"),
    ],
)
@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_os_errors_are_one_readable_error(
    mesh: Mesh,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    name: str,
    code: int,
    words: str,
) -> None:
    """The temporary cannot be created (read-only, forbidden, full): ExportError, path, cause."""
    fmt = bio.FORMATS[name]
    path = target(fmt, tmp_path)
    bio.write(sp_mesh(1), path, format=name)
    before = snapshot(tmp_path)

    def refuse(*args: object, **kw: object) -> int:
        raise OSError(code, os.strerror(code), str(args[0]))

    patch_atomic_os(monkeypatch, open=refuse, mkdir=refuse)
    with pytest.raises(ExportError) as info:
        bio.write(mesh, path, format=name)
    monkeypatch.undo()
    message = str(info.value)
    assert message.startswith(f"cannot write {path.absolute()}") or message.startswith(
        f"cannot write {path.absolute() / 'constant' / 'polyMesh'}"
    ), message
    assert words in message
    assert isinstance(info.value.__cause__, OSError)
    assert snapshot(tmp_path) == before


STRACE = shutil.which("strace")


@pytest.mark.skipif(STRACE is None, reason="strace is not installed (apt-get install strace)")
@pytest.mark.parametrize("name", slow_except(FORMAT_NAMES, "vtu"))
def test_disk_full_during_the_write(tmp_path: Path, name: str) -> None:
    """A real ENOSPC from the kernel (strace fault injection) in the middle of the data."""
    fmt = bio.FORMATS[name]
    path = target(fmt, tmp_path)
    bio.write(sp_mesh(1), path, format=name)
    before = snapshot(tmp_path)
    script = textwrap.dedent(
        f"""
        import os, sys
        sys.path.insert(0, {str(Path(__file__).parents[1])!r})
        import blockmesh.io as bio
        from blockmesh.errors import ExportError
        from helpers_io import sp_mesh
        mesh = sp_mesh(3)
        os.write(1, b"go")  # the last write that is allowed
        try:
            bio.write(mesh, {str(path)!r}, format={name!r})
        except ExportError as error:
            ok = "No space left on device (ENOSPC)" in str(error) and {str(path)!r} in str(error)
            os._exit(42 if ok else 43)
        except BaseException:
            os._exit(44)
        os._exit(0)
        """
    )
    run = subprocess.run(
        [STRACE, "-f", "-qq", "-o", os.devnull, "-e", "trace=write,pwrite64,writev",
         "-e", "inject=write,pwrite64,writev:error=ENOSPC:when=2+", sys.executable, "-B", "-c",
         script],
        capture_output=True,
        timeout=300,
    )  # fmt: skip
    if run.returncode != 0 and b"ptrace" in run.stderr:
        pytest.skip(f"strace cannot trace here: {run.stderr.decode()[:200]}")
    assert run.stdout == b"go"
    assert run.returncode == 42, run.stderr.decode()[-2000:]
    assert snapshot(tmp_path) == before
    assert bio.read(path, format=name).n_cells == 6


@pytest.fixture
def full_disk(tmp_path: Path):
    """A 256 KiB tmpfs mounted at a new folder (root only; skipped where mounting is refused)."""
    folder = tmp_path / "full"
    folder.mkdir()
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(folder)],
        capture_output=True,
        check=False,
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here: {mounted.stderr.decode()[:200]}")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=False)


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_a_real_full_disk(full_disk: Path, name: str) -> None:
    """A file system that fills up during the write: one readable ENOSPC error naming the
    target, the old output whole, no temporary left. (The legacy VTK writer's short write,
    "5345 requested and 2011 written", carried no error number and was not recognised.)"""
    fmt = bio.FORMATS[name]
    path = target(fmt, full_disk)
    bio.write(sp_mesh(1), path, format=name)
    before = snapshot(full_disk)
    with pytest.raises(ExportError) as caught:
        bio.write(sp_mesh(6), path, format=name)  # 46,656 cells: megabytes, even compressed
    message = str(caught.value)
    assert "No space left on device (ENOSPC" in message and str(path) in message, message
    assert snapshot(full_disk) == before
    assert bio.read(path, format=name).n_cells == 6


def test_no_space_in_a_picture_a_table_and_a_domain_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Everything that writes through blockmesh._system.atomic gets the same readable error."""
    import blockmesh
    from blockmesh.plot import plot_mesh

    def full(*args: object, **kw: object) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    domain = blockmesh.load_domain("sp")
    mesh = domain.mesh(1)
    patch_atomic_os(monkeypatch, replace=full)
    for write, path in (
        (lambda p: plot_mesh(mesh, p), tmp_path / "m.png"),
        (domain.write_toml, tmp_path / "d.toml"),
    ):
        with pytest.raises(ExportError, match=rf"cannot write {path}: No space left on device"):
            write(path)
    assert listing(tmp_path) == []


def test_no_space_on_the_command_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from helpers import run_cli

    def full(*args: object, **kw: object) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    patch_atomic_os(monkeypatch, replace=full)
    for argv in (
        ["mesh", "sp", "--level", "1", "-o", str(tmp_path / "m.vtu")],
        ["mesh", "sp", "--level", "1", "--plot", str(tmp_path / "m.png")],
        ["tables", "--table", "1", "--levels", "1", "--csv", str(tmp_path / "t.csv")],
    ):
        code, _, err = run_cli(capsys, *argv)
        assert code == 2, err
        assert "No space left on device (ENOSPC)" in err and "Traceback" not in err, err
    assert listing(tmp_path) == []


def test_points_come_back_bit_for_bit(tmp_path: Path) -> None:
    """Coordinates that are not short decimals survive every format exactly."""
    m = sp_mesh(2)
    m = m.with_points(m.points * np.pi + 1e-7)
    for name, fmt in bio.FORMATS.items():
        (tmp_path / name).mkdir()
        back = bio.read(bio.write(m, target(fmt, tmp_path / name), format=name), format=name)
        np.testing.assert_array_equal(back.points, m.points)


# ----------------------------------------------------------------------- command line
def test_cli_passes_the_compression(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from helpers import run_cli

    heads = {}
    for value in ("none", "zlib", "lzma"):
        path = tmp_path / f"{value}.vtu"
        code, _, err = run_cli(
            capsys, "mesh", "sp", "--level", "2", "-o", str(path), "--compression", value
        )
        assert code == 0, err
        heads[value] = path.read_bytes()[:300]
        assert_same(bio.read(path), bio.read(tmp_path / "none.vtu"))
    assert b"compressor" not in heads["none"]
    assert b"vtkZLibDataCompressor" in heads["zlib"] and b"vtkLZMADataCompressor" in heads["lzma"]
    code, _, err = run_cli(
        capsys, "mesh", "sp", "--level", "2", "-o", str(tmp_path / "z.mat"), "--compression", "zlib"
    )
    assert code == 0, err
    plain = bio.write(bio.read(tmp_path / "z.mat"), tmp_path / "p.mat")
    assert (tmp_path / "z.mat").stat().st_size < plain.stat().st_size


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["-o", "x.msh", "--split", "tri3", "--compression", "lzma"], "msh takes no compression"),
        (
            ["-o", "case", "--format", "openfoam", "--compression", "zlib"],
            "openfoam takes no compression",
        ),
        (
            ["-o", "x.xdmf", "--compression", "lzma"],
            "not available for xdmf; choose one of none, zlib",
        ),
        (["-o", "x.vtu", "--split", "tri5"], "applies to msh only; vtu keeps the pentagons"),
    ],
)
def test_cli_refuses_options_the_format_does_not_take(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    from helpers import run_cli

    argv = [str(tmp_path / a) if a in ("x.msh", "case", "x.xdmf", "x.vtu") else a for a in argv]
    code, out, err = run_cli(capsys, "mesh", "sp", "--level", "1", *argv)
    assert code == 2 and message in err, err
    assert "its options" in err or "choose one of" in err, err
    assert "Traceback" not in err and out == ""  # refused before meshing
    assert listing(tmp_path) == []


def test_cli_msh_has_a_default_split(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from helpers import run_cli

    code, _, err = run_cli(capsys, "mesh", "l-shape", "--level", "1", "-o", str(tmp_path / "m.msh"))
    assert code == 0, err
    assert '"split":"tri5"' in (tmp_path / "m.msh").read_text()


@pytest.mark.parametrize("name", FORMAT_NAMES)
def test_a_broken_mesh_is_not_written(tmp_path: Path, name: str) -> None:
    """The final guard (Mesh.check_geometry) runs before every write: a counter-clockwise but
    not convex pentagon (an arrow head) is refused, and nothing is written."""
    arrow = np.array([[-1, -1], [1, -1], [2, 0], [0, -0.5], [-2, 0.0]])
    broken = Mesh.from_cells(arrow, [[0, 1, 2, 3, 4]])
    with pytest.raises(ExportError, match="not strictly convex and counter-clockwise"):
        bio.write(broken, target(bio.FORMATS[name], tmp_path), format=name)
    assert listing(tmp_path) == []


def _damaged(data: bytes, seed: int) -> bytes:
    """``data`` with a few bytes changed, a piece cut out or the end cut off."""
    rng = np.random.default_rng(seed)
    kind = seed % 3
    out = bytearray(data)
    if kind == 0:
        for at in rng.integers(0, len(out), 4):
            out[at] = int(rng.integers(0, 256))
    elif kind == 1:
        a = int(rng.integers(0, len(out)))
        del out[a : a + int(rng.integers(1, 200))]
    else:
        del out[int(rng.integers(0, len(out))) :]
    return bytes(out)


@pytest.mark.parametrize("name", CHEAP_TO_DAMAGE)
def test_damaged_files_give_export_errors(tmp_path: Path, name: str) -> None:
    """Reading a damaged file gives an ExportError (or a valid mesh), never another exception."""
    fmt = bio.FORMATS[name]
    good = tmp_path / "good"
    good.mkdir()
    path = bio.write(tagged(1), target(fmt, good), format=name)
    files = [p for p in good.rglob("*") if p.is_file() and "system" not in p.parts]
    for seed in range(40):
        work = tmp_path / f"s{seed}"
        shutil.copytree(good, work)
        victim = files[seed % len(files)]
        copy = work / victim.relative_to(good)
        copy.write_bytes(_damaged(victim.read_bytes(), seed))
        try:
            back = bio.read(
                work / path.relative_to(good) if not fmt.directory else work / "case", format=name
            )
        except ExportError:
            continue
        assert back.n_cells > 0  # a damage the format does not notice still gives a valid Mesh
