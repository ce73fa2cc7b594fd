"""A drive in the batch machinery: four per-state columns (``COLUMNS``) that
broadcast with the state arguments and travel to the kernels.  The public
``drive=`` (a ``pendula.Drive`` or an array of them) becomes these columns in
``pendula._drive_args``, above this layer.
"""

import numpy as np

COLUMNS = ("drive_kind", "drive_amplitude", "drive_frequency", "drive_phase")
"""The per-state columns of a drive: its kind code (pendula_drive's
DRIVE_TORQUE or DRIVE_PIVOT, as a float), amplitude, frequency [rad/s] and
phase [rad]."""


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
