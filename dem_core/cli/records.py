"""``dem-core records``: the bundled accelerograms, with where each one's sampling interval comes from."""

import math
import re

from ..inputs import records
from ..inputs.excitation import record
from .console import acceleration_text


def add(sub):
    sub.add_parser("records", help="list the bundled accelerograms: PGA, length, sampling interval and where it "
                   "comes from")


def run(args=None) -> int:
    for name, entry in records.BUNDLED.items():
        horizontal = record(name).horizontal
        what = re.sub(r"\s*\(PGA [^)]*\)", "", entry.description)
        print(f"{name:18s} PGA {acceleration_text(horizontal.peak_acceleration)}, {horizontal.end_time:.4g} s "
              f"every {horizontal.dt:.3g} s ({_sampling_source(entry, horizontal.dt)}): {what}")
    return 0


def _sampling_source(entry, dt: float) -> str:
    """Where a bundled record's sampling interval comes from, in words: the AT2 header, the time column, or (for a
    file without either) dem_core's table of bundled records, with the interval the file's name gives if other."""
    if entry.dt is None:
        return "stated in the file's header" if entry.file.lower().endswith(".at2") else "from its time column"
    named = re.search(r"dt[_=]?(\d+(?:\.\d+)?)", entry.file, re.IGNORECASE)
    other = (f"; the file's name says {float(named.group(1)):g} s" if named and
             not math.isclose(float(named.group(1)), dt, rel_tol=1e-6) else "")
    return (f"not stated in the file, which has no time column: dem_core's reading{other}, see "
            f"dem_core/data/records/SOURCES.md")
