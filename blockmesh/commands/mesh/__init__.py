"""``blockmesh mesh``: refine one or many domains, report quality, draw and export.

With several domains (catalogue names, files or globs) the meshes are made in parallel on up to
two processes; ``-o`` must then name each output with ``{name}`` (and may use ``{level}``). A
domain that fails is reported and does not stop the others; the exit code is then 1.

The command's modules, one job each:

- :mod:`~blockmesh.commands.mesh.command`: the options and the run, which sends the arguments on;
- :mod:`~blockmesh.commands.mesh.arguments`: the arguments checked and gathered into options;
- :mod:`~blockmesh.commands.mesh.single`: one domain meshed, measured, drawn and written;
- :mod:`~blockmesh.commands.mesh.report`: a mesh's report printed;
- :mod:`~blockmesh.commands.mesh.batch`: several domains on up to two processes;
- :mod:`~blockmesh.commands.mesh.partitioned`: one domain in pieces on Dask workers.
"""

from __future__ import annotations

from blockmesh.commands.mesh.arguments import DEFAULT_LEVEL
from blockmesh.commands.mesh.command import OPTIONS, register, run

__all__ = ["DEFAULT_LEVEL", "OPTIONS", "register", "run"]
