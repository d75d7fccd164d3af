"""The whole ``blockmesh mesh`` command against the refinement alone, stage by stage.

Run: ``python benchmarks/bench_pipeline.py``. Three parts, each the best of several runs after a
warm-up, with ratios against the peer measured in the same run (the machines are shared):

1. in one process: the refinement, then each stage the command runs on its result (bandwidth,
   the one-pass quality measures, the picture of a big mesh, an XDMF export), as multiples of the
   refinement's time;
2. fresh processes: ``blockmesh mesh DOMAIN --level L [-o OUT.xdmf]`` against ``python -c``
   refining the same domain [and writing the same file], start-up and imports included in both;
3. start-up: ``blockmesh --version`` and ``--help`` against ``python -c pass``.
"""

from __future__ import annotations

import argparse
import shutil
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
    from blockmesh.measures import measure_cells
    from blockmesh.plot import plot_mesh, pyplot

    pyplot()
    folder = Path(tempfile.mkdtemp(prefix="bench-pipeline-"))
    print("1. stages in one process (warm), as multiples of the refinement")
    print(
        f"{'domain':>10} {'L':>2} {'cells':>11} {'refine':>8} {'ns/cell':>7} {'bandwidth':>9} "
        f"{'quality':>8} {'report/refine':>13} {'plot':>7} {'xdmf':>7}"
    )
    try:
        for name, level in CASES:
            domain = blockmesh.load_domain(name)
            refine = best_of(lambda d=domain, lv=level: blockmesh.refine(d, lv), repeat)
            mesh = blockmesh.refine(domain, level)
            bandwidth = best_of(mesh.bandwidth, repeat)
            quality = best_of(lambda m=mesh: measure_cells(m), repeat)
            plot = best_of(lambda m=mesh: plot_mesh(m, folder / "m.png"), 1)
            xdmf = best_of(
                lambda m=mesh: blockmesh.write(m, folder / "m.xdmf"), max(1, repeat // 2)
            )
            print(
                f"{name:>10} {level:>2} {mesh.n_cells:>11,} {refine * 1e3:>6.0f}ms "
                f"{refine / mesh.n_cells * 1e9:>7.1f} {bandwidth / refine:>8.2f}x "
                f"{quality / refine:>7.2f}x {(bandwidth + quality) / refine:>12.2f}x "
                f"{plot:>6.2f}s {xdmf:>6.2f}s"
            )
            del mesh
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def fresh(repeat: int) -> None:
    python = sys.executable
    folder = Path(tempfile.mkdtemp(prefix="bench-pipeline-"))
    print("\n2. fresh processes: the command against refining alone (start-up included)")
    print(
        f"{'domain':>10} {'L':>2} {'refine':>8} {'mesh':>8} {'ratio':>6} "
        f"{'refine+xdmf':>12} {'mesh -o xdmf':>13} {'ratio':>6}"
    )
    try:
        for name, level in CASES:
            out = folder / "m.xdmf"
            alone = wall(
                [python, "-c", f"import blockmesh; blockmesh.refine(blockmesh.load_domain("
                 f"{name!r}), {level})"],
                repeat,
            )  # fmt: skip
            command = wall(["blockmesh", "mesh", name, "--level", str(level)], repeat)
            alone_out = wall(
                [python, "-c", f"import blockmesh; blockmesh.write(blockmesh.refine("
                 f"blockmesh.load_domain({name!r}), {level}), {str(out)!r})"],
                repeat,
            )  # fmt: skip
            command_out = wall(
                ["blockmesh", "mesh", name, "--level", str(level), "-o", str(out)], repeat
            )
            print(
                f"{name:>10} {level:>2} {alone:>7.2f}s {command:>7.2f}s {command / alone:>5.2f}x "
                f"{alone_out:>11.2f}s {command_out:>12.2f}s {command_out / alone_out:>5.2f}x"
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
    parser.add_argument("--repeat", type=int, default=3)
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
