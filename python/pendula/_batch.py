"""Many pendulums per call (private: the public broadcast API comes later).

``cvode_batch`` does the same with CVODE: one solver per thread, restarted
for each state (CVodeReInit), each state bit-identical to ``pendula.cvode``.
``rk4_batch`` integrates every state of a NumPy-broadcast batch with the
Fortran batch kernel (pendula_rk4_batch): SIMD blocks of states on OpenMP
threads, the GIL released, each state bit-identical to ``pendula.rk4`` for
the same arguments.  A state that fails (unstable h, bad value, non-finite
result) gets its own status code and zero outputs; the others are unaffected.
"""
import numbers
import os
from dataclasses import dataclass

import numpy as np

from . import _fortran, _memory
from ._arrays import broadcast_real, integer_arg
from ._errors import OK, ERR_CANCELLED, _text, raise_for_status
from .integrate import _METHODS, _STAT_NAMES, _grid


@dataclass(frozen=True)
class BatchResult:
    """Result of a batch integration.

    t: the output times [s], shape (n_t,).  theta [rad], omega [rad/s]:
    shape batch_shape + (n_t,) (zero for a failed state).  codes: status
    code per state (``pendula._errors``: 0 = ok), shape batch_shape.
    steps: RK4 steps per state.  code, message: the summary (0 and '' when
    every state succeeded; ERR_CANCELLED when the call was cancelled; else
    the first failed state's code and pendula.rk4's message for it, which
    numbers states from 1).  first_failed: flat index of the first failed
    state, or -1.
    """
    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    codes: np.ndarray
    steps: np.ndarray
    code: int
    message: str
    first_failed: int

    @property
    def ok(self):
        """Boolean mask of the states that succeeded (shape batch_shape)."""
        return self.codes == OK


# GNU OpenMP is not fork-safe: a child forked after its parent ran a
# multi-threaded region hangs in its own first one (the thread pool it
# inherits has no threads).  The pid that started the pool is remembered; a
# forked child runs its batches on one thread (same results, bit for bit).
_pool_pid = None


def _threads(threads):
    global _pool_pid
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads must be an integer, got {type(threads).__name__}")
    if threads < 0 or threads > 4096:
        raise ValueError(f"threads = {threads} is out of range: it must be in [0, 4096] (0: the OpenMP default)")
    if threads == 1:
        return 1
    pid = os.getpid()
    if _pool_pid is None:
        _pool_pid = pid
    return int(threads) if _pool_pid == pid else 1


@dataclass(frozen=True)
class CvodeBatchResult(BatchResult):
    """Result of a CVODE batch: ``BatchResult`` (steps = CVODE steps per
    state), plus stats, CVODE's counters per state as a dict of int64 arrays
    of shape batch_shape (the keys of ``pendula.cvode``'s stats), and the
    method.  A failed state keeps the outputs before its failure time (zero
    after), as the Fortran cvode_solve returns them; a cancelled one is zero.
    """
    stats: dict = None
    method: str = "adams"




def _control(control):
    if control is None:
        return np.zeros(2, dtype=np.int64)
    if not (isinstance(control, np.ndarray) and control.dtype == np.int64 and control.shape == (2,)
            and control.flags.c_contiguous and control.flags.writeable):
        raise TypeError("control must be a writeable contiguous int64 numpy array of shape (2,)")
    return control


def rk4_batch(t, theta0, omega0, w0, gamma, h, threads=0, control=None, max_steps=2_000_000_000):
    """RK4 (as ``pendula.rk4``) for a batch of states over one output grid.

    t: strictly increasing, finite output times [s], 1-D, shared by every
    state.  theta0 [rad], omega0 [rad/s], w0 > 0, gamma >= 0 [1/s] and the
    step h > 0 [s] broadcast together like NumPy to the batch shape; each
    state uses its own h.  threads: OpenMP threads (0 = the OpenMP default,
    which honours OMP_NUM_THREADS; one thread in a process forked after its
    parent used more, since GNU OpenMP is not fork-safe).  control: optional int64 array of 2
    (pendula_control): setting control[0] from another thread cancels the
    call (finished states keep their results; the unfinished get
    ERR_CANCELLED); control[1] counts finished states.

    Returns a ``BatchResult``.  Raises TypeError/ValueError for arguments
    that refuse the whole call (t, shapes, threads, control); per-state
    failures are reported in ``codes``, never raised.
    """
    tt = _grid(t)
    shape, _, flats = broadcast_real(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, h=h)
    budget = float(min(integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True), 2**62))
    nthreads = _threads(threads)
    control = _control(control)
    n = flats["theta0"].size
    # f2py allocates theta and omega (n_t x n each) before any work: refused at once
    theta, omega, codes, steps, first, code, msg = _memory.guard(lambda: _fortran.rk4_batch_f2py(
        tt, *(flats[k] for k in ("theta0", "omega0", "w0", "gamma", "h")), budget, nthreads, control),
        f"the outputs theta and omega of {n} states x {tt.size} times", _trajectory_bytes(n, tt.size))
    code, first = int(code), int(first)
    if code != OK and first == 0 and code != ERR_CANCELLED:
        raise_for_status(code, msg)   # the call itself was refused
    n_t = tt.size
    # Fortran's (n_t, n) column-major block is the C-order (n, n_t) array:
    # each state's series contiguous, no copy.
    return BatchResult(t=tt, theta=theta.T.reshape(shape + (n_t,)), omega=omega.T.reshape(shape + (n_t,)),
                       codes=codes.astype(np.int64).reshape(shape), steps=steps.astype(np.int64).reshape(shape),
                       code=code, message=_text(msg) if code else "", first_failed=first - 1)


