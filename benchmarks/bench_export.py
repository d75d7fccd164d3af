"""Export and import speed, size and memory of every format, against ``np.save`` as the floor.

Builds the level-8 single-pentagon mesh (1 679 616 cells, 2 520 065 nodes), writes it in each
format (each run in a fresh temporary directory) and prints a table: seconds, size in MB, and
both as ratios to ``np.save`` of ``points`` and ``cells`` (the cheapest possible dump). With
``--read`` each file is also read back with :func:`blockmesh.read`, in a forked child so that its
memory is its own: the read time, its ratio to the write time (target: <= 5x), and the peak
resident memory the read adds (``VmHWM`` after the read less ``VmRSS`` before it, Linux), as a
ratio to the mesh's own arrays (``Mesh.nbytes()``; target: <= 3x). The Mesh's own validity
check, which every reader runs, is measured alone on the first line ("Mesh(...) check": the
arrays given as read-only, so not copied). Allocations of 1 MB or more are mapped one by one
(``MALLOC_MMAP_THRESHOLD_``, set by the script) so that freed memory of the parent does not hide
a child's peak. Run::

    PYTHONPATH=. python benchmarks/bench_export.py [--level 8] [--repeat 1] [--read] [--only vtu]

``--vtu`` measures instead the options of the VTU writer (:mod:`blockmesh.io.vtu.writer`) on
a catalogue domain (default ``l-shape`` at level 7, 6.7 M cells) against the stages of
``blockmesh mesh`` before it (refinement, cell measures) and the XDMF writer: no compression,
zlib at levels 1, 3 and 6, each on the default threads and on one, with wall and CPU seconds
(CPU counts every thread) and the size::

    PYTHONPATH=. python benchmarks/bench_export.py --vtu [--domain l-shape] [--level 7]

This is a script, not a test: nothing here asserts a time.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from _page import Page, add_arguments

from blockmesh import io
from blockmesh.mesh import Mesh
from blockmesh.refinement import refine

SP = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0]], dtype=float)

CASES: list[tuple[str, str, dict]] = [
    ("vtu none (default)", "mesh.vtu", {}),
    ("vtu zlib", "mesh.vtu", {"compression": "zlib"}),
    ("vtk (legacy)", "mesh.vtk", {}),
    ("xdmf+h5 (default)", "mesh.xdmf", {}),
    ("xdmf+h5 zlib", "mesh.xdmf", {"compression": "zlib"}),
    ("msh tri5 (default)", "mesh.msh", {}),
    ("msh tri3", "mesh.msh", {"split": "tri3"}),
    ("msh quad5", "mesh.msh", {"split": "quad5"}),
    ("mat", "mesh.mat", {}),
    ("mat zlib", "mesh.mat", {"compression": "zlib"}),
    ("openfoam", "case", {"format": "openfoam"}),
    ("npz", "mesh.npz", {}),
    ("npz zlib", "mesh.npz", {"compression": "zlib"}),
]


def _size(path: Path) -> int:
    if path.is_dir():
        return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())
    return path.stat().st_size


def _timed(fn: Callable[[Path], object], name: str, repeat: int) -> tuple[float, int, Path]:
    best, size, keep = np.inf, 0, Path()
    for _ in range(repeat):
        tmp = Path(tempfile.mkdtemp(prefix="bench_export_"))
        target = tmp / name
        start = time.perf_counter()
        fn(target)
        best = min(best, time.perf_counter() - start)
        size = sum(_size(p) for p in tmp.iterdir())
        if keep != Path():
            shutil.rmtree(keep.parent, ignore_errors=True)
        keep = target
    return best, size, keep


def _status(key: str) -> int:
    """A ``/proc/self/status`` entry in bytes (``VmRSS``, ``VmHWM``)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    raise KeyError(key)


