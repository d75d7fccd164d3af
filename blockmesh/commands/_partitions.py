"""The options of partitioned (Dask) runs, shared by ``blockmesh mesh`` and ``integrate``."""

from __future__ import annotations

import argparse

from blockmesh.errors import BlockMeshError

__all__ = ["add_partition_arguments", "check_partition_arguments"]


def add_partition_arguments(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--partitions``, ``--workers`` and ``--scheduler``; ``what`` says what P pieces do."""
    parser.add_argument(
        "--partitions",
        type=int,
        metavar="P",
        help=f"{what} in P partitions on a Dask cluster (needs pip install "
        "'blockmesh[distributed]')",
    )
    parser.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="with --partitions: a local cluster of N worker processes (default: one per core)",
    )
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="with --partitions: a running Dask scheduler (e.g. tcp://host:8786) instead",
    )


def check_partition_arguments(args: argparse.Namespace) -> bool:
    """Whether a partitioned run was asked for; BlockMeshError for inconsistent options."""
    if args.partitions is None:
        if args.workers is not None or args.scheduler is not None:
            raise BlockMeshError("--workers and --scheduler go with --partitions P")
        return False
    if args.partitions < 1:
        raise BlockMeshError(f"--partitions must be 1 or more, got {args.partitions}")
    if args.workers is not None and args.workers < 1:
        raise BlockMeshError(f"--workers must be 1 or more, got {args.workers}")
    if args.workers is not None and args.scheduler is not None:
        raise BlockMeshError("give --workers (a local cluster) or --scheduler (a running one)")
    return True
