"""What a notebook shows of a run: ``repr(Result)`` in one line, ``_repr_html_`` a table of its facts and its
blocks' measures."""

from dem_core import excitation, scenes, simulate


def test_a_result_reads_in_one_line_and_as_a_notebooks_table():
    result = simulate(scenes.column(4), excitation.record("el_centro_1940", pga=3.0), duration=2.0)
    line = repr(result)
    assert len(line) < 300 and "\n" not in line and "peak |theta|/alpha" in line and "standing" in line
    page = result._repr_html_()
    assert page.startswith("<table>") and "moreau" in page and "drum4" in page
