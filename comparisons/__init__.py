"""The engine comparison: the native core, pymunk, PyBullet and MuJoCo against exact references.

* :mod:`comparisons.references`: the analytical and exact references (docs/method.md section 4);
* :mod:`comparisons.cases`: the benchmark cases, their measures and their acceptance bands;
* :mod:`comparisons.harness`: the runs of every case, ensemble, overturning spectrum and stress test;
* :mod:`comparisons.report`: the verdicts, figures and page of ``python -m comparisons report``;
* :mod:`comparisons.benchmarks`: timings and calibrations run by hand (``python -m comparisons --help``).
"""
