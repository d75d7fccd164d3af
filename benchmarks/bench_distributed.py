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


def scaling(args: argparse.Namespace, folder: Path) -> None:
    domain = blockmesh.load_domain(args.domain)
    level, partitions = args.level, args.partitions
    cells = domain.n_blocks * 6**level

    def serial():  # what the workers do too: refine, measure, write
        mesh = blockmesh.refine(domain, level)
        mesh.quality()
        mesh.bandwidth()
        blockmesh.write(mesh, folder / "serial.xdmf")

    serial_time = best_of(serial, args.repeat)
    print(
        f"1. strong scaling: {args.domain} level {level} ({cells:,} cells), {partitions} "
        "partitions, XDMF output"
    )
    print(
        f"  serial refine + write      {serial_time:7.2f} s  "
        f"{serial_time / cells * 1e9:6.1f} ns/cell"
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
                print(
                    f"  {workers} worker{'s' if workers > 1 else ' '} {suffix:6}          "
                    f"{run:7.2f} s  {run / cells * 1e9:6.1f} ns/cell  serial/this "
                    f"{serial_time / run:5.2f}  (cluster start {startup:.1f} s)"
                )
        finally:
            context.__exit__(None, None, None)
    again = best_of(serial, args.repeat)
    print(
        f"  serial again               {again:7.2f} s  (the machine is shared: ratios above use "
        "the first serial run)"
    )


def overhead(args: argparse.Namespace, folder: Path) -> None:
    from dask.distributed import Client, LocalCluster

    print("\n2. per-task overhead (local cluster of 2 workers)")
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
        print(f"  empty task round trip: {per_task * 1e3:.2f} ms per task ({n} tasks)")
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
            print(
                f"  joined-8 level 3 (10,368 cells) in {partitions:>2} pieces: {run * 1e3:6.1f} ms "
                f"= {run / partitions * 1e3:5.1f} ms per piece (serial with VTU: "
                f"{serial * 1e3:.1f} ms)"
            )


def writers(args: argparse.Namespace, folder: Path) -> None:
    domain = blockmesh.load_domain(args.domain)
    level = args.level
    mesh = blockmesh.refine(domain, level)
    parts = partition(domain, level, args.partitions)
    pieces = [build_piece(parts, p) for p in range(parts.n_partitions)]
    cells = mesh.n_cells
    print(f"\n3. writers, {args.domain} level {level} ({cells:,} cells), in one process")

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
        print(
            f"  {label:38} {seconds:6.2f} s  {seconds / cells * 1e9:6.1f} ns/cell  "
            f"{seconds / base:5.2f}x the first"
        )


def demo(args: argparse.Namespace, folder: Path) -> None:
    domain = blockmesh.load_domain(args.domain)
    limit = int(args.memory_limit)
    print(
        f"\n4. {args.domain} level {args.level} on 2 workers with a {limit / 1e9:.1f} GB memory "
        f"limit each, {args.partitions} partitions, {args.format} pieces in {folder}"
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
    print(
        f"  {made.cells:,} cells, {made.nodes:,} nodes in {made.seconds:.1f} s; arrays "
        f"{made.array_bytes / 1e9:.2f} GB, written {made.bytes_written / 1e9:.2f} GB"
    )
    for worker, peak in sorted(peaks.items()):
        print(f"  worker {worker}: peak resident {peak / 1e9:.2f} GB of {limit / 1e9:.1f} GB")
    print(
        f"  predicted peak per worker {predicted / 1e9:.2f} GB; measured largest "
        f"{max(peaks.values()) / 1e9:.2f} GB ({predicted / max(peaks.values()):.2f}x)"
    )
    print(f"  worker restarts: {restarts}; quality: {made.quality}")


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
    args = parser.parse_args()
    memory_disk = Path("/dev/shm")
    where = memory_disk if memory_disk.is_dir() and not args.demo else None
    folder = Path(args.folder or tempfile.mkdtemp(prefix="bench-distributed-", dir=where))
    folder.mkdir(parents=True, exist_ok=True)
    try:
        if args.demo:
            args.level = args.level or 9
            args.partitions = args.partitions or 16
            demo(args, folder)
            return
        args.level = args.level or 8
        args.partitions = args.partitions or 4
        if args.part in ("all", "scaling"):
            scaling(args, folder)
        if args.part in ("all", "overhead"):
            overhead(args, folder)
        if args.part in ("all", "writers"):
            writers(args, folder)
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
