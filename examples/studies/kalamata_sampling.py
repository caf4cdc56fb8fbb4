"""The sampling interval of the bundled Kalamata 1986 record, settled from evidence.

The file holds 2590 accelerations (m/s^2) and no time column; its source gave 0.02 s. Read at
0.005, 0.01 and 0.02 s, the record's length, peak ground velocity, significant durations and the
peak of its 5%-damped spectrum are set against what is published for the 1986 Kalamata mainshock
(Mw 5.9, normal faulting, the city within a few km of the fault) and the thesis' 2.9-3.5 Hz for
its Kalamata (OTE, N10W) record.

References:
* L. Papaloizou (2009), PhD thesis, University of Cyprus, section 6.4: predominant frequencies
  2.9-3.5 Hz of the Kalamata 1986 OTE N10W record (../shared/THESIS_TABLES.md).
* Akkar, Sandikkaya and Bommer (2014) Bull. Earthquake Eng. 12: 359-387, and Boore, Stewart,
  Seyhan and Atkinson (2014) Earthquake Spectra 30(3): 1057-1085: median PGA and PGV.
* Afshari and Stewart (2016) Earthquake Spectra 32(4): 2057-2081: median significant durations.
* Arias (1970): the cumulative squared acceleration whose 5-75% and 5-95% times give D5-75, D5-95.
"""

import time

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from _study import out_dir, save_figure, write_readme

from dem_core import excitation, records
from dem_core.analyses.spectra import response_spectrum

NAME = "kalamata_sampling"
CANDIDATES = (0.005, 0.01, 0.02)  # s
THESIS_BAND = (2.9, 3.5)  # Hz, predominant frequencies of the thesis' Kalamata record
#: Medians for the 1986 Kalamata scenario: Mw 5.9, normal faulting, Joyner-Boore distance 3 to 6 km,
#: Vs30 300 to 450 m/s, each the range over those four corners (computed once with pygmm 0.8.0,
#: which implements the models; it is not a dependency of this project).
#: PGV / PGA (s): Akkar-Sandikkaya-Bommer 2014 and Boore-Stewart-Seyhan-Atkinson 2014.
MODEL_PGV_OVER_PGA = (0.057, 0.071)
#: PGV (m/s) of the same models.
MODEL_PGV = (0.120, 0.244)
#: Afshari-Stewart 2016 significant durations (s) and their log standard deviations.
MODEL_D5_75, SIGMA_D5_75 = (3.02, 3.55), 0.50
MODEL_D5_95, SIGMA_D5_95 = (6.02, 7.52), 0.43


def significant_duration(acceleration, dt: float, start: float, end: float) -> float:
    """Time (s) for the Arias intensity to grow from fraction ``start`` to ``end`` of its total."""
    arias = np.concatenate([[0.0], np.cumsum(0.5 * (acceleration[1:] ** 2 + acceleration[:-1] ** 2) * dt)])
    t = np.arange(len(acceleration)) * dt
    return float(np.interp(end * arias[-1], arias, t) - np.interp(start * arias[-1], arias, t))


def log_distance(value: float, band: tuple) -> float:
    """ln of how far ``value`` lies outside ``band`` (0 inside): the factor by which it misses."""
    low, high = band
    return float(np.log(value / high)) if value > high else float(np.log(low / value)) if value < low else 0.0


def fourier_peak(samples, dt: float, bandwidth: float = 20.0) -> float:
    """Frequency (Hz, 0.1 to 25 Hz) of the peak of the Fourier amplitude spectrum smoothed with the
    Konno-Ohmachi window of ``bandwidth`` b (Konno and Ohmachi 1998, BSSA 88(1): 228-241)."""
    n = 1 << int(np.ceil(np.log2(4 * len(samples))))
    amplitude = np.abs(np.fft.rfft(samples, n)) * dt
    f = np.fft.rfftfreq(n, dt)
    keep = (f > 0.1) & (f < 25.0)
    f, amplitude = f[keep], amplitude[keep]
    x = bandwidth * np.log10(f[None, :] / f[:, None])
    with np.errstate(invalid="ignore", divide="ignore"):
        window = np.where(np.abs(x) < 1e-12, 1.0, (np.sin(x) / x) ** 4)
    smoothed = window @ amplitude / window.sum(axis=1)
    return float(f[np.argmax(smoothed)])


def measure(samples, dt: float) -> dict:
    motion = excitation.record(samples, dt=dt)
    t = np.arange(len(samples)) * dt
    pga = float(np.max(np.abs(samples)))
    pgv = float(np.max(np.abs(motion.horizontal.velocity(t))))
    spectrum = response_spectrum(motion)
    peak = 1.0 / spectrum.periods[np.argmax(spectrum.psa)]
    return {"dt_s": dt, "length_s": len(samples) * dt, "pga_ms2": pga, "pgv_ms": pgv, "pgv_over_pga_s": pgv / pga,
            "d5_75_s": significant_duration(samples, dt, 0.05, 0.75),
            "d5_95_s": significant_duration(samples, dt, 0.05, 0.95), "psa_peak_hz": peak,
            "fourier_peak_hz": fourier_peak(samples, dt),
            "psa_peak_over_pga": float(spectrum.psa.max() / pga), "spectrum": spectrum}


def misfits(row) -> dict:
    """ln factor by which each measure misses its reference band (0 inside)."""
    return {"pgv_over_pga": log_distance(row["pgv_over_pga_s"], MODEL_PGV_OVER_PGA),
            "d5_75": log_distance(row["d5_75_s"], MODEL_D5_75),
            "d5_95": log_distance(row["d5_95_s"], MODEL_D5_95),
            "psa_peak": log_distance(row["psa_peak_hz"], THESIS_BAND),
            "fourier_peak": log_distance(row["fourier_peak_hz"], THESIS_BAND)}


