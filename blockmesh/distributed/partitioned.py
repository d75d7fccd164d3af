"""Partitioned meshes: made and written piece by piece on the workers, and gathered back.

:func:`refine_to` writes the index and its pieces (a folder of their own at every write, committed
with the index); :func:`gather` reads them back into one :class:`~blockmesh.mesh.Mesh`.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh._system.atomic import atomic_with_folder
from blockmesh._system.bounded import reading
from blockmesh._system.targets import check_target
from blockmesh.distributed.budget import check_workers
from blockmesh.distributed.cluster import ProgressCallback, dask_client, run_tasks
from blockmesh.distributed.files import (
    INDEX_SUFFIXES,
    piece_name,
    pieces_dir,
    read_piece,
    read_pieces,
    write_pvtu_index,
    write_xdmf_index,
)
from blockmesh.distributed.partition import Partitioning, partition
from blockmesh.distributed.tasks import write_piece_task
from blockmesh.errors import ExportError
from blockmesh.mesh.mesh import Mesh, MeshQuality

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain


@dataclass(frozen=True)
class PartitionedMesh:
    """What :func:`refine_to` made: the index, its pieces and the summary of the whole mesh.

    Attributes
    ----------
    path : Path
        The index (``.pvtu`` or ``.xdmf``).
    pieces : tuple of Path
    level, cells, nodes, boundary_edges : int
    area : float
    quality : MeshQuality
        Combined from the pieces' extremes (exactly what the whole mesh's quality is).
    bandwidth : int
        Of the nested (serial) numbering.
    seconds : float
    workers : int
    summaries : tuple of dict
        What each task returned (counts, checksums, bytes, seconds, worker, peak memory).
    """

    path: Path
    pieces: tuple[Path, ...]
    level: int
    cells: int
    nodes: int
    boundary_edges: int
    area: float
    quality: MeshQuality
    bandwidth: int
    seconds: float
    workers: int
    summaries: tuple[dict[str, Any], ...]

    @property
    def bytes_written(self) -> int:
        """Bytes of all pieces."""
        return sum(int(s["bytes"]) for s in self.summaries)

    @property
    def array_bytes(self) -> int:
        """Bytes of the pieces' arrays in memory (mesh arrays, global ids, ghost marks)."""
        return sum(int(s["array_bytes"]) for s in self.summaries)

    @property
    def worker_peak_bytes(self) -> int:
        """The highest peak resident memory a worker reported."""
        return max(int(s["peak_rss"]) for s in self.summaries)


def _index_of(path: str | os.PathLike[str]) -> Path:
    index = Path(path).absolute()
    if index.suffix.lower() not in INDEX_SUFFIXES:
        raise ExportError(
            f"cannot write a partitioned mesh to {index}: the index must be a .pvtu (ParaView "
            "parallel VTU) or an .xdmf file (XDMF collection of HDF5 pieces)"
        )
    check_target(index)
    check_target(pieces_dir(index), directory=True)  # a file or a FIFO in the way: now
    return index


def _combine(parts: Partitioning, summaries: list[dict[str, Any]]) -> tuple[float, MeshQuality]:
    if (
        sum(s["cells"] for s in summaries) != parts.n_cells
        or sum(s["owned_nodes"] for s in summaries) != parts.n_nodes
    ):
        raise ExportError(
            "the pieces do not add up to the mesh (cells or owned nodes); the output is not kept"
        )
    m = [s["measures"] for s in summaries]
    min_area = min(x["min_area"] for x in m)
    max_area = max(x["max_area"] for x in m)
    quality = MeshQuality(
        min(x["min_angle"] for x in m),
        max(x["max_angle"] for x in m),
        max(x["max_aspect_ratio"] for x in m),
        min_area,
        max_area,
        min_area / max_area if max_area > 0 else 0.0,
        sum(x["not_strictly_convex"] for x in m),
    )
    return math.fsum(x["area"] for x in m), quality


