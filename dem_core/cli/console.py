"""What a user reads of the command line: quantities as text, a warning or an error as one line."""

import re
import sys

import numpy as np

from ..inputs.records import G_STANDARD
from ..output_files import reason
from ..simulation import SimulationUnstable


def acceleration_text(value: float, digits: int = 3) -> str:
    """An acceleration as the command line prints it: ``2.75 m/s^2 (0.281 g)`` (g = 9.80665 m/s^2)."""
    return f"{value:.{digits}g} m/s^2 ({value / G_STANDARD:.{digits}g} g)"


def motion_text(motion) -> str:
    """The ground motion's name and, when it has one, its peak horizontal acceleration."""
    peak = motion.horizontal.peak_acceleration
    return f"{motion.name}, PGA {acceleration_text(peak)}" if np.isfinite(peak) and peak > 0 else motion.name


def percent(fraction: float) -> str:
    """0.02 as "2%", 0.005 as "0.5%"."""
    return f"{100 * fraction:.3g}%"


def one_line(exc: BaseException) -> str:
    """An exception as the first line of its message, with its type when that says something."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    if isinstance(exc, OSError) and exc.filename:
        return f"{exc.filename}: {reason(exc)}"
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


class Refused(Exception):
    """An output folder that holds results this command will not mix with its own; the message says which."""


def show_warning(message, category, filename, lineno, file=None, line=None):
    """Warnings as a line a user reads ("warning: a long run: ..."), not Python's file, line and source."""
    print(f"warning: {message}", file=sys.stderr if file is None else file, flush=True)


def stopped_text(exc: SimulationUnstable) -> str:
    """Why a run stopped, without the sentence addressed to Python callers (the result in ``.partial``)."""
    return re.sub(r"\.?\s*The result up to t = \S+ s is in this error's \.partial\.?$", "", str(exc)).strip()


def failed_run(exc: Exception, culprit: str | None = None) -> int:
    """Print why a run that wrote nothing failed and return the exit status: 3 for a run that lost stability,
    2 for input the engine refused (``TypeError``/``ValueError``, prefixed with ``culprit`` where given)."""
    if isinstance(exc, SimulationUnstable):
        print(f"error: {stopped_text(exc)}", file=sys.stderr)
        return 3
    print(f"error: {culprit + ': ' if culprit else ''}{exc}", file=sys.stderr)
    return 2
