"""Numbers and formulas for every stage: Gauss rules, double-double, expressions, polynomials.

- :mod:`~blockmesh.numerics.gauss`: Gauss-Legendre and Gauss-Jacobi rules at full double precision;
- :mod:`~blockmesh.numerics.doubledouble`: about 32 significant digits from pairs of float64;
- :mod:`~blockmesh.numerics.expr`: text such as ``"x^2 + sin(y)"`` to a vectorised f(x, y), never
  through ``eval``; the text parsed and its errors located in :mod:`~blockmesh.numerics.parsing`,
  the tree vetted and turned into closures over numpy in :mod:`~blockmesh.numerics.compiling`;
- :mod:`~blockmesh.numerics.polynomial`: exact polynomials in x and y expanded from expressions.
"""
