"""Record readers: the bundled accelerograms as documented, and errors that name file and line."""

import numpy as np
import pytest

from dem_core import excitation, records
from dem_core.inputs.records import G_STANDARD, RecordError

# SOURCES.md: npts, dt (s), PGA in m/s^2
DOCUMENTED = {
    "el_centro_1940": (5372, 0.01, 0.2808 * G_STANDARD),
    "mexico_city_1985": (8171, 0.02, 0.1712 * G_STANDARD),
    "northridge_1994": (3000, 0.02, 8.268),
    "kalamata_1986": (2590, 0.01, 2.911),  # the file says 0.02 s; read at 0.01 s (SOURCES.md)
}


@pytest.mark.parametrize("name", DOCUMENTED)
def test_bundled_records_match_their_documentation(name):
    npts, dt, pga = DOCUMENTED[name]
    m = excitation.record(name, baseline=False)
    h = m.horizontal
    assert h.dt == pytest.approx(dt)
    assert len(h.samples) in (npts, npts + 1)  # a record starting at t = dt gains the still ground at t = 0
    assert h.peak_acceleration == pytest.approx(pga, rel=2e-3)


def test_at2_header_gives_units_and_step(tmp_path):
    f = tmp_path / "x.AT2"
    f.write_text("HEAD\nEVENT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    3, DT=   .0200 SEC\n .1 .2\n -.1\n")
    a, dt = records.read_at2(f)
    assert dt == 0.02
    np.testing.assert_allclose(a, np.array([0.1, 0.2, -0.1]) * G_STANDARD)


def test_malformed_at2_value_names_file_and_line(tmp_path):
    f = tmp_path / "bad.AT2"
    f.write_text("HEAD\nEVENT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    3, DT=   .0200 SEC\n .1 .2\n -.1x\n")
    with pytest.raises(RecordError, match=r"bad\.AT2:6: cannot read '-\.1x'"):
        records.read_at2(f)


def test_at2_point_count_mismatch(tmp_path):
    f = tmp_path / "short.AT2"
    f.write_text("HEAD\nEVENT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT=   .0200 SEC\n .1 .2\n")
    with pytest.raises(RecordError, match="NPTS=4 but the file holds 2"):
        records.read_at2(f)


def test_column_text_with_time_and_components(tmp_path):
    f = tmp_path / "rec.txt"
    f.write_text("# t ns ew\n0.02 0.1 0.2\n0.04 0.3 0.4\n0.06 0.5 0.6\n")
    m = excitation.record(f, units="g", component=2, baseline=False)
    assert m.horizontal.dt == pytest.approx(0.02)
    # the first sample is at t = 0.02: the ground is still at t = 0
    np.testing.assert_allclose(m.horizontal.samples, np.array([0.0, 0.2, 0.4, 0.6]) * G_STANDARD)


def test_one_column_text_needs_dt(tmp_path):
    f = tmp_path / "one.txt"
    f.write_text("0.1\r\n0.2\r\n0.3\r\n")
    with pytest.raises(RecordError, match="give dt"):
        excitation.record(f)
    assert len(excitation.record(f, dt=0.01, baseline=False).horizontal.samples) == 3


@pytest.mark.parametrize("content, message", [
    ("0.0 1.0\n0.01 2.0\n0.02 x\n", r"rec\.txt:3: cannot read 'x'"),
    ("0.0 1.0\n0.01 2.0\n0.02\n", r"rec\.txt:3: expected 2 columns"),
    ("0.0 1.0\n0.01 2.0\n0.025 3.0\n0.035 1.0\n", r"rec\.txt:3: time step"),
    ("0.0 1.0\n0.01 nan\n0.02 1.0\n", r"rec\.txt:2: value 'nan' is not finite"),
    ("", "no data lines"),
])
def test_malformed_text_records_name_file_and_line(tmp_path, content, message):
    f = tmp_path / "rec.txt"
    f.write_text(content)
    with pytest.raises(RecordError, match=message):
        records.read_text_record(f, time_column=True)


def test_missing_component_and_unknown_units(tmp_path):
    f = tmp_path / "rec.txt"
    f.write_text("0.0 1.0\n0.01 2.0\n0.02 3.0\n")
    with pytest.raises(RecordError, match="component 3"):
        excitation.record(f, component=3)
    with pytest.raises(RecordError, match="unknown units"):
        excitation.record(f, units="furlongs")


def test_missing_file_is_named(tmp_path):
    with pytest.raises(RecordError, match="no such record file"):
        excitation.record(tmp_path / "nope.txt", dt=0.01)
