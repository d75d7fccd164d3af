"""What a partition's task needs on its worker, checked against the workers' memory limits."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh._system.memory import format_bytes
from blockmesh.distributed.cluster import WORKER_BASE_BYTES, worker_limits
from blockmesh.distributed.partition import Partitioning
from blockmesh.distributed.pieces import piece_node_count
from blockmesh.errors import ResourceError
from blockmesh.refinement.template import node_count

if TYPE_CHECKING:
    pass

#: Share of a worker's memory limit a task may use: Dask pauses a worker at 80 %.
_WORKER_SHARE = 0.75


def predict_task_bytes(parts: Partitioning, piece: int) -> int:
    """Peak resident bytes of a worker while it builds and writes partition ``piece``.

    An idle worker (:data:`WORKER_BASE_BYTES`), the piece's arrays (coordinates, global ids and
    ghost marks per node; cells, block, parent and region per cell; boundary edges), one unit's
    working arrays and the template of the remaining levels. The writers stream in chunks.
    """
    nodes = piece_node_count(parts, piece)
    cells = parts.cells(piece)
    boundary = 2**parts.steps * int(
        np.count_nonzero(
            (parts.boundary_unit >= parts.starts[piece])
            & (parts.boundary_unit < parts.starts[piece + 1])
        )
    )
    arrays = 33 * nodes + 64 * cells + 32 * boundary
    working = 25 * node_count(parts.steps) + 62 * 6**parts.steps
    return WORKER_BASE_BYTES + arrays + working


def check_workers(parts: Partitioning, client: Any) -> None:
    """ResourceError when a partition's task would not fit in the workers' memory limit."""
    limits = [limit for limit in worker_limits(client) if limit > 0]
    if not limits:
        return
    limit = min(limits)

    needs = [predict_task_bytes(parts, p) for p in range(parts.n_partitions)]
    worst = int(np.argmax(needs))
    if needs[worst] <= _WORKER_SHARE * limit:
        return
    per_partition = needs[worst] - WORKER_BASE_BYTES
    room = _WORKER_SHARE * limit - WORKER_BASE_BYTES
    advice = (
        f"use at least {math.ceil(parts.n_partitions * per_partition / room)} partitions"
        if room > 0
        else "give the workers more memory"
    )
    raise ResourceError(
        f"partition {worst} of {parts.n_partitions} needs about {format_bytes(needs[worst])} on "
        f"its worker, more than {_WORKER_SHARE:.0%} of a worker's memory limit "
        f"({format_bytes(limit)}); {advice}"
    )
