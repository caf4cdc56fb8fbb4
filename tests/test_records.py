"""Record readers: the bundled accelerograms as documented, and errors that name file and line."""

import math

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


# --- time columns, given dt and spikes (issue 21) ---------------------------------------------------------

JITTER = "0 0.1\n0.01 0.2\n0.03 -0.1\n0.04 0.05\n0.05 0.0\n"  # times 0, .01, .03, .04, .05: one gap of 0.02 s
UNEVEN = (r"jitter\.txt:3: time step 0\.02 s from 0\.01 s \(line 2\) to 0\.03 s, "
          r"the largest gap of an uneven time column")


def test_an_uneven_time_column_with_a_dt_given_is_not_read_as_accelerations(tmp_path):
    """With dt = 0.01 given, a two-column file whose first column is an uneven time column is refused naming
    its largest gap and its line (it was read as accelerations: the last time became the PGA); a file whose time
    column agrees with the dt given loads with its own accelerations."""
    path = tmp_path / "jitter.txt"
    path.write_text(JITTER)
    with pytest.raises(RecordError, match=UNEVEN + r" .*give resample = true"):
        excitation.record(path, dt=0.01)
    even = tmp_path / "even.txt"
    even.write_text(JITTER.replace("0.03 -0.1", "0.02 -0.1").replace("0.04 0.05", "0.03 0.05")
                    .replace("0.05 0.0", "0.04 0.0"))
    h = excitation.record(even, dt=0.01, baseline=False).horizontal
    np.testing.assert_allclose(h.samples, [0.1, 0.2, -0.1, 0.05, 0.0])
    assert h.dt == pytest.approx(0.01)


def test_an_uneven_time_column_without_dt_is_named_as_a_time_column(tmp_path):
    """Without dt, a file whose times go 0, .01, .03, .04, .05 is refused for its uneven time column, naming
    the gap and its line, not for having "no time column"."""
    path = tmp_path / "jitter.txt"
    path.write_text(JITTER)
    with pytest.raises(RecordError, match=UNEVEN + r" \(median step 0\.01 s; 1 of 4 steps differ from it\)"):
        excitation.record(path)


def test_an_uneven_time_column_is_resampled_when_asked(tmp_path):
    """resample=True interpolates the record linearly onto a uniform step from its first time: the time
    column's median step, or the dt given."""
    path = tmp_path / "jitter.txt"
    path.write_text(JITTER)
    h = excitation.record(path, resample=True, baseline=False).horizontal
    assert h.dt == pytest.approx(0.01)
    np.testing.assert_allclose(h.samples, [0.1, 0.2, 0.05, -0.1, 0.05, 0.0], atol=1e-12)
    coarse = excitation.record(path, resample=True, dt=0.025, baseline=False).horizontal
    assert coarse.dt == 0.025
    np.testing.assert_allclose(coarse.samples, [0.1, 0.2 - 0.75 * 0.3, 0.0], atol=1e-12)  # t = 0.025 s: 3/4 of the way


def test_a_dt_that_disagrees_with_a_header_or_a_bundled_record_is_refused(tmp_path):
    """A dt given for an AT2 file or a bundled record must agree with the step they state (it was ignored);
    one that agrees is fine."""
    path = tmp_path / "x.AT2"
    path.write_text("HEAD\nEVENT\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    3, DT=   .0200 SEC\n .1 .2\n -.1\n")
    with pytest.raises(RecordError, match=r"x\.AT2: dt=0\.01 was given but the file's header says DT=0\.02 s"):
        excitation.record(path, dt=0.01)
    assert excitation.record(path, dt=0.02).horizontal.dt == 0.02
    with pytest.raises(RecordError, match=r"el_centro_1940: dt=0\.02 was given but the bundled record is sampled "
                                          r"every 0\.01 s"):
        excitation.record("el_centro_1940", dt=0.02)
    assert excitation.record("el_centro_1940", dt=0.01).horizontal.dt == 0.01


def test_a_single_spike_is_refused_naming_its_line_time_and_value(tmp_path):
    """A sample a thousand times the record's median and a hundred times its 99th percentile is refused naming
    the file, its line, its time and its value (a file, in its units) or its index (an array); a record with a
    long quiet stretch before a strong burst is not a spike."""
    lines = [f"{0.01 * k:.2f} {0.1 * math.sin(k / 5):.4f}" for k in range(500)]
    lines[200] = "2.00 1000.0"
    path = tmp_path / "spike.txt"
    path.write_text("# t a\n" + "\n".join(lines) + "\n")
    with pytest.raises(RecordError, match=r"spike\.txt:202: a spike at t = 2 s: 1000 g, .* times the median \|a\|"):
        excitation.record(path, units="g")
    a = 0.1 * np.sin(np.arange(500) / 5.0)
    a[123] = 1e6
    with pytest.raises(RecordError, match=r"array record: sample 123: a spike at t = 1\.23 s: 1e\+06 m/s\^2"):
        excitation.record(a, dt=0.01)
    quiet_then_burst = np.concatenate([1e-6 * np.sin(np.arange(5000)), 3.0 * np.sin(np.arange(200) / 3.0)])
    assert records.find_spike(quiet_then_burst) is None
    assert records.find_spike(a) == 123
