"""The error of a scene that cannot be simulated, which the scene, its builders and its connectors raise."""


class SceneError(ValueError):
    """A scene that cannot be simulated; the message names the block at fault."""
