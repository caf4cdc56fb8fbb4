"""Record suites: a set of ground motions with what is known of each (source, magnitude, distance, site), read from
a folder of record files and its optional metadata table, or bundled with the package.

A suite folder holds record files (``.at2``, ``.txt``, ``.dat``, ``.csv``) and, optionally, :data:`METADATA`, a CSV
table with a header row and one row per record.  Its columns (:data:`COLUMNS`; only ``file`` is required):

- ``file``: the record's file in the folder, or the name of a record bundled with the package;
- ``name``: the record's name in the suite (default the file's stem);
- ``dt`` (s), ``units`` (``g``, ``m/s^2``, ``cm/s^2``) and ``component`` (1-based): how to read a text file, as
  :func:`dem_core.inputs.excitation.record` takes them (an AT2 file states its own step and units);
- ``magnitude``, ``distance_km``, ``vs30`` (m/s), ``pulse_period`` (s): the earthquake, the site and a near-fault
  pulse's period, where known;
- ``source``: where the record comes from, in words.

With a metadata table, its rows are the suite in their order, and the folder's other files are left out, named in
:attr:`RecordSuite.ignored` (``dem-core records`` lists them); without one, every record file of the folder is in
the suite, by name.  Every record is read when the suite is: a record that cannot be read is an error naming the
record and, where it comes from the table, the table's line.
"""

import csv
import dataclasses
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd

from . import records
from .excitation import GroundMotion, record, strong_motion
from .text_files import did_you_mean, file_errors

#: the metadata table of a suite folder
METADATA = "records.csv"
#: the file suffixes read as records (any case)
RECORD_SUFFIXES = (".at2", ".txt", ".dat", ".csv")
#: the metadata table's columns and how each is read
COLUMNS = {"file": str, "name": str, "dt": float, "units": str, "component": int, "magnitude": float,
           "distance_km": float, "vs30": float, "pulse_period": float, "source": str}
#: the suites bundled with the package (folders under dem_core/data/suites) and what each is
BUNDLED_SUITES = {"demonstration": "40 motions for studies of Greek monuments: the 4 bundled records, 28 stochastic "
                                   "motions of 7 scenarios and 8 near-fault motions with velocity pulses"}
DEFAULT_SUITE = "demonstration"


class SuiteError(ValueError):
    """A suite that cannot be read; the message names the folder, the table's line or the record."""


@dataclass(frozen=True, eq=False)
class SuiteRecord:
    """One motion of a suite and what is known of it (nan where unknown)."""

    name: str
    motion: GroundMotion
    file: str
    source: str = ""
    #: where its sampling interval comes from, in words
    sampling: str = ""
    magnitude: float = math.nan
    distance_km: float = math.nan
    vs30: float = math.nan
    pulse_period: float = math.nan


@dataclass(frozen=True, eq=False)
class RecordSuite:
    """A named, ordered set of :class:`SuiteRecord`."""

    name: str
    records: tuple
    #: the folder's record files its metadata table does not name, left out of the suite
    ignored: tuple = ()

    def __len__(self) -> int:
        return len(self.records)

    def motions(self) -> dict:
        """``{name: GroundMotion}`` in the suite's order, as :func:`~dem_core.analyses.fragility_study.
        fragility_study` takes them."""
        return {entry.name: entry.motion for entry in self.records}

    def table(self) -> pd.DataFrame:
        """One row per record: its name, file, PGA (m/s^2), length and sampling interval (s), strong motion (5-95%
        of its Arias intensity, s), the metadata and the source."""
        rows = []
        for entry in self.records:
            horizontal = entry.motion.horizontal
            start, end = strong_motion(horizontal) or (math.nan, math.nan)
            rows.append({"name": entry.name, "file": entry.file, "pga_m_s2": horizontal.peak_acceleration,
                         "length_s": horizontal.end_time, "dt_s": getattr(horizontal, "dt", math.nan),
                         "strong_start_s": start, "strong_end_s": end, "magnitude": entry.magnitude,
                         "distance_km": entry.distance_km, "vs30": entry.vs30, "pulse_period_s": entry.pulse_period,
                         "source": entry.source})
        return pd.DataFrame(rows)


