"""Ctrl-C as the command line takes it: never raised inside Python code that compiled code calls back."""

import contextlib
import os
import signal
import threading


class Interrupts:
    """Ctrl-C as the command line takes it: ``KeyboardInterrupt`` raised where the program is, except in Python
    code that the compiled driver calls back (numba loading a constant), where an exception crashes the process
    with a segmentation fault; there the request is only noted, and :meth:`check` raises it at the next safe
    point (between a run's chunks, a quarter of a second apart, and after each run)."""

    def __init__(self):
        self.requested = False

    def handle(self, signum, frame):
        self.requested = True
        if not _called_back_from_compiled_code(frame):
            raise KeyboardInterrupt

    def check(self) -> None:
        """Raise ``KeyboardInterrupt`` if Ctrl-C came and was held back."""
        if self.requested:
            raise KeyboardInterrupt

    def installed(self):
        """A context in which SIGINT goes to :meth:`handle` (in the main thread only: elsewhere Python's own)."""
        self.requested = False
        if threading.current_thread() is not threading.main_thread():
            return contextlib.nullcontext()
        previous = signal.signal(signal.SIGINT, self.handle)
        stack = contextlib.ExitStack()
        stack.callback(signal.signal, signal.SIGINT, previous)
        return stack


INTERRUPTS = Interrupts()
#: the folder of the dem_core package
_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep


def _called_back_from_compiled_code(frame) -> bool:
    """Whether ``frame`` runs in numba's Python code called straight from a call in this package (its compiled
    code has no Python frames of its own), compilation (``_compile_for_args``) excepted."""
    above = None
    while frame is not None and not frame.f_code.co_filename.startswith(_PACKAGE):
        if frame.f_code.co_name == "_compile_for_args":
            return False
        above, frame = frame, frame.f_back
    return frame is not None and above is not None and f"{os.sep}numba{os.sep}" in above.f_code.co_filename