def main():
    started = time.perf_counter()
    samples = np.loadtxt(records.bundled_path("kalamata_1986"))
    rows = [measure(samples, dt) for dt in CANDIDATES]
    table = pd.DataFrame([{k: v for k, v in r.items() if k != "spectrum"} | {f"miss_{k}": v for k, v in
                                                                            misfits(r).items()} for r in rows])
    table.to_csv(out_dir(NAME) / "results.csv", index=False)

    fig, (ax_a, ax_s) = plt.subplots(1, 2, figsize=(12, 4))
    for row in rows:
        t = np.arange(len(samples)) * row["dt_s"]
        ax_a.plot(t, samples, lw=0.6, label=f"dt {row['dt_s']:g} s")
        ax_s.plot(1.0 / row["spectrum"].periods, row["spectrum"].psa, label=f"dt {row['dt_s']:g} s")
    ax_a.set(xlabel="time (s)", ylabel="ground acceleration (m/s$^2$)", xlim=(0, 30),
             title="The same 2590 samples at each candidate interval")
    ax_s.axvspan(*THESIS_BAND, color="0.85", label="thesis: 2.9-3.5 Hz")
    ax_s.set(xscale="log", xlabel="frequency (Hz)", ylabel="PSA, 5% damping (m/s$^2$)",
             title="Response spectrum against the thesis' predominant frequencies")
    figures = [save_figure(fig, NAME, "kalamata_sampling.png",
                           "Left: the record's accelerations placed at each candidate interval. Right: their 5%-damped "
                           "pseudo-acceleration spectra, with the thesis' 2.9-3.5 Hz shaded; the table above gives "
                           "each spectrum's peak.", legend=8)]

    measures = {"pgv_over_pga": "PGV/PGA", "d5_75": "D5-75", "d5_95": "D5-95", "psa_peak": "spectrum peak",
                "fourier_peak": "Fourier peak"}
    closest = {k: table.dt_s[table[f"miss_{k}"].abs().idxmin()] for k in measures}
    total = table[[f"miss_{k}" for k in measures]].abs().sum(axis=1)
    chosen = table.loc[total.idxmin()]
    pga = table.pga_ms2.iloc[0]
    lines = ["| dt (s) | length (s) | PGV (m/s) | PGV/PGA (s) | D5-75 (s) | D5-95 (s) | spectrum peak (Hz) | "
             "Fourier peak (Hz) | summed ln misfit |", "|---|---|---|---|---|---|---|---|---|"]
    lines += [f"| {r.dt_s:g} | {r.length_s:.1f} | {r.pgv_ms:.3f} | {r.pgv_over_pga_s:.3f} | {r.d5_75_s:.2f} | "
              f"{r.d5_95_s:.2f} | {r.psa_peak_hz:.2f} | {r.fourier_peak_hz:.2f} | {m:.2f} |"
              for r, m in zip(table.itertuples(), total)]
    lines += [f"| reference | | {MODEL_PGV[0]:.2f}-{MODEL_PGV[1]:.2f} | {MODEL_PGV_OVER_PGA[0]:.3f}-"
              f"{MODEL_PGV_OVER_PGA[1]:.3f} | {MODEL_D5_75[0]:.2f}-{MODEL_D5_75[1]:.2f} | "
              f"{MODEL_D5_95[0]:.2f}-{MODEL_D5_95[1]:.2f} | {THESIS_BAND[0]:g}-{THESIS_BAND[1]:g} | "
              f"{THESIS_BAND[0]:g}-{THESIS_BAND[1]:g} | |", "",
              "References: PGV and PGV/PGA, medians of Akkar-Sandikkaya-Bommer 2014 and Boore-Stewart-Seyhan-Atkinson "
              "2014; D5-75 and D5-95, medians of Afshari-Stewart 2016 (log standard deviations "
              f"{SIGMA_D5_75:g} and {SIGMA_D5_95:g}); all for Mw 5.9, normal faulting, Joyner-Boore distance 3-6 km, "
              "Vs30 300-450 m/s. Peaks: the thesis' predominant frequencies of its Kalamata record. Spectrum peak: "
              "5%-damped pseudo-acceleration; Fourier peak: amplitude smoothed with a Konno-Ohmachi window "
              "(b = 20). A misfit is ln of the factor by which a value lies outside its reference band (0 inside).",
              ""]
    bullets = [
        f"PGA {pga:.3f} m/s^2 ({pga / 9.80665:.3f} g) at any interval: more than the thesis' OTE N10W record "
        "(2.67 m/s^2), so the file is probably another component or station of the same earthquake and its frequencies "
        "need not match the thesis' exactly.",
        "Closest candidate by measure: " + "; ".join(f"{label} dt {closest[k]:g} s" for k, label in measures.items())
        + ".",
        "Inside the thesis' band: " + "; ".join(
            f"{label} at dt " + (", ".join(f"{dt:g}" for dt in table.dt_s[table[f'miss_{k}'] == 0]) or "none")
            for k, label in (("psa_peak", "spectrum peak"), ("fourier_peak", "Fourier peak"))) + " s.",
        f"Smallest summed misfit: dt {chosen.dt_s:g} s (length {chosen.length_s:.1f} s, PGV {chosen.pgv_ms:.2f} "
        f"m/s). Each measure's misfit at dt 0.02 s: " + ", ".join(
            f"{label} {table.loc[table.dt_s == 0.02, f'miss_{k}'].iloc[0]:.2f}" for k, label in measures.items()) + ".",
    ]
    write_readme(NAME, "Sampling interval of the bundled Kalamata 1986 record", bullets, figures, started,
                 "kalamata_sampling.py", resumes=False, tables=lines)


if __name__ == "__main__":
    main()
