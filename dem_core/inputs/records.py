"""Readers for recorded accelerograms: PEER AT2 and plain column text.

Every reader returns accelerations in m/s^2 and raises :class:`RecordError`
naming the file and line of anything it cannot read.  The records bundled
with the package are listed in :data:`BUNDLED` (sources in
``dem_core/data/records/SOURCES.md``).

A text file's first column is its time column when it increases steadily (see
:func:`read_text_record`); its step is then the record's, a ``dt`` given must agree
with it, and an uneven time column is refused naming its largest gap, unless
``resample=True`` asks for the record interpolated linearly onto a uniform step
(the time column's median step, or the ``dt`` given).  A sample that stands alone
far above all the others (:func:`find_spike`: a typo, a misplaced decimal point) is
refused naming its line, its time and its value.
"""

import difflib
import math
import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from .number_types import is_integer, is_real
from .text_files import file_errors

G_STANDARD = 9.80665  # m/s^2, the g that record files in units of g refer to
#: time columns are printed rounded (the Mexico City file steps 0.01999 and 0.02001): steps may differ this much
TIME_STEP_TOLERANCE = 1e-3
#: s, the shortest sampling interval accepted: accelerographs sample at 1e-3 s to 0.05 s, so a smaller
#: dt is a typo or a unit mistake (and makes the baseline correction's equations singular)
MIN_DT = 1e-6
#: share of the first column's steps equal to its median step from which that column is read as time
#: (and then checked line by line), when the caller does not say whether there is a time column
TIME_COLUMN_SHARE = 0.9
#: a sample is a spike when its |a| is more than SPIKE_MEDIAN_RATIO times the median |a| of the record's nonzero
#: samples and more than SPIKE_PERCENTILE_RATIO times the 99th percentile of |a|: the bundled records peak at
#: 25 to 175 times their median and 1.2 to 2.2 times their 99th percentile; the second test keeps a real record
#: with long quiet stretches (a small median) from being taken for a spike
SPIKE_MEDIAN_RATIO = 1e3
SPIKE_PERCENTILE_RATIO = 100.0
#: most samples a resampled record may have (80 MB of floats): a step far below the time column's is a mistake
MAX_RESAMPLED = 10_000_000


class RecordError(ValueError):
    """A record file that cannot be read; the message names the file and line."""


class NoSamplingInterval(RecordError):
    """A record with neither a time column nor a sampling interval given."""


@dataclass(frozen=True)
class BundledRecord:
    file: str
    component: int  # 1-based data column (after the time column, if any)
    units: str
    dt: float | None = None
    vertical_component: int | None = None
    description: str = ""


BUNDLED = {
    "el_centro_1940": BundledRecord("elcentro_1940_NS_RSN6_ELC180.AT2", 1, "g",
                                    description="Imperial Valley 1940, El Centro Array #9, comp 180 (PGA 0.281 g)"),
    "mexico_city_1985": BundledRecord("mexico_1985_SCT_t_NS_EW_V_g.txt", 2, "g", vertical_component=3,
                                      description="Michoacan 1985, Mexico City SCT, EW (PGA 0.171 g), "
                                                  "vertical available"),
    "northridge_1994": BundledRecord("northridge_1994_sylmar_county_hospital_ms2.dat", 1, "m/s^2",
                                     description="Northridge 1994, Sylmar County Hospital (PGA 8.27 m/s^2)"),
    # the file's name keeps the 0.02 s its source gave; 0.01 s is settled in SOURCES.md
    "kalamata_1986": BundledRecord("kalamata_1986_acc_ms2_dt0.02.txt", 1, "m/s^2", dt=0.01,
                                   description="Kalamata 1986, near field, station and component unknown "
                                               "(PGA 2.91 m/s^2; dt 0.01 s, see SOURCES.md)"),
}


def bundled_path(name: str) -> Path:
    """Path of a bundled record file, by its key in :data:`BUNDLED`."""
    if name not in BUNDLED:
        raise KeyError(f"no bundled record named {name!r}{_bundled_hint(name)}")
    return Path(str(resources.files("dem_core") / "data" / "records" / BUNDLED[name].file))


def _bundled_hint(name: str) -> str:
    """The close matches among the bundled names and their list, for a record name or path not found."""
    close = difflib.get_close_matches(Path(name).name, BUNDLED, n=3, cutoff=0.6)
    guess = f"; did you mean the bundled {' or '.join(repr(c) for c in close)}?" if close else ""
    return f"{guess} (bundled records: {', '.join(BUNDLED)})"


