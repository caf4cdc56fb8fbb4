"""Compiled kernels are cached on disk: a second process loads them instead of compiling."""

import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow  # the whole module

PROBE = """
import dem_core
from dem_core.engine import _driver
dem_core.simulate(dem_core.scenes.column(2), duration=0.01)
stats = _driver.drive_serial.stats
print(sum(stats.cache_hits.values()), sum(stats.cache_misses.values()))
"""


def test_second_process_loads_the_kernel_from_the_cache():
    subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, check=True)  # fills the cache
    done = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, check=True)
    hits, misses = done.stdout.split()
    assert int(hits) >= 1
    assert int(misses) == 0


def test_every_function_compiled_for_its_own_call_is_named_with_the_engines_digest():
    """Numba checks only a cached function's own file before loading it, and the engine's functions inline stages
    of other modules: each function cached on its own (not inlined) carries the digest of the whole engine's
    source in its name, so that an edit anywhere in the engine compiles it afresh."""
    import importlib
    import pkgutil

    from numba.core.registry import CPUDispatcher

    import dem_core.engine
    from dem_core.engine._build import ENGINE_DIGEST

    cached = []
    for info in pkgutil.iter_modules(dem_core.engine.__path__):
        module = importlib.import_module(f"dem_core.engine.{info.name}")
        for name, value in vars(module).items():
            if (isinstance(value, CPUDispatcher) and value.targetoptions.get("inline") != "always"
                    and value._cache.__class__.__name__ != "NullCache" and value.__module__ == module.__name__):
                cached.append((module.__name__, name, value.py_func.__name__))
    assert len(cached) >= 10
    assert [c for c in cached if not c[2].endswith(ENGINE_DIGEST)] == []
