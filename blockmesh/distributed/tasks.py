"""What a worker runs for one partition; each returns only small numbers, never the mesh.

These functions import nothing of Dask: a worker process calls them with the (small)
:class:`~blockmesh.distributed.partition.Partitioning` and a partition index.

Examples
--------
>>> import pathlib, tempfile, blockmesh
>>> from blockmesh.distributed.partition import partition
>>> parts = partition(blockmesh.load_domain("joined-2"), 2, 2)
>>> result = write_piece_task(parts, 1, str(tempfile.mkdtemp()), "out.pvtu")
>>> result["cells"], result["owned_nodes"], result["file"]
(36, 60, 'out_0001.vtu')
>>> halves = [integrate_piece_task(parts, p, "1", 3, "paper", 10**9).value for p in (0, 1)]
>>> round(sum(halves), 12) == round(blockmesh.load_domain("joined-2").area, 12)
True
"""

from __future__ import annotations

import os
import socket
import time
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.memory import peak_rss, process_rss
from blockmesh.distributed.files import piece_name, write_h5_piece, write_vtu_piece
from blockmesh.distributed.partition import Partitioning
from blockmesh.distributed.pieces import Piece, build_piece
from blockmesh.errors import BlockMeshWarning
from blockmesh.mesh.measures import measure_cells, widest_id_spread
from blockmesh.quadrature import integrate_with_estimate

__all__ = ["integrate_piece_task", "piece_summary", "write_piece_task"]


def _global_bandwidth(piece: Piece, chunk: int = 1 << 15) -> int:
    """Largest difference of global node ids within one cell of the piece (column by column)."""
    ids = piece.global_node_ids
    cells = piece.mesh.cells
    return max(
        (
            widest_id_spread(np.take(ids, cells[start : start + chunk].T, mode="clip"))
            for start in range(0, cells.shape[0], chunk)
        ),
        default=0,
    )


def _checksum(piece: Piece) -> int:
    """CRC-32 of the piece's coordinates, global node ids and cells (local ids)."""
    crc = zlib.crc32(np.ascontiguousarray(piece.mesh.points).data)
    crc = zlib.crc32(np.ascontiguousarray(piece.global_node_ids).data, crc)
    return zlib.crc32(np.ascontiguousarray(piece.mesh.cells).data, crc)


def piece_summary(piece: Piece) -> dict[str, Any]:
    """Counts, quality extremes and checksums of a piece: what a task sends back."""
    points = piece.mesh.points
    ghosts = points[piece.ghost]  # few: shared unit corners and edges numbered elsewhere
    owned_sum = [float(points[:, axis].sum() - ghosts[:, axis].sum()) for axis in (0, 1)]
    measures = measure_cells(piece.mesh, threads=1)  # Dask already runs pieces side by side
    return {
        "piece": piece.index,
        "cells": piece.mesh.n_cells,
        "nodes": piece.mesh.n_points,
        "owned_nodes": piece.n_owned,
        "boundary_edges": int(piece.mesh.boundary_edges.shape[0]),
        "first_cell": piece.first_cell,
        "owned_sum": owned_sum,
        "crc32": _checksum(piece),
        "bandwidth": _global_bandwidth(piece),
        "measures": {
            "area": measures.area,
            "min_area": measures.min_area,
            "max_area": measures.max_area,
            "min_angle": measures.min_angle,
            "max_angle": measures.max_angle,
            "max_aspect_ratio": measures.max_aspect_ratio,
            "not_strictly_convex": measures.not_strictly_convex,
            "invalid": measures.invalid,
        },
    }


def write_piece_task(parts: Partitioning, piece: int, folder: str, index: str) -> dict[str, Any]:
    """Build partition ``piece``, write it into ``folder``, and return its summary.

    ``index`` is the index file's name (``out.pvtu`` or ``out.xdmf``): it fixes the piece's
    name and format. The summary also says where it ran, how long it took (and each phase: build,
    write, summary) and the worker's peak resident memory so far.
    """
    started = time.perf_counter()
    rss_before = process_rss()
    built = build_piece(parts, piece)
    building = time.perf_counter()
    name = piece_name(Path(index), piece)
    path = Path(folder) / name
    if path.suffix == ".h5":
        write_h5_piece(built, path)
    else:
        write_vtu_piece(built, path)
    writing = time.perf_counter()
    summary = piece_summary(built)
    finished = time.perf_counter()
    summary.update(
        file=name,
        bytes=path.stat().st_size,
        array_bytes=built.mesh.nbytes() + built.global_node_ids.nbytes + built.ghost.nbytes,
        seconds=finished - started,
        phases={
            "build": building - started,
            "write": writing - building,
            "summary": finished - writing,
        },
        worker=f"{socket.gethostname()}:{os.getpid()}",
        rss_before=rss_before,
        peak_rss=peak_rss(),
    )
    return summary


def integrate_piece_task(
    parts: Partitioning,
    piece: int,
    function: Any,
    order: int,
    rule: str,
    max_points: int,
    exact_geometry: bool = False,
):
    """The integral of ``function`` over partition ``piece``, with its error estimate.

    :func:`blockmesh.quadrature.integrate_with_estimate` on the piece's mesh (its warnings stay
    on the worker: the estimate and ``converged`` say the same to the client); with
    ``exact_geometry`` over the piece's true curved cells.
    """
    import warnings

    mesh = build_piece(parts, piece).mesh
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BlockMeshWarning)
        return integrate_with_estimate(
            mesh,
            function,
            order=order,
            rule=rule,
            max_points=max_points,
            exact_geometry=exact_geometry,
        )
