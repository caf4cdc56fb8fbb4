"""Record suites (dem_core.inputs.suites): a folder and its metadata table, the bundled demonstration suite, and
the errors that name what cannot be read."""

import re
import runpy
import sys

import numpy as np
import pytest

from dem_core.inputs import records
from dem_core.inputs.excitation import record
from dem_core.inputs.suites import (
    BUNDLED_SUITES,
    METADATA,
    SuiteError,
    SuiteRecord,
    load_suite,
    read_suite,
    suite_folder,
    write_suite,
)
from dem_core.inputs.synthetic import Scenario, stochastic_motion


def _folder(tmp_path, table: str | None = None):
    """A suite folder with two records with time columns (north, south) and one without (bare, every 0.02 s)."""
    folder = tmp_path / "suite"
    folder.mkdir()
    t = np.arange(0.0, 2.0, 0.01)
    for name, frequency in (("north", 2.0), ("south", 3.0)):
        np.savetxt(folder / f"{name}.txt", np.column_stack([t, np.sin(2 * np.pi * frequency * t)]))
    np.savetxt(folder / "bare.dat", 0.5 * np.sin(2 * np.pi * np.arange(100) * 0.02))
    (folder / "notes.md").write_text("not a record")
    if table is not None:
        (folder / METADATA).write_text(table)
    return folder


def test_a_folders_table_gives_the_order_names_units_and_metadata(tmp_path):
    folder = _folder(tmp_path, "file,name,units,dt,magnitude,distance_km,source\n"
                               "south.txt,Southern,g,,6.5,12,a station\n"
                               "bare.dat,Bare,m/s^2,0.02,,,\n")
    suite = read_suite(folder)
    assert [entry.name for entry in suite.records] == ["Southern", "Bare"] and suite.ignored == ("north.txt",)
    south, bare = suite.records
    in_g = record(folder / "south.txt", units="g").horizontal.peak_acceleration
    assert south.motion.horizontal.peak_acceleration == in_g == pytest.approx(
        record(folder / "south.txt").horizontal.peak_acceleration * records.G_STANDARD)
    assert (south.magnitude, south.distance_km, south.source) == (6.5, 12.0, "a station")
    assert np.isnan(south.vs30) and bare.sampling == f"given in {METADATA}" and bare.motion.horizontal.dt == 0.02
    assert south.sampling == "from its time column"
    table = suite.table()
    assert list(table["name"]) == ["Southern", "Bare"] and table.loc[0, "magnitude"] == 6.5
    assert list(suite.motions()) == ["Southern", "Bare"]


def test_without_a_table_every_record_file_is_in_the_suite_by_name(tmp_path):
    folder = _folder(tmp_path, "file\n")
    (folder / METADATA).unlink()
    np.savetxt(folder / "bare.dat", np.column_stack([np.arange(100) * 0.02, np.zeros(100) + 0.1]))
    suite = read_suite(folder)
    assert [entry.name for entry in suite.records] == ["bare", "north", "south"] and suite.ignored == ()
    assert suite.records[1].sampling == "from its time column" and suite.records[1].source == ""


def test_a_record_without_a_sampling_interval_is_named_with_where_to_give_it(tmp_path):
    with pytest.raises(SuiteError) as refused:
        read_suite(_folder(tmp_path))
    assert str(refused.value) == (f"{tmp_path / 'suite' / 'bare.dat'}: bare.dat has no time column and no sampling "
                                  f"interval: give it in records.csv's dt column")


def test_a_table_naming_a_missing_file_is_refused_naming_its_line(tmp_path):
    folder = _folder(tmp_path, "file,dt\nbare.dat,0.02\nnorht.txt,\n")
    with pytest.raises(SuiteError, match=r"records\.csv:3: names 'norht\.txt', which is neither a file in .* nor a "
                                         r"bundled record \(did you mean 'north\.txt'\?\)"):
        read_suite(folder)


