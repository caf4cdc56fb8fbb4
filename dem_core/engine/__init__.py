"""The engine: what a scene compiles to, the compiled driver that steps it, and what a run returns.

Public modules: ``contact`` (the contact laws' parameters), ``geometry`` (polygons), ``model`` (the
compiled scene), ``model_arrays`` (the model as the driver reads it), ``settings`` (a run's settings, its
integrators' defaults and the codes a run ends with), ``state`` (where a run is, and its outputs), ``scratch``
(what the driver writes within a step), ``stability`` (the time step, from the model), ``stacks`` (columns and
their overturn), ``result`` (``Result``).  The compiled code is in the private modules: ``_driver`` (the one step
loop, and its CPU builds), ``_members`` (the same loop for a batch's members, on a GPU or one CPU thread), and one
stage each: ``_ground``, ``_outputs``, ``_world`` (world geometry and boxes), ``_broadphase``, ``_explicit``
(contact forces and central differences) with ``_manifold`` (corner law geometry), ``_polygon`` (overlap-area law
geometry) and ``_contact_law``, ``_moreau`` (Moreau-Jean) with ``_points`` and ``_active_set``, ``_tally`` (where
slip goes) and ``_checks``, and ``_angles`` (quick sines and cosines of small angles) for several.  The engine
imports nothing from the rest of the package: :mod:`dem_core.simulation` joins it to the inputs.
"""
