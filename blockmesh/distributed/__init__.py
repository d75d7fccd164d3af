"""Meshes beyond one machine: partitioned refinement, output and integration on Dask.

A mesh too big for one machine's memory is made partition by partition on the workers of a Dask
cluster (``pip install 'blockmesh[distributed]'``): each partition is a group of whole blocks
(or of whole cells of a coarser level, :mod:`~blockmesh.distributed.partition`), each worker
builds its piece from a small numbering plan without talking to the others
(:mod:`~blockmesh.distributed.pieces`), writes it, and sends back only counts, quality extremes
and checksums. Nothing gathers the mesh on the client.

- :func:`refine_to` writes ``out.pvtu`` (ParaView's parallel VTU, with ``GlobalNodeIds`` and
  ghost marks) or ``out.xdmf`` (an XDMF spatial collection of HDF5 pieces), pieces in
  ``out.pvtu.pieces/<8 hex digits>/`` (or ``out.xdmf.pieces/...``): a folder of their own at
  every write, committed with the index (:func:`blockmesh._system.atomic.atomic_with_folder`);
- :func:`integrate` and :func:`integrate_with_estimate` sum the integrals of the partitions;
- :func:`gather` reads a partitioned mesh back into one :class:`~blockmesh.mesh.Mesh` (for meshes
  that fit): it equals the serial :func:`blockmesh.refine` result array for array, bit for bit.

Without ``client`` a local cluster of one single-threaded worker process per core is started (and
stopped afterwards); ``scheduler="tcp://host:8786"`` connects to a running cluster instead, whose
workers must see the output folder (a shared file system). Dask is imported only here, when used.

The modules, one job each: :mod:`~blockmesh.distributed.cluster` (the Dask cluster, its workers
and clients), :mod:`~blockmesh.distributed.budget` (a task's memory against a worker's limit),
:mod:`~blockmesh.distributed.partition` (the mesh cut into partitions),
:mod:`~blockmesh.distributed.pieces` (a partition's piece built),
:mod:`~blockmesh.distributed.tasks` (what a worker runs), :mod:`~blockmesh.distributed.files`
(pieces and indexes on disk), :mod:`~blockmesh.distributed.partitioned` (:func:`refine_to`,
:func:`gather`) and :mod:`~blockmesh.distributed.integration` (:func:`integrate`,
:func:`integrate_with_estimate`).

Examples
--------
>>> import pathlib, tempfile, blockmesh
>>> import blockmesh.distributed as bd
>>> domain = blockmesh.load_domain("joined-2")
>>> out = pathlib.Path(tempfile.mkdtemp()) / "j2.pvtu"
>>> made = bd.refine_to(domain, 2, out, partitions=2, workers=1)  # doctest: +SKIP
>>> made.cells, [p.name for p in made.pieces]  # doctest: +SKIP
(72, ['j2_0000.vtu', 'j2_0001.vtu'])
>>> bool((bd.gather(out).points == blockmesh.refine(domain, 2).points).all())  # doctest: +SKIP
True
"""

from __future__ import annotations

from blockmesh.distributed.budget import predict_task_bytes
from blockmesh.distributed.cluster import (
    WORKER_BASE_BYTES,
    WORKERS_PER_CORE,
    dask_client,
    max_workers,
    scheduler_address,
)
from blockmesh.distributed.integration import integrate, integrate_with_estimate
from blockmesh.distributed.partition import MAX_PARTITIONS, Partitioning, partition
from blockmesh.distributed.partitioned import PartitionedMesh, gather, refine_to

__all__ = [
    "MAX_PARTITIONS",
    "WORKERS_PER_CORE",
    "WORKER_BASE_BYTES",
    "PartitionedMesh",
    "Partitioning",
    "dask_client",
    "gather",
    "integrate",
    "integrate_with_estimate",
    "max_workers",
    "partition",
    "predict_task_bytes",
    "refine_to",
    "scheduler_address",
]
