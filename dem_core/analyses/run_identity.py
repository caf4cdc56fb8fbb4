"""What makes two runs the same run: a digest of everything that decides a run's result.

A sweep knows a finished run by :func:`run_digest` of the scene (blocks, base, contact parameters,
friction overrides, gravity), the ground motion (every sample of a record), the settings of
``simulate`` with its defaults filled in, the installed dem_core version and a digest of its source
code (an editable install changes code under one version number).  Two runs with the same digest
compute the same thing; change any of these and the digest changes, whatever parameters of a sweep
were varied to get there.
"""

import dataclasses
import functools
import hashlib
import inspect
import json
import math
import os
import platform
from importlib import metadata
from pathlib import Path

import numpy as np

from ..simulation import simulate

DIGEST_DIGITS = 16
DISTRIBUTION = "dem-colonnade"


def package_version() -> str:
    """The installed version of this package, or "unknown" when it runs from a source tree."""
    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        return "unknown"


@functools.cache
def code_digest() -> str:
    """Hex digest of the package's Python sources (file names and contents)."""
    root = Path(__file__).resolve().parents[1]
    sources = hashlib.sha1()
    for path in sorted(root.rglob("*.py")):
        sources.update(path.relative_to(root).as_posix().encode())
        sources.update(path.read_bytes())
    return sources.hexdigest()[:DIGEST_DIGITS]


def run_digest(scene, excitation, simulation: dict) -> str:
    """Hex digest of ``simulate(scene, excitation, **simulation)`` as run by this dem_core code.

    Raises TypeError for a setting ``simulate`` does not take.
    """
    run = {"scene": describe(scene), "excitation": describe(excitation),
           "simulation": describe(resolved_settings(simulation)), "dem_core": package_version(),
           "code": code_digest()}
    return digest(run)


def resolved_settings(simulation: dict) -> dict:
    """``simulate``'s keyword arguments: those given and the defaults of the others."""
    bound = inspect.signature(simulate).bind_partial(**simulation)
    bound.apply_defaults()
    return {k: v for k, v in bound.arguments.items() if k not in ("scene", "excitation")}


def digest(description) -> str:
    """Hex digest of a JSON-able description."""
    text = json.dumps(description, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha1(text.encode()).hexdigest()[:DIGEST_DIGITS]


def describe(value):
    """A JSON-able description of ``value`` that equal values share.

    Dataclasses by their type and init fields (not caches), arrays by shape, dtype and a digest of
    their bytes, partial functions by their function and arguments, mappings as sorted key-value pairs,
    floats exactly (non-finite ones as text),
    functions and classes by qualified name, other objects by type and attributes.
    """
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, np.generic):
        return describe(value.item())
    if isinstance(value, np.ndarray):
        data = np.ascontiguousarray(value)
        return {"array": list(data.shape), "dtype": data.dtype.str, "sha1": hashlib.sha1(data.tobytes()).hexdigest()}
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, dict):
        pairs = [[describe(k), describe(v)] for k, v in value.items()]
        return {"mapping": sorted(pairs, key=lambda pair: json.dumps(pair, sort_keys=True, default=str))}
    if isinstance(value, (list, tuple)):
        return [describe(v) for v in value]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {"type": _qualified_name(type(value)),
                **{f.name: describe(getattr(value, f.name)) for f in dataclasses.fields(value) if f.init}}
    if isinstance(value, functools.partial):
        return {"partial": describe(value.func), "args": describe(list(value.args)),
                "keywords": describe(value.keywords)}
    if inspect.isroutine(value) or inspect.isclass(value):
        return {"callable": _qualified_name(value)}
    if hasattr(value, "__dict__"):
        return {"type": _qualified_name(type(value)), **{k: describe(v) for k, v in sorted(vars(value).items())}}
    return {"type": _qualified_name(type(value)), "repr": repr(value)}


def _qualified_name(obj) -> str:
    return f"{getattr(obj, '__module__', '?')}.{getattr(obj, '__qualname__', type(obj).__qualname__)}"


def machine() -> str:
    """This machine in words: its architecture, its cores and, where Linux says it, its processor's model."""
    model = platform.processor() or platform.system()
    try:
        with open("/proc/cpuinfo") as info:
            model = next((line.split(":", 1)[1].strip() for line in info if line.startswith("model name")), model)
    except OSError:
        pass
    return f"{platform.machine()}, {os.cpu_count()} cores, {model}"
