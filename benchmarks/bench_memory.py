"""The memory guard against measured peak resident memory, stage by stage and command by command.

Run: ``python benchmarks/bench_memory.py`` (whole commands, levels 6-9) or
``python benchmarks/bench_memory.py --calibrate`` (each stage's extra memory, fitted per cell).

Default mode: runs ``blockmesh mesh DOMAIN --level L [stage options] --json`` in a fresh process
for every stage combination and level, reads the command's own prediction
(``predicted_peak_bytes``) and the process's measured peak resident set (``ru_maxrss`` of the
child), and prints their ratio; the guard is meant to be within 25 % at levels 6-9.

Calibrate mode: in one process, refines once per level, then runs each stage (report, rcm, plots,
every export format) with the peak resident set reset before it (``/proc/self/clear_refs``), and
fits ``extra = per_cell * cells + constant`` over the levels: the numbers in
``blockmesh.refinement.sizes.STAGE_COSTS``. Not a test: figures depend on the machine and its
libraries.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _page import Page, add_arguments

STAGES = {
    "report": [],
    "rcm": ["--numbering", "rcm"],
    "plot": ["--plot", "{dir}/p.png"],
    "quality_plot": ["--quality-plot", "{dir}/q.png"],
    "xdmf": ["-o", "{dir}/o.xdmf"],
    "xdmf:zlib": ["-o", "{dir}/o.xdmf", "--compression", "zlib"],
    "npz": ["-o", "{dir}/o.npz"],
    "mat": ["-o", "{dir}/o.mat"],
    "vtu:none": ["-o", "{dir}/o.vtu", "--compression", "none"],
    "vtu:zlib": ["-o", "{dir}/o.vtu", "--compression", "zlib"],
    "vtu:lzma": ["-o", "{dir}/o.vtu", "--compression", "lzma"],
    "msh:tri3": ["-o", "{dir}/o.msh", "--split", "tri3"],
    "msh:tri5": ["-o", "{dir}/o.msh", "--split", "tri5"],
    "msh:quad5": ["-o", "{dir}/o.msh", "--split", "quad5"],
    "openfoam": ["-o", "{dir}/case", "--format", "openfoam"],
}

RUNNER = """
import json, resource, sys
from blockmesh.cli import main
code = main(sys.argv[1:])
print("PEAK", resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, file=sys.stderr)
sys.exit(code)
"""


def measure_command(domain: str, level: int, stage: str, folder: Path) -> tuple[int, int, float]:
    """(predicted, measured peak bytes, seconds) of one ``blockmesh mesh`` command."""
    extra = [a.format(dir=folder) for a in STAGES[stage]]
    argv = ["mesh", domain, "--level", str(level), "--json", *extra]
    start = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", RUNNER, *argv], capture_output=True, text=True, check=False
    )
    seconds = time.perf_counter() - start
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed: {out.stderr.strip()[-500:]}")
    report = json.loads(out.stdout)
    peak = int(out.stderr.split("PEAK")[-1].split()[0])
    return int(report["predicted_peak_bytes"]), peak, seconds


def check(args: argparse.Namespace) -> None:
    page = Page("memory", "The memory guard", ABOUT)
    table = page.table(
        "`blockmesh mesh DOMAIN --level L [stage]`: predicted peak against measured peak RSS",
        ["domain", "level", "stage", "predicted", "measured", "predicted / measured", "time"],
    )
    worst = 0.0
    for domain in args.domains:
        for level in args.levels:
            for stage in args.stages:
                folder = Path(tempfile.mkdtemp(prefix="bench-memory-"))
                try:
                    predicted, measured, seconds = measure_command(domain, level, stage, folder)
                except RuntimeError as error:
                    table.row(domain, level, stage, "", "", f"failed: {error}", "")
                    continue
                finally:
                    shutil.rmtree(folder, ignore_errors=True)
                ratio = predicted / measured
                worst = max(worst, abs(ratio - 1))
                table.row(
                    domain,
                    level,
                    stage,
                    f"{predicted / 1e6:.0f} MB",
                    f"{measured / 1e6:.0f} MB",
                    f"{ratio:.2f}",
                    f"{seconds:.1f} s",
                )
    table.note(f"Largest deviation: {worst:.0%}.")
    page.write(args)


# ------------------------------------------------------------------------------ calibration
def _rss() -> int:
    from blockmesh._system.memory import process_rss

    return process_rss()


def _stage_extra(run) -> int:
    from blockmesh._system.memory import peak_rss, reset_peak_rss

    gc.collect()
    before = _rss()
    reset_peak_rss()
    run()
    return peak_rss() - before


def calibrate(args: argparse.Namespace) -> None:
    import blockmesh
    import blockmesh.io
    import blockmesh.plot

    blockmesh.plot.pyplot()
    # Imports are not what is measured.
    import scipy.io
    import scipy.sparse.csgraph  # noqa: F401

    domain = blockmesh.load_domain(args.domains[0])
    page = Page("memory-calibration", "The memory guard's calibration", CALIBRATION)
    measured = page.table(
        f"Each stage's extra memory, {args.domains[0]}",
        ["level", "cells", "mesh", "stage", "extra", "bytes per cell"],
    )
    extras: dict[str, list[tuple[int, int]]] = {}
    folder = Path(tempfile.mkdtemp(prefix="bench-memory-"))
    try:
        for level in args.levels:
            mesh = blockmesh.refine(domain, level)
            for stage in args.stages:

                def run(stage=stage, mesh=mesh):
                    if stage == "report":
                        mesh.quality(chunk=4096)
                        mesh.bandwidth()
                    elif stage == "rcm":
                        mesh.with_rcm_numbering()
                    elif stage == "plot":
                        blockmesh.plot.plot_mesh(mesh, folder / "p.png")
                    elif stage == "quality_plot":
                        blockmesh.plot.plot_quality(mesh, folder / "q.png")
                    else:
                        fmt, _, option = stage.partition(":")
                        options = {}
                        if fmt == "msh":
                            options["split"] = option
                        elif option:
                            options["compression"] = option
                        target = folder / ("case" if fmt == "openfoam" else f"o.{fmt}")
                        blockmesh.io.write(mesh, target, format=fmt, **options)

                extra = _stage_extra(run)
                extras.setdefault(stage, []).append((mesh.n_cells, extra))
                measured.row(
                    level,
                    f"{mesh.n_cells:,}",
                    f"{mesh.nbytes() / 1e6:.0f} MB",
                    stage,
                    f"{extra / 1e6:.1f} MB",
                    f"{extra / mesh.n_cells:.1f}",
                )
            del mesh
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    fitted = page.table(
        "Fitted: extra = per_cell * cells + constant", ["stage", "per_cell", "constant"]
    )
    for stage, points in extras.items():
        cells = np.array([c for c, _ in points], dtype=float)
        extra = np.array([e for _, e in points], dtype=float)
        if len(points) > 1:
            per_cell, constant = np.polyfit(cells, extra, 1)
        else:
            per_cell, constant = extra[0] / cells[0], 0.0
        fitted.row(stage, f"{per_cell:.1f}", f"{constant / 1e6:.1f} MB")
    fitted.note(
        "The numbers of `blockmesh.refinement.sizes.STAGE_COSTS`: update them when a writer "
        "changes."
    )
    page.write(args)


ABOUT = """\
The memory guard's prediction of the peak resident memory of `blockmesh mesh DOMAIN --level L
[stage options]` (`predicted_peak_bytes` of `--json`) against the command's measured peak
(`ru_maxrss` of a fresh process), for every stage variant: the report, RCM renumbering, the plots
and every export format. The guard is meant to be within 25 % at levels 6-9."""

CALIBRATION = """\
In one process: refine once per level, then run each stage (report, RCM, plots, every export
format) with the peak resident set reset before it (`/proc/self/clear_refs`), and fit
`extra = per_cell * cells + constant` over the levels: the figures of
`blockmesh.refinement.sizes.STAGE_COSTS`."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calibrate", action="store_true")
    parser.add_argument("--domains", nargs="+", default=["sp"])
    parser.add_argument("--levels", nargs="+", type=int)
    parser.add_argument("--stages", nargs="+", default=list(STAGES), choices=list(STAGES))
    add_arguments(parser)
    args = parser.parse_args()
    if args.levels is None:
        args.levels = [7, 8] if args.calibrate else [6, 7, 8, 9]
    os.environ.setdefault("MPLBACKEND", "Agg")
    (calibrate if args.calibrate else check)(args)


if __name__ == "__main__":
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    main()
