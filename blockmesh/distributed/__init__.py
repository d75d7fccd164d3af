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

import contextlib
import logging
import math
import os
import re
import signal
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh._system.atomic import atomic_with_folder, check_target
from blockmesh._system.bounded import reading
from blockmesh._system.memory import available_memory, format_bytes, format_count
from blockmesh.checks import renamed_keywords, whole_number
from blockmesh.distributed.files import (
    INDEX_SUFFIXES,
    piece_name,
    pieces_dir,
    read_piece,
    read_pieces,
    write_pvtu_index,
    write_xdmf_index,
)
from blockmesh.distributed.partition import MAX_PARTITIONS, Partitioning, partition
from blockmesh.distributed.pieces import piece_node_count
from blockmesh.distributed.tasks import integrate_piece_task, write_piece_task
from blockmesh.errors import ArgumentError, ArgumentTypeError, ExportError, ResourceError
from blockmesh.mesh.mesh import Mesh, MeshQuality
from blockmesh.quadrature import DEFAULT_MAX_POINTS, IntegrationResult, rule_info
from blockmesh.refinement.template import node_count

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = [
    "MAX_PARTITIONS",
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

#: Resident bytes of a worker process with blockmesh imported, before its first piece (measured
#: 75-110 MB on this project's machine).
WORKER_BASE_BYTES = 120 * 10**6
_ENVIRON_KEY = "distributed.nanny.pre-spawn-environ"
#: Share of a worker's memory limit a task may use: Dask pauses a worker at 80 %.
_WORKER_SHARE = 0.75
#: Most local worker processes per core.
WORKERS_PER_CORE = 4
#: The schemes of the Dask addresses blockmesh connects to, and the port Dask listens on.
_SCHEMES = ("tcp", "tls", "ws", "wss")
_DEFAULT_PORT = 8786
_LABEL = re.compile(r"(?!-)[A-Za-z0-9-]{1,63}(?<!-)")


def max_workers() -> int:
    """The most local worker processes this machine runs: by its cores and its memory.

    :data:`WORKERS_PER_CORE` per core, and no more than the available memory holds at
    :data:`WORKER_BASE_BYTES` each (at least one).

    Examples
    --------
    >>> max_workers() >= 1
    True
    """
    return max(1, min(WORKERS_PER_CORE * _cores(), available_memory() // WORKER_BASE_BYTES))


def scheduler_address(text: str) -> str:
    """``text`` as the address of a Dask scheduler, ``SCHEME://HOST:PORT``; checked, not dialled.

    The scheme is one of ``tcp`` (the default), ``tls``, ``ws`` and ``wss``; the host a name of
    DNS labels or an IP address; the port 1..65535 (default 8786).

    Examples
    --------
    >>> scheduler_address("head"), scheduler_address("tls://10.0.0.5:9000")
    ('tcp://head:8786', 'tls://10.0.0.5:9000')
    >>> scheduler_address("inproc://x")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ArgumentError: scheduler address 'inproc://x': the scheme 'inproc' is not ...
    """
    import ipaddress

    raw = str(text).strip()
    shown = raw if len(raw) <= 60 else raw[:57] + "..."

    def bad(why: str) -> ArgumentError:
        return ArgumentError(f"scheduler address {shown!r}: {why}")

    if not raw:
        raise bad("it is empty; give HOST:PORT or tcp://HOST:PORT")
    scheme, sep, rest = raw.partition("://")
    if not sep:
        scheme, rest = "tcp", raw
    if scheme not in _SCHEMES:
        raise bad(f"the scheme {scheme!r} is not one of {', '.join(_SCHEMES)}")
    if rest.startswith("["):  # [IPv6]:port
        host, close, port_text = rest[1:].partition("]")
        if not close or (port_text and not port_text.startswith(":")):
            raise bad("an IPv6 address is written [ADDRESS]:PORT")
        port_text = port_text[1:]
    else:
        host, _, port_text = rest.partition(":")
    if port_text and not (port_text.isdigit() and 1 <= int(port_text) <= 65535):
        raise bad(f"the port {port_text[:20]!r} is not a number in 1..65535")
    port = int(port_text) if port_text else _DEFAULT_PORT
    try:
        address = ipaddress.ip_address(host)
    except ValueError:
        labels = host.rstrip(".").split(".")
        if not host or len(host) > 253 or not all(_LABEL.fullmatch(label) for label in labels):
            raise bad(
                "the host is not a name of letters, digits and hyphens (labels of at most 63, "
                "253 in all) nor an IP address"
            ) from None
        return f"{scheme}://{host}:{port}"
    shown_host = f"[{address}]" if address.version == 6 else str(address)
    return f"{scheme}://{shown_host}:{port}"


ProgressCallback = Callable[[int, int], None]


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


def _distributed():
    try:
        import dask.distributed
    except ImportError:
        raise ResourceError(
            "partitioned meshing runs on Dask, which is not installed: "
            "pip install 'blockmesh[distributed]' (or pip install 'dask[distributed]')"
        ) from None
    return dask.distributed


@contextlib.contextmanager
def dask_client(
    client: Any = None,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    memory_limit: int | str | None = None,
) -> Iterator[Any]:
    """A Dask client: ``client`` itself, one connected to ``scheduler``, or a local cluster's.

    The local cluster has ``workers`` single-threaded worker processes (default: one per core),
    each with ``memory_limit`` bytes (default: the machine's memory shared out), and is closed at
    the end of the block.
    """
    if client is not None:
        yield client
        return
    if workers is not None and scheduler is not None:
        raise ArgumentError(
            "give workers= (a local cluster) or scheduler= (a running one), not both"
        )
    if scheduler is not None:
        scheduler = _reachable(scheduler_address(scheduler))
    n = _check_local(workers, memory_limit) if scheduler is None else 0
    distributed = _distributed()
    if scheduler is not None:
        try:
            remote = distributed.Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as error:
            raise ResourceError(
                f"cannot reach the Dask scheduler at {scheduler}: {error}"
            ) from None
        try:
            yield remote
        finally:
            remote.close()
        return
    import dask

    # Dask starts workers with MALLOC_TRIM_THRESHOLD_ set, which also fixes glibc's mmap
    # threshold at 128 KB: every temporary of the chunked loops is then mapped and unmapped
    # afresh, and faulted in page by page (4-20x slower on this project's machine). The workers
    # get glibc's own adaptive thresholds, as any Python process has.
    environ = {
        key: value
        for key, value in dask.config.get(_ENVIRON_KEY, {}).items()
        if not key.startswith("MALLOC_")
    }
    with _signals_held(), dask.config.set({_ENVIRON_KEY: environ}):
        cluster = distributed.LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            memory_limit=memory_limit if memory_limit is not None else "auto",
            # Any free port: None means Dask's 8787, and a second cluster on the machine then
            # prints "Port 8787 is already in use" through the command's warnings.
            dashboard_address=":0",
            silence_logs=logging.ERROR,
        )
        local = distributed.Client(cluster)
    try:
        yield local
    finally:
        with _signals_held():
            local.close()
            cluster.close()


_HELD_SIGNALS = ("SIGINT", "SIGTERM", "SIGHUP")


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Ctrl-C, SIGTERM and SIGHUP held back while the block runs, then handled as usual.

    A local cluster interrupted while it starts (or stops) is left half made: its workers keep
    running and Dask's exit handler fails with a long traceback. Held back, the signal is
    handled once the cluster is whole, by the handler that was in place (the command line's
    turns it into a clean stop), and the cluster is closed on the way out.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    wanted = [getattr(signal, name) for name in _HELD_SIGNALS if hasattr(signal, name)]
    previous = {signum: signal.getsignal(signum) for signum in wanted}

    def hold(signum: int, _frame: object) -> None:
        caught.append(signum)

    for signum in wanted:
        signal.signal(signum, hold)
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    if caught:
        handler = previous[caught[0]]
        if callable(handler):
            handler(caught[0], None)
        elif handler == signal.SIG_DFL:
            signal.raise_signal(caught[0])


def _reachable(address: str) -> str:
    """``address`` if its host name resolves; ResourceError now (not after a long timeout)."""
    import socket

    host = address.split("://", 1)[1].rsplit(":", 1)[0].strip("[]")
    try:
        socket.getaddrinfo(host, None)
    except (OSError, UnicodeError) as error:
        raise ResourceError(
            f"cannot reach the Dask scheduler at {address}: its host does not resolve ({error})"
        ) from None
    return address


def _check_local(workers: int | None, memory_limit: int | str | None) -> int:
    """The number of local workers, checked with their memory limit against the machine."""
    most = max_workers()
    if workers is None:
        n = min(_cores(), most)
    else:
        n = whole_number(workers, "workers", minimum=1)
        if n > most:
            raise ResourceError(
                f"workers={n:,} is more than this machine runs: at most {most} "
                f"({WORKERS_PER_CORE} per core on {_cores()} cores, each worker needing about "
                f"{format_bytes(WORKER_BASE_BYTES)} of the {format_bytes(available_memory())} "
                "available)"
            )
    if isinstance(memory_limit, bool) or (
        isinstance(memory_limit, int | float) and memory_limit < WORKER_BASE_BYTES
    ):
        raise ArgumentError(
            f"memory_limit={memory_limit!r} bytes per worker is less than a worker needs "
            f"({format_bytes(WORKER_BASE_BYTES)}); give bytes, e.g. 2_000_000_000 or '2GB'"
        )
    return n


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _worker_limits(client: Any) -> list[int]:
    info = client.scheduler_info()
    workers = info.get("workers", {}).values()
    return [int(w.get("memory_limit") or 0) for w in workers]


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


def _check_workers(parts: Partitioning, client: Any) -> None:
    limits = [limit for limit in _worker_limits(client) if limit > 0]
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


def _run_tasks(futures: list[Any], progress: ProgressCallback | None) -> list[Any]:
    distributed = _distributed()
    results: list[Any] = [None] * len(futures)
    where = {future.key: k for k, future in enumerate(futures)}
    try:
        for done, future in enumerate(distributed.as_completed(futures), start=1):
            results[where[future.key]] = future.result()
            if progress is not None:
                progress(done, len(futures))
    except MemoryError:
        raise ResourceError(
            "a worker ran out of memory; use more partitions or give the workers more memory"
        ) from None
    except distributed.KilledWorker as error:
        raise ResourceError(
            f"a worker died running {error.task!r} (most likely over its memory limit); use more "
            "partitions or give the workers more memory"
        ) from None
    finally:
        for future in futures:
            future.cancel()
    return results


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
        _check_workers(parts, active)
        with atomic_with_folder(index, pieces_dir(index)) as (index_tmp, folder, generation):
            scattered = active.scatter(parts, broadcast=True, hash=False)
            futures = [
                active.submit(write_piece_task, scattered, p, str(folder), index.name, pure=False)
                for p in range(parts.n_partitions)
            ]
            summaries = _run_tasks(futures, progress)
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


@renamed_keywords(function="f")
def integrate_with_estimate(
    target: Domain | Mesh,
    f: Any,
    *,
    order: int,
    level: int | None = None,
    rule: str = "paper",
    partitions: int | None = None,
    client: Any = None,
    workers: int | None = None,
    scheduler: str | None = None,
    max_points: int | None = None,
    exact_geometry: bool = False,
    progress: ProgressCallback | None = None,
) -> Any:
    """The integral over ``target`` at ``level``, partition by partition, with its estimate.

    Each worker builds its piece and integrates over it with
    :func:`blockmesh.quadrature.integrate_with_estimate` (``order``, ``rule`` as there); the
    client adds the values (``math.fsum``: the serial value to round-off) and the error
    estimates, and the result has converged when every partition's has. ``level`` is as for
    :func:`blockmesh.integrate`: a Domain's refinement level, or for a Mesh the level to reach
    (above its own). ``f`` is the integrand as for :func:`blockmesh.integrate` and must be
    picklable: an expression string, or a function defined at module level (``function=``, its
    former name, still works with a :class:`DeprecationWarning`). ``max_points`` bounds the
    evaluations of the whole integral.
    ``exact_geometry`` integrates over the true curved cells, as :func:`blockmesh.integrate`
    does (every piece carries its curved edges).

    Returns
    -------
    IntegrationResult
    """
    if level is None:
        steps = 0
    elif isinstance(target, Mesh):
        steps = whole_number(level, "level") - target.level
    else:
        steps = whole_number(level, "level")
    budget = DEFAULT_MAX_POINTS if max_points is None else whole_number(max_points, "max_points")
    if not isinstance(exact_geometry, bool):
        raise ArgumentTypeError(f"exact_geometry must be True or False, got {exact_geometry!r}")
    with dask_client(client, workers=workers, scheduler=scheduler) as active:
        n_workers = len(active.scheduler_info().get("workers", {})) or 1
        parts = partition(target, steps, partitions if partitions is not None else n_workers)
        info = rule_info(rule, order)
        points = parts.n_cells * info.points_per_cell
        if points > budget:
            raise ResourceError(
                f"{format_count(points)} evaluations of f are more than max_points "
                f"({format_count(budget)}); lower the level or the order, or raise max_points"
            )
        _check_workers(parts, active)
        scattered = active.scatter(parts, broadcast=True, hash=False)
        futures = [
            active.submit(
                integrate_piece_task,
                scattered,
                p,
                f,
                order,
                rule,
                budget,
                exact_geometry,
                pure=False,
            )
            for p in range(parts.n_partitions)
        ]
        results = _run_tasks(futures, progress)
    value = math.fsum(r.value for r in results)
    estimate = math.fsum(r.error_estimate for r in results)
    unresolved = [r for r in results if not r.converged]
    message = (
        f"sum of {parts.n_partitions} partitions; {unresolved[0].message}"
        if unresolved
        else f"sum of {parts.n_partitions} partitions, each {results[0].message}"
    )
    level_made = parts.base.level + parts.steps
    return IntegrationResult(
        value=value,
        error_estimate=estimate,
        order=results[0].order,
        level=level_made,
        rule=results[0].rule,
        cells=sum(r.cells for r in results),
        points=sum(r.points for r in results),
        converged=not unresolved,
        message=message,
        history=((level_made, results[0].order, value),),
    )


@renamed_keywords(function="f")
def integrate(target: Domain | Mesh, f: Any, **options: Any) -> float:
    """The value of :func:`integrate_with_estimate` (same options): a float.

    ``f`` as for :func:`blockmesh.integrate` (``function=`` is its deprecated name).

    Examples
    --------
    >>> import blockmesh, blockmesh.distributed as bd
    >>> bd.integrate(blockmesh.load_domain("sp"), f="1", order=1, level=2,
    ...              partitions=3, workers=1)  # doctest: +SKIP
    5.0
    """
    return integrate_with_estimate(target, f, **options).value


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
