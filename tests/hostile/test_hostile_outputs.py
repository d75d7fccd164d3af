"""Outputs go only where a regular file may go; partitioned outputs commit whole (issue 26).

Every test works in its own temporary folder: FIFOs, sockets and device nodes are made there
(a device only when running as root), and ``/dev/null`` is reached only through a link in that
folder, so a regression replaces the link, never the system's node.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest
from helpers import missing, slow_except
from helpers_hostile import assert_refused, listing, run_blockmesh

import blockmesh
import blockmesh.distributed as bd
from blockmesh._system.atomic import atomic_with_folder
from blockmesh.errors import ExportError

FILE_FORMATS = [".vtu", ".vtk", ".xdmf", ".msh", ".mat", ".npz"]


def _fifo(folder: Path, name: str) -> Path:
    path = folder / name
    os.mkfifo(path)
    return path


def _null_link(folder: Path, name: str) -> Path:
    path = folder / name
    path.symlink_to("/dev/null")
    return path


def _socket(folder: Path, name: str) -> Path:
    path = folder / name
    with socket.socket(socket.AF_UNIX) as s:
        s.bind(str(path))
    return path


MAKERS = {"fifo": _fifo, "link to /dev/null": _null_link, "socket": _socket}


@pytest.mark.parametrize("kind", sorted(MAKERS))
@pytest.mark.parametrize("suffix", slow_except(FILE_FORMATS, ".vtu", ".xdmf"))
def test_an_output_onto_a_special_file_is_refused_before_anything_is_written(
    tmp_path, kind, suffix
):
    target = MAKERS[kind](tmp_path, f"out{suffix}")
    before = listing(tmp_path)
    run = run_blockmesh("mesh", "sp", "--level", "1", "-o", target.name, cwd=tmp_path)
    assert_refused(run, names=(target.name, "not a regular file"))
    assert listing(tmp_path) == before
    assert os.readlink(target) == "/dev/null" if kind.startswith("link") else True


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="mknod needs root")
def test_a_device_node_as_output_is_refused_and_stays_a_device(tmp_path):
    device = tmp_path / "null.vtu"
    os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 3))  # a /dev/null of our own
    run = run_blockmesh("mesh", "sp", "--level", "1", "-o", device.name, cwd=tmp_path)
    assert_refused(run, names=("character device",))
    assert stat.S_ISCHR(device.lstat().st_mode)


@pytest.mark.parametrize(
    "argv",
    [
        ("mesh", "sp", "--level", "1", "--plot", "{target}"),
        ("mesh", "sp", "--level", "1", "--quality-plot", "{target}"),
        ("show", "sp", "-o", "{target}"),
        ("solve", "sp", "--level", "1", "-o", "{target}"),
        ("mesh", "sp", "--level", "1", "--partitions", "2", "-o", "{target}"),
    ],
    ids=["plot", "quality-plot", "show", "solve", "partitioned index"],
)
def test_every_command_refuses_a_fifo_output(tmp_path, argv):
    suffix = ".pvtu" if "--partitions" in argv else ".vtu" if argv[0] == "solve" else ".png"
    target = _fifo(tmp_path, f"out{suffix}")
    before = listing(tmp_path)
    run = run_blockmesh(*(a.replace("{target}", target.name) for a in argv), cwd=tmp_path)
    assert_refused(run, names=("FIFO",))
    assert listing(tmp_path) == before


def test_convert_refuses_a_fifo_output(tmp_path):
    source = tmp_path / "in.npz"
    blockmesh.write(blockmesh.load_domain("sp").mesh(1), source)
    target = _fifo(tmp_path, "out.toml")
    before = listing(tmp_path)
    run = run_blockmesh("convert", source.name, "-o", target.name, cwd=tmp_path)
    assert_refused(run, names=("FIFO",))
    assert listing(tmp_path) == before


def test_a_directory_output_for_a_file_format_is_refused(tmp_path):
    (tmp_path / "out.vtu").mkdir()
    before = listing(tmp_path)
    run = run_blockmesh("mesh", "sp", "--level", "1", "-o", "out.vtu", cwd=tmp_path)
    assert_refused(run, names=("directory",))
    assert listing(tmp_path) == before


def test_an_openfoam_case_where_a_fifo_is_is_refused(tmp_path):
    _fifo(tmp_path, "case")
    before = listing(tmp_path)
    run = run_blockmesh(
        "mesh", "sp", "--level", "1", "-o", "case", "--format", "openfoam", cwd=tmp_path
    )
    assert_refused(run, names=("FIFO",))
    assert listing(tmp_path) == before


def test_escape_sequences_in_paths_never_reach_the_terminal(tmp_path):
    name = "f\x1b]0;pwned\x07x.vtu"
    run = run_blockmesh("mesh", "sp", "--level", "1", "-o", name, cwd=tmp_path)
    assert run.code == 0, run.describe()
    assert (tmp_path / name).is_file()
    assert "\x1b" not in run.out + run.err and "\x07" not in run.out + run.err
    assert "\\x1b]0;pwned\\x07x.vtu" in run.out
    bad_input = "in\x1b[2Jput.vtu"
    run = run_blockmesh("check", bad_input, cwd=tmp_path)
    assert_refused(run, names=("in\\x1b[2Jput.vtu",))
    assert "\x1b" not in run.out + run.err


def test_a_failed_templated_write_leaves_no_folder(tmp_path):
    (tmp_path / "blocker").mkdir()
    # the output of sp is a folder already (a file format cannot go there): the write fails
    pattern = "out/{name}/deeper/{name}.vtu"
    (tmp_path / "out" / "sp" / "deeper" / "sp.vtu").mkdir(parents=True)
    before = listing(tmp_path)
    run = run_blockmesh("mesh", "sp", "usp", "--level", "1", "-o", pattern, cwd=tmp_path)
    assert run.code == 1, run.describe()
    assert "sp.vtu: it is a directory" in run.err
    assert (tmp_path / "out" / "usp" / "deeper" / "usp.vtu").is_file()
    assert listing(tmp_path).keys() - before.keys() == {
        "out/usp",
        "out/usp/deeper",
        "out/usp/deeper/usp.vtu",
    }


def test_a_failed_templated_write_removes_the_folders_it_made(tmp_path, monkeypatch, capsys):
    import blockmesh.commands.mesh.single
    from blockmesh.cli import main

    def failing(*_args, **_kwargs):
        raise ExportError("the disk is full (simulated)")

    monkeypatch.setattr(blockmesh.commands.mesh.single, "write", failing)  # the command's reference
    monkeypatch.chdir(tmp_path)
    code = main(["mesh", "sp", "--level", "1", "-o", "new/{name}/m-{level}.vtu"])
    assert code == 2 and "simulated" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------------- partitioned
def test_a_partitioned_write_commits_whole_and_cleans_up(tmp_path):
    index = tmp_path / "m.pvtu"
    pieces = tmp_path / "m.pvtu.pieces"
    with atomic_with_folder(index, pieces) as (light, data, generation):
        (data / "p0").write_text("first")
        light.write_text(f"m.pvtu.pieces/{generation}/p0")
    first = (tmp_path / index.read_text()).parent
    # a killed writer's leftovers: a temporary folder of a dead process, an old generation
    dead = f".deadbeef.{_host()}-999999999-abcdef.tmp"
    (pieces / dead).mkdir()
    (pieces / "0badc0de").mkdir()
    with atomic_with_folder(index, pieces) as (light, data, generation):
        (data / "p0").write_text("second")
        light.write_text(f"m.pvtu.pieces/{generation}/p0")
    assert (tmp_path / index.read_text()).read_text() == "second"
    assert [p.name for p in pieces.iterdir()] == [generation] != [first.name]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.pvtu", "m.pvtu.pieces"]
    with pytest.raises(RuntimeError), atomic_with_folder(index, pieces) as (light, data, _):
        (data / "p0").write_text("third")
        raise RuntimeError("a worker failed")
    assert (tmp_path / index.read_text()).read_text() == "second"
    assert [p.name for p in pieces.iterdir()] == [generation]


def _host() -> str:
    from blockmesh._system.atomic import _HOST

    return _HOST


_KILL_AT_RENAME = """
import sys
import blockmesh, blockmesh.distributed as bd
from dask.distributed import Client, LocalCluster
with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                  dashboard_address=None) as cluster, Client(cluster) as client:
    bd.refine_to(blockmesh.load_domain("sp"), int(sys.argv[2]), sys.argv[1], partitions=2,
                 client=client)
