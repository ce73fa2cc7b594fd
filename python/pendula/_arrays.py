"""Array plumbing between the Pythonic API and the f2py layer (no numerics).

Every public function turns its real arguments into float64 through the one
validation path here, so that a bad argument gets the same answer everywhere:
TypeError naming the argument for something that is not real numbers (str,
bytes, None, complex, bool, datetime64/timedelta64, objects), ValueError naming
it for a ragged nested list or more elements than the Fortran core can index.

``as_real`` and ``broadcast_real`` turn user input into contiguous float64
copies (so the Fortran core never sees, or modifies, a user's array), and
``restore`` gives back scalars for scalar input and arrays of the broadcast
shape otherwise.

Booleans are refused, scalar or array: NumPy would read True as 1.0, but a
bool where a time, an angle or a parameter is wanted is a mistake (a flag
passed in the wrong position), and accepting it in one place and not another
made the answer depend on the path taken.
"""

import numbers

import numpy as np

MAX_ELEMENTS = 2**31 - 1
"""Most elements one call can take: f2py passes array sizes to Fortran as
default (4-byte) integers, so a larger array would reach the core with a
wrapped, negative size."""

_KIND_WORDS = {
    "b": "a bool",
    "c": "complex",
    "m": "a timedelta64",
    "M": "a datetime64",
    "U": "a str",
    "S": "bytes",
    "V": "a structured value",
    "O": "a Python object",
}


def _not_real(name, what):
    return TypeError(f"{name} must be a real number or an array of real numbers, got {what}")


def check_size(n, name):
    """Refuse ``n`` elements for ``name`` when the Fortran core cannot index them."""
    if n > MAX_ELEMENTS:
        raise ValueError(
            f"{name} has {n} elements: at most 2**31 - 1 = {MAX_ELEMENTS} per call "
            f"(the Fortran core indexes with 4-byte integers); split the input"
        )


def as_array(x, name):
    """``np.asarray(x)`` whose failures name the argument: ragged nested lists
    (ValueError) and non-numeric input (TypeError).  Any numeric dtype passes;
    callers check the kind they need.  Never copies a NumPy array."""
    if isinstance(x, (str, bytes)) or x is None:
        raise _not_real(name, type(x).__name__)
    if isinstance(x, numbers.Integral) and not isinstance(x, (bool, np.bool_, np.integer)):
        if not -(2**63) <= x < 2**63:  # NumPy would make an object array of a huge int
            try:
                return np.asarray(float(x))
            except OverflowError:
                raise ValueError(f"{name} = {x} is out of range: it exceeds the largest double") from None
    try:
        arr = np.asarray(x)
    except ValueError as exc:
        if "inhomogeneous" in str(exc) or "sequence" in str(exc):
            raise ValueError(
                f"{name} is a ragged nested sequence (rows of different lengths): it must be "
                f"a real number or a rectangular array of real numbers"
            ) from None
        raise ValueError(f"{name} cannot be read as an array of real numbers: {exc}") from None
    except TypeError as exc:
        raise _not_real(name, f"{type(x).__name__} ({exc})") from None
    check_size(arr.size, name)
    return arr


def _real_array(x, name):
    """as_array, restricted to integer and floating dtypes."""
    arr = as_array(x, name)
    kind = arr.dtype.kind
    if kind not in "iuf":
        what = _KIND_WORDS.get(kind, f"dtype {arr.dtype}")
        if kind in "cmMbO":
            what = f"{what} ({'array of ' if arr.ndim else ''}dtype {arr.dtype})"
        raise _not_real(name, what)
    return arr


def as_real(x, name):
    """Return ``x`` as a float64 ndarray (a copy), rejecting non-real input by name."""
    return np.array(_real_array(x, name), dtype=np.float64, copy=True)


