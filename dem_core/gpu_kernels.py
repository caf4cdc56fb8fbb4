"""The GPU kernels compiled ahead: built where there is no GPU, loaded where one runs.

numba-cuda compiles a kernel of :data:`~dem_core.engine._members.KERNELS` the first time a batch of its integrator
runs on a GPU, and for the one step driver that takes minutes (docs/performance.md).  :func:`compile_kernels` does
that work on any machine with the ``gpu`` extra, for a compute capability named, and writes each integrator's
kernel (numba-cuda's own serialised form: its PTX, argument types and entry, and, where the CUDA wheels' ``ptxas``
is installed, the PTX assembled for the GPU) to one compressed file; :func:`load_kernels` hands them to the kernels'
dispatchers where the GPU is, so that a batch's first launch only loads the assembled kernel (or, without it, has
the driver assemble the PTX).  A file serves the engine's code of the same
:data:`~dem_core.engine._build.ENGINE_DIGEST` under the same numba-cuda version and Python minor version as made
it, and, where a GPU is here, its compute capability; any other is refused by name.  The file is a pickle: load
only files you made.

    python -m dem_core.gpu_kernels build/kernels            (here: compiles for sm_90, the H100 and H200)
    DEM_CORE_GPU_KERNELS=build/kernels dem-core fragility --device gpu   (there)
"""

from __future__ import annotations

import contextlib
import lzma
import os
import pickle
import re
import subprocess
import sys
import tempfile
import time
import types
import warnings
from importlib import metadata
from pathlib import Path

import numpy as np

#: the file :func:`compile_kernels` writes in its folder
FILE_NAME = "kernels.pickle.xz"
#: the variable naming the folder of kernels that :func:`load_named_kernels` loads
ENVIRONMENT = "DEM_CORE_GPU_KERNELS"
#: the H100's and H200's compute capability
HOPPER = (9, 0)
#: the files :func:`load_kernels` gave to the dispatchers in this process, and their integrators
_LOADED: dict = {}


@contextlib.contextmanager
def _compute_capability(cc: tuple):
    """numba-cuda asking for the current device's compute capability (to compile the driver's stages as device
    functions and the kernel's PTX) answered with ``cc``: there may be no GPU here."""
    from numba.cuda import codegen, dispatcher

    device = types.SimpleNamespace(compute_capability=cc)
    saved = dispatcher.get_current_device, codegen.devices
    dispatcher.get_current_device = lambda: device
    codegen.devices = types.SimpleNamespace(get_context=lambda: types.SimpleNamespace(device=device))
    try:
        yield
    finally:
        dispatcher.get_current_device, codegen.devices = saved


def kernel_arguments(integrator: str) -> tuple:
    """The kernel's arguments for a member of the bundled column under ``integrator``: every batch's arrays have
    these types (the shapes differ, not the dtypes, dimensions or layouts)."""
    from . import scenes
    from .batch_gpu import _motions, pack, written_out
    from .inputs.excitation import sine_pulse
    from .simulation import Simulation

    runs = [Simulation(scenes.column(), sine_pulse(2.0, 0.5), 0.1, integrator=integrator)]
    m = pack(runs, _motions(runs))
    return (written_out(m.model), m.settings, m.state, written_out(m.outputs), written_out(m.scratch),
            np.zeros((1, 4, 12)), m.motion, 10, m.status)


def _stamp() -> dict:
    """What a file of kernels must have been made under: the engine's code, numba-cuda, and Python's minor version
    (numba-cuda pickles some of its functions by value, as code objects of that Python)."""
    from .engine._build import ENGINE_DIGEST

    return {"engine": ENGINE_DIGEST, "numba-cuda": metadata.version("numba-cuda"),
            "python": ".".join(str(v) for v in sys.version_info[:2])}


def kernel_resources(ptxas_log: str) -> list:
    """Each function's resources in ``ptxas -v``'s log: (name, bytes of stack frame, of spill stores, of spill
    loads, registers per thread)."""
    found = re.findall(r"Function properties for (\S+)\n\s*(\d+) bytes stack frame, (\d+) bytes spill stores, "
                       r"(\d+) bytes spill loads\n.*?Used (\d+) registers", ptxas_log)
    return [(name, *(int(value) for value in values)) for name, *values in found]


