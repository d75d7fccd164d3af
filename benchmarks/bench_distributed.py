"""Partitioned meshing on Dask: scaling, per-task overhead, piece writers, and a mesh past memory.

Run: ``python benchmarks/bench_distributed.py`` (needs ``pip install -e '.[distributed]'``).

Output goes to ``/dev/shm`` (memory) where it exists, except for the demonstration: repeated
gigabyte writes to a disk are throttled by the kernel's write-back and would hide the computing.

1. strong scaling on this machine: the serial refinement plus its XDMF export against
   :func:`blockmesh.distributed.refine_to` on local clusters of 1 and 2 workers (cluster start-up
   measured apart), same mesh, same number of partitions;
2. per-task overhead: the round trip of an empty task, and tiny partitioned meshes;
3. piece writers against the serial writers, in one process, per cell;
4. ``--demo``: a local cluster of 2 workers with a 2 GB memory limit each writes a mesh whose
   arrays total more than 4 GB (``joined-8`` at level 9 by default), and reports every worker's
   peak resident memory (which must stay under its limit).

Best of several runs after a warm-up; ratios are against the peer measured in the same run. The
local clusters are :func:`blockmesh.distributed.dask_client`'s (workers without Dask's
``MALLOC_TRIM_THRESHOLD_``, which makes them several times slower here).
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

from _page import Page, add_arguments

import blockmesh
import blockmesh.distributed as bd
from blockmesh.distributed.files import write_h5_piece, write_vtu_piece
from blockmesh.distributed.partition import partition
from blockmesh.distributed.pieces import build_piece


def best_of(function, repeat: int) -> float:
    function()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def scaling(page: Page, args: argparse.Namespace, folder: Path) -> None:
    domain = blockmesh.load_domain(args.domain)
    level, partitions = args.level, args.partitions
    cells = domain.n_blocks * 6**level

    def serial():  # what the workers do too: refine, measure, write
        mesh = blockmesh.refine(domain, level)
        mesh.quality()
        mesh.bandwidth()
        blockmesh.write(mesh, folder / "serial.xdmf")

    serial_time = best_of(serial, args.repeat)
    table = page.table(
        f"1. Strong scaling: {args.domain}, level {level} ({cells:,} cells), "
        f"{partitions} partitions",
        ["run", "time", "ns/cell", "serial / this", "cluster start"],
    )
    table.row(
        "serial: refine, measure, write XDMF",
        f"{serial_time:.2f} s",
        f"{serial_time / cells * 1e9:.0f}",
        "1",
        "",
    )
    for workers in (1, 2):
        started = time.perf_counter()
        context = bd.dask_client(workers=workers)
        client = context.__enter__()
        startup = time.perf_counter() - started
        try:
            for suffix in (".xdmf", ".pvtu"):
                index = folder / f"parts{suffix}"
                run = best_of(
                    lambda index=index, client=client: bd.refine_to(
                        domain, level, index, partitions=partitions, client=client
                    ),
                    args.repeat,
                )
                kind = "XDMF" if suffix == ".xdmf" else "VTU"
                table.row(
                    f"{workers} worker{'s' if workers > 1 else ''}, {kind} pieces",
                    f"{run:.2f} s",
                    f"{run / cells * 1e9:.0f}",
                    f"{serial_time / run:.2f}",
                    f"{startup:.1f} s",
                )
        finally:
            context.__exit__(None, None, None)
    again = best_of(serial, args.repeat)
    table.row("serial again", f"{again:.2f} s", f"{again / cells * 1e9:.0f}", "", "")
    table.note(
        "The machine is shared: the ratios use the first serial run; the second shows how much "
        f"the serial path varied within the run. Best of {args.repeat} after a warm-up."
    )


def overhead(page: Page, args: argparse.Namespace, folder: Path) -> None:
    from dask.distributed import Client, LocalCluster

    table = page.table(
        "2. Per-task overhead (a local cluster of 2 workers)",
        ["run", "time", "per task or piece", "serial with VTU"],
    )
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        n = 200

        def empty():
            client.gather([client.submit(int, k, pure=False) for k in range(n)])

        per_task = best_of(empty, args.repeat) / n
        table.row(
            f"{n} empty tasks", f"{per_task * n * 1e3:.1f} ms", f"{per_task * 1e3:.2f} ms", ""
        )
        domain = blockmesh.load_domain("joined-8")
        for partitions in (2, 8, 32):
            run = best_of(
                lambda p=partitions: bd.refine_to(
                    domain, 3, folder / "tiny.pvtu", partitions=p, client=client
                ),
                args.repeat,
            )
            serial = best_of(
                lambda: blockmesh.write(blockmesh.refine(domain, 3), folder / "tiny.vtu"),
                args.repeat,
            )
            table.row(
                f"joined-8 level 3 (10,368 cells) in {partitions} pieces",
                f"{run * 1e3:.1f} ms",
                f"{run / partitions * 1e3:.1f} ms",
                f"{serial * 1e3:.1f} ms",
            )


def writers(page: Page, args: argparse.Namespace, folder: Path) -> None:
    domain = blockmesh.load_domain(args.domain)
    level = args.level
    mesh = blockmesh.refine(domain, level)
    parts = partition(domain, level, args.partitions)
    pieces = [build_piece(parts, p) for p in range(parts.n_partitions)]
    cells = mesh.n_cells
    table = page.table(
        f"3. Writers, {args.domain} level {level} ({cells:,} cells), in one process",
        ["writer", "time", "ns/cell", "over the first"],
    )

    def each(write, suffix):
        def run():
            for piece in pieces:
                write(piece, folder / f"piece_{piece.index}{suffix}")

        return run

    rows = [
        ("serial VTU (meshio, no compression)", lambda: blockmesh.write(
            mesh, folder / "s.vtu", compression="none")),
        ("serial VTU (meshio, zlib)", lambda: blockmesh.write(mesh, folder / "s.vtu")),
        ("serial XDMF + HDF5", lambda: blockmesh.write(mesh, folder / "s.xdmf")),
        (f"{len(pieces)} VTU pieces (raw appended)", each(write_vtu_piece, ".vtu")),
        (f"{len(pieces)} HDF5 pieces", each(write_h5_piece, ".h5")),
    ]  # fmt: skip
    base = None
    for label, run in rows:
        seconds = best_of(run, max(1, args.repeat // 2))
        base = base or seconds
        table.row(
            label, f"{seconds:.2f} s", f"{seconds / cells * 1e9:.0f}", f"{seconds / base:.2f}"
        )


def demo(page: Page, args: argparse.Namespace, folder: Path) -> None:
    domain = blockmesh.load_domain(args.domain)
    limit = int(args.memory_limit)
    table = page.table(
        f"4. Past one worker's memory: {args.domain} level {args.level} on 2 workers with a "
        f"{limit / 1e9:.1f} GB memory limit each, {args.partitions} partitions, "
        f"{args.format} pieces",
        ["measure", "value"],
    )
    with bd.dask_client(workers=2, memory_limit=limit) as client:
        made = bd.refine_to(
            domain, args.level, folder / f"demo.{args.format}", partitions=args.partitions,
            client=client,
        )  # fmt: skip
        restarts = sum(
            w.get("metrics", {}).get("restarts", 0)
            for w in client.scheduler_info()["workers"].values()
        )
    peaks: dict[str, int] = {}
    for s in made.summaries:
        peaks[s["worker"]] = max(peaks.get(s["worker"], 0), int(s["peak_rss"]))
    predicted = max(bd.predict_task_bytes(bd.partition(domain, args.level, args.partitions), p)
                    for p in range(args.partitions))  # fmt: skip
    table.row("cells, nodes", f"{made.cells:,}, {made.nodes:,}")
    table.row("time", f"{made.seconds:.1f} s")
    table.row(
        "arrays, written", f"{made.array_bytes / 1e9:.2f} GB, {made.bytes_written / 1e9:.2f} GB"
    )
    for number, (_, peak) in enumerate(sorted(peaks.items())):
        table.row(f"worker {number}: peak resident", f"{peak / 1e9:.2f} GB of {limit / 1e9:.1f} GB")
    table.row(
        "predicted peak per worker",
        f"{predicted / 1e9:.2f} GB ({predicted / max(peaks.values()):.2f} x the largest measured)",
    )
    table.row("worker restarts", restarts)
    table.row("quality", made.quality)


ABOUT = """\
`blockmesh.distributed` (`pip install -e '.[distributed]'`): the serial refinement with its XDMF
export against `refine_to` on local Dask clusters of 1 and 2 workers (the same mesh, the same
partitions; cluster start-up measured apart), the cost of a task, and the piece writers against
the serial writers in one process. Output in `/dev/shm` where it exists, so that the disk's
write-back does not hide the work. Best of several runs after a warm-up."""

DEMO = """\
`python benchmarks/bench_distributed.py --demo`: a local cluster of 2 workers, each with a memory
limit, writes a mesh whose arrays are larger than one worker's limit, and reports every worker's
peak resident memory (which must stay under its limit) against the prediction."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--domain", default="joined-8")
    parser.add_argument("--level", type=int)
    parser.add_argument("--partitions", type=int)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--part", choices=("all", "scaling", "overhead", "writers"), default="all")
    parser.add_argument(
        "--demo", action="store_true", help="only the past-one-worker demonstration"
    )
    parser.add_argument("--memory-limit", default=2e9, type=float)
    parser.add_argument("--format", choices=("xdmf", "pvtu"), default="pvtu")
    parser.add_argument(
        "--folder",
        help="where the output goes (default: a temporary folder in /dev/shm where it exists, so "
        "that the disk's write-back does not hide the computing; the demonstration: /tmp)",
    )
    parser.add_argument("--keep", action="store_true", help="keep the demonstration's output")
    add_arguments(parser)
    args = parser.parse_args()
    memory_disk = Path("/dev/shm")
    where = memory_disk if memory_disk.is_dir() and not args.demo else None
    folder = Path(args.folder or tempfile.mkdtemp(prefix="bench-distributed-", dir=where))
    folder.mkdir(parents=True, exist_ok=True)
    try:
        if args.demo:
            args.level = args.level or 9
            args.partitions = args.partitions or 16
            page = Page("distributed-demo", "Past one worker's memory", DEMO)
            demo(page, args, folder)
            page.write(args)
            return
        args.level = args.level or 8
        args.partitions = args.partitions or 4
        page = Page("distributed", "Partitioned meshing on Dask", ABOUT)
        if args.part in ("all", "scaling"):
            scaling(page, args, folder)
        if args.part in ("all", "overhead"):
            overhead(page, args, folder)
        if args.part in ("all", "writers"):
            writers(page, args, folder)
        page.write(args)
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
