"""Plumbing shared by pendula.driven and pendula.chaos (no numerics): the
drive's parameters as the arrays the f2py layer takes, thread and count
arguments, and a Fortran batch call run so that Ctrl-C stops it and
progress=True draws a bar (pendula._longcall's watched call)."""
import numpy as np

from . import _longcall
from ._arrays import as_array, as_real, broadcast_real, check_size, integer_arg
from ._codes import DRIVEN_MAX_STEPS, DRIVEN_MIN_STEPS
from ._errors import raise_for_status


def drive_arg(drive):
    """The drive argument checked: a pendula.Drive."""
    from .driven import Drive
    if not isinstance(drive, Drive):
        raise TypeError(f"drive must be a pendula.Drive, got {type(drive).__name__}")
    return drive


def times_arg(t):
    """Output times as a 1-D float64 copy (the Fortran checks order and finiteness)."""
    arr = as_array(t, "t")
    check_size(arr.size, "t")
    arr = as_real(arr, "t")
    if arr.ndim != 1:
        raise ValueError(f"t must be a 1-D array of times, got shape {arr.shape}")
    return arr


def threads_arg(threads):
    """OpenMP threads: 0 (the OpenMP default) or a count."""
    return integer_arg(threads, "threads", 0, 4096, scalar=True)


def steps_arg(steps):
    """RK4 steps per drive period."""
    return integer_arg(steps, "steps_per_period", DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS, scalar=True)


def count_arg(x, name, lo, hi=2**31 - 1):
    """An integer count in [lo, hi]."""
    return integer_arg(x, name, lo, hi, scalar=True)


def states(drive, **named):
    """Broadcast the states and parameters; returns (shape, scalar, kwargs for the glue)."""
    shape, scalar, flats = broadcast_real(**named)
    args = dict(theta0=flats["theta0"], omega0=flats["omega0"], w0=flats["w0"], gamma=flats["gamma"],
                kind=drive.code, amp=np.array([drive.amplitude]), freq=np.array([drive.frequency]),
                phase=np.array([drive.phase]))
    return shape, scalar, args


def watched(fn, work, n, progress, **kwargs):
    """Call the glue ``fn(**kwargs, control=...)`` in a watched thread when
    ``work`` (RK4 lane steps) is large or a progress bar is wanted; raise
    for its status; return its outputs without code and message."""
    control = _longcall.new_control()
    out = _longcall.run(lambda: fn(control=control, **kwargs), control,
                        long=work > _longcall.RK4_LONG_STEPS, progress=progress, total=n, unit="state")
    out = list(out) if isinstance(out, tuple) else [out]
    code, msg = out[-2], out[-1]
    raise_for_status(code, msg)
    return out[:-2]
