"""The comparison report: verdicts, ensembles, overturning spectra, cases and the stability map, as HTML.

``python -m comparisons report [--quick] [--out reports]`` runs the harness
(:mod:`comparisons.harness.case_runs`), the ensembles (:mod:`comparisons.harness.ensembles`), the 8-drum column's
ensemble (:mod:`comparisons.harness.column_ensemble`, shown with the column's case), the overturning spectra
(:mod:`comparisons.harness.overturning_spectra`) and the stability stress tests (:mod:`comparisons.harness.stress`),
then writes into the output folder the tidy tables (``scoreboard.csv``, ``results.csv``, ``ensembles.csv``,
``column_ensemble.csv``, ``spectra.csv``, ``stability.csv``), one PNG per figure (:mod:`comparisons.report.figures`, each checked for
cut text), ``digest.json`` (the digest of the sources the numbers come from,
:func:`comparisons.report.provenance.source_digest`) and ``index.html``, which opens with a line of provenance (the
commit and the digest) and a scoreboard per engine (:mod:`comparisons.report.scoreboard`), heads its tables in plain
words and explains its terms in a glossary (:mod:`comparisons.report.glossary`).
"""

import html
import os
import time
from pathlib import Path

import numpy as np
import pandas as pd

from comparisons.cases.case import ENGINES, REFERENCE_KINDS, exact_floor
from comparisons.cases.catalogue import all_cases
from comparisons.harness import column_ensemble, consensus, ensembles, overturning_spectra
from comparisons.harness.stress import WRONG
from comparisons.report import figures, verdicts
from comparisons.report.glossary import HEADERS, METRICS, glossary
from comparisons.report.provenance import DIGEST_FILE, REPOSITORY, provenance, source_digest, write_digest
from comparisons.report.scoreboard import scoreboard, usual_steps

STUDIES = REPOSITORY / "reports" / "studies"
ENSEMBLE_SHARES = ("median_error", "p90_error", "overturn_agreement")
#: how the native core's runs of an ensemble or a spectrum were made and timed (engines.simulate_members)
BATCHED_RUNS = ("The native core's runs go in batches over the CPU's threads (dem_core.simulate_batch), each the run "
                "it gives alone, bit for bit; a run's time is its own time loop, taken while other runs share the "
                "machine.")
STYLE = """body{font-family:sans-serif;max-width:1150px;margin:1em auto;padding:0 1em;color:#222;line-height:1.4}
h1{margin:0.2em 0 0.1em;font-size:1.7em}
p.prov{font-size:13px;color:#444;margin:0 0 0.6em}
table.score{border-collapse:collapse;font-size:15px;margin:0.3em 0}
table.score th,table.score td{border-bottom:1px solid #ddd;padding:4px 12px;white-space:nowrap}
table.score th{background:#f0f0f0;text-align:right;font-weight:600}table.score th:first-child{text-align:left}
table.score td{text-align:right;font-variant-numeric:tabular-nums}table.score td:first-child{text-align:left;
font-weight:600}
p.caption{font-size:12px;color:#555;margin:0.2em 0 1em;max-width:1100px}
table.matrix td.e{text-align:center;white-space:nowrap}table.matrix th{white-space:nowrap}
td.right{background:#e3f2e1}td.fastest{background:#bfe3bb;font-weight:bold}td.no{color:#a33}
td.none{color:#777;font-style:italic}
img{max-width:49%;vertical-align:top}
img.wide{max-width:100%}
table.t{border-collapse:collapse;font-size:12px;margin:0.5em 0}table.t td,table.t th{border:1px solid #ccc;
padding:2px 6px;vertical-align:top}table.t th{background:#f0f0f0;text-align:left}
.verdict{background:#f4f4f4;padding:0.5em}
.note{background:#fff4e0;padding:0.5em}dt{font-weight:bold;margin-top:0.4em}code{background:#f4f4f4}"""


def _table(frame: pd.DataFrame) -> str:
    """An HTML table with plain headers; numbers to 3 significant digits."""
    shown = frame.rename(columns={c: HEADERS.get(c, c.replace("_", " ")) for c in frame.columns})
    return shown.to_html(index=False, float_format=lambda v: f"{v:.3g}", na_rep="-", border=0, classes="t",
                         escape=True)