"""


@pytest.mark.skipif(shutil.which("strace") is None, reason="needs strace")
@pytest.mark.skipif(
    missing("dask.distributed"), reason="needs Dask (pip install -e '.[distributed]')"
)
@pytest.mark.parametrize("rename", [1, 2])
def test_a_kill_at_either_rename_of_the_commit_leaves_a_readable_mesh(tmp_path, rename):
    index = tmp_path / "m.pvtu"
    script = tmp_path.parent / f"{tmp_path.name}-write.py"
    script.write_text(_KILL_AT_RENAME)
    subprocess.run([sys.executable, str(script), str(index), "2"], check=True, timeout=120)
    assert bd.gather(index).level == 2
    # the commit's renames are: the pieces folder into place, then the index (the commit)
    killed = subprocess.run(
        [
            "strace", "-f", "-qq", "-o", "/dev/null",
            "-e", "trace=rename,renameat,renameat2",
            "-e", f"inject=rename,renameat,renameat2:signal=SIGKILL:when={rename}",
            sys.executable, str(script), str(index), "3",
        ],
        timeout=120,
    )  # fmt: skip
    assert killed.returncode != 0
    gathered = bd.gather(index)  # killed at the rename's entry: the old mesh, whole
    assert gathered.level == 2 and gathered.n_cells == 36
    # the next write cleans up what the kill left
    subprocess.run([sys.executable, str(script), str(index), "3"], check=True, timeout=120)
    assert bd.gather(index).level == 3
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.pvtu", "m.pvtu.pieces"]
    assert len(list((tmp_path / "m.pvtu.pieces").iterdir())) == 1


def _children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                found.append(int(entry.name))
    return found


@pytest.mark.parametrize("after", [0.0, 0.5])
def test_sigterm_while_the_local_cluster_starts_stops_with_one_line(tmp_path, after):
    """SIGTERM once the first worker process exists (the cluster is starting): one line, 143."""
    child = subprocess.Popen(
        [sys.executable, "-m", "blockmesh", "mesh", "sp", "--level", "2", "--partitions", "2",
         "--workers", "2", "-o", "p.pvtu"],
        cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        deadline = time.monotonic() + 60
        while child.poll() is None and not _children(child.pid) and time.monotonic() < deadline:
            time.sleep(0.01)
        time.sleep(after)
        if child.poll() is not None:
            pytest.skip("the command ended before its cluster started (machine too loaded)")
        child.send_signal(signal.SIGTERM)
        _, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode in (0, 128 + signal.SIGTERM), err
    if child.returncode:
        assert err.strip().splitlines() == ["blockmesh mesh: terminated by signal 15"], err
        assert not (tmp_path / "p.pvtu").exists()
    assert "Traceback" not in err