def sampling_source(entry: BundledRecord, dt: float) -> str:
    """Where a bundled record's sampling interval comes from, in words: the AT2 header, the time column, or (for a
    file without either) this module's :data:`BUNDLED`, with the interval the file's name gives if other."""
    if entry.dt is None:
        return "stated in the file's header" if entry.file.lower().endswith(".at2") else "from its time column"
    named = re.search(r"dt[_=]?(\d+(?:\.\d+)?)", entry.file, re.IGNORECASE)
    other = (f"; the file's name says {float(named.group(1)):g} s" if named and
             not math.isclose(float(named.group(1)), dt, rel_tol=1e-6) else "")
    return (f"not stated in the file, which has no time column: dem_core's reading{other}, see "
            f"dem_core/data/records/SOURCES.md")


def check_dt(dt, where: str, what: str = "dt") -> float:
    """``dt`` (s) as a float if it is a usable sampling interval: a finite number of at least
    :data:`MIN_DT`; otherwise :class:`RecordError` naming ``where`` and ``what``."""
    if not is_real(dt):
        raise RecordError(f"{where}: {what} must be a number of seconds, got {dt!r}")
    if not (math.isfinite(dt) and dt >= MIN_DT):
        raise RecordError(f"{where}: {what} must be a finite sampling interval of at least {MIN_DT:g} s, "
                          f"got {float(dt)!r}")
    return float(dt)


def _unit_factor(units: str, where: str) -> float:
    if not isinstance(units, str):
        raise RecordError(f"{where}: units must be a string such as 'g' or 'm/s^2', got {units!r}")
    u = units.strip().lower().replace(" ", "")
    if u == "g":
        return G_STANDARD
    if u in ("m/s^2", "m/s2", "m/s/s", "ms-2", "m/s**2"):
        return 1.0
    if u in ("cm/s^2", "cm/s2", "gal"):
        return 0.01
    raise RecordError(f"{where}: unknown units {units!r} (use 'g', 'm/s^2' or 'cm/s^2')")


def read_at2(path) -> tuple[np.ndarray, float]:
    """Read a PEER NGA AT2 file: ``(acceleration (n,) m/s^2, dt s)``.

    Four header lines; the third names the units, the fourth ``NPTS=..., DT=...``.
    """
    path = Path(path)
    lines = _read_lines(path)
    if len(lines) < 4:
        raise RecordError(f"{path}: an AT2 file has 4 header lines, found only {len(lines)} lines")
    units_line = lines[2].upper()
    if "UNITS OF G" in units_line:
        factor = G_STANDARD
    elif "CM/S" in units_line or "CM/SEC" in units_line:
        factor = 0.01
    else:
        raise RecordError(f"{path}:3: cannot tell the units from {lines[2].strip()!r}")
    m = re.search(r"NPTS\s*=\s*(\d+)\s*,\s*DT\s*=\s*([^\s,]+)", lines[3], re.IGNORECASE)
    if not m:
        raise RecordError(f"{path}:4: expected 'NPTS= n, DT= dt', found {lines[3].strip()!r}")
    npts = int(m.group(1))
    try:
        dt = float(m.group(2))
    except ValueError:
        raise RecordError(f"{path}:4: cannot read DT {m.group(2)!r} as a number of seconds") from None
    dt = check_dt(dt, f"{path}:4", "DT")
    values, value_lines = [], []
    for lineno, line in enumerate(lines[4:], start=5):
        for token in line.split():
            values.append(_number(token, path, lineno))
            value_lines.append(lineno)
    if len(values) != npts:
        raise RecordError(f"{path}: header says NPTS={npts} but the file holds {len(values)} values")
    values = np.array(values)
    refuse_spike(values, np.arange(len(values)) * dt, "g" if factor == G_STANDARD else "cm/s^2",
                 lambda k: f"{path}:{value_lines[k]}")
    return values * factor, dt


def read_columns(path) -> np.ndarray:
    """Read whitespace- or comma-separated numeric columns: ``(n_rows, n_columns)``.

    Blank lines and lines starting with ``#`` are skipped; every other line
    must hold the same number of numbers.
    """
    return _read_rows(Path(path))[0]


