"""How the engine's compiled functions are named: with one digest of its whole source, so that numba's on-disk
cache never serves a function compiled from other source.

Numba files a compiled function by its name, line and bytecode, and before loading it checks only the timestamp of
the function's own file.  Most of the engine's functions inline stages of other modules (the driver inlines the
manifold and the checks; Moreau-Jean's stage inlines the direct solve and its constants), so editing one module
would leave the others' compiled code stale.  :func:`kernel` compiles a function under its name and
:data:`ENGINE_DIGEST`, a digest of every module of the engine: editing any of them compiles each afresh.
"""

import hashlib
import types
from pathlib import Path

import numba as nb


def _engine_digest() -> str:
    """A digest of the source of every module of the engine (this folder's ``*.py``)."""
    digest = hashlib.sha256()
    for path in sorted(Path(__file__).parent.glob("*.py")):
        digest.update(path.read_bytes())
    return digest.hexdigest()[:10]


ENGINE_DIGEST = _engine_digest()


def variant(function, name: str, **replaced):
    """``function`` (a Python function, or a dispatcher's) under another name, its globals named in ``replaced``
    swapped.  Numba's on-disk cache files a kernel by its name, line and bytecode, not by its compile options or
    the functions it calls: each build of one function gets a name of its own."""
    function = getattr(function, "py_func", function)
    clone = types.FunctionType(function.__code__, {**function.__globals__, **replaced}, name, function.__defaults__,
                               function.__closure__)
    clone.__qualname__ = name
    clone.__doc__ = function.__doc__
    return clone


def kernel(**options):
    """A decorator: ``nb.njit(cache=True, **options)`` of the function under its name and :data:`ENGINE_DIGEST`."""
    def compiled(function):
        return nb.njit(cache=True, **options)(variant(function, f"{function.__name__}_{ENGINE_DIGEST}"))
    return compiled