def _percent(frame: pd.DataFrame, columns) -> pd.DataFrame:
    """``columns`` of shares and relative errors written as percentages."""
    return frame.assign(**{c: [f"{100 * v:.3g}%" if np.isfinite(v) else "-" for v in frame[c]] for c in columns})


def _metric_names(frame: pd.DataFrame) -> pd.DataFrame:
    if "metric" in frame:
        frame = frame.assign(metric=[f"{m}: {METRICS.get(m, m)}" for m in frame.metric])
    return frame


def _img(src, alt, wide=False) -> str:
    return f'<img src="{html.escape(src)}" alt="{html.escape(alt)}"' + (' class="wide">' if wide else ">")


def _provenance_line(made, quick: bool, when: str) -> str:
    """The one line under the title: which run, when, the commit and the digest of the sources."""
    modified = (f" <b>with uncommitted changes to {len(made['modified'])} file(s)</b>" if made["modified"] else "")
    return (f'{"Quick" if quick else "Full"} run of {when} from commit <code>{html.escape(made["commit"])}</code>'
            f"{modified}; sources digest <code>{html.escape(made['digest'][:12])}</code> "
            f'(<a href="{DIGEST_FILE}">{DIGEST_FILE}</a>).')


def _provenance_html(made) -> str:
    versions = ", ".join(f"{k} {v}" for k, v in made["versions"].items())
    modified = (f" <b>with uncommitted changes to {html.escape(', '.join(made['modified']))}</b>"
                if made["modified"] else "")
    return (f"Made from commit <code>{html.escape(made['commit'])}</code> (branch {html.escape(made['branch'])})"
            f"{modified}, with Python {made['python']} and {html.escape(versions)}, on {made['machine']} "
            f"with {made['cores']} cores. The sources digest {made['digest'][:12]} covers the "
            f"{len(made['digest_files'])} files that decide the numbers (listed in {DIGEST_FILE}: the engine, its "
            "inputs, the adapters, the cases, the references and the harness); "
            "<code>pytest tests/test_report.py</code> fails when the committed report's digest is no longer that of "
            "the checkout.")


# --- cases ------------------------------------------------------------------------------------------

def _column_ensemble_html(column_table: pd.DataFrame, pairs: pd.DataFrame) -> str:
    """The 8-drum column's ensemble: each configuration's time, and each pair's typical member difference of the top
    drum's peak (``pairs``, :func:`~comparisons.harness.column_ensemble.summarise_pairs`; Moreau-Jean's step against
    its quarter first)."""
    members = len(column_table.drop_duplicates(["record", "scale"]))
    scales = ", ".join(f"{s:g}" for s in sorted(set(column_table.scale)))
    runs = column_ensemble.summarise_runs(column_table)
    shown = pairs.assign(**{c: [_percent_text(v, ".2g") for v in pairs[c]]
                            for c in ("typical_difference", "interval_low", "interval_high", "p90_difference")})
    shown = shown.assign(overturn_agreement=[_percent_text(v, ".3g") for v in pairs.overturn_agreement])
    text = (f"The same column under {members} record runs: the {len(set(column_table.record))} bundled records' "
            f"strong motion at {scales} times its rocking threshold g tan(alpha), {column_ensemble.DURATION:g} s "
            "each, every run in each configuration. A pair's typical difference is the median over the members "
            "that stand in both and rock in the second of |log(peak_a / peak_b)| of the top drum's peak rotation, "
            "with the 90% bootstrap interval of that median over members (the variability lives in the records "
            "and amplitudes). There is no exact answer here: the first row shows whether Moreau-Jean's step of "
            "1e-3 s has converged on what studies measure.")
    return (f'<section id="column_ensemble"><h3>8-drum column under the bundled records: Moreau-Jean\'s step '
            f'judged on {members} runs</h3><p>{html.escape(text)}</p>'
            f'<p class="verdict">{html.escape(_column_ensemble_line(pairs))}</p>{_table(shown)}{_table(runs)}'
            "</section>")


def _column_ensemble_line(pairs: pd.DataFrame) -> str:
    """One sentence: Moreau-Jean's 1e-3 s against its 2.5e-4 s on the column ensemble."""
    first = pairs.iloc[0]
    return (f"{first.run} against {first.against}: the top drum's peak differs by "
            f"{_percent_text(first.typical_difference)} typically (90% interval {_percent_text(first.interval_low)} "
            f"to {_percent_text(first.interval_high)}, {first.compared} runs compared); they agree on overturning in "
            f"{_percent_text(first.overturn_agreement, '.3g')} of the runs.")