def _read_rows(path: Path) -> tuple[np.ndarray, list]:
    """The numeric rows of a column text file and the line number of each."""
    rows, line_numbers = [], []
    width = None
    for lineno, line in enumerate(_read_lines(path), start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        row = [_number(tok, path, lineno) for tok in re.split(r"[,\s;]+", text) if tok]
        if width is None:
            width = len(row)
        elif len(row) != width:
            raise RecordError(f"{path}:{lineno}: expected {width} columns as on the first data line, found {len(row)}")
        rows.append(row)
        line_numbers.append(lineno)
    if not rows:
        raise RecordError(f"{path}: no data lines")
    return np.array(rows, dtype=float), line_numbers


def read_text_record(path, *, dt=None, units="m/s^2", component=1, time_column=None, resample=False):
    """Read one component of a column text record: ``(acceleration m/s^2, dt s, t0 s)``.

    path : 1 column (accelerations; ``dt`` required), or a time column
        followed by one or more components.
    dt : s, the sampling interval of a file without a time column.  With a time column, a ``dt`` that
        disagrees with its step is an error naming both (a time column is never read as accelerations).
    component : 1-based index of the component among the non-time columns.
    time_column : whether column 1 holds time; ``None`` decides from the data: a first column (of two or
        more) that increases strictly, or by one step on at least :data:`TIME_COLUMN_SHARE` of its lines,
        is time (and must then increase strictly on every line).
    resample : an uneven time column is an error naming its largest gap, unless ``resample`` is true:
        the record is then interpolated linearly (the piecewise-linear acceleration the simulation uses)
        onto a uniform step from the first time: the ``dt`` given, else the time column's median step.
        An even time column is resampled only onto a ``dt`` given that differs from its step.
    """
    path = Path(path)
    if dt is not None:
        dt = check_dt(dt, str(path))
    if not is_integer(component):
        raise RecordError(f"{path}: component must be a 1-based column number, got {component!r}")
    factor = _unit_factor(units, str(path))
    data, line_numbers = _read_rows(path)
    has_time = _first_column_is_time(data) if time_column is None else bool(time_column)
    if has_time:
        t = data[:, 0]
        step = _time_step(t, line_numbers, path, dt, bool(resample))
        columns = data[:, 1:]
    else:
        if dt is None:
            why = ("a single column of accelerations" if data.shape[1] == 1 else
                   "the first column does not increase steadily, so every column is read as accelerations")
            raise NoSamplingInterval(f"{path}: no time column ({why}); give dt (the sampling interval in s)")
        t, step = np.arange(len(data)) * dt, dt
        columns = data
    if columns.shape[1] == 0:
        raise RecordError(f"{path}: only a time column, no accelerations")
    if not 1 <= component <= columns.shape[1]:
        raise RecordError(f"{path}: component {component} asked for, the file has {columns.shape[1]} "
                          f"acceleration column(s)")
    raw = columns[:, component - 1]
    refuse_spike(raw, t, units, lambda k: f"{path}:{line_numbers[k]}")
    if has_time and _uneven(t, step):
        raw = _resampled(raw, t, step, path)
    return raw * factor, float(step), float(t[0]) if has_time else 0.0


def find_spike(a):
    """Index of the sample of ``a`` that stands alone far above the others, or None: its |a| is more than
    :data:`SPIKE_MEDIAN_RATIO` times the median |a| of the nonzero samples and more than
    :data:`SPIKE_PERCENTILE_RATIO` times the 99th percentile of |a|."""
    magnitude = np.abs(np.asarray(a, dtype=float))
    nonzero = magnitude[magnitude > 0]
    if nonzero.size == 0:
        return None
    k = int(np.argmax(magnitude))
    if (magnitude[k] > SPIKE_MEDIAN_RATIO * np.median(nonzero)
            and magnitude[k] > SPIKE_PERCENTILE_RATIO * np.percentile(magnitude, 99)):
        return k
    return None


def refuse_spike(a, times, units: str, where) -> None:
    """:class:`RecordError` naming the spike of ``a`` (:func:`find_spike`), if it has one: where it is
    (``where(k)``, e.g. the file and line), its time (``times[k]`` s) and its value in ``units``."""
    k = find_spike(a)
    if k is None:
        return
    magnitude = np.abs(np.asarray(a, dtype=float))
    median = float(np.median(magnitude[magnitude > 0]))
    raise RecordError(f"{where(k)}: a spike at t = {times[k]:.6g} s: {a[k]:g} {units}, {magnitude[k] / median:.3g} "
                      f"times the median |a| of the record's nonzero samples ({median:.3g} {units}) and more than "
                      f"{SPIKE_PERCENTILE_RATIO:g} times its 99th percentile; correct or remove that sample "
                      f"(a typo, a misplaced decimal point?)")


def _first_column_is_time(data) -> bool:
    if data.shape[1] < 2 or data.shape[0] < 3:
        return False
    steps = np.diff(data[:, 0])
    if np.all(steps > 0):
        return True  # an accelerogram's component never rises on every line: an uneven time column
    step = np.median(steps)
    if not step > 0:
        return False
    return np.mean(np.abs(steps - step) <= TIME_STEP_TOLERANCE * step) >= TIME_COLUMN_SHARE


def _time_step(t, line_numbers, path, dt, resample: bool) -> float:
    """The step of the time column ``t``: its own if it increases evenly (a ``dt`` given must agree), or,
    with ``resample``, the step it is resampled onto (the ``dt`` given, else its median step).  Otherwise
    :class:`RecordError` naming the line: a time that does not increase, the largest gap of an uneven
    column, a ``dt`` given that disagrees."""
    if len(t) < 2:
        raise RecordError(f"{path}:{line_numbers[0]}: a time column needs at least 2 lines")
    steps = np.diff(t)
    back = np.flatnonzero(steps <= 0)
    if back.size:
        k = back[0] + 1
        raise RecordError(f"{path}:{line_numbers[k]}: time {t[k]:.6g} s does not come after {t[k - 1]:.6g} s "
                          f"on line {line_numbers[k - 1]}: the time column must increase strictly")
    step = check_dt(float(np.median(steps)), str(path), "the time column's step")
    off = np.abs(steps - step) > TIME_STEP_TOLERANCE * step
    if resample:
        return step if dt is None else dt
    if off.any():
        k = int(np.argmax(steps)) + 1 if off[np.argmax(steps)] else int(np.argmin(steps)) + 1
        what = "the largest gap" if steps[k - 1] > step else "the shortest step"
        onto = step if dt is None else dt
        raise RecordError(f"{path}:{line_numbers[k]}: time step {steps[k - 1]:.6g} s from {t[k - 1]:.6g} s "
                          f"(line {line_numbers[k - 1]}) to {t[k]:.6g} s, {what} of an uneven time column (median "
                          f"step {step:.6g} s; {int(off.sum())} of {len(steps)} steps differ from it): give "
                          f"resample = true (resample=True) to interpolate the record linearly onto a uniform "
                          f"{onto:.6g} s step")
    if dt is not None and abs(dt - step) > TIME_STEP_TOLERANCE * step:
        raise RecordError(f"{path}: dt={dt:g} was given but the time column steps by {step:.6g} s (lines "
                          f"{line_numbers[0]} to {line_numbers[-1]}, from {t[0]:.6g} s): leave dt out to use the "
                          f"time column, or give resample = true (resample=True) to interpolate the record "
                          f"onto dt")
    return step


def _uneven(t, step) -> bool:
    """Whether some step of the times ``t`` differs from ``step`` by more than :data:`TIME_STEP_TOLERANCE`."""
    return bool(np.any(np.abs(np.diff(t) - step) > TIME_STEP_TOLERANCE * step))


def _resampled(a, t, step, path) -> np.ndarray:
    """``a`` given at the times ``t``, interpolated linearly at ``t[0] + k * step`` up to ``t[-1]``."""
    n = int(np.floor((t[-1] - t[0]) / step + 1e-9)) + 1
    if n < 2:
        raise RecordError(f"{path}: the time column spans {t[-1] - t[0]:.6g} s, less than one {step:.6g} s step "
                          f"to resample onto")
    if n > MAX_RESAMPLED:
        raise RecordError(f"{path}: resampling {t[-1] - t[0]:.6g} s of record onto a {step:.6g} s step would make "
                          f"{n} samples (at most {MAX_RESAMPLED}): is the step right?")
    return np.interp(t[0] + np.arange(n) * step, t, a)


def _read_lines(path: Path) -> list:
    with file_errors(path, RecordError, "record file", hint=lambda: _bundled_hint(str(path))):
        with open(path, encoding="utf-8", errors="strict", newline=None) as fh:
            return fh.read().splitlines()


def _number(token: str, path, lineno: int) -> float:
    try:
        value = float(token)
    except ValueError:
        raise RecordError(f"{path}:{lineno}: cannot read {token!r} as a number") from None
    if not np.isfinite(value):
        raise RecordError(f"{path}:{lineno}: value {token!r} is not finite")
    return value