def suite_folder(name: str) -> Path:
    """The folder of a bundled suite, by its key in :data:`BUNDLED_SUITES`."""
    if name not in BUNDLED_SUITES:
        raise SuiteError(f"no bundled suite named {name!r} (bundled suites: {', '.join(BUNDLED_SUITES)})")
    return Path(str(resources.files("dem_core") / "data" / "suites" / name))


def load_suite(source=DEFAULT_SUITE, units: str = "m/s^2") -> RecordSuite:
    """A bundled suite by name (:data:`BUNDLED_SUITES`), or the suite of a folder (:func:`read_suite`)."""
    if isinstance(source, str) and source in BUNDLED_SUITES and not Path(source).exists():
        return read_suite(suite_folder(source), units, name=source)
    return read_suite(source, units)


def read_suite(folder, units: str = "m/s^2", name: str | None = None) -> RecordSuite:
    """The suite of ``folder``: its :data:`METADATA` table's rows, or without one its record files.  ``units`` are those
    of text files the table gives none for.  :class:`SuiteError` naming the culprit for a folder that is missing or
    holds no record, a table line that cannot be read or names a missing file, a record that cannot be read (a
    text file without a time column needs its ``dt`` in the table), or two records of one name."""
    folder = Path(folder)
    if not folder.is_dir():
        raise SuiteError(f"{folder}: not a folder{'; bundled suites: ' + ', '.join(BUNDLED_SUITES)}")
    files = sorted(p.name for p in folder.iterdir()
                   if p.is_file() and p.suffix.lower() in RECORD_SUFFIXES and p.name != METADATA)
    table = folder / METADATA
    rows = _metadata(table, folder, files) if table.is_file() else [({"file": file}, None) for file in files]
    named = {row["file"] for row, _ in rows}
    if not rows:
        raise SuiteError(f"{folder}: no record in it: a suite folder holds record files ({', '.join(RECORD_SUFFIXES)})"
                         f" and optionally {METADATA}")
    entries, where = [], {}
    for row, line in rows:
        at = f"{folder / METADATA}:{line}" if line else str(folder / row["file"])
        entry = _entry(folder, row, units, at)
        if entry.name in where:
            raise SuiteError(f"{at}: a second record named {entry.name!r} (the first: {where[entry.name]}); give "
                             f"each its own name")
        where[entry.name] = at
        entries.append(entry)
    return RecordSuite(name or folder.name, tuple(entries), tuple(file for file in files if file not in named))


def _metadata(path: Path, folder: Path, files: list) -> list:
    """``[(row, line)]`` of a metadata table, each row {column: value} with the columns it fills."""
    with file_errors(path, SuiteError, "metadata table"), open(path, encoding="utf-8-sig", newline="") as handle:
        lines = list(csv.reader(handle))
    header = [cell.strip() for cell in lines[0]] if lines else []
    unknown = [column for column in header if column not in COLUMNS]
    twice = [column for column in COLUMNS if header.count(column) > 1]
    if unknown or twice or "file" not in header:
        why = (f"unknown column {unknown[0]!r}{did_you_mean(unknown[0], COLUMNS)}" if unknown else
               f"the column {twice[0]!r} twice" if twice else "no 'file' column")
        raise SuiteError(f"{path}:1: {why}; the columns are {', '.join(COLUMNS)} (only file is required)")
    rows = []
    for line, cells in enumerate(lines[1:], start=2):
        if not any(cell.strip() for cell in cells):
            continue
        if len(cells) > len(header):
            raise SuiteError(f"{path}:{line}: {len(cells)} cells, the header has {len(header)} columns")
        row = {}
        for column, cell in zip(header, cells):
            if cell.strip():
                row[column] = _cell(cell.strip(), column, f"{path}:{line}")
        if "file" not in row:
            raise SuiteError(f"{path}:{line}: no file given")
        if not (folder / row["file"]).is_file() and row["file"] not in records.BUNDLED:
            raise SuiteError(f"{path}:{line}: names {row['file']!r}, which is neither a file in {folder} nor a "
                             f"bundled record{did_you_mean(row['file'], files + list(records.BUNDLED))}")
        rows.append((row, line))
    return rows


