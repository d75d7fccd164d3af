"""Independent pieces of work shared by worker threads, results and progress in the caller.

numpy releases the interpreter lock inside its loops, so threads running whole-array operations on
separate pieces of a mesh use several cores. :func:`run_parallel` hands the pieces out in order
through a queue (a thread takes the next when it is done, which balances uneven pieces and
uneven cores), gives each thread its own working arrays, reports every finished piece to the
calling thread (where progress is printed), and stops at the first failure, which it raises.

Examples
--------
>>> import numpy as np
>>> data = np.arange(10.0)
>>> sums = run_parallel(lambda piece, _: float(data[piece].sum()), [slice(0, 5), slice(5, 10)],
...                     threads=2)
>>> sums
[10.0, 35.0]
"""

from __future__ import annotations

import os
import queue
import threading
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

__all__ = ["MAX_THREADS", "default_threads", "run_parallel"]

#: Worker threads at most by default: the work is bound by memory bandwidth, which a few cores
#: saturate.
MAX_THREADS = 8

Item = TypeVar("Item")
Result = TypeVar("Result")


def default_threads() -> int:
    """Worker threads the mesh's whole-array work uses by default.

    ``BLOCKMESH_THREADS`` in the environment when set (a whole number >= 1), else the cores this
    process may run on, at most :data:`MAX_THREADS`.

    Examples
    --------
    >>> default_threads() >= 1
    True
    """
    text = os.environ.get("BLOCKMESH_THREADS", "").strip()
    if text.isdigit() and int(text) >= 1:
        return int(text)
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    return max(1, min(cores, MAX_THREADS))


def run_parallel(
    work: Callable[[Item, Any], Result],
    items: Sequence[Item],
    *,
    threads: int | None = None,
    workspace: Callable[[], Any] = lambda: None,
    finished: Callable[[int, Result], None] | None = None,
) -> list[Result]:
    """``[work(item, space) for item in items]``, on ``threads`` threads.

    Parameters
    ----------
    work : callable
        Called as ``work(item, space)``; ``space`` is the calling thread's own ``workspace()``.
    items : sequence
        The pieces, handed out in order.
    threads : int, optional
        Default :func:`default_threads`; 1 (or a single item) works in the calling thread.
    finished : callable, optional
        ``finished(k, result)`` in the calling thread as piece ``k`` is done (in any order).

    Returns
    -------
    list
        The results in the order of ``items``.
    """
    threads = default_threads() if threads is None else threads
    results: list[Any] = [None] * len(items)
    workers = min(threads, len(items))
    if workers <= 1:
        space = workspace()
        for k, item in enumerate(items):
            results[k] = work(item, space)
            if finished is not None:
                finished(k, results[k])
        return results
    todo: queue.SimpleQueue[int] = queue.SimpleQueue()
    for k in range(len(items)):
        todo.put(k)
    done: queue.SimpleQueue[tuple[int, Any] | BaseException] = queue.SimpleQueue()
    stop = threading.Event()

    def run() -> None:
        try:
            space = workspace()
            while not stop.is_set():
                try:
                    k = todo.get_nowait()
                except queue.Empty:
                    return
                done.put((k, work(items[k], space)))
        except BaseException as error:  # handed to the calling thread, which raises it
            done.put(error)

    pool = [threading.Thread(target=run, name=f"blockmesh-worker-{k}") for k in range(workers)]
    for thread in pool:
        thread.start()
    try:
        for _ in range(len(items)):
            message = done.get()
            if isinstance(message, BaseException):
                raise message
            k, results[k] = message
            if finished is not None:
                finished(k, results[k])
    finally:
        stop.set()
        for thread in pool:
            thread.join()
    return results