def _in_child(fn: Callable[[], object]) -> tuple[float, int]:
    """Seconds and peak added resident bytes of ``fn()``, run in a forked child process."""
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: reset the high-water mark, run, report
        os.close(read_end)
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        base = _status("VmRSS")
        start = time.perf_counter()
        fn()
        seconds = time.perf_counter() - start
        os.write(write_end, f"{seconds} {_status('VmHWM') - base}".encode())
        os._exit(0)
    os.close(write_end)
    with os.fdopen(read_end) as f:
        text = f.read()
    os.waitpid(pid, 0)
    seconds, peak = text.split()
    return float(seconds), int(peak)


ABOUT = """\
The single-pentagon mesh (level 8 by default: 1,679,616 cells, 2,520,065 nodes) written in every
format, each in a fresh folder: seconds and size, both as ratios to `np.save` of `points` and
`cells` (the cheapest possible dump). With `--read`, each file is also read back with
`blockmesh.read` in a forked child: the read time, its ratio to the write time (target <= 5), and
the peak resident memory the read adds, as a ratio to the mesh's own arrays (target <= 3).
Allocations of 1 MB or more are mapped one by one (`MALLOC_MMAP_THRESHOLD_`), so that memory the
parent freed does not hide a child's peak."""


def _stage(label: str, fn: Callable[[], object], size: Callable[[], int] | None = None) -> None:
    cpu, wall = time.process_time(), time.perf_counter()
    fn()
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    megabytes = f"{size() / 1e6:9.1f}" if size else ""
    print(f"{label:<32} {wall:8.2f} {cpu:8.2f} {megabytes}", flush=True)


def vtu_options(domain_name: str, level: int) -> None:
    """The VTU writer's options against the command's other stages (see the module doc)."""
    import blockmesh
    from blockmesh._system.threads import default_threads
    from blockmesh.io.vtu import writer as vtu_writer

    domain = blockmesh.load_domain(domain_name)
    refine(domain, 2)  # templates and imports are not what is measured
    print(f"{'stage':<32} {'wall s':>8} {'CPU s':>8} {'MB':>9}")
    found: dict[str, Mesh] = {}
    _stage(f"refine {domain_name} to level {level}", lambda: found.update(m=refine(domain, level)))
    mesh = found["m"]
    _stage("measure the cells (quality)", mesh.quality)
    folder = Path(tempfile.mkdtemp(prefix="bench_export_"))
    try:
        for label, name, kwargs in (("xdmf+h5", "m.xdmf", {}), ("xdmf+h5 zlib", "m.xdmf",
                                     {"compression": "zlib"})):  # fmt: skip
            target = folder / name
            _stage(label, lambda t=target, kw=kwargs: io.write(mesh, t, **kw),
                   lambda: sum(p.stat().st_size for p in folder.iterdir()))  # fmt: skip
            for p in folder.iterdir():
                p.unlink()
        target = folder / "m.vtu"
        threads = default_threads()
        original = vtu_writer.ZLIB_LEVEL
        for compression, zlib_level in (("none", 0), ("zlib", 1), ("zlib", 3), ("zlib", 6)):
            for count in sorted({threads, 1}, reverse=True):
                vtu_writer.ZLIB_LEVEL = zlib_level or original
                label = f"vtu {compression}" + (
                    f" level {zlib_level}, {count} thread{'s' if count > 1 else ''}"
                    if zlib_level
                    else ""
                )
                _stage(
                    label,
                    lambda c=compression, n=count: _write_vtu(mesh, target, c, n),
                    lambda: target.stat().st_size,
                )
                if compression == "none":
                    break  # no threads to share
        vtu_writer.ZLIB_LEVEL = original
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _write_vtu(mesh: Mesh, target: Path, compression: str, threads: int) -> None:
    from blockmesh.io.vtu.format import _field_data_xml, field_data
    from blockmesh.io.vtu.writer import write_vtu_stream

    with open(target, "wb") as out:
        write_vtu_stream(
            out, mesh, _field_data_xml(field_data(mesh)), compression=compression, threads=threads
        )


