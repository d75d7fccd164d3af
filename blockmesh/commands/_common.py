"""Options and output shared by the subcommands."""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from ..domain import Domain
from ..errors import BlockMeshError, DomainFormatError, ExportError
from ..loading import load_domain, parse_polygon_string

__all__ = [
    "ProgressBar",
    "add_domain_arguments",
    "check_folders",
    "inline_polygon",
    "parse_size",
    "print_json",
    "resolve_domain",
]


def add_domain_arguments(parser: argparse.ArgumentParser, *, many: bool = False) -> None:
    """Add ``DOMAIN`` (catalogue name or file; several with ``many``), ``--polygon``, ``--hole``."""
    parser.add_argument(
        "domain",
        metavar="DOMAIN",
        nargs="*" if many else "?",
        help="catalogue name (see 'blockmesh catalogue'), a domain file (.toml, .wkt, .geojson) "
        "or a mesh to convert (.msh, .vtu, ...)"
        + ("; several names, files or globs" if many else ""),
    )
    parser.add_argument(
        "--polygon",
        metavar='"x1,y1 x2,y2 ..."',
        help="a polygon (convex or not) given inline instead of DOMAIN (decomposed automatically)",
    )
    parser.add_argument(
        "--hole",
        metavar='"x1,y1 x2,y2 ..."',
        action="append",
        default=[],
        help="a hole in the --polygon (repeat for more holes)",
    )


def resolve_domain(args: argparse.Namespace) -> Domain:
    """The one domain named on the command line (``DOMAIN`` or ``--polygon``)."""
    domain = args.domain
    if isinstance(domain, list):
        if len(domain) > 1:
            raise BlockMeshError("this command takes one DOMAIN")
        domain = domain[0] if domain else None
    if args.polygon is not None and domain:
        raise BlockMeshError("give either DOMAIN or --polygon, not both")
    if args.polygon is not None:
        return inline_polygon(args.polygon, args.hole)
    if args.hole:
        raise BlockMeshError(
            '--hole adds a hole to --polygon "x1,y1 x2,y2 ..."; give --polygon too'
        )
    if not domain:
        raise BlockMeshError(
            'no domain: give a catalogue name or a .toml file, or --polygon "x1,y1 x2,y2 ..." '
            "(see 'blockmesh catalogue')"
        )
    return load_domain(domain)


def inline_polygon(text: str, holes: list[str] | None = None) -> Domain:
    """The domain of ``--polygon TEXT`` with ``--hole`` texts; parse errors name the option."""
    try:
        corners = parse_polygon_string(text)
    except DomainFormatError as error:
        raise DomainFormatError(f"--{error}") from None
    rings = []
    for k, hole in enumerate(holes or []):
        try:
            rings.append(parse_polygon_string(hole, what=f"hole {k}"))
        except DomainFormatError as error:
            raise DomainFormatError(f"--hole: {error}") from None
    return Domain.from_polygon(corners, rings, name="polygon")


def check_folders(*targets: str | None) -> None:
    """Fail now, not after the work, when an output's folder is missing (``{name}`` allowed)."""
    for target in targets:
        if not target:
            continue
        folder = Path(target).absolute().parent
        if "{" not in str(folder) and not folder.is_dir():
            raise ExportError(
                f"cannot write {target}: the directory {folder} does not exist; create it first "
                f"(mkdir -p {folder})"
            )


def _plain(value: Any) -> Any:
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        value = float(value)
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"cannot write {type(value).__name__} as JSON")


def print_json(payload: dict[str, Any]) -> None:
    """Print exactly one JSON object on stdout."""
    print(json.dumps(payload, indent=2, default=_plain, allow_nan=False))


_UNITS = {"": 1, "B": 1, "K": 1e3, "KB": 1e3, "M": 1e6, "MB": 1e6, "G": 1e9, "GB": 1e9}
_UNITS.update({"T": 1e12, "TB": 1e12, "KIB": 2**10, "MIB": 2**20, "GIB": 2**30, "TIB": 2**40})


def parse_size(text: str) -> int:
    """``"8G"``, ``"500MB"``, ``"2GiB"`` or a number of bytes, as an int (for ``--max-memory``).

    Examples
    --------
    >>> parse_size("1.5G"), parse_size("2GiB"), parse_size("1000")
    (1500000000, 2147483648, 1000)
    """
    stripped = text.strip().upper()
    number = stripped.rstrip("BKMGTI")
    unit = stripped[len(number) :].strip()
    try:
        value = float(number)
    except ValueError:
        value = -1.0
    if unit not in _UNITS or value <= 0:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a size; write e.g. 8G, 500MB, 2GiB or a number of bytes"
        )
    return int(value * _UNITS[unit])


class ProgressBar:
    """A one-line progress bar on stderr, drawn only when ``enabled`` (a terminal, no --json)."""

    def __init__(self, label: str, *, enabled: bool) -> None:
        self.label = label
        self.enabled = enabled
        self.start = time.perf_counter()

    @staticmethod
    def wanted(args: argparse.Namespace) -> bool:
        """True when stdout is a terminal and no JSON was asked for."""
        return sys.stdout.isatty() and not getattr(args, "json", False)

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        width = 30
        filled = int(width * done / max(total, 1))
        elapsed = time.perf_counter() - self.start
        sys.stderr.write(
            f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] {done}/{total} "
            f"{elapsed:6.1f} s"
        )
        if done >= total:
            sys.stderr.write("\n")
        sys.stderr.flush()
