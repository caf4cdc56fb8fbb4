"""The exact references the engines are judged against (docs/method.md section 4).

* :mod:`.analytical`: closed forms and exact integrations of a rigid block (Housner's free rocking,
  Newmark's sliding block, rigid-plastic sliding under a record, the onset and slide-rock criteria);
* :mod:`.rocking_equation`: the rigid rocking equation with Housner's impact rule under any ground
  motion, compiled;
* :mod:`.stacked_rocking`: two rigid stacked blocks up to their first impact (Psycharis).
"""
