"""Where domains come from: catalogue names, domain files and inline polygons.

:func:`load_domain` turns what a user names on the command line or in a script into a
:class:`~blockmesh.domain.Domain`; :func:`parse_polygon_string` reads the inline
``"x1,y1 x2,y2 ..."`` polygon form.

Examples
--------
>>> load_domain("usp").n_blocks
1
>>> parse_polygon_string("0,0 2,0 1,1").shape
(3, 2)
"""

from __future__ import annotations

import difflib
from pathlib import Path

import numpy as np

from .domain import Domain
from .errors import DomainFormatError

__all__ = ["load_domain", "parse_polygon_string"]


def parse_polygon_string(text: str) -> np.ndarray:
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
    points = []
    for k, token in enumerate(tokens, start=1):
        parts = token.split(",")
        try:
            if len(parts) != 2:
                raise ValueError
            points.append((float(parts[0]), float(parts[1])))
        except ValueError:
            raise DomainFormatError(
                f"polygon: token {k} {token!r} is not a pair 'x,y' of numbers (write the "
                'corners as "x1,y1 x2,y2 ...")'
            ) from None
    if not points:
        raise DomainFormatError('the polygon is empty; write the corners as "x1,y1 x2,y2 ..."')
    return np.array(points, dtype=np.float64)


def load_domain(name_or_path: str | Path) -> Domain:
    """A catalogue domain by name, or a domain file by path.

    Examples
    --------
    >>> load_domain("sp").vertices.tolist()
    [[-1.0, -1.0], [1.0, -1.0], [2.0, 0.0], [0.0, 1.0], [-2.0, 0.0]]
    """
    from .catalogue import catalogue_names, catalogue_path

    text = str(name_or_path)
    path = Path(text)
    if path.suffix == ".toml" or path.exists() or "/" in text:
        if not path.exists():
            raise DomainFormatError(f"{path}: no such file")
        return Domain.from_toml(path)
    names = catalogue_names()
    if text not in names:
        close = difflib.get_close_matches(text, names, n=3)
        hint = f" Did you mean {', '.join(close)}?" if close else ""
        raise DomainFormatError(
            f"{text!r} is neither a catalogue domain nor a .toml file.{hint} The catalogue has: "
            f"{', '.join(names)} (see 'blockmesh catalogue')"
        )
    return Domain.from_toml(catalogue_path(text))