def _case_section(table, case, out: Path, column_line: str) -> tuple[str, dict]:
    metric = verdicts.primary_metric(case, table)
    rows = table[(table.case == case.name) & (table.metric == metric) & (table.status == "ok")]
    pareto, convergence = f"pareto_{case.name}.png", f"convergence_{case.name}.png"
    figures.pareto_figure(rows[np.isfinite(rows.error)], case.name, metric, out / pareto, case_title=case.title)
    figures.convergence_figure(rows[np.isfinite(rows.error)], case.name, metric, out / convergence,
                               case_title=case.title)
    verdict = verdicts.case_verdict(table, case)
    summary = verdicts.case_summary(table, case)
    parts = [f'<section id="{case.name}"><h3>{html.escape(case.title)}</h3>',
             f'<p>Reference: {html.escape(REFERENCE_KINDS[case.reference_kind])}.</p>',
             f'<p class="verdict">{html.escape(verdict["text"])}</p>']
    if case.note:
        parts.append(f'<p class="note">{html.escape(case.note)}</p>')
    parts += [_img(pareto, f"error against run time for {case.name}"),
              _img(convergence, f"convergence in dt for {case.name}"), _table(_metric_names(summary))]
    if case.by_consensus:
        parts.append(_consensus_details(table, case))
    if case.name == "column_record" and column_line:
        parts.append(f'<p>The <a href="#column_ensemble">column ensemble</a>: {html.escape(column_line)}</p>')
    stopped = table[(table.case == case.name) & (table.status != "ok")][["engine", "step", "settings", "message"]]
    if len(stopped):
        parts.append(f"<h4>Runs the engine stopped</h4>{_table(stopped.drop_duplicates())}")
    return "".join(parts) + "</section>", verdict


def _consensus_details(table, case) -> str:
    rows = table[table.case == case.name]
    parts = ["<h4>The consensus: each engine's finest and next-finest answers</h4>"]
    for measure in ("peak_rotation", consensus.OVERTURNED):
        answers = consensus.finest_answers(rows.assign(metric=rows.metric.replace(consensus.OVERTURN,
                                                                                   consensus.OVERTURNED)), measure)
        if len(answers):
            parts.append(f"<p>{html.escape(METRICS.get(measure, measure))}:</p>{_table(answers)}")
    return "".join(parts)


# --- ensembles and spectra ----------------------------------------------------------------------------

def _ensemble_section(table, ens, out: Path) -> tuple[str, dict]:
    mine = table[table.ensemble == ens.name]
    summary = ensembles.summarise(mine)
    pareto, members = f"ensemble_{ens.name}.png", f"ensemble_members_{ens.name}.png"
    figures.ensemble_pareto_figure(summary, ens.name, out / pareto, overturning=ens.kind == "rocking",
                                   ensemble_title=f"{ens.kind.capitalize()} ensemble")
    figures.ensemble_members_figure(mine, ens.name, "alpha" if ens.kind == "rocking" else "mm", out / members)
    verdict = verdicts.ensemble_verdict(summary, overturning=ens.kind == "rocking")
    n = len(ens.members())
    text = (f"{n} runs per engine and step: {len(ens.blocks)} block(s) x {len(ens.records)} record(s) x "
            f"{len(ens.scales)} amplitudes; the reference overturns in {summary.reference_overturns.iloc[0]} "
            f"of them. {BATCHED_RUNS}" if len(summary) else "")
    section = (f'<section id="{ens.name}"><h3>{html.escape(ens.title)}</h3><p>{html.escape(text)}</p>'
               f'<p class="verdict">{html.escape(verdict["text"])}</p>'
               f'{_img(pareto, f"ensemble statistics against run time for {ens.name}", wide=True)}'
               f'{_img(members, f"peaks run by run at the usual steps for {ens.name}", wide=True)}'
               f'{_table(_percent(summary.drop(columns=["ensemble"]), ENSEMBLE_SHARES))}</section>')
    return section, verdict


