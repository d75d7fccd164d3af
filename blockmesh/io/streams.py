"""What the direct readers of blockmesh's own file layouts share: their errors and their entry.

:mod:`blockmesh.io.vtu.stream` and :mod:`blockmesh.io.vtk.stream` read the files blockmesh
writes straight into the mesh's arrays, and leave every other file to meshio. Their parser
raises :class:`NotOursError` for a file of another layout and :class:`DamagedError` for a damaged
one; :func:`read_own_layout` opens the file (a regular file, under a read guard) and turns them
into the readers' answers: ``None`` (meshio reads the file, and reports what is wrong with it)
or an :class:`~blockmesh.errors.ExportError` naming the file and the :class:`Place` reached.
Damage counts as blockmesh's to report once ``Place.ours`` is set: a reader whose layout is
recognised as it goes (VTU: by its ``blockmesh`` field data) starts with it unset, one whose
first line already tells (VTK 5.1) starts with it set.

Examples
--------
>>> import pathlib, tempfile
>>> path = pathlib.Path(tempfile.mkdtemp()) / "a.txt"
>>> _ = path.write_bytes(b"blockmesh 3")
>>> def parse(f, size, guard, place):
...     if f.read(10) != b"blockmesh ":
...         raise NotOursError("another file")
...     place.ours, place.where = True, "the count"
...     return int(f.read())
>>> read_own_layout(path, parse, Place())
3
>>> _ = path.write_bytes(b"blockmesh x")
>>> read_own_layout(path, parse, Place(), not_ours=(ValueError,)) is None
True
>>> def damaged(f, size, guard, place):
...     raise DamagedError("the count is cut short")
>>> read_own_layout(path, damaged, Place()) is None  # not known to be blockmesh's yet
True
>>> read_own_layout(path, damaged, Place(ours=True))  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
blockmesh.errors.ExportError: .../a.txt: the header: the count is cut short
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, TypeVar

from blockmesh._system.bounded import ReadGuard, open_regular, reading
from blockmesh.errors import ExportError

__all__ = ["DamagedError", "NotOursError", "Place", "read_own_layout"]

T = TypeVar("T")


class NotOursError(Exception):
    """The file is not one this reader handles; meshio reads it instead."""


class DamagedError(NotOursError):
    """The file is damaged: an error if it is blockmesh's (``Place.ours``), else meshio's."""


@dataclass
class Place:
    """Where the parser is, for messages: whether the file is blockmesh's, and which part."""

    ours: bool = False
    where: str = "the header"


def read_own_layout(
    path: Path,
    parse: Callable[[BinaryIO, int, ReadGuard, Place], T],
    place: Place,
    *,
    not_ours: tuple[type[Exception], ...] = (),
) -> T | None:
    """``parse(f, size, guard, place)`` of the regular file ``path``; None if it is not ours.

    ``not_ours``: the exceptions of ``parse`` that also mean another layout (a number that does
    not parse, an index past a list's end). Raises :class:`~blockmesh.errors.ExportError` for a
    :class:`DamagedError` once ``place.ours`` is set, naming the file and ``place.where``, and
    whatever :func:`~blockmesh._system.bounded.open_regular` and the read guard raise.
    """
    where = str(path)
    with reading(where) as guard, open_regular(path) as f:
        size = os.fstat(f.fileno()).st_size
        try:
            return parse(f, size, guard, place)
        except DamagedError as exc:
            if not place.ours:
                return None  # not blockmesh's: meshio reports what is wrong
            raise ExportError(f"{where}: {place.where}: {exc}") from None
        except NotOursError:
            return None  # another layout: meshio reads it
        except not_ours:
            return None