def _assemble(library) -> str:
    """``library``'s PTX for the compute capability numba-cuda is told of (:func:`_compute_capability`) assembled by
    the CUDA wheels' ``ptxas`` into the cubin numba-cuda keeps for it (where it looks before asking the driver to
    assemble the PTX), ptxas' log kept as the linker's; returns the entry's resources, or why it did not assemble:
    the ``nvidia-cuda-nvcc`` wheel is not installed."""
    try:
        from nvidia import cuda_nvcc
    except ImportError:
        return "not assembled: no ptxas here (the gpu extra's nvidia-cuda-nvcc wheel)"
    key = library._ensure_cc(None)  # numba-cuda's own key: Hopper's and later take the arch-specific "a"
    arch = f"sm_{key[0]}{key[1]}{key[2]}"
    with tempfile.TemporaryDirectory() as folder:
        ptx, cubin = Path(folder) / "kernel.ptx", Path(folder) / "kernel.cubin"
        ptx.write_text(library.get_asm_str(key))
        done = subprocess.run([str(Path(cuda_nvcc.__path__[0]) / "bin" / "ptxas"), f"-arch={arch}", "-v", str(ptx),
                               "-o", str(cubin)], capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"ptxas -arch={arch} failed: {done.stderr[-2000:]}")
        library._cubin_cache[key] = cubin.read_bytes()
    library._linkerinfo_cache[key] = done.stderr
    return "; ".join(f"{arch} {name}: {registers} registers, {stack} B stack, {stores} B spill stores, {loads} B "
                     f"spill loads" for name, stack, stores, loads, registers in kernel_resources(done.stderr)
                     if name == library._entry_name)


def compile_kernels(folder: str | Path, cc: tuple = HOPPER, integrators=None) -> Path:
    """Compile the kernel of each of ``integrators`` (default both) for compute capability ``cc`` and write them to
    ``folder``/:data:`FILE_NAME`; returns its path.  Needs no GPU; takes minutes (the compile a first batch would)."""
    from numba import typeof
    from numba.cuda.dispatcher import _Kernel

    from .engine._members import KERNELS
    from .engine.settings import INTEGRATORS

    chosen = list(integrators or INTEGRATORS)
    unknown = [name for name in chosen if name not in INTEGRATORS]
    if unknown:
        raise ValueError(f"compile_kernels: unknown integrator(s) {unknown}; choose from {list(INTEGRATORS)}")
    built = {}
    with _compute_capability(tuple(cc)):
        for name in chosen:
            dispatcher = KERNELS[INTEGRATORS.index(name)]
            argument_types = tuple(typeof(a) for a in kernel_arguments(name))
            began = time.perf_counter()
            built[name] = _Kernel(dispatcher.py_func, argument_types, **dispatcher.targetoptions)
            made = time.perf_counter()  # numba-cuda makes the kernel's PTX with it (NVVM's time inside)
            assembled = _assemble(built[name]._codelibrary)
            print(f"{name}: numba-cuda {made - began:.0f} s, ptxas {time.perf_counter() - made:.0f} s; {assembled}",
                  flush=True)
    path = Path(folder) / FILE_NAME
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(lzma.compress(pickle.dumps(({**_stamp(), "cc": tuple(cc)}, pickle.dumps(built)))))
    return path


