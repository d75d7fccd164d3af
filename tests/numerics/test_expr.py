"""Safe expressions: evaluation, polynomials, and hostile or malformed input."""

from __future__ import annotations

import ast
import builtins
import math

import numpy as np
import pytest

from blockmesh.errors import ArgumentError, ArgumentTypeError, ExpressionError
from blockmesh.numerics.expr import FUNCTIONS, MAX_LENGTH, Expression, parse_expression

X = np.linspace(-1.7, 2.3, 11)
Y = np.linspace(0.4, -2.9, 11)


@pytest.mark.parametrize(
    ("text", "reference"),
    [
        ("(x^4 + y^3) / (1 + x^2)", lambda x, y: (x**4 + y**3) / (1 + x**2)),
        ("(x**4 + y**3) / (1 + x**2)", lambda x, y: (x**4 + y**3) / (1 + x**2)),
        ("(1 - x) * sin(10*x*y)", lambda x, y: (1 - x) * np.sin(10 * x * y)),
        ("(0.2*x + 0.3*y)^19", lambda x, y: (0.2 * x + 0.3 * y) ** 19),
        ("(x - y)^20 / 10^5", lambda x, y: (x - y) ** 20 / 1e5),
        ("-x^2", lambda x, y: -(x**2)),
        ("x^2^3", lambda x, y: x**8),
        ("2^-1 * x", lambda x, y: 0.5 * x),
        ("+x - -y", lambda x, y: x + y),
        ("x^-3", lambda x, y: x**-3.0),
        ("abs(x)^1.5", lambda x, y: np.abs(x) ** 1.5),
        ("atan2(y, x) + hypot(x, y)", lambda x, y: np.arctan2(y, x) + np.hypot(x, y)),
        (
            "exp(-((x - 1/2)^2 + (y - 1/2)^2))",
            lambda x, y: np.exp(-((x - 0.5) ** 2 + (y - 0.5) ** 2)),
        ),
        ("pi * e + 1e-3 + 0x10", lambda x, y: np.full_like(x, math.pi * math.e + 1e-3 + 16)),
        ("  sqrt(abs(x*y))  ", lambda x, y: np.sqrt(np.abs(x * y))),
    ],
)
def test_evaluates_like_numpy(text, reference):
    f = parse_expression(text)
    np.testing.assert_allclose(f(X, Y), reference(X, Y), rtol=4e-15, atol=0)


def test_odd_and_even_integer_powers_of_negative_numbers():
    x = np.array([-2.0, -0.5, 0.0, 0.5, 2.0])
    for k in range(-7, 30):
        np.testing.assert_allclose(
            parse_expression(f"x^({k})")(x + 0.25, 0.0), (x + 0.25) ** k, rtol=4e-15
        )


def test_result_has_the_broadcast_shape():
    assert parse_expression("2").__call__(np.zeros((3, 4)), 0.0).shape == (3, 4)
    assert parse_expression("x")(np.zeros(3), np.zeros((2, 3))).shape == (2, 3)
    assert parse_expression("y")(1.0, 2.0).shape == ()
    assert parse_expression("1 + 0*x").is_constant is False
    assert parse_expression("sin(2) * pi").is_constant is True
    assert parse_expression("x + pi").variables == frozenset({"x"})


def test_never_calls_eval_exec_or_compiles_code(monkeypatch):
    """ast.parse compiles to a tree only (PyCF_ONLY_AST); nothing is compiled to code or run."""
    real_compile = builtins.compile

    def refuse(*args, **kwargs):
        raise AssertionError("eval/exec called")

    def tree_only(source, filename, mode, flags=0, *args, **kwargs):
        if not flags & ast.PyCF_ONLY_AST:
            raise AssertionError("compile() to a code object")
        return real_compile(source, filename, mode, flags, *args, **kwargs)

    with monkeypatch.context() as patch:
        patch.setattr(builtins, "eval", refuse)
        patch.setattr(builtins, "exec", refuse)
        patch.setattr(builtins, "compile", tree_only)
        values = parse_expression("sin(x)^2 + cos(x)^2 + 0*y")(X, Y)
    np.testing.assert_allclose(values, 1.0, rtol=1e-15)


