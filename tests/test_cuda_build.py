"""The GPU kernels build for the H100 (compute capability 9.0) on a machine without a GPU: numba-cuda compiles
``engine/_members.KERNELS`` (the one step driver, built for each integrator) to PTX, and the CUDA wheels' ``ptxas``
assembles them for sm_90; the run's summary prints each kernel's registers, stack and spills.  It runs where the ``gpu`` extra
is installed (``bash .ci/run`` installs it); the kernel's behaviour is tested under numba's CUDA simulator and on
one CPU thread in tests/test_batch_gpu.py."""

import re
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import KERNEL_RESOURCES

pytestmark = pytest.mark.slow
nvcc = pytest.importorskip("nvidia.cuda_nvcc", reason="the gpu extra (pip install -e '.[gpu]') is not installed")
pytest.importorskip("numba_cuda", reason="the gpu extra (pip install -e '.[gpu]') is not installed")

REPOSITORY = Path(__file__).resolve().parents[1]
#: compiled in a process of its own: numba-cuda asks the current device for its compute capability when it compiles
#: the driver's stages as device functions, and here there is none, so a stand-in answers 9.0 for that process
COMPILE = """
import sys, types
import numba.cuda.dispatcher
numba.cuda.dispatcher.get_current_device = lambda: types.SimpleNamespace(compute_capability=(9, 0))
import numpy as np
from numba import cuda, typeof
from dem_core import scenes
from dem_core.batch_gpu import _motions, pack
from dem_core.engine._members import KERNELS
from dem_core.engine.settings import INTEGRATORS
from dem_core.inputs.excitation import sine_pulse
from dem_core.simulation import Simulation
for name, kernel in zip(INTEGRATORS, KERNELS):
    runs = [Simulation(scenes.column(), sine_pulse(2.0, 0.5), 0.1, integrator=name)]
    m = pack(runs, _motions(runs))
    arguments = (m.model, m.settings, m.state, m.outputs, m.scratch, np.zeros((1, 4, 12)), m.motion, 10, m.status)
    ptx, _ = cuda.compile_ptx(kernel.py_func, tuple(typeof(a) for a in arguments), cc=(9, 0))
    open(f"{sys.argv[1]}/{name}.ptx", "w").write(ptx)
"""


def test_the_gpu_kernels_build_for_sm_90_without_a_gpu(tmp_path, request):
    done = subprocess.run([sys.executable, "-c", COMPILE, str(tmp_path)], capture_output=True, text=True, timeout=900,
                          cwd=REPOSITORY)
    assert done.returncode == 0, done.stderr[-3000:]
    ptxas = Path(nvcc.__path__[0]) / "bin" / "ptxas"
    said = []
    for name in ("explicit", "moreau"):
        ptx, cubin = tmp_path / f"{name}.ptx", tmp_path / f"{name}.cubin"
        assert ".target sm_90" in ptx.read_text()
        built = subprocess.run([str(ptxas), "-arch=sm_90", "-v", str(ptx), "-o", str(cubin)], capture_output=True,
                               text=True, timeout=300)
        assert built.returncode == 0, built.stderr[-3000:]
        assert cubin.stat().st_size > 0
        kernels = re.findall(r"Function properties for (\S+)\n\s*(\d+) bytes stack frame, (\d+) bytes spill stores, "
                             r"(\d+) bytes spill loads\n.*?Used (\d+) registers", built.stderr)
        entry = f"advance_members_{name}"
        assert any(entry in found for found, *_ in kernels), built.stderr[-3000:]
        said += [f"sm_90 {entry if entry in found else found}: {registers} registers, {stack}-byte stack frame, "
                  f"{stores} bytes of spill stores, {loads} of spill loads"
                  for found, stack, stores, loads, registers in kernels]
    request.config.cache.set(KERNEL_RESOURCES, said)  # the run's summary prints them (tests/conftest.py)
