"""The whole ``blockmesh mesh`` command against the refinement alone, stage by stage.

Run: ``python benchmarks/bench_pipeline.py``. Three parts, each the best of several runs after a
warm-up, with ratios against the peer measured in the same run (the machines are shared):

1. in one process: the refinement, then each stage the command runs on its result (the one-pass
   cell measures, which give the report its quality, area and bandwidth; the picture of a big
   mesh; an XDMF export), as multiples of the refinement's time;
2. fresh processes: ``blockmesh mesh DOMAIN --level L [-o OUT.xdmf]`` against ``python -c``
   refining the same domain [and writing the same file], start-up and imports included in both;
3. start-up: ``blockmesh --version`` and ``--help`` against ``python -c pass``.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _page import Page, add_arguments

CASES = [("sp", 8), ("joined-8", 7), ("l-shape", 6), ("ring", 7), ("joined-8", 8)]


def best_of(function, repeat: int) -> float:
    function()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def wall(argv: list[str], repeat: int) -> float:
    def run():
        subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    return best_of(run, repeat)


def in_process(page: Page, repeat: int) -> None:
    import blockmesh
    from blockmesh.mesh.measures import measure_cells
    from blockmesh.plot import plot_mesh, pyplot

    pyplot()
    folder = Path(tempfile.mkdtemp(prefix="bench-pipeline-"))
    table = page.table(
        "1. Stages in one process (warm), against the refinement",
        ["domain", "level", "cells", "refine", "report", "report / refine", "plot", "XDMF"],
    )
    try:
        for name, level in CASES:
            domain = blockmesh.load_domain(name)
            refine = best_of(lambda d=domain, lv=level: blockmesh.refine(d, lv), repeat)
            mesh = blockmesh.refine(domain, level)
            report = best_of(lambda m=mesh: measure_cells(m), repeat)
            plot = best_of(lambda m=mesh: plot_mesh(m, folder / "m.png"), 1)
            xdmf = best_of(
                lambda m=mesh: blockmesh.write(m, folder / "m.xdmf"), max(1, repeat // 2)
            )
            table.row(
                name,
                level,
                f"{mesh.n_cells:,}",
                f"{refine * 1e3:.0f} ms ({refine / mesh.n_cells * 1e9:.0f} ns/cell)",
                f"{report * 1e3:.0f} ms ({report / mesh.n_cells * 1e9:.0f} ns/cell)",
                f"{report / refine:.2f}",
                f"{plot:.2f} s",
                f"{xdmf:.2f} s",
            )
            del mesh
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    table.note(
        "report: the one pass of cell measures that gives the report its quality, area and "
        "bandwidth; plot: the mesh picture (cell density beyond 200,000 cells); XDMF: writing the "
        "mesh. Best of runs after a warm-up."
    )


def interleaved(commands: dict[str, list[str]], repeat: int) -> dict[str, list[float]]:
    """Wall times of each command, run in turn ``repeat`` times after one warm-up round (so that
    a slow spell of the shared machine hits all of them alike)."""
    times: dict[str, list[float]] = {key: [] for key in commands}
    for round_ in range(repeat + 1):
        for key, argv in commands.items():
            start = time.perf_counter()
            subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            if round_:
                times[key].append(time.perf_counter() - start)
    return times


def fresh(page: Page, repeat: int) -> None:
    python = sys.executable
    folder = Path(tempfile.mkdtemp(prefix="bench-pipeline-"))
    table = page.table(
        "2. Fresh processes: the command against refining alone, start-up included",
        [
            "domain",
            "level",
            "refine alone",
            "`blockmesh mesh`",
            "ratio (best, median)",
            "refine + XDMF",
            "`mesh -o m.xdmf`",
            "ratio (best, median)",
        ],
    )
    try:
        for name, level in CASES:
            out = folder / "m.xdmf"
            t = interleaved(
                {
                    "alone": [python, "-c", f"import blockmesh; blockmesh.refine("
                              f"blockmesh.load_domain({name!r}), {level})"],
                    "command": ["blockmesh", "mesh", name, "--level", str(level)],
                    "alone_out": [python, "-c", f"import blockmesh; blockmesh.write("
                                  f"blockmesh.refine(blockmesh.load_domain({name!r}), {level}), "
                                  f"{str(out)!r})"],
                    "command_out": ["blockmesh", "mesh", name, "--level", str(level), "-o",
                                    str(out)],
                },
                repeat,
            )  # fmt: skip
            best = {key: min(values) for key, values in t.items()}
            median = {key: statistics.median(values) for key, values in t.items()}
            table.row(
                name,
                level,
                f"{best['alone']:.2f} s",
                f"{best['command']:.2f} s",
                f"{best['command'] / best['alone']:.2f}, {median['command'] / median['alone']:.2f}",
                f"{best['alone_out']:.2f} s",
                f"{best['command_out']:.2f} s",
                f"{best['command_out'] / best['alone_out']:.2f}, "
                f"{median['command_out'] / median['alone_out']:.2f}",
            )
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    table.note(
        f"`blockmesh mesh DOMAIN --level L [-o m.xdmf]` against `python -c` refining the same "
        f"domain [and writing the same file]; {repeat} interleaved runs of the four commands, the "
        "ratio of the best times and of the medians."
    )


def startup(page: Page, repeat: int) -> None:
    python = sys.executable
    floor = wall([python, "-c", "pass"], repeat)
    version = wall(["blockmesh", "--version"], repeat)
    helping = wall(["blockmesh", "--help"], repeat)
    importing = wall([python, "-c", "import numpy"], repeat)
    table = page.table(
        "3. Start-up, fresh processes (best of runs)", ["command", "time", "over python"]
    )
    table.row("`python -c pass`", f"{floor * 1e3:.0f} ms", "1")
    table.row("`python -c 'import numpy'`", f"{importing * 1e3:.0f} ms", f"{importing / floor:.1f}")
    table.row("`blockmesh --version`", f"{version * 1e3:.0f} ms", f"{version / floor:.1f}")
    table.row("`blockmesh --help`", f"{helping * 1e3:.0f} ms", f"{helping / floor:.1f}")


ABOUT = """\
What `blockmesh mesh` costs on top of the refinement: in one process, each stage the command runs
on the refined mesh as a multiple of the refinement's time; in fresh processes (what a user runs),
the command against `python -c` refining the same domain, with and without writing an XDMF file;
and the start-up of the command. Ratios are against the peer measured in the same run (the
machines are shared)."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--part", choices=("all", "stages", "fresh", "startup"), default="all")
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("pipeline", "The whole command", ABOUT)
    if args.part in ("all", "stages"):
        in_process(page, args.repeat)
    if args.part in ("all", "fresh"):
        fresh(page, args.repeat)
    if args.part in ("all", "startup"):
        startup(page, max(5, args.repeat))
    page.write(args)


if __name__ == "__main__":
    main()
