"""The ``drive=`` argument of ``rk4``, ``cvode`` and ``sweep``: one
``pendula.Drive`` for every state, or an array of them (a list, nested lists
or a NumPy object array), one per state, that broadcasts with theta0,
omega0, w0, gamma like any other state argument.

A sweep over a drive parameter is an array of drives:
``[pendula.Drive("torque", F, 2/3) for F in amplitudes]``.  Here the drive
becomes the four per-state columns of ``pendula._many.drives.COLUMNS``,
which the batch machinery and the kernels take (``_many`` does not know the
public ``Drive`` type); a batch result's ``inputs`` and a sweep's carry them.
"""

import numpy as np

from ._many.drives import COLUMNS
from .driven import Drive


def is_many(drive):
    """True when ``drive`` is not None and not a single ``Drive`` (then it is
    one drive per state: the call is a batch)."""
    return drive is not None and not isinstance(drive, Drive)


def _object_array(drive):
    arr = np.empty(np.shape(np.asarray(drive, dtype=object)), dtype=object)
    arr[...] = np.asarray(drive, dtype=object)
    return arr


def columns(drive):
    """The four columns (``COLUMNS``) of ``drive`` as float arrays of the
    drive's shape (() for one Drive).  Raises TypeError naming ``drive`` (and
    the element) for anything but a Drive or an array of Drives."""
    if isinstance(drive, Drive):
        return dict(
            zip(COLUMNS, (np.array(float(v)) for v in (drive.code, drive.amplitude, drive.frequency, drive.phase)))
        )
    if isinstance(drive, (str, bytes, dict)) or not isinstance(drive, (list, tuple, np.ndarray)):
        raise TypeError(
            f"drive must be a pendula.Drive or an array of them (one per state), got {type(drive).__name__}"
        )
    arr = _object_array(drive)
    flat = arr.reshape(-1)
    out = {k: np.empty(flat.size) for k in COLUMNS}
    for i, d in enumerate(flat):
        if not isinstance(d, Drive):
            where = [int(k) for k in np.unravel_index(i, arr.shape)]
            raise TypeError(f"drive{where} is a {type(d).__name__}: every element of drive must be a pendula.Drive")
        for k, v in zip(COLUMNS, (d.code, d.amplitude, d.frequency, d.phase)):
            out[k][i] = v
    return {k: v.reshape(arr.shape) for k, v in out.items()}


def per_state(drive, shape):
    """``drive`` for each state of a batch of ``shape``, flattened: a list of
    ``Drive`` (the same object for a single drive)."""
    n = int(np.prod(shape, dtype=np.int64)) if shape else 1
    if isinstance(drive, Drive):
        return [drive] * n
    return list(np.broadcast_to(_object_array(drive), shape).reshape(-1))
