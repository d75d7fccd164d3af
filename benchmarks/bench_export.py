"""Export speed and size of every format, against ``np.save`` of the raw arrays as the floor.

Builds the level-8 single-pentagon mesh (1 679 616 cells, 2 520 065 nodes), writes it in each
format (each run in a fresh temporary directory) and prints a table: seconds, size in MB, and
both as ratios to ``np.save`` of ``points`` and ``cells`` (the cheapest possible dump). Run::

    PYTHONPATH=. python benchmarks/bench_export.py [--level 8] [--repeat 1] [--read]

This is a script, not a test: nothing here asserts a time.
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from blockmesh import io
from blockmesh.mesh import Mesh
from blockmesh.refinement import refine

SP = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0]], dtype=float)

CASES: list[tuple[str, str, dict]] = [
    ("vtu zlib (default)", "mesh.vtu", {}),
    ("vtu none", "mesh.vtu", {"compression": "none"}),
    ("xdmf+h5 (default)", "mesh.xdmf", {}),
    ("xdmf+h5 zlib", "mesh.xdmf", {"compression": "zlib"}),
    ("msh tri3", "mesh.msh", {"split": "tri3"}),
    ("msh tri5", "mesh.msh", {"split": "tri5"}),
    ("msh quad5", "mesh.msh", {"split": "quad5"}),
    ("mat", "mesh.mat", {}),
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", type=int, default=8)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--read", action="store_true", help="also time reading each file back")
    args = parser.parse_args()

    start = time.perf_counter()
    mesh = refine(Mesh.from_cells(SP, [[0, 1, 2, 3, 4]]), args.level)
    print(
        f"level {args.level}: {mesh.n_cells:,} cells, {mesh.n_points:,} nodes "
        f"(refined in {time.perf_counter() - start:.2f} s)\n"
    )

    def floor(target: Path) -> None:
        target.mkdir()
        np.save(target / "points.npy", mesh.points)
        np.save(target / "cells.npy", mesh.cells)

    t0, s0, d0 = _timed(floor, "raw", args.repeat)
    shutil.rmtree(d0.parent, ignore_errors=True)
    header = f"{'format':<20} {'write s':>8} {'x floor':>8} {'MB':>8} {'x floor':>8}"
    if args.read:
        header += f" {'read s':>8}"
    print(header)
    print("-" * len(header))
    print(f"{'np.save (floor)':<20} {t0:8.2f} {1:8.1f} {s0 / 1e6:8.1f} {1:8.1f}")
    for label, name, kwargs in CASES:
        t, s, target = _timed(lambda p, kw=kwargs: io.write(mesh, p, **kw), name, args.repeat)
        row = f"{label:<20} {t:8.2f} {t / t0:8.1f} {s / 1e6:8.1f} {s / s0:8.1f}"
        if args.read:
            fmt = kwargs.get("format")
            start = time.perf_counter()
            io.read(target, format=fmt)
            row += f" {time.perf_counter() - start:8.2f}"
        print(row, flush=True)
        shutil.rmtree(target.parent, ignore_errors=True)


if __name__ == "__main__":
    main()
