"""Options and output shared by the subcommands."""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import stat
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from ..bounded import file_kind
from ..domain import Domain
from ..errors import BlockMeshError, DomainFormatError, ExportError
from ..loading import load_domain, parse_polygon_string
from ..mesh import Mesh
from ._progress import StageProgress

__all__ = [
    "ProgressBar",
    "add_domain_arguments",
    "check_folders",
    "check_level_options",
    "check_range",
    "fill_template",
    "inline_polygon",
    "is_mesh_file",
    "load_target",
    "parse_size",
    "plural",
    "print_json",
    "printable",
    "resolve_domain",
    "resolve_target",
    "safe_component",
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
    """The one domain named on the command line (``DOMAIN`` or ``--polygon``).

    A mesh file (``.vtu``, ``.xdmf``, ``.npz``, …) is refused with a message saying so; commands
    that also work on meshes use :func:`resolve_target`.
    """
    target = resolve_target(args)
    if isinstance(target, Mesh):
        raise BlockMeshError(
            f"{_one_name(args)} is a mesh file, not a domain; this command needs a domain "
            "(a catalogue name, a .toml file or --polygon)"
        )
    return target


def resolve_target(args: argparse.Namespace) -> Domain | Mesh:
    """The domain named on the command line, or the mesh in a mesh file blockmesh reads.

    A refined mesh is a valid thing to check, integrate over or refine further, so ``DOMAIN``
    may be any file :func:`blockmesh.read` reads (its extension says which).
    """
    domain = _one_name(args)
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
    return load_target(domain, progress=StageProgress.wanted(args))


def _one_name(args: argparse.Namespace) -> str | None:
    domain = args.domain
    if isinstance(domain, list):
        if len(domain) > 1:
            raise BlockMeshError("this command takes one DOMAIN")
        domain = domain[0] if domain else None
    return domain


def is_mesh_file(name: str) -> bool:
    """Whether ``name`` is an existing file (or OpenFOAM case) in a format blockmesh reads."""
    path = Path(name)
    if not path.exists():  # a catalogue name: the formats are not imported
        return False
    from ..io import FORMATS

    suffix = path.suffix.lower()
    extensions = {ext for fmt in FORMATS.values() if fmt.can_read for ext in fmt.extensions}
    return suffix in extensions or (path.is_dir() and (path / "constant" / "polyMesh").is_dir())


def load_target(
    name: str, *, progress: bool = False, max_memory: int | None = None
) -> Domain | Mesh:
    """A catalogue domain, a domain file, or a mesh file read by :func:`blockmesh.read`.

    With ``progress``, a read that takes over a second shows a line on stderr
    (``mesh.msh: reading ...  3.0 s``, then ``done in``), as the command's other stages do.
    ``max_memory`` (``--max-memory``) limits what reading a mesh file may allocate, for a file
    read to convert too (see :mod:`blockmesh.bounded`).
    """
    from ..bounded import reading

    if not is_mesh_file(name):
        with reading(name, max_memory=max_memory):
            return load_domain(name)
    from ..io import read

    try:
        with StageProgress(printable(Path(name).name), enabled=progress).stage("reading"):
            return read(name, max_memory=max_memory)
    except ExportError as error:
        raise ExportError(
            f"{error}. If {name} is a triangle or quadrilateral mesh rather than one blockmesh "
            "wrote, turn it into pentagonal blocks with 'blockmesh convert'"
        ) from None


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


#: The fields an output path may contain, e.g. ``out/{name}-{level}.vtu``.
TEMPLATE_FIELDS = ("{name}", "{level}")


def check_folders(*targets: str | None) -> None:
    """Fail now, not after the work, when an output's folder is missing.

    A templated output (with ``{name}`` or ``{level}``) gets its folders when it is filled in
    (:func:`fill_template`), so only the part of its folder before the first field must exist.
    """
    for target in targets:
        if not target:
            continue
        _refuse_special(target)
        folder = Path(target).absolute().parent
        if any(field in str(folder) for field in TEMPLATE_FIELDS):
            continue
        if not folder.is_dir():
            if is_templated(target):
                continue
            raise ExportError(
                f"cannot write {target}: the directory {folder} does not exist; create it first "
                f"(mkdir -p {folder})"
            )


def _refuse_special(target: str) -> None:
    """ExportError now if ``target`` is a FIFO, a device or a socket (links followed).

    Such a path is no place for an output: writing would replace the node (or, through a link,
    write into the device). A directory is left to the format (OpenFOAM writes one).
    """
    try:
        mode = os.stat(target).st_mode
    except (OSError, ValueError):
        return  # nothing there yet
    if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise ExportError(
            f"cannot write {printable(target)}: it is {file_kind(mode)}, not a regular file; "
            "blockmesh writes only where a regular file may go (give another name)"
        )


def is_templated(pattern: str) -> bool:
    """Whether an output path contains a template field."""
    return any(field in pattern for field in TEMPLATE_FIELDS)


def safe_component(text: str) -> str:
    """``text`` as one harmless path component: letters, digits, ``_ - .``; no ``..``, no ``/``.

    A domain file chooses its own name, so ``{name}`` must not let it choose where output goes.

    Examples
    --------
    >>> safe_component("../../ESCAPED"), safe_component("l-shape"), safe_component("a b/c")
    ('ESCAPED', 'l-shape', 'a_b_c')
    """
    cleaned = "".join(c if c.isascii() and (c.isalnum() or c in "_-.") else "_" for c in text)
    cleaned = cleaned.strip("._") or "domain"
    while ".." in cleaned:
        cleaned = cleaned.replace("..", ".")
    return cleaned


@contextlib.contextmanager
def fill_template(pattern: str, *, name: str, level: int) -> Iterator[str]:
    """``pattern`` with ``{name}`` and ``{level}`` filled in, its missing folders created.

    The name is made a safe single path component first (:func:`safe_component`). The folders
    made for it are removed again (those left empty) when the block raises: a failed write leaves
    nothing behind.

    Examples
    --------
    >>> with fill_template("{name}-{level}.vtu", name="../x", level=2) as path:
    ...     path
    'x-2.vtu'
    """
    filled = pattern.replace("{name}", safe_component(name)).replace("{level}", str(int(level)))
    made: list[Path] = []
    if is_templated(pattern):
        folder = Path(filled).parent
        made = [p for p in (folder, *folder.parents) if not p.exists()]
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            _remove_empty(made)
            raise ExportError(
                f"cannot create the folder {printable(str(folder))} for {printable(filled)}: "
                f"{error.strerror}"
            ) from None
    try:
        yield filled
    except BaseException:
        _remove_empty(made)
        raise


def _remove_empty(folders: list[Path]) -> None:
    """Remove ``folders`` (deepest first) while they are empty."""
    for folder in folders:
        try:
            folder.rmdir()
        except OSError:
            return


def check_range(value: int | None, flag: str, minimum: int, maximum: int, why: str = "") -> None:
    """BlockMeshError now unless ``value`` (if given) is in ``minimum..maximum``.

    Examples
    --------
    >>> check_range(10**30, "--level", 0, 10_000, " (beyond any machine)")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.BlockMeshError: --level must be 0..10,000 (beyond any machine), got ...
    """
    if value is None or minimum <= value <= maximum:
        return
    shown = str(value) if len(str(value)) <= 20 else f"a number of {len(str(abs(value)))} digits"
    raise BlockMeshError(f"{flag} must be {minimum:,}..{maximum:,}{why}, got {shown}")


def check_level_options(args: argparse.Namespace) -> None:
    """``--level`` and ``--smooth`` (where the command has them) within their bounds."""
    from ..refinement import MAX_LEVEL, MAX_SMOOTH

    check_range(
        getattr(args, "level", None), "--level", 0, MAX_LEVEL,
        " (each level multiplies the cells by 6: level 30 is beyond any machine)",
    )  # fmt: skip
    check_range(
        getattr(args, "smooth", None), "--smooth", 0, MAX_SMOOTH,
        " (Laplacian sweeps per level: a few cure most distortion)",
    )  # fmt: skip


def plural(count: int, noun: str) -> str:
    """``"1 block"``, ``"2 blocks"``, ``"1,296 cells"``.

    Examples
    --------
    >>> plural(1, "block"), plural(1296, "cell")
    ('1 block', '1,296 cells')
    """
    return f"{count:,} {noun}{'' if count == 1 else 's'}"


def printable(text: str, *, keep: str = "") -> str:
    r"""``text`` with control characters shown as escapes, safe to print on a terminal.

    Examples
    --------
    >>> print(printable("ring\x1b[2J"))
    ring\x1b[2J
    """
    return "".join(c if c.isprintable() or c in keep else repr(c)[1:-1] for c in text)


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
    if unit not in _UNITS or not math.isfinite(value) or value <= 0 or value * _UNITS[unit] > 2**62:
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
            f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] {done:,}/{total:,} "
            f"{elapsed:6.1f} s"
        )
        if done >= total:
            sys.stderr.write("\n")
        sys.stderr.flush()