def main() -> None:
    if os.environ.get("MALLOC_MMAP_THRESHOLD_") is None:
        # every allocation of 1 MB or more gets its own pages (no reuse of freed heap memory),
        # so a read's peak resident memory is measured, not hidden by the parent's free heap
        os.environ["MALLOC_MMAP_THRESHOLD_"] = str(1 << 20)
        os.execv(sys.executable, [sys.executable, *sys.argv])
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--level", type=int, default=8)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--read", action="store_true", help="also time reading each file back")
    parser.add_argument(
        "--only",
        nargs="+",
        metavar="LABEL",
        help="the formats whose label starts with one of these",
    )
    parser.add_argument("--vtu", action="store_true", help="the VTU writer's options instead")
    parser.add_argument("--domain", default="l-shape", help="with --vtu: the catalogue domain")
    add_arguments(parser)
    args = parser.parse_args()
    if args.vtu:
        vtu_options(args.domain, 7 if "--level" not in sys.argv else args.level)
        return
    page = Page("export", "Export and import", ABOUT)

    start = time.perf_counter()
    mesh = refine(Mesh.from_cells(SP, [[0, 1, 2, 3, 4]]), args.level)
    size = mesh.nbytes()
    title = (
        f"Level {args.level} of the paper's pentagon: {mesh.n_cells:,} cells, {mesh.n_points:,} "
        f"nodes, {size / 1e6:.0f} MB of arrays"
    )
    refined = time.perf_counter() - start

    def floor(target: Path) -> None:
        target.mkdir()
        np.save(target / "points.npy", mesh.points)
        np.save(target / "cells.npy", mesh.cells)

    t0, s0, d0 = _timed(floor, "raw", args.repeat)
    shutil.rmtree(d0.parent, ignore_errors=True)
    columns = ["format", "write", "x floor", "size", "x floor"]
    if args.read:
        columns += ["read", "read / write", "read peak", "read peak / mesh"]
    table = page.table(title, columns)
    blank = [""] * (len(columns) - 5)
    table.row(
        "`np.save` of the raw arrays (floor)",
        f"{t0:.2f} s",
        "1.0",
        f"{s0 / 1e6:.0f} MB",
        "1.0",
        *blank,
    )
    if args.read:
        names = ("points", "cells", "block_id", "parent", "region", "boundary_edges")
        arrays = {k: getattr(mesh, k) for k in (*names, "boundary_patch")}

        def check() -> Mesh:  # read-only arrays: taken over, not copied
            return Mesh(**arrays, patch_names=mesh.patch_names, region_names=mesh.region_names)

        tc, pc = _in_child(check)
        table.row(
            "`Mesh(...)` check alone",
            "",
            "",
            "",
            "",
            f"{tc:.2f} s",
            "",
            f"{pc / 1e6:.0f} MB",
            f"{pc / size:.2f}",
        )
    for label, name, kwargs in CASES:
        if args.only and not label.startswith(tuple(args.only)):
            continue
        t, s, target = _timed(lambda p, kw=kwargs: io.write(mesh, p, **kw), name, args.repeat)
        row = [label, f"{t:.2f} s", f"{t / t0:.1f}", f"{s / 1e6:.0f} MB", f"{s / s0:.1f}"]
        if args.read:
            fmt = kwargs.get("format")
            tr, peak = _in_child(lambda target=target, fmt=fmt: io.read(target, format=fmt))
            row += [f"{tr:.2f} s", f"{tr / t:.1f}", f"{peak / 1e6:.0f} MB", f"{peak / size:.2f}"]
        table.row(*row)
        shutil.rmtree(target.parent, ignore_errors=True)
    table.note(
        f"Refined in {refined:.2f} s; best of {args.repeat} write(s), each in a fresh folder. "
        "Every write includes the mesh's final check, every read builds a checked `Mesh`; "
        '"read peak": the resident memory a read adds (in a forked process), the mesh included.'
    )
    page.write(args)


if __name__ == "__main__":
    main()
