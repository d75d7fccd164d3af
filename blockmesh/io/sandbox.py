"""meshio (and the gmsh API) on files nobody vouches for: in a child process, within limits.

blockmesh's own readers check every size a file declares; meshio's readers do not. They inflate
compressed blocks whole, loop over counts a file states (a ``.msh`` announcing 10^12 string tags
loops at its end), copy text for every array of a file, and may call ``sys.exit``; the gmsh API
can crash the interpreter. So files that blockmesh's readers do not handle (another tool's VTU,
a triangle mesh to convert, the formats only meshio reads) are read by meshio in a child process
whose address space and CPU time are limited (``setrlimit``):

- memory: the read's limit (:class:`blockmesh._system.bounded.ReadGuard`), and at most
  :data:`MEMORY_BASE` plus :data:`MEMORY_PER_BYTE` times what the file may expand to
  (:attr:`~blockmesh._system.bounded.ReadGuard.expansion_allowed`);
- CPU time: :data:`CPU_SECONDS` plus one second per :data:`BYTES_PER_SECOND` bytes of the file.

The child hands the mesh back as a plain ``.npz`` (no pickles), read with
``allow_pickle=False``. A child that fails, runs out of its memory or time, or dies, becomes one
:class:`~blockmesh.errors.ExportError` naming the file. Where ``setrlimit`` does not exist (not
POSIX) meshio runs in this process.

Examples
--------
>>> import pathlib, tempfile, meshio, numpy as np
>>> path = pathlib.Path(tempfile.mkdtemp()) / "t.vtu"
>>> meshio.write(path, meshio.Mesh(np.eye(3), [("triangle", np.array([[0, 1, 2]]))]))
>>> read_with_meshio(path).cells[0].type
'triangle'
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.bounded import (
    CHILD_LIMITS,
    MAX_EXPANSION,
    check_regular,
    current_guard,
    open_regular,
)
from blockmesh.errors import ExportError

__all__ = [
    "BYTES_PER_SECOND",
    "CPU_SECONDS",
    "MAX_VTU_ARRAYS",
    "MEMORY_BASE",
    "MEMORY_PER_BYTE",
    "read_with_meshio",
]

#: Memory meshio may use per byte the file may expand to (its text, a tree, decoded copies),
#: on top of :data:`MEMORY_BASE`.
MEMORY_PER_BYTE = 2
#: Memory meshio may use for any file.
MEMORY_BASE = 64 * 2**20
#: CPU seconds meshio may take for any file, on top of one per :data:`BYTES_PER_SECOND` bytes.
CPU_SECONDS = 6
#: Bytes meshio reads per CPU second, at the least (it reads 20-100 MB/s).
BYTES_PER_SECOND = 2 * 2**20
#: Most data arrays of a VTU file given to meshio, which copies the appended data for each one.
MAX_VTU_ARRAYS = 1_000

_CHILD = r"""
import contextlib, io, json, os, resource, sys
path, out, kind = sys.argv[1], sys.argv[2], sys.argv[5]
memory, cpu = int(sys.argv[3]), int(sys.argv[4])
import numpy as np
import meshio

{limits}
used = resource.getrusage(resource.RUSAGE_SELF)
_lower(resource.RLIMIT_AS, _vm() + memory)
spent = int(used.ru_utime + used.ru_stime) + 1
_lower(resource.RLIMIT_CPU, spent + cpu)

def fail(code, text):
    sys.stderr.write(" ".join(str(text).split())[:600] + "\n")
    sys.stderr.flush()
    os._exit(code)

try:
    with contextlib.redirect_stdout(io.StringIO()):
        if kind == "vtu":
            mesh = meshio.vtu.read(path)
        elif kind == "vtk":
            mesh = meshio.vtk.read(path)
        else:
            try:
                mesh = meshio.read(path)
            except BaseException as first:
                if not path.lower().endswith(".msh"):
                    raise
                try:
                    import gmsh  # noqa: F401
                except ImportError:
                    raise first from None
                from blockmesh.decompose.conversion import _read_with_gmsh
                mesh = _read_with_gmsh(path)
except MemoryError:
    fail(4, "it needs more memory than allowed")
except BaseException as error:
    fail(3, f"{type(error).__name__}: {error}")

try:
    arrays = {"points": np.asarray(mesh.points)}
    meta = {"cells": [], "cell_data": [], "cell_sets": [], "field_data": []}
    for k, block in enumerate(mesh.cells):
        meta["cells"].append(str(block.type))
        arrays[f"c{k}"] = np.asarray(block.data)
    for i, (name, parts) in enumerate(mesh.cell_data.items()):
        meta["cell_data"].append([str(name), len(parts)])
        for k, part in enumerate(parts):
            arrays[f"d{i}_{k}"] = np.asarray(part)
    for i, (name, parts) in enumerate(mesh.cell_sets.items()):
        meta["cell_sets"].append([str(name), len(parts)])
        for k, part in enumerate(parts):
            arrays[f"s{i}_{k}"] = np.asarray([] if part is None else part)
    for i, (name, value) in enumerate(mesh.field_data.items()):
        meta["field_data"].append(str(name))
        arrays[f"f{i}"] = np.asarray(value)
    for key, value in arrays.items():
        if value.dtype.kind not in "biuf":
            fail(3, f"meshio gave {value.dtype} data ({key}); blockmesh takes numbers")
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    with open(out, "wb") as f:
        np.savez(f, **arrays)
