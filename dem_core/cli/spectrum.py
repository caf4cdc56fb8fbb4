"""``dem-core spectrum RECORD ... --out spectra.png``: elastic response spectra of records
(:mod:`dem_core.analyses.spectra`), a figure and a table beside it."""

import sys
from pathlib import Path

import numpy as np
import pandas as pd

from ..analyses.spectra import response_spectrum, spectrum_figure
from ..inputs.excitation import record
from ..output_files import output_file, replacing
from .arguments import DAMPING
from .console import acceleration_text


def add(sub):
    spectrum = sub.add_parser("spectrum", help="elastic response spectra of records")
    spectrum.add_argument("records", nargs="+", help="bundled record names or record files")
    spectrum.add_argument("--damping", type=DAMPING, default=0.05, help="damping ratio, 0 <= damping < 1 "
                          "(default: 0.05)")
    spectrum.add_argument("--out", default="spectra.png", help="figure to write; a .csv beside it holds the values")


def run(args) -> int:
    import matplotlib.pyplot as plt  # matplotlib loads only for the commands that draw
    from matplotlib.figure import Figure

    out = Path(args.out) if Path(args.out).suffix else Path(args.out).with_suffix(".png")
    formats = Figure().canvas.get_supported_filetypes()
    if out.suffix[1:].lower() not in formats:
        print(f"error: --out {out}: the figure's format is taken from its name: end it in one of "
              f"{', '.join('.' + f for f in sorted(formats))}", file=sys.stderr)
        return 2
    output_file(out, "--out")
    table_path = output_file(out.with_suffix(".csv"), "--out")
    try:
        spectra = [response_spectrum(record(name), damping=args.damping) for name in args.records]
    except (OSError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    figure = spectrum_figure(spectra)
    try:
        with replacing(out) as tmp:
            figure.savefig(tmp, dpi=130, format=out.suffix[1:].lower())
    finally:
        plt.close(figure)
    table = pd.concat([pd.DataFrame({"record": s.name, "period_s": s.periods, "sd_m": s.sd, "psv_m_s": s.psv,
                                     "psa_m_s2": s.psa, "damping": s.damping}) for s in spectra])
    with replacing(table_path) as tmp:
        table.to_csv(tmp, index=False)
    for s in spectra:
        k = int(np.argmax(s.psa))
        print(f"{s.name}: PGA {acceleration_text(s.pga)}, peak PSA {acceleration_text(s.psa[k])} at "
              f"T = {s.periods[k]:.3g} s, peak SD {np.max(s.sd):.3g} m")
    print(f"written {out} and {table_path}")
    return 0
