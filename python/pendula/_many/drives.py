"""The ``drive=`` argument of the integrators and of ``sweep``: one
``pendula.Drive`` for every state, or an array of them (a list, nested
lists or a NumPy object array), one per state, that broadcasts with theta0,
omega0, w0, gamma like any other state argument.

A sweep over a drive parameter is an array of drives:
``[pendula.Drive("torque", F, 2/3) for F in amplitudes]``.  The drive's
fields travel to the kernels as four per-state columns (``COLUMNS``); a
batch result's ``inputs`` and a sweep's carry them as coordinates.
"""

import numpy as np

from ..driven import Drive

COLUMNS = ("drive_kind", "drive_amplitude", "drive_frequency", "drive_phase")
"""The per-state columns of a drive: its kind code (pendula_drive's
DRIVE_TORQUE or DRIVE_PIVOT, as a float), amplitude, frequency [rad/s] and
phase [rad]."""


def is_many(drive):
    """True when ``drive`` is not None and not a single ``Drive`` (then it is
    one drive per state: the call is a batch)."""
    return drive is not None and not isinstance(drive, Drive)


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
    arr = np.empty(np.shape(np.asarray(drive, dtype=object)), dtype=object)
    arr[...] = np.asarray(drive, dtype=object)
    flat = arr.reshape(-1)
    out = {k: np.empty(flat.size) for k in COLUMNS}
    for i, d in enumerate(flat):
        if not isinstance(d, Drive):
            where = [int(k) for k in np.unravel_index(i, arr.shape)]
            raise TypeError(f"drive{where} is a {type(d).__name__}: every element of drive must be a pendula.Drive")
        out["drive_kind"][i] = d.code
        out["drive_amplitude"][i] = d.amplitude
        out["drive_frequency"][i] = d.frequency
        out["drive_phase"][i] = d.phase
    return {k: v.reshape(arr.shape) for k, v in out.items()}


def kernel_args(flats):
    """The f2py arguments (kind as int32, amplitude, frequency, phase) from
    the flat columns of a broadcast (an empty batch passes one placeholder
    drive: the kernels take one drive or one per state, and f2py no
    zero-length drive arrays)."""
    if flats["drive_kind"].size == 0:
        return np.ones(1, dtype=np.int32), np.zeros(1), np.ones(1), np.zeros(1)
    return (
        np.ascontiguousarray(flats["drive_kind"], dtype=np.int32),
        flats["drive_amplitude"],
        flats["drive_frequency"],
        flats["drive_phase"],
    )


def per_state(drive, shape):
    """``drive`` for each state of a batch of ``shape``, flattened: a list of
    ``Drive`` (the same object for a single drive)."""
    n = int(np.prod(shape, dtype=np.int64)) if shape else 1
    if isinstance(drive, Drive):
        return [drive] * n
    arr = np.empty(np.shape(np.asarray(drive, dtype=object)), dtype=object)
    arr[...] = np.asarray(drive, dtype=object)
    return list(np.broadcast_to(arr, shape).reshape(-1))
