"""Shared fixtures: the Housner block as a reference and as a scene; the study scripts as modules."""

import importlib.util
import sys
from pathlib import Path

import pytest

from comparisons.cases import catalogue as cases
from comparisons.references import analytical


@pytest.fixture(scope="session")
def housner_block():
    return analytical.RockingBlock.from_size(cases.HOUSNER_WIDTH, cases.HOUSNER_HEIGHT)


@pytest.fixture(scope="session")
def housner_scene():
    return cases.housner_scene()


STUDIES = Path(__file__).parents[1] / "examples" / "studies"


@pytest.fixture
def overturning_scene_file(tmp_path):
    """A scene file of a 2-drum column under a 20 m/s^2 harmonic for 3 s: it overturns within the first second."""
    path = tmp_path / "falls.toml"
    path.write_text("[scene]\nbuilder = \"column\"\nn_drums = 2\n[excitation]\nkind = \"harmonic\"\nfrequency = 1.0\n"
                    "pga = 20.0\n[simulation]\nduration = 3.0\n")
    return path


@pytest.fixture(scope="session")
def load_study():
    """``load_study(name)``: the study script ``examples/studies/<name>.py`` as a module, imported with its folder
    first on ``sys.path`` (for its ``_study`` and ``_rigid`` helpers), as running the script would."""
    def load(name):
        sys.path.insert(0, str(STUDIES))
        try:
            spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            return module
        finally:
            sys.path.remove(str(STUDIES))

    return load


#: where tests/test_cuda_build.py leaves each kernel's registers and spills, which the run's summary prints (a line
#: a worker of pytest-xdist prints would not reach the terminal)
KERNEL_RESOURCES = "dem/sm_90_kernels"


#: the test files started first, in this order, the longest first, so that the short ones fill the end of a run on
#: both workers of pytest-xdist (`.ci/run` keeps this order of files with ``--no-loadscope-reorder``).  The GPU
#: kernels' build compiles nothing for the CPU, so on one worker it keeps the other from compiling the CPU's driver
#: at the same time (docs/performance.md, "What a fresh clone's suite compiles")
FIRST_FILES = ("test_cuda_build.py", "test_harness.py", "test_batch_gpu.py", "test_simulation.py",
               "test_nested_fragility.py", "test_adapters.py")


def pytest_collection_modifyitems(config, items):
    items.sort(key=lambda item: FIRST_FILES.index(item.path.name) if item.path.name in FIRST_FILES
               else len(FIRST_FILES))


def pytest_sessionstart(session):
    if not hasattr(session.config, "workerinput"):
        session.config.cache.set(KERNEL_RESOURCES, [])


def pytest_terminal_summary(terminalreporter, config):
    lines = config.cache.get(KERNEL_RESOURCES, [])
    if lines:
        terminalreporter.section("GPU kernels built for sm_90 (tests/test_cuda_build.py)")
        for line in lines:
            terminalreporter.write_line(line)


@pytest.fixture(scope="module")
def results():
    """The committed report's cases (``reports/results.csv``), for the tests that read the docs' figures."""
    import pandas as pd

    return pd.read_csv(Path(__file__).resolve().parents[1] / "reports" / "results.csv")


@pytest.fixture(scope="module")
def ensembles():
    """The committed report's ensembles (``reports/ensembles.csv``)."""
    import pandas as pd

    return pd.read_csv(Path(__file__).resolve().parents[1] / "reports" / "ensembles.csv")