def _spectrum_section(table, spec, out: Path) -> tuple[str, dict]:
    mine = table[table.spectrum == spec.name]
    summary = overturning_spectra.summarise(mine)
    image = f"{spec.name}.png"
    closed = overturning_spectra.closed_form_rectangular if spec.pulse == "rectangular" else None
    figures.spectrum_figure(mine, spec, closed, out / image)
    verdict = verdicts.spectrum_verdict(summary)
    extra = ""
    if closed is not None:
        first = mine.drop_duplicates("column")
        gap = np.array([t[0] / closed(c) - 1.0 for c, t in zip(first.column, first.transitions, strict=True)
                        if len(t)])
        extra = (f" The linearised closed form 1/(1 - exp(-p t_d)) is within {np.max(np.abs(gap)):.2%} of the "
                 "rocking equation's boundary at these columns." if len(gap) else "")
    section = (f'<section id="{spec.name}"><h3>{html.escape(spec.title)}</h3>'
               f'<p>Reference: the rocking equation with Housner\'s impact rule.{html.escape(extra)} '
               f'{html.escape(BATCHED_RUNS)}</p>'
               f'<p class="verdict">{html.escape(verdict["text"])}</p>'
               f'{_img(image, f"overturning spectrum {spec.name}, engine by engine", wide=True)}'
               f'{_table(_percent(summary.drop(columns=["spectrum"]), ["agreement"]))}</section>')
    return section, verdict


# --- stress tests ----------------------------------------------------------------------------------------

def _stability_sections(stability: pd.DataFrame, out: Path) -> str:
    parts = []
    for k, test in enumerate(dict.fromkeys(stability.test)):
        rows = stability[stability.test == test]
        image = f"stability_{k + 1}.png"
        figures.stability_map_figure(rows, test, WRONG, out / image)
        extra = ""
        if "contact stiffness" in test:
            figures.stiffness_figure(rows, out / "stability_stiffness.png")
            extra = _img("stability_stiffness.png", "errors and time step against contact stiffness")
        parts.append(f"<h3>{html.escape(test)}</h3>{_img(image, f'stability map: {test}', wide=True)}{extra}")
    return "".join(parts)


def _studies_html(out: Path) -> str:
    if not STUDIES.is_dir():
        return "<p>No studies are bundled with this checkout.</p>"
    items = []
    for folder in sorted(p for p in STUDIES.iterdir() if (p / "README.md").is_file()):
        link = os.path.relpath(folder / "README.md", out.resolve())
        items.append(f'<li><a href="{html.escape(link)}">{html.escape(folder.name)}</a></li>')
    return ("<p>The thesis' parametric studies, run with the native core (each folder holds its figures, its "
            "table and a README stating the trends found):</p><ul>" + "".join(items) + "</ul>")


def _verdict_record(kind, name, title, reference, verdict, engines, note="") -> dict:
    """One row of the verdict table: what was judged, its reference, who ran it, who is right and fastest."""
    fastest = verdict.get("fastest")
    if fastest is None:
        quickest = ""
    elif "wall_time_s" in fastest:
        quickest = f"{fastest.engine} at {fastest.step} ({fastest.wall_time_s:.3g} s)"
    else:
        quickest = f"{fastest.engine} at {fastest.step} ({fastest.median_wall_time_s:.3g} s a run)"
    return {"kind": kind, "name": name, "title": title, "reference": reference,
            "has_reference": bool(verdict.get("has_reference", True)), "engines": tuple(engines),
            "right": tuple(verdict["right"]), "fastest": None if fastest is None else fastest.engine,
            "fastest_run": quickest, "note": note}


def _verdict_matrix(records: pd.DataFrame, engines) -> str:
    """The verdict table: a row per case, ensemble and spectrum, a column per engine (right, fastest, no)."""
    head = "".join(f"<th>{html.escape(e)}</th>" for e in engines)
    rows = []
    for r in records.itertuples():
        note = f' <span title="{html.escape(r.note)}">(note)</span>' if r.note else ""
        cells = []
        for engine in engines:
            if engine not in r.engines:
                cells.append('<td class="e"></td>')
            elif not r.has_reference:
                cells.append('<td class="e none">-</td>')
            elif r.fastest == engine:
                cells.append('<td class="e fastest">fastest</td>')
            elif engine in r.right:
                cells.append('<td class="e right">right</td>')
            else:
                cells.append('<td class="e no">no</td>')
        reference = ('<td class="none">no reference</td>' if not r.has_reference
                     else f"<td>{html.escape(r.reference)}</td>")
        rows.append(f'<tr><td>{html.escape(r.kind)}</td><td><a href="#{r.name}">{html.escape(r.title)}</a>{note}'
                    f"</td>{reference}{''.join(cells)}<td>{html.escape(r.fastest_run)}</td></tr>")
    return (f'<table class="t matrix"><thead><tr><th>Kind</th><th>Case</th><th>Reference</th>{head}'
            f"<th>Fastest right run</th></tr></thead><tbody>{''.join(rows)}</tbody></table>")