@pytest.mark.parametrize(("table", "said"), [
    ("file,magnitud\nnorth.txt,6\n", r"records\.csv:1: unknown column 'magnitud' \(did you mean 'magnitude'\?\)"),
    ("name\nnorth\n", r"records\.csv:1: no 'file' column"),
    ("file,dt\nbare.dat,fast\n", r"records\.csv:2: dt 'fast' is not a number"),
    ("file,dt\nbare.dat,0.02,3\n", r"records\.csv:2: 3 cells, the header has 2 columns"),
    ("file,name,dt\nbare.dat,north,0.02\nnorth.txt,,\n", r"records\.csv:3: a second record named 'north'"),
    ("file,dt,dt\nbare.dat,0.02,0.01\n", r"records\.csv:1: the column 'dt' twice"),
])
def test_a_table_that_cannot_be_read_is_refused_naming_its_line(tmp_path, table, said):
    with pytest.raises(SuiteError, match=said):
        read_suite(_folder(tmp_path, table))


def test_an_empty_or_missing_folder_is_refused_naming_it(tmp_path):
    (tmp_path / "empty").mkdir()
    (tmp_path / "empty" / "readme.md").write_text("no records here")
    with pytest.raises(SuiteError, match=r"empty: no record in it"):
        read_suite(tmp_path / "empty")
    with pytest.raises(SuiteError, match=r"nowhere: not a folder; bundled suites: demonstration"):
        load_suite(str(tmp_path / "nowhere"))


def test_a_table_saved_with_a_byte_order_mark_is_read(tmp_path):
    folder = _folder(tmp_path)
    (folder / METADATA).write_text("file,dt\nbare.dat,0.02\n", encoding="utf-8-sig")
    assert [entry.name for entry in read_suite(folder).records] == ["bare"]


def test_a_written_suite_reads_back_with_its_metadata(tmp_path):
    scenario = Scenario(6.0, 10.0, 760.0, "NS")
    motion = stochastic_motion(scenario, 5)
    written = [SuiteRecord("one", motion, "one.txt", "synthetic", magnitude=6.0, distance_km=10.0, vs30=760.0),
               SuiteRecord("el_centro_1940", load_suite().records[0].motion, "el_centro_1940", "recorded")]
    read = read_suite(write_suite(written, tmp_path / "out").parent)
    one, el_centro = read.records
    np.testing.assert_allclose(one.motion.horizontal.samples, motion.horizontal.samples, rtol=1e-4,
                               atol=1e-4 * motion.horizontal.peak_acceleration)
    assert (one.magnitude, one.distance_km, one.vs30, one.source) == (6.0, 10.0, 760.0, "synthetic")
    assert el_centro.file == "el_centro_1940" and not (tmp_path / "out" / "el_centro_1940.txt").exists()
    assert el_centro.sampling == "stated in the file's header"


def test_the_demonstration_suite_is_what_its_description_says():
    """The bundled suite's description counts its motions: the total, the bundled records, the stochastic and the
    near-fault ones; every motion states its source."""
    suite = load_suite("demonstration")
    counts = {what: int(number) for number, what in
              re.findall(r"(\d+) (motions|bundled records|stochastic|near-fault)", BUNDLED_SUITES["demonstration"])}
    assert counts["motions"] == len(suite) >= 30
    sources = [entry.source for entry in suite.records]
    assert sum(source.startswith("recorded") for source in sources) == counts["bundled records"] == len(
        records.BUNDLED)
    assert sum(source.startswith("synthetic, stochastic") for source in sources) == counts["stochastic"]
    assert sum(source.startswith("synthetic, near-fault") for source in sources) == counts["near-fault"]
    assert all(np.isfinite(entry.magnitude) for entry in suite.records)


def test_the_demonstration_suite_is_made_again_by_its_script(tmp_path, monkeypatch):
    """The synthetic motions' provenance: examples/suites/demonstration.py writes the bundled files again, byte
    for byte, with the pinned numpy and pygmm."""
    monkeypatch.setattr(sys, "argv", ["demonstration.py", str(tmp_path)])
    runpy.run_path("examples/suites/demonstration.py", run_name="__main__")
    bundled = suite_folder("demonstration")
    for path in sorted(bundled.iterdir()):
        assert (tmp_path / path.name).read_bytes() == path.read_bytes(), path.name
