"""Fixed-amplitude harmonic motion at 0.5, 2 and 20 Hz: how much of the ground's travel the 8-drum column
slides (the thesis' chapter 6 runs at fixed displacement amplitude).

The ground moves as u_g = A sin(2 pi f t) at a fixed amplitude A; the PGA, A (2 pi f)^2, grows with the
square of the frequency.  Measures: the motion mode (rest, rocking, sliding, slide-rock:
:func:`dem_core.analyses.thresholds.motion_mode`), the total sliding summed over the interfaces, the
ground's total travel 4 A f T over the run, their ratio, and the peak offset of the bottom drum over the base
(its displacement along the joint, rocking about an end left out:
:func:`dem_core.analyses.thresholds.interface_offsets`) over A.  At low frequency the column moves with the ground (ratio near 0); far
above mu g the ground slides under a column that barely moves, and the ratio tends to 1.
"""

import time

import matplotlib.pyplot as plt
import numpy as np
from _study import DEFAULT_MODEL, markdown_table, results_table, save_figure, write_readme

import dem_core
from dem_core import excitation, scenes
from dem_core.analyses.thresholds import interface_offsets, interface_slips, motion_mode

NAME = "harmonic_sliding"
FREQUENCIES = (0.5, 2.0, 20.0)  # Hz
AMPLITUDES = (0.005, 0.02)  # m
DURATION = 5.0  # s
FRICTION = 0.485
N_DRUMS = 8
G = 9.80665


def run(frequency, amplitude):
    scene = scenes.column(N_DRUMS, friction=FRICTION)
    started = time.perf_counter()
    row = {"frequency": frequency, "amplitude": amplitude, "pga": amplitude * (2 * np.pi * frequency) ** 2}
    try:
        result = dem_core.simulate(scene, excitation.harmonic(amplitude, frequency), duration=DURATION,
                                   output_dt=min(0.002, 0.05 / frequency))
    except dem_core.SimulationUnstable as exc:
        return {**row, "status": "unstable", "error": str(exc), "wall_time_s": time.perf_counter() - started}
    end = result.t[-1]
    base = result.interfaces.index(("base", "drum1"))
    travel = 4.0 * amplitude * frequency * end
    row.update(status="ok", error="", mode=motion_mode(scene, result), overturned=result.overturned, end_time=end,
               total_sliding=float(np.sum(interface_slips(result)[-1])), ground_travel=travel,
               base_slip_peak=float(np.max(np.abs(interface_offsets(scene, result)[:, base]))),
               peak_theta=float(np.max(np.abs(result.theta))), dt=result.dt, wall_time_s=time.perf_counter() - started)
    row["sliding_ratio"] = row["total_sliding"] / travel
    row["start_drift"] = (amplitude * 2 * np.pi * frequency) ** 2 / (2 * FRICTION * G)
    row["base_slip_over_amplitude"] = row["base_slip_peak"] / amplitude
    return row


def main():
    started = time.perf_counter()
    table = results_table(NAME, [run(f, a) for a in AMPLITUDES for f in FREQUENCIES])
    setup = [f"Set-up: 8-drum column 6 m x 1 m, friction {FRICTION:g} at every interface (sliding starts at mu g = "
             f"{FRICTION * G:.3g} m/s^2, rocking at g b/h = {G / 6:.3g} m/s^2 for a rigid column), "
             f"{DEFAULT_MODEL}; u_g = A sin(2 pi f t) for {DURATION:g} s (or up to "
             "an overturn). Total sliding: the slip accumulated at every interface (paths, summed); ground travel: "
             "4 A f times the run's length. The motion starts with the ground at its peak velocity A 2 pi f: a column "
             "at rest that slides at once drifts by (A 2 pi f)^2 / (2 mu g) before friction stops it (start drift).",
             ""]
    ok = table[table.status == "ok"]
    rows = [[f"{r.amplitude * 1e3:g}", f"{r.frequency:g}", f"{r.pga:.3g}", r.mode,
             "yes" if r.overturned else "no", f"{r.total_sliding * 1e3:.3g}", f"{r.ground_travel * 1e3:.3g}",
             f"{r.sliding_ratio:.3f}", f"{r.base_slip_over_amplitude:.3f}", f"{r.start_drift / r.amplitude:.3g}",
             f"{r.peak_theta * 1e3:.3g}"]
            for r in ok.itertuples(index=False)]
    setup += markdown_table(["A (mm)", "f (Hz)", "PGA (m/s^2)", "mode", "overturned", "total sliding (mm)",
                             "ground travel (mm)", "sliding / ground travel", "peak base slip / A",
                             "start drift / A", "peak rotation (mrad)"], rows)
    findings = []
    for a in AMPLITUDES:
        runs = ok[ok.amplitude == a].sort_values("frequency")
        findings.append(f"A = {a * 1e3:g} mm: sliding over ground travel " + ", ".join(
            f"{r.sliding_ratio:.3f} at {r.frequency:g} Hz ({r.mode})" for r in runs.itertuples()) + ".")
    failed = table[table.status != "ok"]
    findings.append(f"Runs that did not finish: {len(failed)}" + (": " + ", ".join(
        f"{r.amplitude * 1e3:g} mm at {r.frequency:g} Hz ({r.status})" for r in failed.itertuples())
        if len(failed) else "") + ".")
    write_readme(NAME, "Sliding of the 8-drum column under fixed-amplitude harmonic motion", findings,
                 [figure(ok)], started, "harmonic_sliding.py", resumes=False, tables=setup)


def figure(table):
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for a in AMPLITUDES:
        runs = table[table.amplitude == a].sort_values("frequency")
        line = ax.plot(runs.frequency, runs.sliding_ratio, "o-", label=f"A = {a * 1e3:g} mm")[0]
        fallen = runs[runs.overturned]
        ax.plot(fallen.frequency, fallen.sliding_ratio, "x", color=line.get_color(), ms=12, mew=2)
    ax.set(xscale="log", xlabel="frequency (Hz)", ylabel="total sliding / ground travel",
           title=f"8-drum column, friction {FRICTION:g}, default contact law")
    return save_figure(fig, NAME, "harmonic_sliding.png",
                       "The table's ratio of total sliding to the ground's travel against frequency, one line per "
                       "amplitude; a cross marks a run that overturned (its ratio up to the overturn).", legend=8,
                       grid={"which": "both"})


if __name__ == "__main__":
    main()
