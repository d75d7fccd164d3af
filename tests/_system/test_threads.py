"""Work shared by threads: results in order, failures raised in the caller, progress there too."""

from __future__ import annotations

import threading
import time

import pytest

from blockmesh._system.threads import run_parallel


@pytest.mark.parametrize("threads", [1, 2, 5])
def test_results_come_back_in_the_order_of_the_items(threads):
    items = list(range(40))
    seen = []
    got = run_parallel(
        lambda item, space: (item * item, space),
        items,
        threads=threads,
        workspace=lambda: threading.current_thread().name,
        finished=lambda k, result: seen.append((k, threading.current_thread())),
    )
    assert [value for value, _ in got] == [k * k for k in items]
    # Each thread uses its own workspace throughout; the caller hears of every item.
    assert len({space for _, space in got}) <= threads
    assert sorted(k for k, _ in seen) == items
    assert {thread for _, thread in seen} == {threading.current_thread()}


def test_the_first_failure_is_raised_and_the_threads_stop():
    started = []

    def work(item, _):
        started.append(item)
        time.sleep(0.002)
        if item == 3:
            raise KeyError("three")
        return item

    with pytest.raises(KeyError, match="three"):
        run_parallel(work, list(range(1000)), threads=2)
    assert len(started) < 100  # the other thread stopped at its next item
    assert not [t for t in threading.enumerate() if t.name.startswith("blockmesh-worker")]
