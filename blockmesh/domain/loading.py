"""Where domains come from: catalogue names, domain files, map outlines, meshes, inline polygons.

:func:`load_domain` turns what a user names on the command line or in a script into a
:class:`~blockmesh.domain.Domain`:

=================================== ===========================================================
``NAME``                            a catalogue domain (``blockmesh catalogue`` lists them)
``FILE.toml``                       a domain file (polygon with holes, or explicit blocks)
``FILE.wkt``                        one Polygon in Well-Known Text (holes as its interior rings);
                                    a MULTIPOLYGON or GEOMETRYCOLLECTION is a composite domain
                                    (regions ``part0``, ``part1``, ...), as are lines
                                    ``NAME = GEOMETRY`` (one part each, named)
``FILE.geojson`` / ``FILE.json``    one Polygon (a geometry, a Feature or a collection of one);
                                    the feature's ``properties`` may hold ``name``,
                                    ``description`` and ``patches`` (as in a domain file); a
                                    FeatureCollection of several features (or of features
                                    with ``properties.region``) is a composite domain, one part
                                    per feature, named by ``region`` (else ``name``)
``FILE.msh`` ``.vtu`` ``.vtk`` ...  an existing triangle/quadrilateral mesh, converted
                                    (:meth:`Domain.from_mesh`)
=================================== ===========================================================

The extension decides how a file is read (its content is not sniffed): a file with another
extension, or none, is refused with the list of the known ones.

:func:`parse_polygon_string` reads the inline ``"x1,y1 x2,y2 ..."`` form of ``--polygon`` and
``--hole``.

Examples
--------
>>> load_domain("usp").n_blocks
1
>>> parse_polygon_string("0,0 2,0 1,1").shape
(3, 2)
"""

from __future__ import annotations

import difflib
import json
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh.decompose.polygon import check_corner_count, check_file_corners
from blockmesh.domain.catalogue import catalogue_names, catalogue_path
from blockmesh.domain.compose import compose_parts
from blockmesh.domain.domain import Domain
from blockmesh.domain.parts import part_from_shapely
from blockmesh.domain.tomlio.bounds import read_text_bounded
from blockmesh.errors import DomainError, DomainFormatError

__all__ = ["MESH_SUFFIXES", "convert_mesh", "load_domain", "parse_polygon_string"]

#: File suffixes read as existing meshes to convert (meshio's formats; blockmesh's own too).
MESH_SUFFIXES = frozenset(
    {".msh", ".vtu", ".vtk", ".xdmf", ".xmf", ".npz", ".mat", ".med", ".inp", ".mesh", ".su2"}
    | {".obj", ".off", ".ply", ".stl", ".bdf", ".nas", ".fem", ".dat", ".e", ".exo", ".h5m"}
)
_DOMAIN_SUFFIXES = (".toml", ".wkt", ".geojson", ".json")


def convert_mesh(source: Any, *, name: str | None = None, description: str = "") -> Domain:
    """The Domain of an existing mesh, a path or a mesh object (:meth:`Domain.from_mesh`).

    Examples
    --------
    >>> import meshio, numpy as np
    >>> points = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    >>> convert_mesh(meshio.Mesh(points, [("quad", [[0, 1, 2, 3]])]), name="square").n_blocks
    12
    """
    return Domain.from_mesh(source, name=name, description=description)


def parse_polygon_string(text: str, *, what: str = "polygon") -> np.ndarray:
    """Parse ``"x1,y1 x2,y2 ..."`` (the inline polygon form) into an (n, 2) array.

    Examples
    --------
    >>> parse_polygon_string("0,0 1,0 0,1").tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    >>> parse_polygon_string("0,0 1;0")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.DomainFormatError: polygon: token 2 '1;0' is not a pair 'x,y' of numbers ...
    """
    tokens = text.split()
    check_corner_count(len(tokens), f"the {what}")  # counted before the numbers are parsed
    points = []
    for k, token in enumerate(tokens, start=1):
        parts = token.split(",")
        try:
            if len(parts) != 2:
                raise ValueError
            points.append((float(parts[0]), float(parts[1])))
        except ValueError:
            shown = token if len(token) <= 40 else token[:37] + "..."
            raise DomainFormatError(
                f"{what}: token {k} {shown!r} is not a pair 'x,y' of numbers (write the "
                'corners as "x1,y1 x2,y2 ...")'
            ) from None
    if not points:
        raise DomainFormatError(f'the {what} is empty; write the corners as "x1,y1 x2,y2 ..."')
    return np.array(points, dtype=np.float64)


