"""Functions of the C library already loaded in the process.

For the few Linux calls that numpy and the standard library do not offer (``renameat2``,
``madvise``).

Examples
--------
>>> import ctypes
>>> getpid = libc_function("getpid", (), ctypes.c_int)
>>> getpid is None or getpid() > 0
True
"""

from __future__ import annotations

import ctypes
import functools
import sys
from collections.abc import Callable
from typing import Any

__all__ = ["libc_function"]


@functools.cache
def libc_function(name: str, argtypes: tuple[Any, ...], restype: Any) -> Callable[..., Any] | None:
    """The C library's ``name`` with its argument and result types, or None where unavailable.

    None off Linux or where the library lacks the function; errno is kept for
    ``ctypes.get_errno``. Cached: one lookup per function.
    """
    if not sys.platform.startswith("linux"):
        return None
    try:
        function = ctypes.CDLL(None, use_errno=True)[name]
    except (AttributeError, OSError):
        return None
    function.argtypes = list(argtypes)
    function.restype = restype
    return function