def _percent_text(value: float, digits: str = ".2g") -> str:
    return f"{100 * value:{digits}}%" if np.isfinite(value) else "-"


def _scoreboard_html(board: pd.DataFrame, records: pd.DataFrame, usual: dict) -> str:
    """The scoreboard as a table whose best value in each column is bold, with a caption defining it."""
    def best(column, largest):
        values = board[column].to_numpy(dtype=float)
        if not np.isfinite(values).any():
            return np.nan
        return np.nanmax(values) if largest else np.nanmin(values)

    tops = {"right": best("right", True), "fastest": best("fastest", True),
            "rocking_median": best("rocking_median", False), "sliding_median": best("sliding_median", False),
            "overturn_agreement": best("overturn_agreement", True),
            "median_wall_time_s": best("median_wall_time_s", False)}

    def cell(column, value, text):
        bold = np.isfinite(value) and np.isfinite(tops[column]) and np.isclose(value, tops[column])
        return f"<td><b>{text}</b></td>" if bold else f"<td>{text}</td>"

    rows = []
    for r in board.itertuples():
        rows.append(
            f"<tr><td>{html.escape(r.engine)}</td>"
            + cell("right", r.right, f"{r.right} of {r.judged}")
            + cell("fastest", r.fastest, f"{r.fastest}")
            + cell("rocking_median", r.rocking_median, _percent_text(r.rocking_median))
            + cell("sliding_median", r.sliding_median, _percent_text(r.sliding_median))
            + cell("overturn_agreement", r.overturn_agreement,
                   f"{_percent_text(r.overturn_agreement, '.3g')} of {r.overturn_points}")
            + cell("median_wall_time_s", r.median_wall_time_s,
                   f"{r.median_wall_time_s:.3g}" if np.isfinite(r.median_wall_time_s) else "-")
            + "</tr>")
    heads = ("Engine", "Right", "Fastest", "Rocking error", "Sliding error", "Overturning agrees", "Run time (s)")
    table = ('<table class="score"><thead><tr>' + "".join(f"<th>{h}</th>" for h in heads) + "</tr></thead><tbody>"
             + "".join(rows) + "</tbody></table>")
    unreferenced = records[~records.has_reference]
    left_out = ("" if unreferenced.empty else
                f" Left out, having no reference: {html.escape(', '.join(unreferenced.title))}.")
    steps = ", ".join(sorted(set(usual.values())))
    caption = (f"<b>Right</b>: the cases, ensembles and spectra of the <a href=\"#verdicts\">verdicts</a> on which "
               f"the engine is right, out of those with a reference that it ran.{left_out} <b>Fastest</b>: on how many "
               "of them it is the fastest right engine. <b>Rocking</b> and <b>sliding error</b>: the median "
               "|peak error| of the rocking and of the sliding ensemble. <b>Overturning agrees</b>: the share of the "
               "overturning spectra's points where the engine overturns exactly when the rocking equation does. "
               f"<b>Run time</b>: the median wall time of a case run. Ensembles, spectra and run times at each "
               f"engine's usual step ({html.escape(steps)}); best of each column in bold.")
    return f'<section id="scoreboard">{table}<p class="caption">{caption}</p></section>'


def _stress_table(stability: pd.DataFrame) -> pd.DataFrame:
    """The stress-test rows with relative errors in percent (the other values in their units); "-" where the run
    stopped, "inf" where it finished but the measure could not be taken (a rocking that died out too soon)."""
    values = ["-" if np.isnan(v) else f"{100 * v:.3g}%" if figures.is_relative_error(m) and np.isfinite(v) else
              f"{v:.3g}" for m, v in zip(stability.metric, stability.value, strict=True)]
    return _metric_names(stability.assign(value=values))


