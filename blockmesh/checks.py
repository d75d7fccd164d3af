"""Argument checks shared by every stage: whole numbers, choices, table keys, read-only arrays.

Each check raises :class:`~blockmesh.errors.ArgumentError` (a ``ValueError``) or
:class:`~blockmesh.errors.ArgumentTypeError` (a ``TypeError``) with the argument's name, what it
got and what it takes. Messages speak of the library's own names (``level``, ``split``); the command
line adds its flag spellings.

Examples
--------
>>> whole_number(3, "level")
3
>>> whole_number(-1, "level")
Traceback (most recent call last):
...
blockmesh.errors.ArgumentError: level must be a whole number >= 0, got -1
>>> choice("tri9", ("tri5", "tri3"), "split")
Traceback (most recent call last):
...
blockmesh.errors.ArgumentError: unknown split 'tri9'; choose one of: tri5, tri3
"""

from __future__ import annotations

import functools
import inspect
import numbers
import warnings
from collections.abc import Callable, Iterable, Mapping
from typing import Any, TypeVar

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError

__all__ = ["choice", "key_list", "readonly", "renamed_keywords", "unknown_keys", "whole_number"]

T = TypeVar("T")


def whole_number(value: object, name: str, *, minimum: int = 0, maximum: int | None = None) -> int:
    """``value`` as an ``int`` if it is a whole number in ``minimum..maximum``.

    Booleans and floats are refused (``2.0`` is refused: say ``2``). Raises ArgumentTypeError for
    a non-integer type and ArgumentError for a value out of range.

    Examples
    --------
    >>> whole_number(np.int64(4), "order", minimum=1, maximum=10)
    4
    >>> whole_number(11, "order", minimum=1, maximum=10)
    Traceback (most recent call last):
    ...
    blockmesh.errors.ArgumentError: order must be a whole number in 1..10, got 11
    """
    wanted = (
        f"a whole number >= {minimum}"
        if maximum is None
        else f"a whole number in {minimum}..{maximum}"
    )
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ArgumentTypeError(f"{name} must be {wanted}, got {value!r}")
    number = int(value)
    if number < minimum or (maximum is not None and number > maximum):
        raise ArgumentError(f"{name} must be {wanted}, got {number!r}")
    return number


def choice(value: T, choices: Iterable[T], name: str) -> T:
    """``value`` if it is one of ``choices``, else ArgumentError listing them.

    Examples
    --------
    >>> choice("rcm", ("nested", "rcm"), "numbering")
    'rcm'
    """
    options = tuple(choices)
    try:
        known = value in options
    except TypeError:  # unhashable or incomparable values are simply not among the choices
        known = False
    if not known:
        listed = ", ".join(str(c) for c in options)
        raise ArgumentError(f"unknown {name} {value!r}; choose one of: {listed}")
    return value


def unknown_keys(table: Iterable[Any], allowed: Iterable[Any]) -> str:
    """The keys of ``table`` that ``allowed`` lacks, as a message names them; ``""`` if none.

    One unknown key reads ``key 'x'``, several ``keys 'a', 'b'`` (sorted): the words that follow
    "unknown" in the message of the caller, which says where the table is and what it takes
    (often with :func:`key_list`).

    Examples
    --------
    >>> unknown_keys({"size": 1, "sise": 2, "colour": 3}, ("size", "growth"))
    "keys 'colour', 'sise'"
    >>> unknown_keys({"size": 1}, ("size", "growth"))
    ''
    """
    unknown = sorted(set(table) - set(allowed))
    if not unknown:
        return ""
    return f"key{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))}"


def key_list(allowed: Mapping[str, str]) -> str:
    """The keys a table takes with what each one is, for a message: ``name (text); ...``.

    Examples
    --------
    >>> key_list({"size": "a number", "growth": "a ratio > 1"})
    'size (a number); growth (a ratio > 1)'
    """
    return "; ".join(f"{name} ({text})" for name, text in allowed.items())


def readonly(values: Any, dtype: Any = None) -> np.ndarray:
    """A read-only array of ``values`` that shares no memory with a writeable caller's array.

    An array that is already read-only is returned as it is (no copy); anything else is copied
    once (converted to ``dtype`` when given) and frozen.

    Examples
    --------
    >>> a = np.arange(3)
    >>> b = readonly(a)
    >>> b.flags.writeable, a.flags.writeable, readonly(b) is b
    (False, True, True)
    """
    if (
        isinstance(values, np.ndarray)
        and not values.flags.writeable
        and (dtype is None or values.dtype == np.dtype(dtype))
    ):
        return values
    array = np.array(values, dtype=dtype, copy=True)
    array.setflags(write=False)
    return array


def renamed_keywords(**renamed: str) -> Callable[[Callable[..., T]], Callable[..., T]]:
    """Let a function still take its keywords' earlier names, with a DeprecationWarning.

    ``renamed`` maps each earlier name to the current one; giving both is an ArgumentError.

    Examples
    --------
    >>> import warnings
    >>> @renamed_keywords(function="f")
    ... def integrate(f=None):
    ...     return f
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     integrate(function="x*y")
    'x*y'
    >>> integrate(1, function=2)
    Traceback (most recent call last):
    ...
    blockmesh.errors.ArgumentError: integrate() got both f and its earlier name function; give f
    """

    def decorate(function: Callable[..., T]) -> Callable[..., T]:
        positions = {name: k for k, name in enumerate(inspect.signature(function).parameters)}

        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> T:
            for old, new in renamed.items():
                if old not in kwargs:
                    continue
                if new in kwargs or positions.get(new, len(args)) < len(args):
                    raise ArgumentError(
                        f"{function.__name__}() got both {new} and its earlier name {old}; "
                        f"give {new}"
                    )
                warnings.warn(
                    f"{function.__name__}(): {old}= is now {new}=", DeprecationWarning, stacklevel=2
                )
                kwargs[new] = kwargs.pop(old)
            return function(*args, **kwargs)

        return wrapper

    return decorate
