"""What an HDF5 file holds, found by a child process with a time and memory limit.

The HDF5 library trusts a file's structure: a damaged one can make it loop for ever (reading a
variable-length string attribute whose heap is damaged never returns) or crash the interpreter,
and no signal interrupts it. So before blockmesh reads an HDF5 file named by an XDMF file (or a
partitioned mesh's piece), a child process opens it, reads its ``blockmesh`` attribute, and
describes every dataset reached by a link (its link kind, shape, type, filters, chunks, stored
bytes, and whether its first and last values can be read, which walks its chunk index). The
reader then checks that description and reads only the datasets it needs, in this process.

A child that runs past :data:`PROBE_SECONDS` of CPU or wall time, past :data:`PROBE_MEMORY`
bytes, or dies, makes the file refused with one :class:`~blockmesh.errors.ExportError`.

Examples
--------
>>> import pathlib, tempfile, h5py, numpy as np
>>> path = pathlib.Path(tempfile.mkdtemp()) / "d.h5"
>>> with h5py.File(path, "w") as f:
...     f.attrs["blockmesh"] = '{"level": 1}'
...     _ = f.create_dataset("mesh/points", data=np.zeros((3, 2)))
>>> found = probe_hdf5(path, "d.xdmf")
>>> found.attribute, found.datasets["mesh/points"]["shape"]
('{"level": 1}', [3, 2])
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from blockmesh._system.bounded import CHILD_LIMITS
from blockmesh.errors import ExportError

__all__ = ["PROBE_MEMORY", "PROBE_OBJECTS", "PROBE_SECONDS", "Probe", "probe_hdf5"]

#: Seconds the child may take (its metadata only: a healthy file takes milliseconds).
PROBE_SECONDS = 5
#: Bytes the child may use beyond its libraries (a file's metadata, never its data).
PROBE_MEMORY = 256 * 2**20
#: Most links the child visits.
PROBE_OBJECTS = 10_000


@dataclass(frozen=True)
class Probe:
    """What :func:`probe_hdf5` found.

    Attributes
    ----------
    attribute : str or None
        The root attribute ``blockmesh`` (JSON text), if the file has one.
    datasets : dict
        ``path -> description`` of every link (path without the leading ``/``): ``link``
        (``HardLink``, ``SoftLink``, ``ExternalLink``), and for datasets reached by hard links
        ``shape``, ``dtype`` (a numpy type string), ``chunks``, ``filters``, ``stored`` (bytes),
        ``chunks_stored``, ``virtual``, ``external`` and ``readable`` (its first and last
        values could be read).
    """

    attribute: str | None
    datasets: dict[str, dict[str, Any]] = field(default_factory=dict)


_CHILD = r"""
import json, os, resource, sys
path, memory, objects = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
import h5py, numpy as np

{limits}
_lower(resource.RLIMIT_AS, _vm() + memory)
out = {"attribute": None, "datasets": {}, "error": None}
try:
    f = h5py.File(path, "r")
    raw = f.attrs.get("blockmesh")
    if raw is not None:
        out["attribute"] = raw if isinstance(raw, str) else (
            raw.decode("utf-8", "replace") if isinstance(raw, bytes) else None)
    names = []
    def collect(name):
        names.append(name)
        return True if len(names) > objects else None
    f.visit_links(collect)
    if len(names) > objects:
        raise ValueError(f"more than {objects} links")
    for name in names:
        parent, _, base = name.rpartition("/")
        group = f[parent] if parent else f
        link = group.get(base, getlink=True)
        info = {"link": type(link).__name__}
        out["datasets"][name] = info
        if not isinstance(link, h5py.HardLink):
            continue
        node = group[base]
        if not isinstance(node, h5py.Dataset):
            info["link"] = "group"
            continue
        info.update(shape=[int(s) for s in node.shape], dtype=node.dtype.str,
                    kind=node.dtype.kind, itemsize=int(node.dtype.itemsize),
                    chunks=list(node.chunks) if node.chunks else None,
                    filters=sorted(node._filters), stored=int(node.id.get_storage_size()),
                    virtual=bool(node.is_virtual), external=bool(node.external),
                    chunks_stored=int(node.id.get_num_chunks()) if node.chunks else None,
                    readable=False)
        if node.dtype.kind in "iuf" and not node.is_virtual and not node.external:
            if node.size:
                node[(0,) * node.ndim]
                node[tuple(s - 1 for s in node.shape)]
            info["readable"] = True
except BaseException as error:
    out["error"] = f"{type(error).__name__}: {error}"
sys.stdout.write(json.dumps(out))
""".replace("{limits}", CHILD_LIMITS)


def probe_hdf5(path: str | os.PathLike[str], where: str) -> Probe:
    """What the HDF5 file ``path`` holds (see the module notes); ``where`` names the reader.

    Raises
    ------
    ExportError
        When the child cannot open or describe the file, stalls, runs out of its memory, or
        dies.
    """
    path = Path(path)
    argv = [sys.executable, "-c", _CHILD, str(path), str(PROBE_MEMORY), str(PROBE_OBJECTS)]
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    try:
        child = subprocess.run(
            argv,
            stdin=subprocess.DEVNULL,
            capture_output=True,
            timeout=PROBE_SECONDS,
            env=env,
            check=False,
        )
    except subprocess.TimeoutExpired:
        raise ExportError(
            f"{where}: the HDF5 library stalls reading {path.name} (more than {PROBE_SECONDS} s "
            "for its metadata): the file is damaged"
        ) from None
    try:
        found = json.loads(child.stdout.decode("utf-8", errors="replace"))
    except ValueError:
        found = None
    if child.returncode != 0 or not isinstance(found, dict):
        died = f" (signal {-child.returncode})" if child.returncode < 0 else ""
        raise ExportError(
            f"{where}: the HDF5 library cannot read {path.name}{died}: the file is damaged"
        )
    if found.get("error"):
        raise ExportError(f"cannot read {path} as HDF5: {str(found['error'])[:300]}")
    return Probe(found.get("attribute"), dict(found.get("datasets") or {}))