def refine_to(
    target: Domain | Mesh,
    level: int,
    path: str | os.PathLike[str],
    *,
    partitions: int | None = None,
    client: Any = None,
    workers: int | None = None,
    scheduler: str | None = None,
    memory_limit: int | str | None = None,
    progress: ProgressCallback | None = None,
) -> PartitionedMesh:
    """Refine ``target`` to ``level`` on a Dask cluster, writing one piece per partition.

    Parameters
    ----------
    target : Domain or Mesh
    level : int
        Levels of refinement (>= 1), as :func:`blockmesh.refine`.
    path : str or PathLike
        The index: ``out.pvtu`` (VTU pieces) or ``out.xdmf`` (HDF5 pieces); the pieces go to
        ``out.pvtu.pieces/<8 hex digits>/`` (``out.xdmf.pieces/...``), a new folder at every
        write. The index is renamed in last (the commit), when every piece is written: a failure
        or a kill at any step leaves the old index with its pieces, and the next write removes
        what it left.
    partitions : int, optional
        Number of pieces (default: one per worker).
    client : dask.distributed.Client, optional
        Use this client; otherwise ``scheduler`` or a local cluster (see :func:`dask_client`).
    workers, scheduler, memory_limit
        For the cluster :func:`dask_client` makes.
    progress : callable, optional
        ``progress(done, total)`` after each piece.

    Raises
    ------
    ResourceError
        When Dask is missing, a partition would not fit in a worker's memory limit (naming it
        and how many partitions would fit), or a worker runs out of memory.
    ExportError
        For an index that is not ``.pvtu``/``.xdmf`` or a missing folder.
    """
    index = _index_of(path)
    started = time.perf_counter()
    with dask_client(
        client, workers=workers, scheduler=scheduler, memory_limit=memory_limit
    ) as active:
        n_workers = len(active.scheduler_info().get("workers", {})) or 1
        parts = partition(target, level, partitions if partitions is not None else n_workers)
        check_workers(parts, active)
        with atomic_with_folder(index, pieces_dir(index)) as (index_tmp, folder, generation):
            scattered = active.scatter(parts, broadcast=True, hash=False)
            futures = [
                active.submit(write_piece_task, scattered, p, str(folder), index.name, pure=False)
                for p in range(parts.n_partitions)
            ]
            summaries = run_tasks(futures, progress)
            area, quality = _combine(parts, summaries)
            names = [piece_name(index, p) for p in range(parts.n_partitions)]
            where = f"{pieces_dir(index).name}/{generation}"
            sources = [f"{where}/{name}" for name in names]
            meta = {
                "blockmesh_partitioned": 1,
                "name": parts.base.name,
                "level": parts.base.level + parts.steps,
                "patch_names": list(parts.base.patch_names),
                "region_names": list(parts.base.region_names),
                "pieces": parts.n_partitions,
                "cells_total": parts.n_cells,
                "nodes_total": parts.n_nodes,
            }
            if index.suffix.lower() == ".pvtu":
                write_pvtu_index(index_tmp, sources, meta)
            else:
                write_xdmf_index(index_tmp, sources, summaries, meta)
    return PartitionedMesh(
        path=index,
        pieces=tuple(pieces_dir(index) / generation / name for name in names),
        level=parts.base.level + parts.steps,
        cells=parts.n_cells,
        nodes=parts.n_nodes,
        boundary_edges=sum(s["boundary_edges"] for s in summaries),
        area=area,
        quality=quality,
        bandwidth=max(s["bandwidth"] for s in summaries),
        seconds=time.perf_counter() - started,
        workers=n_workers,
        summaries=tuple(summaries),
    )


def gather(path: str | os.PathLike[str]) -> Mesh:
    """Read a partitioned mesh (its ``.pvtu`` or ``.xdmf`` index) into one Mesh.

    The pieces' nodes go to their global ids, their cells (in global ids) follow each other in
    order and their boundary edges to their places in the whole boundary list: the result equals
    the serial refinement's Mesh. Needs the whole mesh's memory, so it is for meshes that fit.
    """
    with reading(path) as guard:
        pieces = [read_piece(source) for source in read_pieces(Path(path))]
        if not pieces:
            raise ExportError(f"{path} names no pieces")
        first = pieces[0]
        if sorted(p.index for p in pieces) != list(range(first.n_pieces)) or any(
            (p.n_nodes_total, p.n_boundary_total, p.n_cells_total)
            != (first.n_nodes_total, first.n_boundary_total, first.n_cells_total)
            for p in pieces
        ):
            raise ExportError(
                f"{path}: the pieces are not 0..{first.n_pieces - 1} of one mesh (an interrupted "
                "copy? write the mesh again)"
            )
        if sum(p.mesh.n_cells for p in pieces) != first.n_cells_total:
            raise ExportError(f"{path}: the pieces do not add up to the mesh's cells")
        guard.allocate(17 * first.n_nodes_total + 24 * first.n_boundary_total, "the gathered mesh")
    pieces.sort(key=lambda p: p.index)
    points = np.empty((first.n_nodes_total, 2))
    seen = np.zeros(first.n_nodes_total, dtype=bool)
    edges = np.empty((first.n_boundary_total, 2), dtype=np.int64)
    patch = np.empty(first.n_boundary_total, dtype=np.int64)
    for piece in pieces:
        points[piece.global_node_ids] = piece.mesh.points
        seen[piece.global_node_ids] = True
        edges[piece.boundary_order] = piece.global_node_ids[piece.mesh.boundary_edges]
        patch[piece.boundary_order] = piece.mesh.boundary_patch
    if not seen.all():
        raise ExportError(f"{path}: the pieces do not cover every node")
    return Mesh._trusted(
        points=points,
        cells=np.concatenate([p.global_node_ids[p.mesh.cells] for p in pieces]),
        block_id=np.concatenate([p.mesh.block_id for p in pieces]),
        parent=np.concatenate([p.mesh.parent for p in pieces]),
        boundary_edges=edges,
        boundary_patch=patch,
        patch_names=first.mesh.patch_names,
        region=np.concatenate([p.mesh.region for p in pieces]),
        region_names=first.mesh.region_names,
        level=first.mesh.level,
        name=first.mesh.name,
    )
