"""Options and output shared by the subcommands."""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import re
import stat
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh import io as mesh_io
from blockmesh._system.bounded import file_kind, reading
from blockmesh.commands import Option
from blockmesh.commands._progress import StageProgress, printable
from blockmesh.domain.domain import Domain
from blockmesh.domain.loading import load_domain, parse_polygon_string
from blockmesh.errors import BlockMeshError, DomainFormatError, ExportError
from blockmesh.geometry.polygons import DIRECTIONS
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.pipeline import MAX_LEVEL, MAX_SMOOTH

__all__ = [
    "ProgressBar",
    "check_folders",
    "check_level_options",
    "check_range",
    "domain_arguments",
    "fill_template",
    "inline_polygon",
    "is_mesh_file",
    "json_error",
    "json_objects_printed",
    "levels_to_add",
    "load_target",
    "parse_patch_options",
    "parse_size",
    "plural",
    "print_json",
    "printable",
    "resolve_target",
    "safe_component",
]


def domain_arguments(*, many: bool = False) -> tuple[Option, ...]:
    """``DOMAIN`` (a catalogue name or file; several with ``many``) and the inline polygon.

    ``--polygon`` instead of ``DOMAIN``, ``--hole`` in it and ``--patch`` naming its edges.
    """
    return (
        Option(
            "domain",
            metavar="DOMAIN",
            nargs="*" if many else "?",
            help="catalogue name (see 'blockmesh catalogue'), a domain file (.toml, .wkt, "
            ".geojson) or a mesh file blockmesh wrote (.npz, .vtu, .xdmf, .msh, .mat, .vtk)"
            + ("; several names, files or globs" if many else ""),
        ),
        Option(
            "--polygon",
            metavar='"x1,y1 x2,y2 ..."',
            help="a polygon (convex or not) given inline instead of DOMAIN (decomposed "
            "automatically)",
        ),
        Option(
            "--hole",
            metavar='"x1,y1 x2,y2 ..."',
            action="append",
            default=[],
            help="a hole in the --polygon (repeat for more holes)",
        ),
        Option(
            "--patch",
            metavar="NAME=EDGES",
            action="append",
            default=[],
            help="name edges of a --polygon or of a .wkt/.geojson outline as patch NAME (repeat "
            "for more patches): EDGES is a comma list of edge numbers (edge i runs from corner i "
            "to i+1, from 0), ranges such as 2-4, 'hole K' (every edge of hole K), 'hole K:E', or "
            "left, right, top, bottom (the outer edges facing that way); other edges stay in "
            "'boundary'",
        ),
    )


def resolve_target(args: argparse.Namespace) -> Domain | Mesh | PolygonMesh:
    """The domain named on the command line, or the mesh in a mesh file blockmesh reads.

    A refined mesh is a valid thing to check, integrate over or refine further, so ``DOMAIN``
    may be any file :func:`blockmesh.read` reads (its extension says which); its read honours
    the command's ``--max-memory`` where it has one.
    """
    domain = _one_name(args)
    if args.polygon is not None and domain:
        raise BlockMeshError("give either DOMAIN or --polygon, not both")
    patches = parse_patch_options(args.patch)
    if args.polygon is not None:
        return inline_polygon(args.polygon, args.hole, patches)
    if args.hole:
        raise BlockMeshError(
            '--hole adds a hole to --polygon "x1,y1 x2,y2 ..."; give --polygon too'
        )
    if not domain:
        raise BlockMeshError(
            "no domain: give a catalogue name, a .toml, .wkt or .geojson file or a mesh file, "
            "or --polygon \"x1,y1 x2,y2 ...\" (see 'blockmesh catalogue')"
        )
    return load_target(
        domain,
        progress=StageProgress.wanted(args),
        patches=patches,
        max_memory=getattr(args, "max_memory", None),
    )


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
    suffix = path.suffix.lower()
    # The registry imports every format module: asked for only when a file name needs it.
    readable = mesh_io.FORMATS.values()
    extensions = {ext for fmt in readable if fmt.can_read for ext in fmt.extensions}
    return suffix in extensions or (path.is_dir() and (path / "constant" / "polyMesh").is_dir())


def load_target(
    name: str,
    *,
    progress: bool = False,
    patches: dict[str, list[int | str]] | None = None,
    max_memory: int | None = None,
) -> Domain | Mesh | PolygonMesh:
    """A catalogue domain, a domain file, or a mesh file read by :func:`blockmesh.read`.

    With ``progress``, a read that takes over a second shows a line on stderr
    (``mesh.msh: reading ...  3.0 s``, then ``done in``), as the command's other stages do.
    ``patches`` (from ``--patch``) name edges of a ``.wkt`` or ``.geojson`` outline.
    ``max_memory`` (``--max-memory``) limits what reading a mesh file may allocate, for a file
    read to convert too (see :mod:`blockmesh._system.bounded`).
    """
    if patches and Path(name).suffix.lower() not in (".wkt", ".geojson", ".json"):
        raise BlockMeshError(
            f"--patch names edges of a polygon outline (--polygon, a .wkt or .geojson file); "
            f"{name} names its own patches (a .toml file in its [patches] table, a mesh file on "
            "its boundary)"
        )
    if not is_mesh_file(name):
        with reading(name, max_memory=max_memory):
            return load_domain(name, patches=patches)

    try:
        with StageProgress(printable(Path(name).name), enabled=progress).stage("reading"):
            return mesh_io.read(name, max_memory=max_memory)
    except ExportError as error:
        raise ExportError(
            f"{error}. If {name} is a triangle or quadrilateral mesh rather than one blockmesh "
            "wrote, turn it into pentagonal blocks with 'blockmesh convert'"
        ) from None