def broadcast_real(size1=False, **named):
    """Broadcast named real inputs together.

    Returns ``(shape, scalar, flats)``: the broadcast shape, whether every input
    was a scalar, and a dict of contiguous 1-D float64 copies of the same length
    (with ``size1``, an input of one element stays one element, for the kernels
    that take size n or 1).  Raises ValueError naming the arguments when shapes
    are incompatible or the broadcast result is too large for the core.
    """
    arrays = {k: _real_array(v, k) for k, v in named.items()}
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k}{a.shape}" for k, a in arrays.items())
        raise ValueError(f"arguments cannot be broadcast together: {shapes}") from None
    n = int(np.prod(shape, dtype=np.int64)) if shape else 1
    if n > MAX_ELEMENTS:
        shapes = ", ".join(f"{k}{a.shape}" for k, a in arrays.items())
        check_size(n, f"the broadcast of {shapes}")
    scalar = all(a.ndim == 0 for a in arrays.values())
    # one contiguous float64 copy each: the core never holds a user's array
    flats = {
        k: np.array(
            a if size1 and a.size == 1 else np.broadcast_to(a, shape), dtype=np.float64, order="C", copy=True
        ).reshape(-1)
        for k, a in arrays.items()
    }
    return shape, scalar, flats


def restore(values, shape, scalar):
    """Reshape a flat result to ``shape``; a Python float when ``scalar``."""
    values = np.asarray(values).reshape(shape)
    if scalar:
        return float(values)
    return values


def real_scalar(x, name):
    """Return ``x`` as a Python float, rejecting arrays and non-reals by name."""
    if type(x) is float or type(x) is int:
        try:
            return float(x)
        except OverflowError:
            raise ValueError(f"{name} = {x} is out of range: it exceeds the largest double") from None
    if isinstance(x, numbers.Real) and not isinstance(x, (bool, np.bool_, np.generic)):
        try:
            return float(x)  # fractions.Fraction, decimal-like numbers.Real
        except OverflowError:
            raise ValueError(f"{name} = {x} is out of range: it exceeds the largest double") from None
    arr = _real_array(x, name)
    if arr.ndim != 0:
        raise TypeError(f"{name} must be a real scalar, got an array of shape {arr.shape}")
    return float(arr)


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
        v = int(x)  # exact: Python ints do not wrap
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


def time_grid(t):
    """The output times ``t`` [s] as a contiguous 1-D float64 copy of at least one element."""
    arr = as_real(t, "t")
    if arr.ndim != 1:
        raise ValueError(f"t must be a 1-D array of output times, got an array of shape {arr.shape}")
    if arr.size < 1:
        raise ValueError("t has 0 elements: it needs at least 1 (t[0] is the initial time)")
    return np.ascontiguousarray(arr)


def output_pair(out, shape, names=("theta", "omega")):
    """The caller's output arrays ``out`` (NumPy's ``out=`` convention) checked
    for results of ``shape``: a tuple of two distinct, non-overlapping,
    writeable, C-contiguous float64 arrays of exactly that shape.  None gives
    None (the call allocates its own).  Refusing anything else (TypeError for
    the wrong kind of object or dtype, ValueError for shape, layout, a
    read-only or overlapping array) happens before any work, so a refused
    ``out`` is never written."""
    if out is None:
        return None
    what = f"out must be a tuple ({names[0]}, {names[1]}) of two float64 arrays of shape {shape}"
    if not isinstance(out, tuple):
        raise TypeError(f"{what}, got {type(out).__name__}")
    if len(out) != 2:
        raise ValueError(f"{what}, got a tuple of {len(out)}")
    for name, a in zip(names, out):
        if not isinstance(a, np.ndarray) or a.dtype != np.float64:
            got = f"dtype {a.dtype}" if isinstance(a, np.ndarray) else type(a).__name__
            raise TypeError(f"{what}; out {name} is {got}")
        if a.shape != tuple(shape):
            raise ValueError(f"{what}; out {name} has shape {a.shape}")
        if not a.flags.c_contiguous or not a.flags.writeable:
            raise ValueError(f"{what}; out {name} is {'read-only' if not a.flags.writeable else 'not C-contiguous'}")
    if np.shares_memory(out[0], out[1]):
        raise ValueError(f"{what}; out {names[0]} and {names[1]} share memory")
    return out


def step_budget(max_steps):
    """max_steps checked exactly (no wrap), capped at 2**62 for the Fortran double."""
    return min(integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True), 2**62)


class SharedTimes:
    """The output times of a SceneBatch (a read-only array this package made):
    every scene of the batch refers to it instead of holding its own copy."""

    __slots__ = ("array",)

    def __init__(self, array):
        self.array = array