def _cell(text: str, column: str, where: str):
    kind = COLUMNS[column]
    if kind is str:
        return text
    try:
        value = kind(text)
    except ValueError:
        raise SuiteError(f"{where}: {column} {text!r} is not {'a whole number' if kind is int else 'a number'}") \
            from None
    if not math.isfinite(value):
        raise SuiteError(f"{where}: {column} {text!r} is not finite")
    return value


def _entry(folder: Path, row: dict, units: str, where: str) -> SuiteRecord:
    """The :class:`SuiteRecord` of a metadata row (or of a file without one)."""
    file = row["file"]
    source = str(folder / file) if (folder / file).is_file() else file
    try:
        motion = record(source, dt=row.get("dt"), units=row.get("units", units), component=row.get("component"))
    except records.NoSamplingInterval:
        raise SuiteError(f"{where}: {file} has no time column and no sampling interval: give it in {METADATA}'s "
                         f"dt column") from None
    except (OSError, ValueError) as exc:  # the record's own error names its file, and its line where it has one
        said = str(exc)
        raise SuiteError(said if said.startswith(where) else f"{where}: {said}") from None
    known = {key: float(row[key]) for key in ("magnitude", "distance_km", "vs30", "pulse_period") if key in row}
    name = row.get("name", Path(file).stem)
    return SuiteRecord(name, dataclasses.replace(motion, name=name), file, row.get("source", ""),
                       _sampling(file, source, "dt" in row, motion.horizontal.dt), **known)


def _sampling(file: str, source: str, in_table: bool, dt: float) -> str:
    """Where a suite record's sampling interval comes from, in words."""
    if file in records.BUNDLED and source == file:
        return records.sampling_source(records.BUNDLED[file], dt)
    if file.lower().endswith(".at2"):
        return "stated in the file's header"
    return f"given in {METADATA}" if in_table else "from its time column"


def write_suite(entries, folder, fmt: str = "%.5g") -> Path:
    """Write ``entries`` (:class:`SuiteRecord`) into ``folder`` as a suite :func:`read_suite` reads back, and return
    the path of its :data:`METADATA` table.  An entry whose ``file`` is a bundled record's name is a row naming it
    (its motion is that record as bundled); any other is its horizontal component's samples (a sampled motion) as
    the one-column text file ``<name>.txt`` in m/s^2, ``fmt`` each, with its sampling interval in the table."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with open(folder / METADATA, "w", encoding="utf-8", newline="") as handle:
        table = csv.writer(handle, lineterminator="\n")
        table.writerow(COLUMNS)
        for entry in entries:
            known = [("" if math.isnan(value) else f"{value:g}") for value in
                     (entry.magnitude, entry.distance_km, entry.vs30, entry.pulse_period)]
            if entry.file in records.BUNDLED:
                table.writerow([entry.file, entry.name, "", "", "", *known, entry.source])
                continue
            horizontal = entry.motion.horizontal
            file = f"{entry.name}.txt"
            np.savetxt(folder / file, horizontal.samples, fmt=fmt,
                       header=f"{entry.name}: accelerations in m/s^2 every {horizontal.dt:g} s; {entry.source}")
            table.writerow([file, entry.name, f"{horizontal.dt:g}", "m/s^2", 1, *known, entry.source])
    return folder / METADATA
