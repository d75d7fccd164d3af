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


def in_process(repeat: int) -> None:
    import blockmesh
    from blockmesh.mesh.measures import measure_cells
    from blockmesh.plot import plot_mesh, pyplot

    pyplot()
    folder = Path(tempfile.mkdtemp(prefix="bench-pipeline-"))
    print("1. stages in one process (warm), as multiples of the refinement")
    print(
        f"{'domain':>10} {'L':>2} {'cells':>11} {'refine':>8} {'ns/cell':>7} {'report':>8} "
        f"{'ns/cell':>7} {'report/refine':>13} {'plot':>7} {'xdmf':>7}"
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
            print(
                f"{name:>10} {level:>2} {mesh.n_cells:>11,} {refine * 1e3:>6.0f}ms "
                f"{refine / mesh.n_cells * 1e9:>7.1f} {report * 1e3:>6.0f}ms "
                f"{report / mesh.n_cells * 1e9:>7.1f} {report / refine:>12.2f}x "
                f"{plot:>6.2f}s {xdmf:>6.2f}s"
            )
            del mesh
    finally:
        shutil.rmtree(folder, ignore_errors=True)


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


def fresh(repeat: int) -> None:
    python = sys.executable
    folder = Path(tempfile.mkdtemp(prefix="bench-pipeline-"))
    print("\n2. fresh processes: the command against refining alone (start-up included); best of")
    print(f"   {repeat} interleaved runs, and the ratio of the medians")
    print(
        f"{'domain':>10} {'L':>2} {'refine':>8} {'mesh':>8} {'ratio':>6} {'median':>6} "
        f"{'refine+xdmf':>12} {'mesh -o xdmf':>13} {'ratio':>6} {'median':>6}"
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
            print(
                f"{name:>10} {level:>2} {best['alone']:>7.2f}s {best['command']:>7.2f}s "
                f"{best['command'] / best['alone']:>5.2f}x "
                f"{median['command'] / median['alone']:>5.2f}x "
                f"{best['alone_out']:>11.2f}s {best['command_out']:>12.2f}s "
                f"{best['command_out'] / best['alone_out']:>5.2f}x "
                f"{median['command_out'] / median['alone_out']:>5.2f}x"
            )
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def startup(repeat: int) -> None:
    python = sys.executable
    floor = wall([python, "-c", "pass"], repeat)
    version = wall(["blockmesh", "--version"], repeat)
    helping = wall(["blockmesh", "--help"], repeat)
    importing = wall([python, "-c", "import numpy"], repeat)
    print("\n3. start-up (best of runs, fresh processes)")
    print(f"  python -c pass        {floor * 1e3:6.0f} ms")
    print(f"  python -c 'import numpy' {importing * 1e3:4.0f} ms")
    print(f"  blockmesh --version   {version * 1e3:6.0f} ms ({version / floor:.1f}x python)")
    print(f"  blockmesh --help      {helping * 1e3:6.0f} ms ({helping / floor:.1f}x python)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--part", choices=("all", "stages", "fresh", "startup"), default="all")
    args = parser.parse_args()
    if args.part in ("all", "stages"):
        in_process(args.repeat)
    if args.part in ("all", "fresh"):
        fresh(args.repeat)
    if args.part in ("all", "startup"):
        startup(max(5, args.repeat))


if __name__ == "__main__":
    main()
