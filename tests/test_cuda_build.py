"""The GPU kernel builds for the H100 (compute capability 9.0) on a machine without a GPU: numba-cuda compiles
``engine/_members.advance_members`` (the one step driver, both integrators) to PTX, and the CUDA wheels' ``ptxas``
assembles it for sm_90; the test prints each kernel's registers, stack and spills.  It runs where the ``gpu`` extra
is installed (``bash .ci/run`` installs it); the kernel's behaviour is tested under numba's CUDA simulator and on
one CPU thread in tests/test_batch_gpu.py."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

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
from dem_core.engine._members import advance_members
from dem_core.inputs.excitation import sine_pulse
from dem_core.simulation import Simulation
runs = [Simulation(scenes.column(), sine_pulse(2.0, 0.5), 0.1, integrator=integrator)
        for integrator in ("explicit", "moreau")]
m = pack(runs, _motions(runs))
arguments = (m.model, m.settings, m.state, m.outputs, m.scratch, np.zeros((1, 4, 12)), m.motion, 10, m.status)
ptx, _ = cuda.compile_ptx(advance_members.py_func, tuple(typeof(a) for a in arguments), cc=(9, 0))
open(sys.argv[1], "w").write(ptx)
"""


def test_the_gpu_kernel_builds_for_sm_90_without_a_gpu(tmp_path, capsys):
    ptx = tmp_path / "members.ptx"
    done = subprocess.run([sys.executable, "-c", COMPILE, str(ptx)], capture_output=True, text=True, timeout=900,
                          cwd=REPOSITORY)
    assert done.returncode == 0, done.stderr[-3000:]
    assert ".target sm_90" in ptx.read_text()
    ptxas = Path(nvcc.__path__[0]) / "bin" / "ptxas"
    built = subprocess.run([str(ptxas), "-arch=sm_90", "-v", str(ptx), "-o", str(tmp_path / "members.cubin")],
                           capture_output=True, text=True, timeout=300)
    assert built.returncode == 0, built.stderr[-3000:]
    assert (tmp_path / "members.cubin").stat().st_size > 0
    kernels = re.findall(r"Function properties for (\S+)\n\s*(\d+) bytes stack frame, (\d+) bytes spill stores, "
                         r"(\d+) bytes spill loads\n.*?Used (\d+) registers", built.stderr)
    assert any("advance_members" in name for name, *_ in kernels), built.stderr[-3000:]
    with capsys.disabled():
        for name, stack, stores, loads, registers in kernels:
            print(f"\nsm_90 {'advance_members' if 'advance_members' in name else name}: {registers} registers, "
                  f"{stack}-byte stack frame, {stores} bytes of spill stores, {loads} of spill loads")