def load_domain(
    name_or_path: str | Path, *, patches: Mapping[str, Iterable[int | str]] | None = None
) -> Domain:
    """A catalogue domain by name, or a domain, outline or mesh file by path.

    ``patches`` names edges of an outline (a ``.wkt`` or ``.geojson`` file), as
    :meth:`Domain.from_polygon` takes them (edge numbers, ``"hole K"``, ``"hole K:E"``,
    ``"left"`` ...), added to a GeoJSON feature's own; the other sources name their patches
    themselves, and giving ``patches`` for them is an error.

    Examples
    --------
    >>> load_domain("sp").vertices.tolist()
    [[-1.0, -1.0], [1.0, -1.0], [2.0, 0.0], [0.0, 1.0], [-2.0, 0.0]]
    """
    text = str(name_or_path)
    path = Path(text)
    suffix = path.suffix.lower()
    if suffix in _DOMAIN_SUFFIXES or suffix in MESH_SUFFIXES or path.exists() or "/" in text:
        if not path.exists():
            raise DomainFormatError(f"{path}: no such file")
        if suffix == ".wkt":
            return _from_wkt(path, patches)
        if suffix in (".geojson", ".json"):
            return _from_geojson(path, patches)
        if patches:
            raise DomainFormatError(_NOT_AN_OUTLINE.format(name=path))
        if suffix in MESH_SUFFIXES or path.is_dir():
            return Domain.from_mesh(path)
        if suffix != ".toml" and path.is_file():  # (a device or a FIFO: said by the reader)
            raise DomainFormatError(_unknown_kind(path, suffix))
        return Domain.from_toml(path)
    names = catalogue_names()
    if patches and text in names:
        raise DomainFormatError(_NOT_AN_OUTLINE.format(name=text))
    if text not in names:
        close = difflib.get_close_matches(text, names, n=3)
        hint = f" Did you mean {', '.join(close)}?" if close else ""
        raise DomainFormatError(
            f"{text!r} is neither a catalogue domain nor a .toml file (nor a .wkt, .geojson or "
            f"mesh file).{hint} The catalogue has: {', '.join(names)} (see 'blockmesh catalogue')"
        )
    return Domain.from_toml(catalogue_path(text))


_NOT_AN_OUTLINE = (
    "patches name edges of a polygon outline (a .wkt or .geojson file, or an inline polygon); "
    "{name} names its own patches (a domain file in its [patches] table, a mesh file on its "
    "boundary)"
)
_NOT_ONE_OUTLINE = (
    "{path}: patches name edges of one polygon outline, and this file is a composite domain of "
    "{count} parts; name the patches of each part in the file (a GeoJSON feature's "
    "properties.patches, or a domain file's [[parts]] with their own patches)"
)


def _unknown_kind(path: Path, suffix: str) -> str:
    """The message for a file whose extension says nothing blockmesh reads (no sniffing)."""
    what = f"the extension {suffix!r} is not one" if suffix else "it has no extension, one"
    return (
        f"{path}: {what} blockmesh knows (it goes by the extension); it reads domain files "
        f".toml, .wkt, .geojson and .json, and meshes {' '.join(sorted(MESH_SUFFIXES))} (or an "
        "OpenFOAM case folder): rename the file to the extension of its contents (a Well-Known "
        "Text polygon: .wkt)"
    )


#: A line ``NAME = GEOMETRY`` (or ``NAME: GEOMETRY``) of a WKT file of named parts.
_NAMED_WKT = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_.\-]*)\s*[:=]\s*(\S.*)$")


def _from_wkt(path: Path, patches: Mapping[str, Iterable[int | str]] | None = None) -> Domain:
    import shapely

    text = read_text_bounded(path, what="WKT file")
    check_file_corners(text.count(",") + 1, path, "comma")  # counted before parsing
    lines = [
        line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")
    ]
    named = [_NAMED_WKT.match(line) for line in lines]
    if lines and all(named):
        if patches:
            raise DomainFormatError(_NOT_ONE_OUTLINE.format(path=path, count=len(lines)))
        geometries = {}
        for number, match in enumerate(named, start=1):
            region, wkt = match.group(1), match.group(2)  # type: ignore[union-attr]
            if region in geometries:
                raise DomainError(
                    f"{path}: line {number} names the region {region!r} again; a region is one "
                    "part (put its pieces in one MULTIPOLYGON)"
                )
            geometries[region] = _parse_wkt(wkt, path, f"line {number}")
        return _with_source(path, lambda: _composite(geometries, path.stem))
    geometry = _parse_wkt(text, path, "")
    if isinstance(geometry, shapely.GeometryCollection | shapely.MultiPolygon) and (
        len(geometry.geoms) > 1
    ):
        if patches:
            raise DomainFormatError(_NOT_ONE_OUTLINE.format(path=path, count=len(geometry.geoms)))
        parts = {f"part{k}": g for k, g in enumerate(geometry.geoms)}
        return _with_source(path, lambda: _composite(parts, path.stem))
    return _with_source(
        path,
        lambda: Domain.from_shapely(_one_polygon(geometry, path), name=path.stem, patches=patches),
    )