def levels_to_add(level: int | None, target: Domain | Mesh | PolygonMesh, default: int) -> int:
    """The levels ``--level`` adds to ``target``: as given, else ``default`` (a domain), 0 (a mesh).

    A mesh read from a file keeps its own level unless ``--level`` asks for more.

    Examples
    --------
    >>> import blockmesh
    >>> domain = blockmesh.load_domain("sp")
    >>> [levels_to_add(None, domain, 2), levels_to_add(None, domain.mesh(3), 2)]
    [2, 0]
    >>> levels_to_add(1, domain.mesh(3), 2)
    1
    """
    if level is not None:
        return level
    return 0 if isinstance(target, Mesh | PolygonMesh) else default


def inline_polygon(
    text: str, holes: list[str] | None = None, patches: dict[str, list[int | str]] | None = None
) -> Domain:
    """The domain of ``--polygon TEXT`` with ``--hole`` texts and ``--patch`` names.

    Parse errors name the option.
    """
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
    return Domain.from_polygon(corners, rings, name="polygon", patches=patches or None)


_RANGE = re.compile(r"^(\d+)\s*-\s*(\d+)$")


def parse_patch_options(items: list[str]) -> dict[str, list[int | str]]:
    """The ``--patch NAME=EDGES`` options as the ``patches`` of :meth:`Domain.from_polygon`.

    EDGES is a comma list of edge numbers, ranges ``A-B``, ``hole K``, ``hole K:E`` and the
    words ``left``, ``right``, ``top``, ``bottom``; a NAME given twice gets both lists.

    Examples
    --------
    >>> parse_patch_options(["wall=0, 2-4", "in=left", "wall=hole 0"])
    {'wall': [0, 2, 3, 4, 'hole 0'], 'in': ['left']}
    >>> parse_patch_options(["in=up"])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.BlockMeshError: --patch 'in=up': 'up' is not an edge; ...
    """
    patches: dict[str, list[int | str]] = {}
    for item in items:
        name, sign, spec = (part.strip() for part in item.partition("="))
        if not sign or not name or not spec:
            raise BlockMeshError(
                f"--patch {item!r}: write NAME=EDGES, e.g. --patch inlet=0 or --patch wall=left"
            )
        edges = patches.setdefault(name, [])
        for token in (t.strip() for t in spec.split(",")):
            found = _RANGE.match(token)
            if token.isdigit():
                edges.append(int(token))
            elif found and int(found[1]) <= int(found[2]):
                edges += range(int(found[1]), int(found[2]) + 1)
            elif token.lower() in DIRECTIONS or re.fullmatch(r"hole \d+(:\d+)?", token):
                edges.append(token.lower())
            else:
                raise BlockMeshError(
                    f"--patch {item!r}: {token!r} is not an edge; write edge numbers (0, 3), "
                    "ranges (2-4), 'hole K', 'hole K:E' or left, right, top, bottom"
                )
    return patches


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
    if value < minimum:
        raise BlockMeshError(f"{flag} must be {minimum:,} or more, got {shown}")
    raise BlockMeshError(f"{flag} must be {minimum:,}..{maximum:,}{why}, got {shown}")


def check_level_options(args: argparse.Namespace) -> None:
    """``--level`` and ``--smooth`` (where the command has them) within their bounds."""
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


#: How many JSON objects :func:`print_json` has printed in this process.
_JSON_PRINTED = [0]


def _finite(value: Any) -> Any:
    """``value`` with every non-finite float written as text (JSON has no inf or NaN)."""
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(item) for item in value]
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return value


def print_json(payload: dict[str, Any]) -> None:
    """Print exactly one JSON object on stdout (an infinite or NaN number as "inf" or "nan").

    Examples
    --------
    >>> print_json({"l2_relative": float("inf"), "errors": [1.5, float("nan")]})
    {
      "l2_relative": "inf",
      "errors": [
        1.5,
        "nan"
      ]
    }
    """
    print(json.dumps(_finite(payload), indent=2, default=_plain, allow_nan=False))
    _JSON_PRINTED[0] += 1


def json_objects_printed() -> int:
    """How many JSON objects :func:`print_json` has printed in this process.

    The command line prints an error object only when the command printed none.
    """
    return _JSON_PRINTED[0]


def json_error(kind: str, message: str, exit_code: int) -> dict[str, Any]:
    """The ``--json`` object of a failed command: ``{"error": {type, message, exit_code}}``.

    Examples
    --------
    >>> json_error("ResourceError", "too big", 2)
    {'error': {'type': 'ResourceError', 'message': 'too big', 'exit_code': 2}}
    """
    return {"error": {"type": kind, "message": message, "exit_code": exit_code}}


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
        """Redraw the bar at ``done`` of ``total`` (nothing when not enabled)."""
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
