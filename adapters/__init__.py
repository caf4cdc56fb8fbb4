"""The scenes of :mod:`dem_core` built in other physics engines, returning the same result type.

``pymunk_adapter`` is the first; PyBullet and MuJoCo follow (issue 3).
"""
