"""The comparison report: verdicts, figures, words and provenance of ``python -m comparisons report``.

* :mod:`.page`: writes the tables and ``index.html``;
* :mod:`.verdicts`: which engines are right, and the fastest of them;
* :mod:`.figures`: the figures, each checked for cut text;
* :mod:`.glossary`: column headers, metric names and the glossary;
* :mod:`.provenance`: the commit and versions a report is made from.
"""
