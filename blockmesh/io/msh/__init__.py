"""Gmsh ``.msh`` 4.1: the format record, the writer and the reader."""

from __future__ import annotations

from blockmesh.io.msh.format import FORMAT, read_msh, write_msh

__all__ = ["FORMAT", "read_msh", "write_msh"]