def _sections(table, ensemble_table, spectra_table, column_line: str, out: Path) -> tuple:
    """The page's sections of ensembles, spectra and cases, and one verdict record per section:
    ``(records, ensemble_parts, spectrum_parts, case_parts, ensemble kinds, spectrum labels)``."""
    records, case_parts, ensemble_parts, spectrum_parts = [], [], [], []
    kinds = {}
    for ens in ensembles.all_ensembles():
        kinds[ens.name] = ens.kind
        if len(ensemble_table) and ens.name in set(ensemble_table.ensemble):
            section, verdict = _ensemble_section(ensemble_table, ens, out)
            ensemble_parts.append(section)
            reference = "rocking equation" if ens.kind == "rocking" else "rigid-plastic sliding"
            ran = dict.fromkeys(ensemble_table.engine[ensemble_table.ensemble == ens.name])
            records.append(_verdict_record("ensemble", ens.name, ens.title, f"{reference}, run by run", verdict, ran))
    spectrum_labels = {}
    for spec in overturning_spectra.all_spectra():
        spectrum_labels[spec.name] = figures.spectrum_label(spec)
        if len(spectra_table) and spec.name in set(spectra_table.spectrum):
            section, verdict = _spectrum_section(spectra_table, spec, out)
            spectrum_parts.append(section)
            ran = dict.fromkeys(spectra_table.engine[spectra_table.spectrum == spec.name])
            records.append(_verdict_record("spectrum", spec.name, spec.title, "rocking equation", verdict, ran))
    for case in all_cases():
        if case.name in set(table.case):
            section, verdict = _case_section(table, case, out, column_line)
            case_parts.append(section)
            ran = dict.fromkeys(table.engine[table.case == case.name])
            records.append(_verdict_record("case", case.name, case.title, verdict["short_reference"], verdict, ran,
                                           case.note))
    return records, ensemble_parts, spectrum_parts, case_parts, kinds, spectrum_labels


def _overview_images(ensemble_table, spectra_table, spectrum_labels, out: Path) -> str:
    """The verdicts' overview figures: the first ensemble's statistics and the spectra's agreement."""
    overview_images = ""
    if len(ensemble_table):
        first = next(e.name for e in ensembles.all_ensembles() if e.name in set(ensemble_table.ensemble))
        overview_images += _img(f"ensemble_{first}.png", f"ensemble statistics of {first}", wide=True)
    if len(spectra_table):
        figures.spectra_overview_figure(overturning_spectra.summarise(spectra_table), out / "spectra_overview.png",
                                        labels=spectrum_labels)
        overview_images += _img("spectra_overview.png", "overturning-spectrum agreement against run time")
    return overview_images


