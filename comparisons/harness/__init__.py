"""Running the engines: every case, ensemble, overturning spectrum and stress test, each into a tidy table.

* :mod:`.engines`: the engines judged, their steps, and one run of a scene in any of them;
* :mod:`.case_runs`: every case in every engine over a ladder of steps and settings;
* :mod:`.consensus`: the reference of a scene without a closed form, from the engines' converged answers;
* :mod:`.ensembles`: every bundled record at many amplitudes, run by run against the references;
* :mod:`.overturning_spectra`: which pulses overturn a block, against the rocking equation;
* :mod:`.stress`: where each engine breaks and whether it says so.
"""
