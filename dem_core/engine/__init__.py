"""The engine: what a scene compiles to, the compiled kernels that step it, and what a run returns.

``contact`` (the contact laws' parameters), ``geometry`` (polygons), ``stability`` (the time step),
``stacks`` (columns and their overturn), ``simulation`` (``simulate``), ``result`` (``Result``);
the compiled kernels are the private ``_``-modules.
"""
