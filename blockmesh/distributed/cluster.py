"""The Dask cluster the partitioned work runs on: addresses, local workers, clients, tasks run.

Dask is imported only here, when a client is made (:func:`dask_client`) or tasks are run: a
missing Dask is a :class:`~blockmesh.errors.ResourceError` saying how to install it.
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import signal
import threading
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

from blockmesh._system.memory import available_memory, format_bytes
from blockmesh.checks import whole_number
from blockmesh.errors import ArgumentError, ResourceError

if TYPE_CHECKING:
    pass

#: Resident bytes of a worker process with blockmesh imported, before its first piece (measured
#: 75-110 MB on this project's machine).
WORKER_BASE_BYTES = 120 * 10**6
_ENVIRON_KEY = "distributed.nanny.pre-spawn-environ"
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


def worker_limits(client: Any) -> list[int]:
    """The memory limit of each of the client's workers in bytes (0 where none is set)."""
    info = client.scheduler_info()
    workers = info.get("workers", {}).values()
    return [int(w.get("memory_limit") or 0) for w in workers]


def run_tasks(futures: list[Any], progress: ProgressCallback | None) -> list[Any]:
    """The futures' results in order; a worker out of memory or killed as a ResourceError."""
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
