"""The engine: what a scene compiles to, the compiled kernels that step it, and what a run returns.

Public modules: ``contact`` (the contact laws' parameters), ``geometry`` (polygons), ``model`` (the
compiled scene), ``state`` (where a run is), ``stability`` (the time step, from the model), ``stacks``
(columns and their overturn), ``result`` (``Result``).  The compiled kernels are the private modules,
one stage each: ``_broadphase``, ``_manifold`` (corner law geometry), ``_polygon`` (overlap-area law
geometry), ``_contact_law``, ``_checks`` and ``_step``.  The engine imports nothing from the rest of
the package: :mod:`dem_core.simulation` joins it to the inputs.
"""