def cvode_batch(t, theta0, omega0, w0, gamma, rtol=1e-8, atol=1e-10, method="adams", max_steps=10_000_000,
                threads=0, control=None, events=False):
    """CVODE (as ``pendula.cvode``) for a batch of states over one output grid.

    t: strictly increasing, finite output times [s], 1-D, shared by every
    state.  theta0 [rad], omega0 [rad/s], w0 > 0, gamma >= 0 [1/s] and the
    tolerances rtol > 0, atol >= 0 broadcast together like NumPy to the batch
    shape; method ("adams" or "bdf") and the per-state step budget max_steps
    are shared.  Each state's theta, omega, stats and code are bit-identical
    to ``pendula.cvode`` for the same arguments (whose exception becomes the
    state's code).  threads, control: as ``rk4_batch`` (control[1] counts
    finished states).  events: not supported in batch mode (ValueError for
    True: call ``pendula.cvode(..., events=True)`` per state).

    Returns a ``CvodeBatchResult``.  Raises TypeError/ValueError for arguments
    that refuse the whole call (t, shapes, method, max_steps, threads,
    control, events), NotImplementedError when this build has no CVODE;
    per-state failures are reported in ``codes``, never raised.
    """
    if not isinstance(events, bool):
        raise TypeError(f"events must be True or False, got {type(events).__name__}")
    if events:
        raise ValueError("events=True is not supported by cvode_batch: call pendula.cvode(..., events=True) "
                         "for each state that needs its events")
    tt = _grid(t)
    shape, _, flats = broadcast_real(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, rtol=rtol, atol=atol)
    if not isinstance(method, str) or method.lower() not in _METHODS:
        raise ValueError(f"method = {method!r} is invalid: it must be 'adams' or 'bdf'")
    max_steps = integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True)
    nthreads = _threads(threads)
    control = _control(control)
    n = flats["theta0"].size
    theta, omega, codes, stats, first, code, msg = _memory.guard(lambda: _fortran.cvode_batch_f2py(
        tt, *(flats[k] for k in ("theta0", "omega0", "w0", "gamma", "rtol", "atol")),
        _METHODS[method.lower()], float(min(max_steps, 2**62)), nthreads, control),
        f"the outputs theta and omega of {n} states x {tt.size} times", _trajectory_bytes(n, tt.size))
    code, first = int(code), int(first)
    if code != OK and first == 0 and code != ERR_CANCELLED:
        raise_for_status(code, msg)   # the call itself was refused
    n_t = tt.size
    # stats has shape (7, n): row i is counter i of every state
    counts = {name: stats[i].astype(np.int64).reshape(shape) for i, name in enumerate(_STAT_NAMES)}
    return CvodeBatchResult(t=tt, theta=theta.T.reshape(shape + (n_t,)), omega=omega.T.reshape(shape + (n_t,)),
                            codes=codes.astype(np.int64).reshape(shape), steps=counts["steps"], code=code,
                            message=_text(msg) if code else "", first_failed=first - 1, stats=counts,
                            method=method.lower())


def _trajectory_bytes(n, n_t):
    """Bytes of a batch's theta and omega: n states x n_t times, float64 (the
    one prediction of a batch's output size: the batch calls and sweep use it)."""
    return 2 * 8 * n * n_t


def openmp():
    """True when this build runs the batch kernels on OpenMP threads."""
    return bool(_fortran.rk4_batch_openmp_f2py())