HOSTILE = [
    ("__import__('os')", "unknown function '__import__'", 1),
    ("x.__class__", "attribute access ('.__class__') is not allowed", 2),
    ("().__class__.__bases__[0]", "not allowed", None),
    ("os.system('ls')", "attribute access ('.system') is not allowed", 3),
    ("lambda: 1", "lambda functions are not allowed", 1),
    ("[x for x in y]", "list comprehensions are not allowed", 1),
    ("{x: 1 for x in y}", "dict comprehensions are not allowed", 1),
    ("(x for x in y)", "generator expressions are not allowed", 1),
    ("open('f')", "unknown function 'open'", 1),
    ("x**10**10", "the exponent 10**10 = 1e+10 is too large", 4),
    ("x^10^10", "the exponent 10^10 = 1e+10 is too large", 3),
    ("x**2000", "the exponent 2000 = 2000 is too large", 4),
    ("'a'", "strings are not allowed", 1),
    ("b'a'", "strings are not allowed", 1),
    ("f'{x}'", "f-strings are not allowed", 1),
    ("x if y else 1", "conditional expressions ('if ... else') are not allowed", 1),
    ("x; y", "invalid syntax", 2),
    ("x = 1", "invalid syntax", None),
    ("foo(x)", "unknown function 'foo'", 1),
    ("os", "unknown name 'os'", 1),
    ("2^x + foo", "unknown name 'foo'", 7),
    ("sin(x, y)", "sin takes 1 argument, got 2", 1),
    ("atan2(y)", "atan2 takes 2 arguments, got 1", 1),
    ("sin()", "sin takes 1 argument, got 0", 1),
    ("sin(x=1)", "keyword arguments are not allowed", 7),
    ("sin(*x)", "starred arguments are not allowed", 5),
    ("x[0]", "subscripts ('[...]') are not allowed", 2),
    ("x < y", "comparisons are not allowed", 1),
    ("x and y", "'and' / 'or' are not allowed", 1),
    ("x % 2", "operator '%' is not allowed", 1),
    ("x // 2", "operator '//' is not allowed", 1),
    ("x @ y", "operator '@' is not allowed", 1),
    ("~x", "operator '~' is not allowed", 1),
    ("not x", "operator 'not' is not allowed", 1),
    ("True", "True is not allowed", 1),
    ("None", "None is not allowed", 1),
    ("1j * x", "complex numbers are not allowed", 1),
    ("(x := 1)", "assignments (':=') are not allowed", 2),
    ("[x, y]", "lists are not allowed", 1),
    ("x()", "'x' is not a function", 1),
    ("sin", "unknown name 'sin'", 1),
    ("(lambda: 0)()", "only the named functions can be called", 2),
    ("1/0 + x", "division by zero", 1),
    ("sqrt(-1) * x", "the constant sqrt(-1) cannot be evaluated", 1),
    ("exp(1000)", "the constant exp(1000) cannot be evaluated", 1),
    ("x + 1e999", "too large for a float64", 5),
    ("x π", "'π' is not allowed", 3),
    ("x\ny", "a line break is not allowed", 2),
    ("", "the expression is empty", None),
    ("x +* 2", "invalid syntax", 4),
    ("(" * 250 + "x" + ")" * 250, "too many nested parentheses", None),
    ("-" * 400 + "x", "nested too deeply", None),
    ("x" * (MAX_LENGTH + 1), f"at most {MAX_LENGTH} are allowed", None),
]


@pytest.mark.parametrize(("text", "message", "column"), HOSTILE)
def test_hostile_and_malformed_input_is_refused(text, message, column):
    with pytest.raises(ExpressionError) as info:
        parse_expression(text)
    text_of_error = str(info.value)
    assert message in text_of_error
    if column is not None:
        first = text_of_error.splitlines()[0]
        assert first.endswith(f"at column {column}")
        caret_line = text_of_error.splitlines()[2]
        assert caret_line.index("^") - 2 == column - 1


def test_caret_line_points_at_the_offending_token():
    with pytest.raises(ExpressionError) as info:
        parse_expression("x^2 + os.getcwd()")
    assert str(info.value) == (
        "attribute access ('.getcwd') is not allowed at column 9\n"
        "  x^2 + os.getcwd()\n"
        "          ^^^^^^^"
    )


def test_long_expression_errors_show_a_window():
    text = "x + " * 100 + "bad"
    with pytest.raises(ExpressionError) as info:
        parse_expression(text)
    lines = str(info.value).splitlines()
    assert lines[0].startswith("unknown name 'bad'")
    assert lines[0].endswith(f"at column {len(text) - 2}")
    assert len(lines[1]) < 90 and lines[1].strip().startswith("...")
    assert lines[2].endswith("^^^")
    assert lines[1][lines[2].index("^") :].startswith("bad")


def test_not_a_string():
    with pytest.raises(ArgumentTypeError, match="must be a string"):
        parse_expression(42)  # type: ignore[arg-type]


def test_bad_arguments_to_an_expression():
    f = parse_expression("x + y")
    with pytest.raises(ArgumentTypeError, match="takes numbers or arrays of numbers"):
        f("a", 1.0)
    with pytest.raises(ArgumentError, match="do not broadcast"):
        f(np.zeros(3), np.zeros(4))


@pytest.mark.parametrize(
    ("text", "column"),
    [("x+", 3), ("x +  ", 4), ("sin(x) *", 9), ("2^", 3), ("(x + y) -", 10), ("lambda", 7)],
)
def test_a_missing_operand_is_marked_after_the_text(text, column):
    """The caret under `--function "x+"` pointed at column 1 (issue 11)."""
    with pytest.raises(ExpressionError) as info:
        parse_expression(text)
    first, _shown, caret = str(info.value).splitlines()
    assert first == f"invalid syntax: the expression ends early at column {column}"
    assert caret.index("^") - 2 == column - 1


@pytest.mark.parametrize("text", ["1e-400 * x", "x + 2e-324"])
def test_numbers_that_would_be_read_as_zero_are_refused(text):
    with pytest.raises(ExpressionError, match="too small for a float64"):
        parse_expression(text)
    assert float(parse_expression("1e-320 + 0*x")(0.0, 0.0)) == 1e-320  # subnormal: fine


def test_every_whitelisted_function_evaluates():
    for name, (count, ufunc) in FUNCTIONS.items():
        args = ", ".join(["x", "y"][:count])
        x, y = np.array([0.3, 0.6]), np.array([0.2, 0.7])
        with np.errstate(all="ignore"):
            expected = ufunc(*([x, y][:count]))
            values = parse_expression(f"{name}({args})")(x, y)
        np.testing.assert_array_equal(values, expected)


def test_long_chains_are_not_nested_too_deeply():
    text = " + ".join(["x*y"] * 300) + " - x/2"
    f = parse_expression(text)
    assert float(f(2.0, 3.0)) == 300 * 6 - 1
    assert float(parse_expression("1" + "+1" * 999)(0.0, 0.0)) == 1000


def test_expression_repr_and_type():
    f = parse_expression("x + y")
    assert isinstance(f, Expression)
    assert repr(f) == "Expression('x + y')"
