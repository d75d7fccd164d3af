"""Mutation fuzzing of every reader: valid files, damaged at random, read in a bounded process.

Targets: the mesh formats (``vtu vtk msh xdmf npz mat openfoam``, read by :func:`blockmesh.read`),
the domain forms (``toml wkt geojson``, read by :func:`blockmesh.load_domain`) and
``expressions`` (parsed, evaluated and expanded). Each case takes a valid seed (several layouts
per format: compressions, splits, curved edges...), damages one of its files with one to three
mutations (bit flips, interesting bytes, cut, deleted or repeated spans, numbers replaced by
extreme ones) and reads it. A case passes when it reads or raises a :class:`BlockMeshError`
(warnings are counted, not failures); it fails when anything else escapes, when it runs longer
than ``--case-seconds`` of CPU time (SIGPROF) or three times that of real time (SIGALRM: a read
that blocks uses no CPU), or when it needs more than ``--memory`` bytes (the address space is
limited: ``MemoryError``). The peak resident memory of each case is measured (the
process's high-water mark, reset before the case).

Run by the slow test ``test_hostile_fuzz.py`` for a few seconds a target, and by hand for long
runs, e.g. ten minutes of each reader::

    python tests/hostile/fuzz_readers.py --seconds 600 --target vtu --out fuzz-vtu.json

Failing inputs are saved under ``--keep`` (default: a temporary folder) to reproduce them.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import random
import resource
import shutil
import signal
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter
from pathlib import Path

TARGETS = (
    "vtu", "vtk", "msh", "xdmf", "npz", "mat", "openfoam", "toml", "wkt", "geojson", "expressions",
)  # fmt: skip

#: Replacements for a number of a text file: the values that break sizes and indices.
_NUMBERS = [
    b"-1", b"0", b"-7", b"2147483648", b"4294967297", b"9223372036854775808", b"1e308", b"-1e308",
    b"1e-320", b"nan", b"inf", b"-inf", b"99999999999999999999999", b"1000000000000", b"3.5",
    b"1e300", b"0x10",
]  # fmt: skip
_BYTES = [0x00, 0xFF, 0x7F, 0x80, ord("9"), ord("-"), ord('"'), ord("<"), ord(">"), ord("{")]


class _Hang(BaseException):
    """A case ran past its time (raised by SIGALRM)."""


# ------------------------------------------------------------------------------ seeds
Seed = tuple[dict[str, bytes], str]  # the files of a case (relative name -> bytes), what to read


def _files_under(folder: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def make_seeds(target: str, work: Path) -> list[Seed]:
    """Valid inputs of ``target``, in several layouts each."""
    import blockmesh

    folder = Path(tempfile.mkdtemp(dir=work))
    if target == "expressions":
        texts = [
            "x^2 + y", "sin(pi*x)*exp(-y^2)", "sqrt(x^2 + y^2 + 1)", "1/(1 + x*x)",
            "abs(x - 0.5) + max(x, y)", "log(2 + cos(x)) - tanh(y)", "x^10 - 3*x*y^4",
        ]  # fmt: skip
        return [({"f.txt": t.encode()}, "f.txt") for t in texts]
    if target in ("toml", "wkt", "geojson"):
        return _domain_seeds(target, folder)
    meshes = [
        blockmesh.load_domain("sp").mesh(1),
        blockmesh.load_domain("l-shape").mesh(1),
        blockmesh.load_domain("joined-2").mesh(1),
        blockmesh.load_domain("disc").mesh(1),  # curved edges (kept by npz, xdmf, vtu)
        blockmesh.refine(blockmesh.load_domain("sp").mesh(1), cells=[0, 3]),  # a PolygonMesh
    ]
    variants: list[dict] = {
        "vtu": [{"compression": c} for c in ("zlib", "lzma", "none")],
        "vtk": [{}],
        "msh": [{"split": s} for s in ("tri5", "tri3", "quad5")],
        "xdmf": [{"compression": c} for c in ("none", "zlib")],
        "npz": [{"compression": c} for c in ("none", "zlib")],
        "mat": [{"compression": c} for c in ("none", "zlib")],
        "openfoam": [{}],
    }[target]
    seeds = []
    for k, mesh in enumerate(meshes):
        for j, options in enumerate(variants):
            case = folder / f"{k}-{j}"
            case.mkdir()
            name = "case" if target == "openfoam" else f"m.{target}"
            fmt = "openfoam" if target == "openfoam" else None
            try:
                blockmesh.write(mesh, case / name, format=fmt, **options)
            except blockmesh.BlockMeshError:  # an option the polygon mesh does not take
                shutil.rmtree(case)
                continue
            seeds.append((_files_under(case), name))
    return seeds


def _domain_seeds(target: str, folder: Path) -> list[Seed]:
    import blockmesh

    if target == "toml":
        names = ["sp", "l-shape", "joined-2", "plate-hole", "square"]
        texts = [blockmesh.load_domain(n).to_toml() for n in names if _known(n)]
        texts += [
            "polygon = [[0, 0], [4, 0], [4, 2], [0, 2]]\n"
            "holes = [[[1.5, 0.5], [2.5, 0.5], [2.5, 1.5], [1.5, 1.5]]]\n"
            '[patches]\ninlet = [3]\ncylinder = ["hole 0"]\n',
            'circle = {center = [0, 0], radius = 1, patch = "rim"}\n',
            "polygon = [[0, 0], [3, 0], [3, 2], [0, 2]]\n"
            'circles = [{center = [1.5, 1], radius = 0.4, patch = "hole"}]\n'
            "[[arcs]]\nedge = 0\nthrough = [1.5, -0.3]\n",
            "vertices = [[0, 0], [2, 0], [2, 1], [1, 2], [0, 1]]\nblocks = [[0, 1, 2, 3, 4]]\n"
            "[[edges]]\nspline = [0, 1]\npoints = [[0.5, -0.1], [1.0, -0.15], [1.5, -0.1]]\n"
            "[[edges]]\narc = [2, 3]\nthrough = [1.6, 1.6]\n",
        ]
        return [({"d.toml": t.encode()}, "d.toml") for t in texts]
    rings = [
        [(0, 0), (4, 0), (4, 2), (0, 2)],
        [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)],
        [(math.cos(2 * math.pi * k / 40), math.sin(2 * math.pi * k / 40)) for k in range(40)],
    ]
    hole = [(1.5, 0.5), (1.5, 1.5), (2.5, 1.5), (2.5, 0.5)]
    seeds = []
    for k, ring in enumerate(rings):
        holes = [hole] if k == 0 else []
        if target == "wkt":
            parts = [ring, *holes]
            text = (
                "POLYGON ("
                + ", ".join(
                    "(" + ", ".join(f"{x!r} {y!r}" for x, y in [*p, p[0]]) + ")" for p in parts
                )
                + ")"
            )
            seeds.append(({"d.wkt": text.encode()}, "d.wkt"))
        else:
            feature = {
                "type": "Feature",
                "properties": {"name": f"d{k}", "patches": {"bottom": [0]}},
                "geometry": {
                    "type": "Polygon",
                    "coordinates": [[[x, y] for x, y in [*p, p[0]]] for p in [ring, *holes]],
                },
            }
            text = json.dumps({"type": "FeatureCollection", "features": [feature]})
            seeds.append(({"d.geojson": text.encode()}, "d.geojson"))
    return seeds


def _known(name: str) -> bool:
    from blockmesh.domain.catalogue import catalogue_names

    return name in catalogue_names()


# ------------------------------------------------------------------------------ mutation
def mutate(data: bytes, rng: random.Random) -> bytes:
    """``data`` damaged by one to three random mutations."""
    out = bytearray(data)
    for _ in range(rng.randint(1, 3)):
        if not out:
            out += bytes([rng.randrange(256)])
        kind = rng.randrange(8)
        at = rng.randrange(len(out))
        if kind == 0:  # flip bits
            for _ in range(rng.randint(1, 8)):
                out[rng.randrange(len(out))] ^= 1 << rng.randrange(8)
        elif kind == 1:  # interesting bytes
            for _ in range(rng.randint(1, 4)):
                out[rng.randrange(len(out))] = rng.choice(_BYTES)
        elif kind == 2:  # cut the end
            del out[at:]
        elif kind == 3:  # delete a span
            del out[at : at + rng.randint(1, 64)]
        elif kind == 4:  # repeat a span
            span = out[at : at + rng.randint(1, 64)]
            out[at:at] = span * rng.randint(1, 200)
        elif kind == 5:  # a number replaced by an extreme one
            out = bytearray(_replace_number(bytes(out), rng))
        elif kind == 6:  # a span copied over another place
            span = out[at : at + rng.randint(1, 32)]
            where = rng.randrange(len(out))
            out[where : where + len(span)] = span
        else:  # random bytes inserted
            out[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 16)))
    return bytes(out)


def _replace_number(data: bytes, rng: random.Random) -> bytes:
    import re

    numbers = [m.span() for m in re.finditer(rb"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?", data[: 1 << 20])]
    if not numbers:
        return data
    start, end = rng.choice(numbers)
    return data[:start] + rng.choice(_NUMBERS) + data[end:]


# ------------------------------------------------------------------------------ running
def _read(target: str, path: Path) -> None:
    import numpy as np

    import blockmesh
    from blockmesh.errors import BlockMeshError
    from blockmesh.numerics.expr import parse_expression

    if target == "expressions":
        f = parse_expression(path.read_bytes().decode("utf-8", errors="replace"))
        x = np.array([-1.5, 0.0, 0.25, 2.0])
        with np.errstate(all="ignore"):
            f(x, x[::-1])
        with contextlib.suppress(BlockMeshError):
            f.polynomial()
    elif target in ("toml", "wkt", "geojson"):
        blockmesh.load_domain(path)
    else:
        blockmesh.read(path, format="openfoam" if target == "openfoam" else None)


def _peak() -> int:
    from blockmesh._system.memory import peak_rss

    return peak_rss()


def fuzz(
    target: str,
    seconds: float,
    *,
    seed: int = 0,
    case_seconds: float = 10.0,
    keep: Path | None = None,
    cases: int | None = None,
) -> dict:
    """Fuzz ``target`` for ``seconds`` (or ``cases`` cases); the counts and the failures."""
    from blockmesh._system.memory import reset_peak_rss
    from blockmesh.errors import BlockMeshError

    work = Path(tempfile.mkdtemp(prefix=f"blockmesh-fuzz-{target}-"))
    keep = keep or work / "failures"
    rng = random.Random(seed)
    seeds = make_seeds(target, work)
    counts: Counter[str] = Counter()
    errors: Counter[str] = Counter()
    said: Counter[str] = Counter()
    failures: list[dict] = []
    slowest = 0.0
    peak = 0
    started = time.monotonic()

    def alarm(signum: int, _frame: object) -> None:
        raise _Hang("CPU" if signum == signal.SIGPROF else "real")

    # A case may use case_seconds of CPU, and three times that of real time (a blocked read uses
    # none): on a machine shared with other work, real time alone would call a busy case hung.
    signal.signal(signal.SIGALRM, alarm)
    signal.signal(signal.SIGPROF, alarm)
    slowest_cpu = 0.0
    try:
        while time.monotonic() - started < seconds and (cases is None or counts["cases"] < cases):
            files, entry = rng.choice(seeds)
            victim = rng.choice(sorted(files))
            case = work / "case"
            shutil.rmtree(case, ignore_errors=True)
            case.mkdir()
            for name, data in files.items():
                (case / name).parent.mkdir(parents=True, exist_ok=True)
                (case / name).write_bytes(mutate(data, rng) if name == victim else data)
            counts["cases"] += 1
            reset_peak_rss()
            begun, begun_cpu = time.monotonic(), time.process_time()
            outcome = None
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                signal.setitimer(signal.ITIMER_PROF, case_seconds)
                signal.setitimer(signal.ITIMER_REAL, 3 * case_seconds)
                try:
                    _read(target, case / entry)
                    counts["read"] += 1
                except BlockMeshError as error:
                    counts["refused"] += 1
                    errors[type(error).__name__] += 1
                except _Hang as hang:
                    limit = case_seconds if str(hang) == "CPU" else 3 * case_seconds
                    outcome = f"ran past {limit} s of {hang} time"
                except MemoryError:
                    outcome = "MemoryError: past the memory limit"
                except Exception as error:  # what the fuzz is looking for
                    lines = traceback.format_exception(error)
                    outcome = (
                        f"{type(error).__name__}: {str(error)[:300]} @ {lines[-2].strip()[:300]}"
                    )
                finally:
                    signal.setitimer(signal.ITIMER_PROF, 0)
                    signal.setitimer(signal.ITIMER_REAL, 0)
            for warning in caught:
                counts[f"warning {warning.category.__name__}"] += 1
                at = f"{Path(warning.filename).name}:{warning.lineno}"
                said[f"{warning.category.__name__} at {at}: {str(warning.message)[:120]}"] += 1
            took = time.monotonic() - begun
            slowest_cpu = max(slowest_cpu, time.process_time() - begun_cpu)
            case_peak = _peak()
            if took > slowest or case_peak > peak:
                extreme = keep / f"{target}-extreme-{'time' if took > slowest else 'memory'}"
                shutil.rmtree(extreme, ignore_errors=True)
                shutil.copytree(case, extreme)
            slowest = max(slowest, took)
            peak = max(peak, case_peak)
            if outcome is not None:
                counts["failures"] += 1
                saved = keep / f"{target}-{counts['cases']}"
                shutil.copytree(case, saved, dirs_exist_ok=True)
                failures.append({"case": counts["cases"], "what": outcome, "saved": str(saved),
                                 "entry": entry, "mutated": victim})  # fmt: skip
    finally:
        signal.signal(signal.SIGALRM, signal.SIG_DFL)
        shutil.rmtree(work / "case", ignore_errors=True)
    return {
        "target": target,
        "seconds": round(time.monotonic() - started, 1),
        "seeds": len(seeds),
        "cases": counts["cases"],
        "read": counts["read"],
        "refused": counts["refused"],
        "failures": counts["failures"],
        "errors": dict(errors),
        "warnings": {k[8:]: v for k, v in counts.items() if k.startswith("warning ")},
        "warning_texts": dict(said.most_common(10)),
        "slowest_case_seconds": round(slowest, 2),
        "slowest_case_cpu_seconds": round(slowest_cpu, 2),
        "peak_rss_bytes": peak,
        "failure_list": failures[:50],
    }


def limit_memory(extra: int) -> None:
    """Limit this process's address space to what it has now plus ``extra`` bytes."""
    from blockmesh._system.procfs import proc_kilobytes

    now = proc_kilobytes("/proc/self/status", "VmSize") or 0
    resource.setrlimit(resource.RLIMIT_AS, (now + extra, now + extra))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--target", choices=TARGETS, required=True)
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--cases", type=int)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--case-seconds", type=float, default=10.0)
    parser.add_argument("--memory", type=float, default=2e9, help="bytes a case may add")
    parser.add_argument("--keep", type=Path)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    import h5py  # noqa: F401
    import meshio  # noqa: F401
    import scipy.io  # noqa: F401
    import shapely  # noqa: F401

    import blockmesh
    import blockmesh.io  # noqa: F401

    limit_memory(int(args.memory))
    report = fuzz(
        args.target, args.seconds, seed=args.seed, case_seconds=args.case_seconds,
        keep=args.keep, cases=args.cases,
    )  # fmt: skip
    text = json.dumps(report, indent=2)
    if args.out:
        args.out.write_text(text)
    print(text)
    return 1 if report["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())
