"""What the curve checks cost on a curved polygon domain, and the commands that load it.

Run: ``python benchmarks/bench_curve_checks.py``. Builds the bracket of issue 22 (an L-shaped
plate with a fillet arc at its inner corner and two circular bolt holes: 1,272 blocks, 105
curved edges), writes it as a domain file, then prints the best of several runs of
:func:`blockmesh.domain.curve_checks.check_curved_blocks`, of reading the file
(:meth:`blockmesh.Domain.from_toml`, whose validation runs the checks), and the CPU time of
``blockmesh check``, ``show``, ``mesh --level 1`` and ``solve --level 1`` on the file, each in a
fresh process. Not a test: timings on shared machines are noisy (CPU time of the child processes
is reported for the commands, the best wall time of several runs for the functions).
"""

from __future__ import annotations

import argparse
import resource
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from _page import Page, add_arguments
from bench_curved import best_of  # the best of several runs after a warm-up

import blockmesh
import blockmesh.domain.curve_checks as curve_checks
from blockmesh.curves import Arc
from blockmesh.domain.curve_checks import check_curved_blocks


def bracket(holes_per_arm: int = 1, sides: int = 8) -> blockmesh.Domain:
    """An L-bracket with a fillet at its inner corner and circular bolt holes in both arms."""
    ring = [(0, 0), (20, 0), (20, 3), (4, 3), (3, 4), (3, 20), (0, 20)]
    circles = []
    for k in range(holes_per_arm):
        along = 6 + 13 * k / max(holes_per_arm - 1, 1)
        circles.append({"center": (along, 1.5), "radius": 0.5, "sides": sides})
        circles.append({"center": (1.5, along), "radius": 0.5, "sides": sides})
    return blockmesh.Domain.from_polygon(
        ring,
        arcs={3: Arc(center=(4, 4))},
        circles=circles,
        name="bracket",
        patches={"fixed": [6], "load": [1]},
    )


def command_seconds(folder: Path, *argv: str) -> float:
    """CPU seconds (user + system) of one ``blockmesh`` command in a fresh process.

    It runs in ``folder``: ``python -m`` puts the working folder first on the path, which in a
    checkout would shadow the blockmesh that ``PYTHONPATH`` names (to measure another version).
    """
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(
        [sys.executable, "-m", "blockmesh", *argv], check=True, capture_output=True, cwd=folder
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("curve-checks", "Checks of curved blocks", __doc__)
    domain = bracket()
    page.text(f"The bracket: {domain.n_blocks:,} blocks, {len(domain.curves)} curved edges.")
    table = page.table("Seconds", ["what", "seconds", "how"])
    folder = Path(tempfile.mkdtemp(prefix="bench-curve-checks-"))
    path = domain.write_toml(folder / "bracket.toml")

    def forget() -> None:
        """Measure the work, not the memory of a pass (blockmesh before issue 22 had none)."""
        getattr(curve_checks, "_PASSED", {}).clear()

    def check(fresh: bool) -> None:
        if fresh:
            forget()
        check_curved_blocks(domain.vertices, domain.blocks, domain.curves)

    checks = best_of(lambda: check(True), args.repeat)
    table.row("check_curved_blocks", f"{checks:.3f}", f"best of {args.repeat}")
    again = best_of(lambda: check(False), args.repeat)
    table.row("the same domain again", f"{again:.3f}", "remembered")

    def load_fresh() -> None:
        forget()
        blockmesh.Domain.from_toml(path)

    load = best_of(load_fresh, args.repeat)
    table.row("Domain.from_toml", f"{load:.3f}", f"best of {args.repeat}; checks included")
    try:
        for argv in (
            ["check", str(path)],
            ["show", str(path), "-o", str(folder / "b.png")],
            ["mesh", str(path), "--level", "1"],
            ["solve", str(path), "--level", "1", "--source", "1", "--dirichlet", "fixed=0"],
        ):
            seconds = min(command_seconds(folder, *argv) for _ in range(max(1, args.repeat // 2)))
            table.row(f"blockmesh {argv[0]}", f"{seconds:.3f}", "CPU, fresh process")
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    page.write(args)


if __name__ == "__main__":
    main()
