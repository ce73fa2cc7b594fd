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
