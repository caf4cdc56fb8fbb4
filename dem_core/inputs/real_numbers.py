"""What every input takes for a number: a real number (an int, a float, a numpy scalar), never a boolean, since
``True`` is an int to Python but no length, time or factor a user means."""

import numbers


def is_real(value) -> bool:
    """Whether ``value`` is a real number and not a boolean."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool)