except MemoryError:
    fail(4, "it needs more memory than allowed")
except BaseException as error:
    fail(3, f"{type(error).__name__}: {error}")
""".replace("{limits}", CHILD_LIMITS)


def _limits(size: int) -> tuple[int, int]:
    """Memory (bytes) and CPU seconds allowed for reading a file of ``size`` bytes."""
    guard = current_guard()
    allowance = guard.expansion_allowed + MAX_EXPANSION * size  # this file's share as well
    memory = min(max(guard.limit - guard.allocated, 0), MEMORY_BASE + MEMORY_PER_BYTE * allowance)
    return memory, CPU_SECONDS + size // BYTES_PER_SECOND


def read_with_meshio(path: str | os.PathLike[str], kind: str = "auto") -> Any:
    """The :class:`meshio.Mesh` of ``path`` read by meshio in a limited child process.

    ``kind`` is ``"vtu"`` or ``"vtk"`` for those readers of meshio, else ``"auto"``
    (:func:`meshio.read` by the extension; for a ``.msh`` it cannot read, the gmsh API where
    installed).

    Raises
    ------
    ExportError
        A file that is not regular, that meshio cannot read, or whose reading needs more memory
        or time than allowed (see the module notes).
    """
    path = Path(path)
    where = str(path)
    size = check_regular(path).st_size
    if kind == "vtu" or (kind == "auto" and path.suffix.lower() == ".vtu"):
        _count_arrays(path, where)
    memory, cpu = _limits(size)
    if not hasattr(os, "fork") or sys.platform == "win32":  # no setrlimit: read it here
        return _in_process(path, kind)
    folder = Path(tempfile.mkdtemp(prefix="blockmesh-meshio-"))
    out = folder / "mesh.npz"
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    env.pop("PYTHONSTARTUP", None)
    argv = [sys.executable, "-c", _CHILD, where, str(out), str(memory), str(cpu), kind]
    try:
        try:
            child = subprocess.run(
                argv,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                timeout=3 * cpu + 20,
                env=env,
                check=False,
            )
        except subprocess.TimeoutExpired:
            raise ExportError(
                f"cannot read {where}: meshio did not finish within {3 * cpu + 20} s; the file "
                "is damaged or made to stall a reader"
            ) from None
        told = child.stderr.decode(errors="replace").strip().splitlines()
        reason = told[-1] if told else ""
        if child.returncode == 4 or (child.returncode != 0 and "MemoryError" in reason):
            raise ExportError(
                f"cannot read {where}: meshio needs more than the {memory:,} bytes allowed for "
                "this file (a damaged file, a decompression bomb, or too little memory free)"
            )
        if child.returncode in (-signal.SIGXCPU, -signal.SIGKILL):
            raise ExportError(
                f"cannot read {where}: meshio took more than its {cpu} s of CPU time; the file "
                "is damaged or made to stall a reader"
            )
        if child.returncode != 0:
            died = f" (it died of signal {-child.returncode})" if child.returncode < 0 else ""
            raise ExportError(f"cannot read {where} with meshio{died}: {reason or 'no reason'}")
        return _mesh_from_npz(out, where)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _count_arrays(path: Path, where: str) -> None:
    """ExportError when a VTU file has more than :data:`MAX_VTU_ARRAYS` data arrays.

    meshio copies the rest of the appended data for each array (quadratic time); the tags are
    counted first, a chunk at a time.
    """
    token, count, tail = b"<DataArray", 0, b""
    with open_regular(path) as handle:
        while chunk := handle.read(1 << 22):
            data = tail + chunk
            count += data.count(token)
            tail = data[-(len(token) - 1) :]
            if count > MAX_VTU_ARRAYS:
                raise ExportError(
                    f"cannot read {where}: it has more than {MAX_VTU_ARRAYS:,} data arrays "
                    "(meshio, which reads other tools' VTU files, takes time quadratic in them)"
                )


def _in_process(path: Path, kind: str) -> Any:
    import contextlib
    import io

    import meshio

    try:
        with contextlib.redirect_stdout(io.StringIO()):
            if kind == "vtu":
                return meshio.vtu.read(str(path))
            if kind == "vtk":
                return meshio.vtk.read(str(path))
            return meshio.read(path)
    except (Exception, SystemExit) as error:  # meshio raises many kinds, and may even exit
        raise ExportError(f"cannot read {path} with meshio: {error}") from None


def _mesh_from_npz(out: Path, where: str) -> Any:
    """The meshio mesh the child wrote to ``out``."""
    import meshio

    try:
        with np.load(out, allow_pickle=False) as data:
            meta = json.loads(bytes(data["meta"]).decode())
            cells = [(kind, data[f"c{k}"]) for k, kind in enumerate(meta["cells"])]
            cell_data = {
                name: [data[f"d{i}_{k}"] for k in range(n)]
                for i, (name, n) in enumerate(meta["cell_data"])
            }
            cell_sets = {
                name: [data[f"s{i}_{k}"] for k in range(n)]
                for i, (name, n) in enumerate(meta["cell_sets"])
            }
            field_data = {name: data[f"f{i}"] for i, name in enumerate(meta["field_data"])}
            points = data["points"]
        return meshio.Mesh(
            points, cells, cell_data=cell_data, cell_sets=cell_sets, field_data=field_data
        )
    except Exception as error:  # what meshio handed back does not make a mesh
        raise ExportError(f"cannot read {where}: meshio's result is not a mesh ({error})") from None