def load_kernels(folder: str | Path) -> list:
    """Give the kernels in ``folder``/:data:`FILE_NAME` to :data:`~dem_core.engine._members.KERNELS`; returns the
    integrators loaded.  ``ValueError`` naming the file where it cannot be read, or was made for other code,
    another numba-cuda or Python, or (where a GPU is here) another compute capability."""
    from .engine._members import KERNELS
    from .engine.settings import INTEGRATORS

    path = Path(folder) / FILE_NAME
    if path.resolve() in _LOADED:
        return _LOADED[path.resolve()]
    if not path.is_file():
        raise ValueError(f"{path}: no compiled kernels there (python -m dem_core.gpu_kernels {folder} writes them)")
    # a file this module wrote (the docstring says so): its stamp, then the kernels, read once the stamp matches
    try:
        stamp, payload = pickle.loads(lzma.decompress(path.read_bytes()))
    except (lzma.LZMAError, pickle.UnpicklingError, EOFError, ValueError, TypeError) as error:
        raise ValueError(f"{path}: not a file of kernels python -m dem_core.gpu_kernels wrote, or cut short "
                         f"({type(error).__name__}: {error})") from None
    gpu = _device_capability()
    here = {**_stamp(), **({"cc": gpu} if gpu else {})}
    differ = [f"{key} {stamp.get(key)} (here {value})" for key, value in here.items() if stamp.get(key) != value]
    if differ:
        raise ValueError(f"{path}: made for {', '.join(differ)}; compile them again with what runs here")
    kernels = pickle.loads(payload)
    for name, kernel in kernels.items():
        _load_assembled(name, kernel._codelibrary)
        KERNELS[INTEGRATORS.index(name)].add_overload(kernel, kernel.argument_types)
    _LOADED[path.resolve()] = list(kernels)
    return _LOADED[path.resolve()]


def _device_capability() -> tuple | None:
    """The compute capability of this process's GPU, ``(major, minor)``; None without one (or under numba's CUDA
    simulator)."""
    from numba import config, cuda

    if config.ENABLE_CUDASIM or not cuda.is_available():
        return None
    return tuple(cuda.get_current_device().compute_capability)


def _load_assembled(name: str, library) -> None:
    """The kernel assembled ahead (a cubin) handed to numba-cuda in the form its linker gives, and loaded onto this
    process's GPU if one is here; where the driver refuses it, it is dropped with a warning, and the driver
    assembles the PTX at the first launch."""
    from cuda.core import ObjectCode
    from numba import cuda

    # kept as bytes in the file; numba-cuda loads the cubins its linker makes, cuda.core's ObjectCode
    library._cubin_cache = {key: ObjectCode.from_cubin(cubin) if isinstance(cubin, bytes) else cubin
                            for key, cubin in library._cubin_cache.items()}
    if not library._cubin_cache or not cuda.is_available():
        return
    try:
        library.get_cufunc()
    except Exception as refused:  # the driver's error, whichever of numba-cuda's bindings raised it
        library._cubin_cache.clear()
        library._cufunc_cache.clear()
        warnings.warn(f"{name}: the kernel assembled ahead was refused ({refused}); the driver assembles its PTX")


def load_named_kernels() -> list:
    """The kernels of the folder :data:`ENVIRONMENT` names loaded (:func:`load_kernels`) before a GPU batch, if it
    names one; none under numba's CUDA simulator, whose kernels are Python.  Returns the integrators loaded."""
    from numba import config

    folder = os.environ.get(ENVIRONMENT)
    if not folder or config.ENABLE_CUDASIM:
        return []
    return load_kernels(folder)


def main(argv=None) -> int:
    """``python -m dem_core.gpu_kernels FOLDER [--cc 9.0] [--integrator NAME]``."""
    import argparse

    from .engine.settings import INTEGRATORS

    parser = argparse.ArgumentParser(prog="python -m dem_core.gpu_kernels", description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", help=f"where to write {FILE_NAME}")
    parser.add_argument("--cc", default="9.0", help="compute capability (default 9.0: H100, H200)")
    parser.add_argument("--integrator", action="append", choices=INTEGRATORS, help="one integrator (default both)")
    args = parser.parse_args(argv)
    if not re.fullmatch(r"\d+\.\d+", args.cc):
        parser.error(f"--cc {args.cc!r}: give it as major.minor, e.g. 9.0")
    cc = tuple(int(part) for part in args.cc.split("."))
    began = time.perf_counter()
    path = compile_kernels(args.folder, cc, args.integrator)
    print(f"{path}: {', '.join(args.integrator or INTEGRATORS)} for compute capability {args.cc}, "
          f"{time.perf_counter() - began:.0f} s; on the GPU's machine set {ENVIRONMENT}={args.folder}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
