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
