"""The GPU kernels build for the H100 and H200 (compute capability 9.0) on a machine without a GPU:
``python -m dem_core.gpu_kernels`` compiles ``engine/_members.KERNELS`` (the one step driver, built for each
integrator) to PTX, assembles it for sm_90a with the CUDA wheels' ``ptxas`` (the cubin a GPU's driver loads as it
is) and writes them; a new process loads that file into the kernels' dispatchers, as the GPU's machine does, each
kernel's cubin in the form numba-cuda loads; the run's summary prints each kernel's registers, stack and spills
from ptxas' log.  It runs where the ``gpu`` extra is installed (``bash .ci/run`` installs it);
the kernel's behaviour is tested under numba's CUDA simulator and on one CPU thread in tests/test_batch_gpu.py."""

import re
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import KERNEL_RESOURCES

from dem_core.gpu_kernels import kernel_resources

pytestmark = pytest.mark.slow
pytest.importorskip("nvidia.cuda_nvcc", reason="the gpu extra (pip install -e '.[gpu]') is not installed")
pytest.importorskip("numba_cuda", reason="the gpu extra (pip install -e '.[gpu]') is not installed")

REPOSITORY = Path(__file__).resolve().parents[1]
#: in a process of its own, as on the GPU's machine: the kernels loaded from the file, their argument types those
#: of a batch's arrays, and the PTX they carry for Hopper (compute capability 9.0, numba-cuda's arch sm_90a)
LOAD = """
import sys
from numba import typeof
from dem_core.engine._members import KERNELS
from dem_core.engine.settings import INTEGRATORS
from dem_core.gpu_kernels import kernel_arguments, load_kernels
assert load_kernels(sys.argv[1]) == list(INTEGRATORS)
for name, dispatcher in zip(INTEGRATORS, KERNELS):
    (kernel,) = dispatcher.overloads.values()
    assert kernel.argument_types == tuple(typeof(a) for a in kernel_arguments(name)), name
    open(f"{sys.argv[1]}/{name}.ptx", "w").write(kernel.inspect_asm((9, 0, "a")))
    library = kernel._codelibrary
    assembled = library._cubin_cache[(9, 0, "a")]
    assert (type(assembled).__name__, assembled.code_type) == ("ObjectCode", "cubin"), (name, assembled)
    open(f"{sys.argv[1]}/{name}.ptxas.log", "w").write(library.get_linkerinfo((9, 0, "a")))
    open(f"{sys.argv[1]}/{name}.entry", "w").write(library._entry_name)
"""


def test_the_gpu_kernels_build_for_sm_90_without_a_gpu(tmp_path, request):
    printed = []
    for command in ([sys.executable, "-m", "dem_core.gpu_kernels", str(tmp_path)],
                    [sys.executable, "-c", LOAD, str(tmp_path)]):
        done = subprocess.run(command, capture_output=True, text=True, timeout=900, cwd=REPOSITORY)
        assert done.returncode == 0, done.stderr[-3000:]
        printed.append(done.stdout)
    # where the build's time went, per kernel: numba-cuda's typing, lowering and PTX (NVVM), ptxas' cubin
    said = [f"sm_90a advance_members_{name} built in {times}" for name, times in
            re.findall(r"^(\w+): (numba-cuda \d+ s, ptxas \d+ s);", printed[0], re.MULTILINE)]
    assert len(said) == 2, printed[0]
    for name in ("explicit", "moreau"):
        assert ".target sm_90a" in (tmp_path / f"{name}.ptx").read_text()
        log, entry = (tmp_path / f"{name}.ptxas.log").read_text(), (tmp_path / f"{name}.entry").read_text()
        kernels = kernel_resources(log)
        assert entry in [found for found, *_ in kernels] and f"advance_members_{name}" in entry, log[-3000:]
        said += [f"sm_90a {f'advance_members_{name}' if found == entry else found}: {registers} registers, "
                 f"{stack}-byte stack frame, {stores} bytes of spill stores, {loads} of spill loads"
                 for found, stack, stores, loads, registers in kernels]
    request.config.cache.set(KERNEL_RESOURCES, said)  # the run's summary prints them (tests/conftest.py)


def test_kernels_made_under_another_python_or_numba_cuda_are_refused_by_name(tmp_path):
    """A file of kernels is read only where it was made for: numba-cuda pickles some of its own functions by value,
    as code objects of one Python, so a file from Python 3.11 broke on the GPU's Python 3.12 inside numba-cuda."""
    import lzma
    import pickle

    from dem_core import gpu_kernels

    stamp = {**gpu_kernels._stamp(), "python": "2.7", "numba-cuda": "0.0.1", "cc": (9, 0)}
    (tmp_path / gpu_kernels.FILE_NAME).write_bytes(lzma.compress(pickle.dumps((stamp, b"never read"))))
    with pytest.raises(ValueError, match=r"made for numba-cuda 0\.0\.1 .*python 2\.7 \(here 3\.\d+\)"):
        gpu_kernels.load_kernels(tmp_path)
    with pytest.raises(ValueError, match="no compiled kernels there"):
        gpu_kernels.load_kernels(tmp_path / "elsewhere")


def test_kernels_for_another_gpu_or_a_broken_file_are_refused_by_name(tmp_path, monkeypatch):
    """Where a GPU is here, a file made for another compute capability is refused naming both (numba-cuda would
    compile its kernels again, for minutes, at the first launch); a file that is not one of these, or cut short,
    is refused naming it."""
    import lzma
    import pickle

    from dem_core import gpu_kernels

    (tmp_path / gpu_kernels.FILE_NAME).write_bytes(lzma.compress(pickle.dumps(({**gpu_kernels._stamp(), "cc": (9, 0)},
                                                                               b"never read"))))
    monkeypatch.setattr(gpu_kernels, "_device_capability", lambda: (8, 0))
    with pytest.raises(ValueError, match=r"made for cc \(9, 0\) \(here \(8, 0\)\)"):
        gpu_kernels.load_kernels(tmp_path)
    cut = tmp_path / "cut"
    cut.mkdir()
    (cut / gpu_kernels.FILE_NAME).write_bytes((tmp_path / gpu_kernels.FILE_NAME).read_bytes()[:40])
    with pytest.raises(ValueError, match=r"cut.*not a file of kernels .* or cut short"):
        gpu_kernels.load_kernels(cut)


@pytest.mark.parametrize("options, words", [(["--integrator", "rk4"], "invalid choice: 'rk4'"),
                                            (["--cc", "9"], "give it as major.minor")])
def test_the_kernel_builders_bad_options_are_refused_naming_them(tmp_path, capsys, options, words):
    from dem_core import gpu_kernels

    with pytest.raises(SystemExit) as stopped:
        gpu_kernels.main([str(tmp_path), *options])
    assert stopped.value.code == 2 and words in capsys.readouterr().err
