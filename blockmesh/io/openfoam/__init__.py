"""OpenFOAM ``polyMesh``: the format record, the writer and the reader."""

from __future__ import annotations

from blockmesh.io.openfoam.format import (
    EMPTY_PATCH,
    FORMAT,
    foam_word,
    polymesh_dir,
    read_openfoam,
    write_openfoam,
)

__all__ = ["EMPTY_PATCH", "FORMAT", "foam_word", "polymesh_dir", "read_openfoam", "write_openfoam"]
