"""Refinement speed and memory, side by side with Triangle and gmsh on the same domain.

Run: ``python benchmarks/bench_refine.py`` (needs ``pip install -e '.[bench]'`` for the peers).
Prints ns per cell and cells per second for a single pentagon (the paper's SP) at levels 4-8,
warm (template cached) and on the first call in a fresh process, every catalogue domain at the
level that gives about 3 M cells (default threads and one thread) against SP in the same run, the
peak memory over the output arrays, the template cache, and the peers meshing a comparable number
of triangles of the same pentagon, with ratios. Not a test: timings on shared machines are
noisy; each figure is the best of several runs after a warm-up.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
import time
import tracemalloc

import numpy as np
from _page import Page, add_arguments

import blockmesh
from blockmesh._system.threads import default_threads
from blockmesh.domain.catalogue import catalogue_names
from blockmesh.refinement.template import (
    TEMPLATE_CACHE_BYTES,
    cached_template_bytes,
    pentagon_template,
)

SP = [(-1.0, -1.0), (1.0, -1.0), (2.0, 0.0), (0.0, 1.0), (-2.0, 0.0)]


def best_of(function, repeat: int) -> float:
    function()  # warm-up
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def first_call(level: int) -> tuple[float, float]:
    """Seconds of refine() on the first call in a fresh Python process (template not yet built),
    and, in another fresh process, the peak memory of that call over the output arrays."""
    code = (
        "import sys, time, tracemalloc, blockmesh\n"
        "d = blockmesh.load_domain('sp')\n"
        "memory = sys.argv[1] == 'memory'\n"
        "if memory: tracemalloc.start()\n"
        "t = time.perf_counter()\n"
        f"m = blockmesh.refine(d, {level})\n"
        "t = time.perf_counter() - t\n"
        "print(tracemalloc.get_traced_memory()[1] / m.nbytes() if memory else t)\n"
    )

    def fresh(what: str) -> float:
        out = subprocess.run(
            [sys.executable, "-c", code, what], capture_output=True, text=True, check=True
        )
        return float(out.stdout)

    return min(fresh("time") for _ in range(3)), fresh("memory")


def peak_ratio(domain, level: int) -> tuple[float, int]:
    """Peak bytes allocated during a warm refine, over the bytes of the mesh it returns."""
    pentagon_template(level)
    tracemalloc.start()
    mesh = blockmesh.refine(domain, level)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / mesh.nbytes(), mesh.nbytes()


def triangle_rate(target_triangles: int, repeat: int) -> tuple[float, int]:
    import triangle

    area = 5.0 / target_triangles * 1.15
    geometry = {
        "vertices": np.array(SP),
        "segments": np.array([[i, (i + 1) % 5] for i in range(5)]),
    }
    out = {}

    def run():
        out["mesh"] = triangle.triangulate(geometry, f"pqa{area:.10f}")

    seconds = best_of(run, repeat)
    count = len(out["mesh"]["triangles"])
    return count / seconds, count


def gmsh_rate(target_triangles: int) -> tuple[float, int]:
    import gmsh

    size = np.sqrt(4 * 5.0 / np.sqrt(3) / target_triangles)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        best = np.inf
        count = 0
        for _ in range(2):
            gmsh.clear()
            gmsh.model.add("sp")
            tags = [gmsh.model.geo.addPoint(x, y, 0, size) for x, y in SP]
            lines = [gmsh.model.geo.addLine(tags[i], tags[(i + 1) % 5]) for i in range(5)]
            loop = gmsh.model.geo.addCurveLoop(lines)
            gmsh.model.geo.addPlaneSurface([loop])
            gmsh.model.geo.synchronize()
            start = time.perf_counter()
            gmsh.model.mesh.generate(2)
            best = min(best, time.perf_counter() - start)
            _, element_tags, _ = gmsh.model.mesh.getElements(2)
            count = sum(len(t) for t in element_tags)
        return count / best, count
    finally:
        gmsh.finalize()


ABOUT = """\
`blockmesh.refine` on a single pentagon (the paper's SP) at levels 4-8, warm (the template cached)
and on the first call in a fresh process; every catalogue domain at the level that gives about
3 M cells, with the default worker threads and with one, against SP in the same run and against
the floor of allocating and writing as many bytes as the output (`np.ones`); the peak memory over
the output arrays; and the peers (Triangle, gmsh; `pip install -e '.[bench]'`) meshing the same
pentagon. Best of several runs after a warm-up; timings on shared machines are noisy."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--gmsh-triangles", type=int, default=200_000)
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("refine", "Refinement", ABOUT)

    sp = blockmesh.load_domain("sp")
    single = page.table(
        "A single pentagon (SP), warm (template cached)",
        ["level", "cells", "time", "ns/cell", "M cells/s"],
    )
    rates = {}
    for level in range(4, 9):
        repeat = args.repeat if level >= 7 else 4 * args.repeat
        seconds = best_of(lambda level=level: blockmesh.refine(sp, level), repeat)
        cells = 6**level
        rates[level] = cells / seconds
        single.row(
            level,
            f"{cells:,}",
            f"{seconds * 1e3:.2f} ms",
            f"{seconds / cells * 1e9:.1f}",
            f"{cells / seconds / 1e6:.1f}",
        )
    first, first_peak = first_call(8)
    single.note(
        f"First call in a fresh process, level 8: {first * 1e3:.0f} ms = "
        f"{6**8 / first / 1e6:.1f} M cells/s ({first / 6**8 * 1e9:.0f} ns/cell), "
        f"peak memory {first_peak:.2f} x the output arrays."
    )
    threads = default_threads()
    domains = page.table(
        "Every catalogue domain at the level giving about 3 M cells, warm",
        [
            "domain",
            "blocks",
            "level",
            "cells",
            "time",
            f"ns/cell, {threads} thread(s)",
            "ns/cell, 1 thread",
            "over SP",
            "floor ns/cell",
        ],
    )
    sp_ns = best_of(lambda: blockmesh.refine(sp, 8), args.repeat) / 6**8
    worst = ("", 0.0)
    for name in catalogue_names():
        domain = blockmesh.load_domain(name)
        level = max(1, round(math.log(3e6 / domain.n_blocks, 6)))
        cells = domain.n_blocks * 6**level
        seconds = best_of(lambda d=domain, lv=level: blockmesh.refine(d, lv), args.repeat)
        one = best_of(lambda d=domain, lv=level: blockmesh.refine(d, lv, threads=1), args.repeat)
        nbytes = blockmesh.refine(domain, level).nbytes()
        floor = best_of(lambda n=nbytes: np.ones(n // 8), args.repeat)
        ns = seconds / cells * 1e9
        worst = max(worst, (name, ns), key=lambda pair: pair[1])
        domains.row(
            name,
            domain.n_blocks,
            level,
            f"{cells:,}",
            f"{seconds * 1e3:.1f} ms",
            f"{ns:.1f}",
            f"{one / cells * 1e9:.1f}",
            f"{ns / (sp_ns * 1e9):.2f}",
            f"{floor / cells * 1e9:.1f}",
        )
    domains.note(
        f'{threads} worker thread(s) is the default here. "over SP": ns per cell over SP\'s at '
        f"level 8 in the same run ({sp_ns * 1e9:.1f}); floor: allocating and writing as many "
        f"bytes as the output (np.ones). Slowest domain: {worst[0]} at {worst[1]:.1f} ns per cell."
    )
    joined = blockmesh.load_domain("joined-8")
    memory = [
        f"Template cache: {cached_template_bytes() / 1e6:.0f} MB kept "
        f"(bounded by {TEMPLATE_CACHE_BYTES / 2**20:.0f} MiB)."
    ]
    for name, domain, level in (("SP", sp, 8), ("joined-8", joined, 7)):
        ratio, nbytes = peak_ratio(domain, level)
        memory.append(
            f"Peak memory (tracemalloc), {name} at level {level}: {ratio:.2f} x the output "
            f"arrays ({nbytes / 1e6:.0f} MB)."
        )
    page.text(" ".join(memory))

    peers = page.table(
        "Peers meshing the same pentagon",
        ["peer", "triangles", "M triangles/s", "blockmesh (SP level 8) faster per element"],
    )
    try:
        tri_rate, tri_count = triangle_rate(6**8, max(2, args.repeat // 2))
        peers.row(
            "Triangle", f"{tri_count:,}", f"{tri_rate / 1e6:.2f}", f"{rates[8] / tri_rate:.0f}x"
        )
    except ImportError:
        page.text("Triangle is not installed (`pip install triangle`).")
    try:
        gm_rate, gm_count = gmsh_rate(args.gmsh_triangles)
        peers.row("gmsh", f"{gm_count:,}", f"{gm_rate / 1e6:.3f}", f"{rates[8] / gm_rate:.0f}x")
    except ImportError:
        page.text("gmsh is not installed (`pip install gmsh`).")
    page.write(args)


if __name__ == "__main__":
    main()
