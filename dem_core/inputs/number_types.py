"""What every input takes for a number: a real number (an int, a float, a numpy scalar) or, where a count is meant,
an integer (a Python or numpy one); never a boolean, since ``True`` is an int to Python but no length, time,
factor or count a user means."""

import numbers


def is_real(value) -> bool:
    """Whether ``value`` is a real number and not a boolean."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def is_integer(value) -> bool:
    """Whether ``value`` is an integer (Python's or numpy's) and not a boolean."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def is_whole(value) -> bool:
    """Whether ``value`` is an integer or a real number with no fraction (2.0, as a count from a file), not a
    boolean."""
    return is_integer(value) or (is_real(value) and float(value).is_integer())
