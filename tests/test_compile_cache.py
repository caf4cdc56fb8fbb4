"""Compiled kernels are cached on disk: a second process loads them instead of compiling; and one compile of the
driver serves every run of a process."""

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


#: runs of every kind a scene and its options give the driver: both integrators, both contact laws, connectors, a
#: moving base and a run going on from another's end; then the driver's signatures and each run's compile time
KINDS = """
import dem_core
from dem_core import ContactParameters, scenes
from dem_core.engine import _driver
from dem_core.inputs.connectors import titanium_bar
from dem_core.inputs.excitation import record, scaled, sine_pulse
pulse, el_centro = sine_pulse(2.0, 0.5), scaled(record("el_centro_1940"), 2.0)
times = []
for integrator in ("explicit", "moreau"):
    first = dem_core.simulate(scenes.block(1.0, 6.0), pulse, 0.1, integrator=integrator)
    runs = [first,
            dem_core.simulate(scenes.column(connectors=[(titanium_bar(), "all")]), el_centro, 0.1,
                              integrator=integrator),
            dem_core.simulate(scenes.colonnade(), el_centro, 0.1, integrator=integrator, ground_motion="moving_base"),
            dem_core.simulate(scenes.block(1.0, 6.0), pulse, 0.1, integrator=integrator, start=first)]
    times += [run.info["compile_time_s"] for run in runs]
overlap = dem_core.simulate(scenes.stack([(0.8, 1.0), (0.6, 0.8)], contact=ContactParameters(law="overlap_area")),
                            pulse, 0.1, integrator="explicit")
times.append(overlap.info["compile_time_s"])
print(len(_driver.drive_serial.signatures), *times)
"""


def test_one_compile_of_the_driver_serves_runs_of_every_kind():
    """The driver's arguments have one type for every scene and option, so a process compiles it (or loads it from
    the cache) once, at its first run, and every later run's set-up skips the compiling call (compile time 0)."""
    done = subprocess.run([sys.executable, "-c", KINDS], capture_output=True, text=True, check=True)
    signatures, first, *later = done.stdout.split()
    assert int(signatures) == 1
    assert float(first) > 0.0
    assert [float(t) for t in later] == [0.0] * 8
