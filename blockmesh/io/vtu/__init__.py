"""VTK XML ``.vtu``: the format record, the writer and the streaming reader."""

from __future__ import annotations

from blockmesh.io.vtu.format import (
    FORMAT,
    field_data,
    mesh_from_meshio,
    meshio_arrays,
    meshio_mesh,
    own_arrays,
    padded_arrays,
    read_vtu,
    write_vtu,
)

__all__ = [
    "FORMAT",
    "field_data",
    "mesh_from_meshio",
    "meshio_arrays",
    "meshio_mesh",
    "own_arrays",
    "padded_arrays",
    "read_vtu",
    "write_vtu",
]
