"""Memory for outputs: allocated up front, before any work, or refused with
``MemoryError`` naming what and how much (the one rule of every many-state
path, as the Fortran core's ``PENDULA_ERR_MEMORY``, whose message this one
copies).

A batch call's outputs are known before it runs (states x output times x
fields); asking for them first turns a call that could never finish into an
error in milliseconds rather than after the work.
"""

import numpy as np

#: Most bytes of trajectory one sweep chunk keeps at a time (theta and omega of
#: its states): a sweep over long grids runs in smaller chunks, not in more memory.
CHUNK_BYTES = 1 << 28


def message(what, nbytes, detail=""):
    """The out-of-memory message (the wording of pendula_status's check_alloc)."""
    detail = detail or f"{nbytes} bytes"
    size = f"{nbytes / 2**30:.3g} GiB" if nbytes >= 2**30 else f"{nbytes / 2**20:.3g} MiB"
    return f"out of memory: {what} need {size} ({detail}), which could not be allocated"


def empty(shape, what, dtype=float):
    """``numpy.empty(shape, dtype)``, or MemoryError naming ``what`` and its size
    (also for a shape too large for numpy to describe)."""
    values = int(np.prod(shape, dtype=object))
    itemsize = np.dtype(dtype).itemsize
    try:
        return np.empty(shape, dtype)
    except (MemoryError, ValueError):
        raise MemoryError(message(what, values * itemsize, f"{values} values of {itemsize} bytes")) from None


def reserve(nbytes, what):
    """Refuse up front (MemoryError naming ``what`` and its size) a call whose
    outputs, ``nbytes`` in all, cannot be allocated now: the block is asked
    for once and given back before the work."""
    block = empty((max(int(nbytes), 0),), what, dtype=np.uint8)
    del block


def guard(call, what, nbytes):
    """Run ``call()`` (an f2py call whose outputs f2py allocates first) and turn
    a MemoryError from it into one naming ``what`` and its predicted size."""
    try:
        return call()
    except MemoryError:
        raise MemoryError(message(what, nbytes)) from None