def write_report(table: pd.DataFrame, stability: pd.DataFrame, out: Path, *, quick: bool, run_time_s: float,
                 ensemble_table: pd.DataFrame | None = None, spectra_table: pd.DataFrame | None = None,
                 column_table: pd.DataFrame | None = None, made: dict | None = None) -> Path:
    """Write figures, CSV tables, ``digest.json`` and index.html into ``out``; returns the path of index.html.

    made : :func:`~comparisons.report.provenance.provenance` taken when the runs started (default: now)."""
    out.mkdir(parents=True, exist_ok=True)
    ensemble_table = pd.DataFrame() if ensemble_table is None else ensemble_table
    spectra_table = pd.DataFrame() if spectra_table is None else spectra_table
    column_table = pd.DataFrame() if column_table is None else column_table
    made = provenance() if made is None else made
    if "digest" not in made:
        made = {**made, **dict(zip(("digest", "digest_files"), source_digest(), strict=True))}
    table.to_csv(out / "results.csv", index=False)
    stability.to_csv(out / "stability.csv", index=False)
    ensemble_table.to_csv(out / "ensembles.csv", index=False)
    column_table.to_csv(out / "column_ensemble.csv", index=False)
    spectra_table.drop(columns=["transitions"], errors="ignore").to_csv(out / "spectra.csv", index=False)
    write_digest(out, made)
    column_pairs = column_ensemble.summarise_pairs(column_table) if len(column_table) else None
    column_line = _column_ensemble_line(column_pairs) if column_pairs is not None else ""
    records, ensemble_parts, spectrum_parts, case_parts, kinds, spectrum_labels = _sections(
        table, ensemble_table, spectra_table, column_line, out)
    records = pd.DataFrame(records, columns=["kind", "name", "title", "reference", "has_reference", "engines",
                                             "right", "fastest", "fastest_run", "note"])
    engines = [e for e in ENGINES if e in set(table.engine)] + sorted(set(table.engine) - set(ENGINES))
    usual = usual_steps([e for e in engines if e in ENGINES])
    board = scoreboard(records, ensemble_table, spectra_table, table, ensemble_kinds=kinds, engines=engines,
                       usual=usual)
    board.to_csv(out / "scoreboard.csv", index=False)
    overview_images = _overview_images(ensemble_table, spectra_table, spectrum_labels, out)
    simulations = (len(table.drop_duplicates(["case", "engine", "step", "settings"])) + len(ensemble_table)
                   + len(column_table) + len(spectra_table))
    terms = "".join(f"<dt>{html.escape(t)}</dt><dd>{html.escape(d)}</dd>" for t, d in glossary())
    stability_html = (_stability_sections(stability, out) + _table(_stress_table(stability))) if len(stability) else ""
    when = time.strftime("%Y-%m-%d %H:%M")
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Engine comparison: rocking and sliding of stone blocks</title>
<style>{STYLE}</style></head><body>
<h1>Engine comparison: rocking and sliding of stone blocks</h1>
<p class="prov">{_provenance_line(made, quick, when)}</p>
{_scoreboard_html(board, records, usual)}
<p>{"Quick" if quick else "Full"} run of {simulations} simulations ({table.case.nunique()} cases,
{ensemble_table.ensemble.nunique() if len(ensemble_table) else 0} ensembles,
{spectra_table.spectrum.nunique() if len(spectra_table) else 0} overturning spectra) in {run_time_s:.0f} s of wall
time, {when}. {_provenance_html(made)}</p>
<p>Six engines: the native core with its default integrator, Moreau-Jean, on the corner law's points
(<b>dem-moreau</b>: rigid contacts, no stiffness), and with its explicit integrator under the corner contact law
(<b>dem</b>) and under the thesis' overlap-area law (<b>dem-overlap</b>), pymunk, PyBullet and MuJoCo. Each is
judged against an exact reference where one exists (docs/method.md section 4), and against the consensus of the
other engines on the multi-block scenes, where none does. Errors below {exact_floor("peak_rotation"):g} (relative)
or {exact_floor("drift_m"):g} m or rad count as exact and are not ranked. Errors are in percent of the reference
unless a unit is named. Wall times exclude compiling and building. The terms are explained in the
<a href="#glossary">glossary</a>; the thesis' parametric studies are <a href="#studies">linked below</a>.
Tables: <a href="scoreboard.csv">scoreboard.csv</a>, <a href="results.csv">results.csv</a>,
<a href="ensembles.csv">ensembles.csv</a>, <a href="column_ensemble.csv">column_ensemble.csv</a>, <a href="spectra.csv">spectra.csv</a>,
<a href="stability.csv">stability.csv</a>.</p>
<p>Contents: <a href="#verdicts">Verdicts</a> | <a href="#ensembles">Ensembles under records</a> |
<a href="#spectra">Overturning spectra</a> | <a href="#cases">Cases</a> | <a href="#stability">Stability map</a> |
<a href="#studies">Studies</a> | <a href="#glossary">Glossary</a></p>
<section id="verdicts"><h2>Verdicts</h2>
<p>Per case, the engines that are right (within the case's accuracy, or the reference's uncertainty where that is
larger), and the fastest of them; "-" where the case has no reference, blank where the engine did not run it.
Single runs of rocking under records are luck; the ensembles judge accuracy.</p>
{_verdict_matrix(records, engines)}{overview_images}</section>
<section id="ensembles"><h2>Ensembles under records</h2>{"".join(ensemble_parts) or "<p>Not run.</p>"}
{_column_ensemble_html(column_table, column_pairs) if column_pairs is not None else ""}</section>
<section id="spectra"><h2>Overturning spectra</h2>{"".join(spectrum_parts) or "<p>Not run.</p>"}</section>
<section id="cases"><h2>Cases</h2>{"".join(case_parts)}</section>
<section id="stability"><h2>Stability map</h2>{stability_html}</section>
<section id="studies"><h2>Studies</h2>{_studies_html(out)}</section>
<section id="glossary"><h2>Glossary</h2><dl>{terms}</dl></section>
</body></html>"""
    index = out / "index.html"
    index.write_text(page, encoding="utf-8")
    return index
