"""Array plumbing between the Pythonic API and the f2py layer (no numerics).

``as_real`` and ``broadcast_real`` turn user input into contiguous float64
copies (so the Fortran core never sees, or modifies, a user's array), and
``restore`` gives back scalars for scalar input and arrays of the broadcast
shape otherwise.
"""
import numbers

import numpy as np


def as_real(x, name):
    """Return ``x`` as a float64 ndarray, rejecting non-real input by name."""
    if isinstance(x, (str, bytes)) or x is None:
        raise TypeError(f"{name} must be a real number or an array of real numbers, got {type(x).__name__}")
    arr = np.asarray(x)
    if arr.dtype == object or arr.dtype.kind not in "biuf":
        if arr.dtype.kind == "c":
            raise TypeError(f"{name} must be real, got a complex array")
        raise TypeError(f"{name} must be a real number or an array of real numbers, got dtype {arr.dtype}")
    return np.array(arr, dtype=np.float64, copy=True)


def broadcast_real(**named):
    """Broadcast named real inputs together.

    Returns ``(shape, scalar, flats)``: the broadcast shape, whether every input
    was a scalar, and a dict of contiguous 1-D float64 copies of the same length.
    Raises ValueError naming the arguments when shapes are incompatible.
    """
    arrays = {k: as_real(v, k) for k, v in named.items()}
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k}{a.shape}" for k, a in arrays.items())
        raise ValueError(f"arguments cannot be broadcast together: {shapes}") from None
    scalar = all(a.ndim == 0 for a in arrays.values())
    flats = {k: np.ascontiguousarray(np.broadcast_to(a, shape)).reshape(-1) for k, a in arrays.items()}
    return shape, scalar, flats


def restore(values, shape, scalar):
    """Reshape a flat result to ``shape``; a Python float when ``scalar``."""
    values = np.asarray(values).reshape(shape)
    if scalar:
        return float(values)
    return values


def real_scalar(x, name):
    """Return ``x`` as a Python float, rejecting arrays and non-reals by name."""
    if isinstance(x, bool) or not isinstance(x, (numbers.Real, np.floating, np.integer)):
        arr = np.asarray(x) if not isinstance(x, (str, bytes)) and x is not None else None
        if arr is not None and arr.ndim == 0 and arr.dtype.kind in "iuf":
            return float(arr)
        raise TypeError(f"{name} must be a real scalar, got {type(x).__name__}")
    return float(x)


def integer_arg(x, name, lo, hi, scalar=False):
    """Check an integer argument (scalar or array) against [lo, hi] before any conversion.

    Accepts Python ints and NumPy integer scalars/arrays of any width and
    signedness; rejects bool (True is not a count or an index), floats and
    anything else with TypeError naming the argument.  The range test is done
    on exact Python ints (or, for arrays, with a comparison that cannot wrap:
    uint64 values above 2**63 - 1 are never cast to int64), so 2**63 or
    2**64 - 1 is refused with ValueError instead of wrapping to 0 or -1.
    Returns a Python int for scalars and an int64 ndarray for arrays
    (``scalar=True`` refuses arrays with TypeError).  lo and hi must lie in
    the int64 range.
    """
    if isinstance(x, (bool, np.bool_)):
        raise TypeError(f"{name} must be an integer, got bool")
    if isinstance(x, (numbers.Integral, np.integer)):
        v = int(x)                      # exact: Python ints do not wrap
        if not lo <= v <= hi:
            raise ValueError(f"{name} = {v} is out of range: it must be an integer in [{lo}, {hi}]")
        return v
    if scalar or isinstance(x, (str, bytes)) or x is None:
        what = "an integer" if scalar else "an integer or an array of integers"
        raise TypeError(f"{name} must be {what}, got {type(x).__name__}")
    try:
        arr = np.asarray(x)
    except (ValueError, TypeError) as err:
        raise TypeError(f"{name} must be an integer or an array of integers ({err})") from None
    if arr.dtype == object:
        # a list of Python ints too large for int64 arrives as object: check each exactly
        flat = arr.reshape(-1)
        for v in flat:
            integer_arg(v, name, lo, hi, scalar=True)
        return np.array([int(v) for v in flat], dtype=np.int64).reshape(arr.shape)
    if arr.dtype.kind not in "iu":
        raise TypeError(f"{name} must be an integer or an array of integers, got dtype {arr.dtype}")
    if arr.size:
        # min/max in the array's own dtype, converted exactly to Python ints
        amin, amax = int(arr.min()), int(arr.max())
        if amin < lo or amax > hi:
            bad = amin if amin < lo else amax
            raise ValueError(f"{name} = {bad} is out of range: it must be an integer in [{lo}, {hi}]")
    return arr.astype(np.int64)
