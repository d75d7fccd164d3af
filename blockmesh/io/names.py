"""Names made valid for a format (OpenFOAM words, MATLAB identifiers, Gmsh physical names).

One mechanism, one :class:`NameRule` per format: characters the format cannot hold become ``_``,
a name that must start with a letter and does not gets a prefix, long names are cut, and
:meth:`NameRule.unique` numbers names that become equal (``inlet``, ``inlet_2``). Formats that
change names also keep the real ones where blockmesh reads them back.

Examples
--------
>>> FOAM_WORD.clean("outer wall"), MATLAB_NAME.clean("2nd"), GMSH_NAME.clean('say "hi"')
('outer_wall', 'p_2nd', 'say _hi_')
>>> FOAM_WORD.unique(["a b", "a_b", "frontAndBack"], taken={"frontAndBack"})
['a_b', 'a_b_2', 'frontAndBack_2']
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

__all__ = ["FOAM_WORD", "GMSH_NAME", "MATLAB_NAME", "NameRule"]


@dataclass(frozen=True)
class NameRule:
    """How one format restricts names.

    Attributes
    ----------
    what : str
        What the format calls such a name (for messages).
    invalid : str
        A regular expression matching one character the format cannot hold (replaced by ``_``).
    first : str
        A regular expression the first character must match, or ``""`` for any; a name that does
        not start so gets ``prefix``.
    prefix : str
    max_length : int or None
        The longest name the format takes.
    """

    what: str
    invalid: str
    first: str = ""
    prefix: str = "p_"
    max_length: int | None = None

    def clean(self, name: str) -> str:
        """``name`` made valid: invalid characters replaced, prefixed if needed, cut to length."""
        word = re.sub(self.invalid, "_", name)
        if self.first and not re.match(self.first, word):
            word = self.prefix + word
        return word[: self.max_length] if self.max_length else word

    def unique(self, names: Iterable[str], taken: Iterable[str] = ()) -> list[str]:
        """:meth:`clean` of each name, numbered where names would clash.

        A name equal to an earlier one or to one in ``taken`` gets ``_2``, ``_3`` …
        """
        used = set(taken)
        out: list[str] = []
        for name in names:
            base = candidate = self.clean(name)
            k = 1
            while candidate in used:
                k += 1
                suffix = f"_{k}"
                keep = self.max_length - len(suffix) if self.max_length else len(base)
                candidate = base[:keep] + suffix
            used.add(candidate)
            out.append(candidate)
        return out


#: OpenFOAM ``word`` (patch and zone names): letters, digits and ``_ . : -``, not starting with
#: a digit or punctuation.
FOAM_WORD = NameRule("OpenFOAM word", r"[^A-Za-z0-9_.:-]", first=r"[A-Za-z_]")
#: MATLAB identifier (struct field names): ASCII letters, digits and ``_``, starting with a
#: letter, at most 63 characters.
MATLAB_NAME = NameRule("MATLAB identifier", r"[^A-Za-z0-9_]", first=r"[A-Za-z]", max_length=63)
#: Gmsh physical name: anything but a double quote or a line break.
GMSH_NAME = NameRule("Gmsh physical name", r'["\r\n]')
