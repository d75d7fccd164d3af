"""Fuzzing the expression parser: only BlockMeshErrors escape, nothing is ever run as code.

Random token soups (numbers, names, operators, brackets, hostile words, odd characters) and
random text go through parse -> evaluate -> polynomial. Time is bounded by the example count.
"""

from __future__ import annotations

import ast
import builtins
import contextlib
import warnings
from unittest import mock

import numpy as np
from helpers import examples
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from blockmesh.errors import BlockMeshError
from blockmesh.numerics.expr import FUNCTIONS, parse_expression

_TOKENS = [
    "x", "y", "pi", "e", "0", "1", "2", "0.5", "1e308", "1e-400", "9" * 40, "0x1F", "1_000",
    "+", "-", "*", "/", "^", "**", "%", "//", "@", "&", "|", "~", "<", "==", "(", ")", "[", "]",
    "{", "}", ",", ".", ":", ";", "=", ":=", "'", '"', "lambda", "if", "else", "for", "in",
    "not", "and", "__import__", "os", "system", "__class__", "open", "eval", "exec", "True",
    "None", "...", "1j", " ", "\t", "\n", "π", "\x00", "\\", "#", "$", "`",
    *FUNCTIONS,
]  # fmt: skip

_REAL_COMPILE = builtins.compile


def _refuse(*_args, **_kwargs):
    raise AssertionError("eval/exec called")


def _tree_only(source, filename, mode, flags=0, *args, **kwargs):
    if not flags & ast.PyCF_ONLY_AST:
        raise AssertionError("compile() to a code object")
    return _REAL_COMPILE(source, filename, mode, flags, *args, **kwargs)


def _exercise(text: str) -> None:
    """Parse, evaluate and expand ``text``: only BlockMeshError may come out, and no warning."""
    with (
        warnings.catch_warnings(),
        mock.patch.object(builtins, "eval", _refuse),
        mock.patch.object(builtins, "exec", _refuse),
        mock.patch.object(builtins, "compile", _tree_only),
    ):
        warnings.simplefilter("error")
        try:
            f = parse_expression(text)
        except BlockMeshError:
            return
        x = np.array([-1.5, 0.0, 0.25, 2.0])
        with np.errstate(all="ignore"):
            values = f(x, x[::-1])
        assert values.shape == x.shape and values.dtype == np.float64
        with contextlib.suppress(BlockMeshError):
            f.polynomial()


@settings(max_examples=examples(600), suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(_TOKENS), max_size=24).map("".join))
def test_token_soup(text):
    _exercise(text)


@settings(max_examples=examples(300))
@given(st.text(max_size=60))
def test_random_text(text):
    _exercise(text)


@settings(max_examples=examples(200))
@given(
    st.recursive(
        st.sampled_from(["x", "y", "2", "0.5", "pi", "1e300", "1e-300"]),
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "^"]), inner).map(
                lambda t: f"({t[0]} {t[1]} {t[2]})"
            ),
            st.tuples(
                st.sampled_from(sorted(n for n, (k, _) in FUNCTIONS.items() if k == 1)), inner
            ).map(lambda t: f"{t[0]}({t[1]})"),
        ),
        max_leaves=30,
    )
)
def test_well_formed_expressions(text):
    """Valid-looking trees with extreme constants: overflow and underflow are located errors."""
    _exercise(text)
