"""The benchmark cases: what is run, what it is measured against, and how close each engine must come.

* :mod:`.case`: what a case is (:class:`~.case.Case`), the engines it judges, the exact floors;
* :mod:`.catalogue`: every case of docs/method.md section 4, declared once for the tests and the report;
* :mod:`.measures`: measurements taken from time histories the same way for every engine and reference;
* :mod:`.strong_motion`: the strong-motion window of a bundled record, the motion of the ensembles.
"""
