"""The options of partitioned (Dask) runs, shared by ``blockmesh mesh`` and ``integrate``."""

from __future__ import annotations

import argparse
from typing import TypedDict

from blockmesh._system.memory import format_bytes
from blockmesh.commands import Option
from blockmesh.commands.common import check_range
from blockmesh.errors import BlockMeshError

__all__ = [
    "PartitionKeywords",
    "check_partition_arguments",
    "partition_keywords",
    "partition_options",
]


class PartitionKeywords(TypedDict):
    """The keywords of a partitioned run (:mod:`blockmesh.distributed`) that its options give."""

    partitions: int
    workers: int | None
    scheduler: str | None


def partition_options(what: str) -> tuple[Option, ...]:
    """``--partitions``, ``--workers`` and ``--scheduler``; ``what`` says what P pieces do."""
    return (
        Option(
            "--partitions",
            type=int,
            metavar="P",
            help=f"{what} in P partitions on a Dask cluster (needs pip install "
            "'blockmesh[distributed]')",
        ),
        Option(
            "--workers",
            type=int,
            metavar="N",
            help="with --partitions: a local cluster of N worker processes (default: one per core)",
        ),
        Option(
            "--scheduler",
            metavar="ADDRESS",
            help="with --partitions: a running Dask scheduler (e.g. tcp://host:8786) instead",
        ),
    )


def check_partition_arguments(args: argparse.Namespace) -> bool:
    """Whether a partitioned run was asked for; BlockMeshError for inconsistent options.

    Everything is checked here, before a domain is read or Dask started: the partition count,
    the workers against this machine's cores and memory, the scheduler's address (parsed, and
    its host resolved), and ``--max-memory`` against what a worker needs.
    """
    if args.partitions is None:
        if args.workers is not None or args.scheduler is not None:
            raise BlockMeshError("--workers and --scheduler go with --partitions P")
        return False
    from blockmesh.distributed import (
        MAX_PARTITIONS,
        WORKER_BASE_BYTES,
        max_workers,
        scheduler_address,
    )

    check_range(args.partitions, "--partitions", 1, MAX_PARTITIONS)
    if args.workers is not None and args.scheduler is not None:
        raise BlockMeshError("give --workers (a local cluster) or --scheduler (a running one)")
    if args.workers is not None:
        check_range(
            args.workers, "--workers", 1, max_workers(),
            " (by this machine's cores and memory: each worker needs about "
            f"{format_bytes(WORKER_BASE_BYTES)})",
        )  # fmt: skip
    if args.scheduler is not None:
        try:
            args.scheduler = scheduler_address(args.scheduler)
        except BlockMeshError as error:
            raise BlockMeshError(f"--scheduler: {error}") from None
    max_memory = getattr(args, "max_memory", None)
    if max_memory is not None and max_memory < WORKER_BASE_BYTES:
        raise BlockMeshError(
            f"--max-memory {format_bytes(max_memory)} is each worker's memory limit with "
            f"--partitions, less than a worker needs ({format_bytes(WORKER_BASE_BYTES)})"
        )
    return True


def partition_keywords(args: argparse.Namespace) -> PartitionKeywords:
    """The keywords ``partitions``, ``workers`` and ``scheduler`` of a partitioned run.

    Read from ``args``, which has passed :func:`check_partition_arguments` (a partitioned run).
    """
    return {"partitions": args.partitions, "workers": args.workers, "scheduler": args.scheduler}