def _parse_wkt(text: str, path: Path, where: str) -> Any:
    import shapely

    try:
        return shapely.from_wkt(text.strip())
    except (shapely.errors.ShapelyError, ValueError) as error:
        at = f" ({where})" if where else ""
        raise DomainFormatError(f"{path}{at}: not Well-Known Text ({error})") from None


def _composite(geometries: dict[str, Any], name: str, **options: Any) -> Domain:
    """The composite Domain of named shapely geometries, in order (a part per geometry)."""
    patches = options.pop("patches", {})
    parts = [
        part_from_shapely(region, geometry, f"part {k} ({region!r})", patches.get(region))
        for k, (region, geometry) in enumerate(geometries.items())
    ]
    return compose_parts(Domain, parts, name=name, **options)


def _from_geojson(path: Path, extra: Mapping[str, Iterable[int | str]] | None = None) -> Domain:
    import shapely.geometry

    text = read_text_bounded(path, what="GeoJSON file")
    check_file_corners(text.count("["), path, "bracket")  # counted before parsing
    try:
        document = json.loads(text, parse_int=_json_int, parse_constant=_json_constant)
    except (json.JSONDecodeError, RecursionError) as error:
        raise DomainFormatError(f"{path}: not JSON ({error})") from None
    except ValueError as error:  # a number the hooks refused
        raise DomainFormatError(f"{path}: {error}") from None
    if _is_composite(document):
        if extra:
            count = len(document["features"])
            raise DomainFormatError(_NOT_ONE_OUTLINE.format(path=path, count=count))
        return _composite_geojson(document, path)
    feature = _one_feature(document, path)
    properties = feature.get("properties") or {}
    if not isinstance(properties, dict):
        raise DomainFormatError(f"{path}: the feature's properties must be an object")
    geometry = feature.get("geometry")
    if not isinstance(geometry, dict) or "type" not in geometry:
        raise DomainFormatError(f"{path}: the feature has no geometry object")
    flat = _flat(geometry)

    check_corner_count(_positions(flat.get("coordinates")), f"{path}: the polygon")
    try:
        shape = shapely.geometry.shape(flat)
    except (shapely.errors.ShapelyError, ValueError, TypeError, KeyError, IndexError) as error:
        raise DomainFormatError(f"{path}: the geometry cannot be read ({error})") from None
    name = properties.get("name", path.stem)
    description = properties.get("description", "")
    patches = properties.get("patches")
    if patches is not None and not isinstance(patches, dict):
        raise DomainFormatError(
            f"{path}: properties.patches must be an object of patch name: [edges], got "
            f"{type(patches).__name__}"
        )
    if extra:
        patches = {**(patches or {}), **extra}
    return _with_source(
        path,
        lambda: Domain.from_shapely(
            _one_polygon(shape, path), name=name, patches=patches, description=description
        ),
    )


#: Most digits of a JSON integer (a coordinate beyond them is no coordinate).
_JSON_DIGITS = 30


def _json_int(text: str) -> int:
    if len(text.lstrip("-")) > _JSON_DIGITS:
        raise ValueError(
            f"an integer of {len(text.lstrip('-'))} digits; numbers have at most {_JSON_DIGITS}"
        )
    return int(text)


def _json_constant(text: str) -> float:
    raise ValueError(f"{text} is not a number JSON allows; coordinates must be finite numbers")


def _positions(coordinates: Any) -> int:
    """The number of [x, y] positions in nested GeoJSON coordinates (without recursing deep)."""
    count, stack = 0, [coordinates]
    while stack:
        value = stack.pop()
        if isinstance(value, list):
            if value and all(isinstance(v, int | float) for v in value):
                count += 1
            else:
                stack.extend(value)
    return count


