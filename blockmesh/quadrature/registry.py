"""The registry of composite rules, keyed by name.

========  ==================================  ==============================  ==========  =======
rule      sectors per cell                    points per sector (order n)      per cell    degree
========  ==================================  ==============================  ==========  =======
paper     5, apex at the cell's vertex mean   (n+1) Gauss-Legendre x n GL      5 n (n+1)   2n - 1
jacobi    5, apex at the cell's vertex mean   n Gauss-Jacobi(0, 1) x n GL      5 n^2       2n - 1
fan       3, fanned from the best corner      n Gauss-Jacobi(0, 1) x n GL      3 n^2       2n - 1
========  ==================================  ==============================  ==========  =======

"degree" is the largest total degree integrated exactly, and it is sharp (the tests check every
monomial). A new rule is one module defining ``RULE = Rule(...)`` (see :mod:`.paper`), added to
the tuple below.

Examples
--------
>>> list(RULES)
['paper', 'jacobi', 'fan']
>>> get_rule("simpson")
Traceback (most recent call last):
...
blockmesh.errors.UnknownNameError: unknown rule 'simpson'; choose one of: paper, jacobi, fan
"""

from __future__ import annotations

import blockmesh.quadrature.fan as fan
import blockmesh.quadrature.jacobi as jacobi
import blockmesh.quadrature.paper as paper
from blockmesh.checks import whole_number
from blockmesh.errors import ArgumentTypeError, UnknownNameError
from blockmesh.quadrature.rule import Rule, RuleInfo

__all__ = ["RULES", "get_rule", "order_of", "rule_info"]

#: The rules, by name, in the order of the table above.
RULES: dict[str, Rule] = {m.RULE.name: m.RULE for m in (paper, jacobi, fan)}


def get_rule(rule: str | Rule) -> Rule:
    """The :class:`Rule` named ``rule`` (a Rule passes through, so unregistered rules work too).

    Raises
    ------
    UnknownNameError
        For a name that is not registered, listing the names.
    ArgumentTypeError
        When ``rule`` is neither a name nor a Rule.
    """
    if isinstance(rule, Rule):
        return rule
    if not isinstance(rule, str):
        raise ArgumentTypeError(f"rule must be a rule name or a Rule, got {rule!r}")
    try:
        return RULES[rule]
    except KeyError:
        raise UnknownNameError(
            f"unknown rule {rule!r}; choose one of: {', '.join(RULES)}"
        ) from None


def order_of(rule: Rule, order: object) -> int:
    """``order`` checked as a whole number in ``1..rule.max_order``."""
    return whole_number(order, "order", minimum=1, maximum=rule.max_order)


def rule_info(rule: str | Rule, order: int) -> RuleInfo:
    """Points and exactness degree of ``rule`` at ``order``.

    Examples
    --------
    >>> rule_info("paper", 10)
    RuleInfo(rule='paper', order=10, points_per_triangle=110, triangles_per_cell=5, degree=19)
    """
    found = get_rule(rule)
    return found.info(order_of(found, order))
