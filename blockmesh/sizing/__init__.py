"""Size control: the cell size wanted at every point, and the sizes a mesh achieved.

- :mod:`~blockmesh.sizing.fields`: size fields (constant, expression, function, near a patch or a
  point, per region, their minimum);
- :mod:`~blockmesh.sizing.spec`: what a user writes (a number, an expression, a ``[size]`` table)
  checked and turned into a field once the domain's patches and regions are known;
- :mod:`~blockmesh.sizing.gradation`: fields made to grow by a bounded ratio per cell;
- :mod:`~blockmesh.sizing.predict`: the cell count a field asks for, before anything is built;
- :mod:`~blockmesh.sizing.measure`: cell diameters, neighbours' size ratios, size got vs asked.

The decomposition (:func:`blockmesh.decompose.sized.sized_blocks`) makes blocks of the sizes a
field asks for; :meth:`blockmesh.Domain.with_size` and ``blockmesh mesh --size`` use it.

Examples
--------
>>> import numpy as np
>>> field = as_size_spec({"default": 0.1, "expression": "0.01 + abs(x)"}).field()
>>> field(np.array([[0.0, 0.0], [1.0, 0.0]])).tolist()
[0.01, 0.1]
"""

from blockmesh.sizing import fields
from blockmesh.sizing.fields import (  # noqa: F401 (given through fields.FIELD_NAMES)
    PENTAGON_AREA,
    Callback,
    Constant,
    Expression,
    InRegion,
    Minimum,
    Near,
    SizeField,
)
from blockmesh.sizing.gradation import DEFAULT_GRADATION, grade
from blockmesh.sizing.measure import SizeReport, cell_diameters, size_report
from blockmesh.sizing.predict import CellCount, ideal_count, mesh_ideal_count
from blockmesh.sizing.spec import SizeSpec, as_size_spec

__all__ = [
    *fields.FIELD_NAMES,
    "DEFAULT_GRADATION",
    "CellCount",
    "SizeReport",
    "SizeSpec",
    "as_size_spec",
    "cell_diameters",
    "grade",
    "ideal_count",
    "mesh_ideal_count",
    "size_report",
]