def _is_composite(document: Any) -> bool:
    """A FeatureCollection of several features, or of features that name their region."""
    if not isinstance(document, dict) or document.get("type") != "FeatureCollection":
        return False
    features = document.get("features")
    if not isinstance(features, list) or not features:
        return False
    regions = [
        isinstance(f, dict)
        and isinstance(f.get("properties"), dict)
        and "region" in f["properties"]
        for f in features
    ]
    return len(features) > 1 or any(regions)


def _composite_geojson(document: dict[str, Any], path: Path) -> Domain:
    """One part per feature: its region ``properties.region`` (else ``name``, else ``partK``)."""
    import shapely.geometry

    geometries: dict[str, Any] = {}
    patches: dict[str, Any] = {}
    for k, feature in enumerate(document["features"]):
        where = f"{path}: feature {k}"
        if not isinstance(feature, dict) or feature.get("type") != "Feature":
            raise DomainFormatError(f"{where} must be a Feature object")
        properties = feature.get("properties") or {}
        if not isinstance(properties, dict):
            raise DomainFormatError(f"{where}: its properties must be an object")
        region = properties.get("region", properties.get("name", f"part{k}"))
        if not isinstance(region, str):
            raise DomainFormatError(f"{where}: properties.region must be a string, got {region!r}")
        if region in geometries:
            raise DomainError(
                f"{where} names the region {region!r} again; a region is one part (put its "
                "pieces in one MultiPolygon feature)"
            )
        geometry = feature.get("geometry")
        if not isinstance(geometry, dict) or "type" not in geometry:
            raise DomainFormatError(f"{where} has no geometry object")
        try:
            geometries[region] = shapely.geometry.shape(_flat(geometry))
        except (shapely.errors.ShapelyError, ValueError, TypeError, KeyError, IndexError) as error:
            raise DomainFormatError(f"{where}: the geometry cannot be read ({error})") from None
        if properties.get("patches") is not None:
            if not isinstance(properties["patches"], dict):
                raise DomainFormatError(
                    f"{where}: properties.patches must be an object of patch name: [edges]"
                )
            patches[region] = properties["patches"]
    name = document.get("name", path.stem)
    description = document.get("description", "")
    interfaces = document.get("interfaces")
    if not isinstance(name, str) or not isinstance(description, str):
        raise DomainFormatError(f"{path}: the collection's name and description must be strings")
    return _with_source(
        path,
        lambda: _composite(
            geometries,
            name,
            description=description,
            interfaces=interfaces,
            patches=patches,
        ),
    )


def _one_feature(document: Any, path: Path) -> dict[str, Any]:
    if not isinstance(document, dict):
        raise DomainFormatError(f"{path}: a GeoJSON document is an object")
    kind = document.get("type")
    if kind == "FeatureCollection":
        features = document.get("features")
        if not isinstance(features, list) or len(features) != 1:
            count = len(features) if isinstance(features, list) else 0
            raise DomainFormatError(
                f"{path}: the FeatureCollection has {count} features; a domain is one Polygon "
                "feature (put each part in its own file)"
            )
        document = features[0]
        if not isinstance(document, dict):
            raise DomainFormatError(f"{path}: the feature must be an object")
        kind = document.get("type")
    if kind == "Feature":
        return document
    if kind in ("Polygon", "MultiPolygon"):
        return {"type": "Feature", "geometry": document, "properties": {}}
    raise DomainFormatError(
        f"{path}: expected a Polygon geometry, a Feature or a FeatureCollection of one, got "
        f"{kind!r}"
    )


def _flat(geometry: dict[str, Any]) -> dict[str, Any]:
    """The geometry with every position cut to (x, y) (GeoJSON allows an altitude)."""

    def cut(value: Any) -> Any:
        if isinstance(value, list) and value and all(isinstance(v, int | float) for v in value):
            return value[:2]
        if isinstance(value, list):
            return [cut(v) for v in value]
        return value

    return {**geometry, "coordinates": cut(geometry.get("coordinates"))}


def _one_polygon(geometry: Any, path: Path) -> Any:
    import shapely

    if isinstance(geometry, shapely.MultiPolygon) and len(geometry.geoms) == 1:
        return geometry.geoms[0]
    if not isinstance(geometry, shapely.Polygon | shapely.MultiPolygon):
        raise DomainFormatError(f"{path}: expected one Polygon, got a {geometry.geom_type}")
    return geometry


def _with_source(path: Path, build):
    try:
        return build()
    except DomainError as error:
        raise type(error)(f"{path}: {error}") from None
