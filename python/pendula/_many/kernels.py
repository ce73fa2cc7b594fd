"""The Fortran batch kernels: many pendulums per call, the GIL released.

``rk4_batch`` integrates every state of a NumPy-broadcast batch with the
Fortran batch kernel (pendula_rk4_batch): SIMD blocks of states on OpenMP
threads, each state bit-identical to ``pendula.rk4`` for the same arguments.
``cvode_batch`` does the same with CVODE: one solver per thread, restarted
for each state (CVodeReInit), each state bit-identical to ``pendula.cvode``.
A state that fails (unstable h, bad value, non-finite result) gets its own
status code and NaN outputs from the point it failed (the package's failure
contract, docs/robustness.md); the others are unaffected.
"""

from dataclasses import dataclass

import numpy as np

from .. import _fortran, _memory
from .._arrays import broadcast_real, integer_arg, output_pair, time_grid
from .._defaults import (
    CVODE_ATOL,
    CVODE_MAX_STEPS,
    CVODE_METHOD,
    CVODE_METHODS,
    CVODE_RTOL,
    RK4_MAX_STEPS,
    STAT_NAMES,
    choose_threads,
)
from .._errors import ERR_CANCELLED, OK, _text, raise_for_status
from . import drives as _drives


@dataclass(frozen=True)
class BatchResult:
    """Result of a batch integration.

    t: the output times [s], shape (n_t,).  theta [rad], omega [rad/s]:
    shape batch_shape + (n_t,) (NaN for a failed state).  codes: status
    code per state (``pendula._errors``: 0 = ok), shape batch_shape.
    steps: RK4 steps per state.  code, message: the summary (0 and '' when
    every state succeeded; ERR_CANCELLED when the call was cancelled; else
    the first failed state's code and pendula.rk4's message for it, which
    is rewritten by the callers in the package's index convention).  first_failed: flat index of the first failed
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


@dataclass(frozen=True)
class CvodeBatchResult(BatchResult):
    """Result of a CVODE batch: ``BatchResult`` (steps = CVODE steps per
    state), plus stats, CVODE's counters per state as a dict of int64 arrays
    of shape batch_shape (the keys of ``pendula.cvode``'s stats), and the
    method.  A failed state keeps the outputs before its failure time (NaN
    after); a cancelled one is NaN.
    """

    stats: dict = None
    method: str = CVODE_METHOD


def _control(control):
    if control is None:
        return np.zeros(2, dtype=np.int64)
    if not (
        isinstance(control, np.ndarray)
        and control.dtype == np.int64
        and control.shape == (2,)
        and control.flags.c_contiguous
        and control.flags.writeable
    ):
        raise TypeError("control must be a writeable contiguous int64 numpy array of shape (2,)")
    return control


def rk4_work(tt, h):
    """Predicted work of an RK4 batch in steps: sum over the states of span/h + outputs."""
    h = np.asarray(h, dtype=float)
    with np.errstate(all="ignore"):  # inf/NaN work (extreme windows, h): threads, the kernel refuses what it must
        per = float(tt[-1] - tt[0]) / h + tt.size
        return float(np.sum(per)) if h.size else 0.0


def cvode_work(tt, w0, n):
    """Predicted work of a CVODE batch of ``n`` states in RK4-step units:
    ~50 steps a period of the fastest state, plus the outputs, per state."""
    with np.errstate(all="ignore"):
        periods = abs(float(tt[-1] - tt[0])) * float(np.max(np.asarray(w0, dtype=float), initial=0.0)) / (2 * np.pi)
        return n * (periods * 50 + tt.size)


def _with_drive(named, drive):
    """The named state arguments plus the drive's columns (``drive``: a dict
    of ``drives.COLUMNS``, arrays that broadcast with the states)."""
    if drive is None:
        return named
    return dict(named, **{k: drive[k] for k in _drives.COLUMNS})


def rk4_batch(
    t, theta0, omega0, w0, gamma, h, threads=None, control=None, max_steps=RK4_MAX_STEPS, drive=None, out=None
):
    """RK4 (as ``pendula.rk4``) for a batch of states over one output grid.

    t: strictly increasing, finite output times [s], 1-D, shared by every
    state.  theta0 [rad], omega0 [rad/s], w0 > 0, gamma >= 0 [1/s] and the
    step h > 0 [s] broadcast together like NumPy to the batch shape; each
    state uses its own h.  threads: None (chosen from the predicted work,
    ``pendula._defaults.choose_threads``), 0 (the OpenMP default, which
    honours OMP_NUM_THREADS) or a count; one thread in a process forked after
    its parent used more, since GNU OpenMP is not fork-safe.  control:
    optional int64 array of 2 (pendula_control): setting control[0] from
    another thread cancels the call (finished states keep their results; the
    unfinished get ERR_CANCELLED); control[1] counts finished states.

    drive: None, or the drive as a dict of its columns (``drives.COLUMNS``,
    arrays that broadcast with the states; ``pendula._drive_args.columns``
    makes them from a Drive or an array of Drives): the driven pendulum
    (pendula_rk4_batch's drive path, bit-identical to ``pendula.rk4`` with
    the state's drive).

    out: None, or (theta, omega) arrays of the result's shape that the kernel
    fills in place (``output_pair``): repeated calls then reuse their pages.

    Returns a ``BatchResult`` (a failed state's rows NaN: the kernel keeps no
    partial series).  Raises TypeError/ValueError for arguments that refuse
    the whole call (t, shapes, threads, control); per-state failures are
    reported in ``codes``, never raised.
    """
    tt = time_grid(t)
    shape, _, flats = broadcast_real(**_with_drive(dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, h=h), drive))
    budget = float(min(integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True), 2**62))
    nthreads = choose_threads(threads, rk4_work(tt, flats["h"]))
    control = _control(control)
    n = flats["theta0"].size
    states = tuple(flats[k] for k in ("theta0", "omega0", "w0", "gamma", "h"))
    n_t = tt.size
    given = output_pair(out, shape + (n_t,))

    # The outputs in C order (n, n_t), passed as their transposes, the Fortran
    # (n_t, n) blocks the kernel fills in place: each state's series is
    # contiguous, nothing is copied, and numpy.empty leaves the pages untouched
    # until the kernel's threads write them (f2py would zero-fill outputs it
    # allocates itself, on this thread, before any work).  f2py refuses a
    # zero-size inout array, so an empty batch passes one unused column.
    def outputs():
        if given is not None:
            theta, omega = (a.reshape(n, n_t) for a in given)  # views: C-contiguous
        else:
            theta, omega = np.empty((n, n_t)), np.empty((n, n_t))
        if n == 0:
            return theta, omega, np.empty((n_t, 1), order="F"), np.empty((n_t, 1), order="F")
        return theta, omega, theta.T, omega.T

    if drive is None:

        def call():
            theta, omega, th_f, om_f = outputs()
            out = _fortran.rk4_batch_f2py(tt, *states, budget, nthreads, control, th_f, om_f)
            return (theta, omega) + tuple(out)
    else:

        def call():
            theta, omega, th_f, om_f = outputs()
            out = _fortran.rk4_batch_drive_f2py(
                tt, *states, *_drives.kernel_args(flats), budget, nthreads, control, th_f, om_f
            )
            return (theta, omega) + tuple(out)

    # the outputs (n_t x n each) are allocated before any work: refused at once
    theta, omega, codes, steps, first, code, msg = _memory.guard(
        call,
        f"the outputs theta and omega of {n} states x {tt.size} times",
        _trajectory_bytes(n, tt.size),
    )
    code, first = int(code), int(first)
    if code != OK and first == 0 and code != ERR_CANCELLED:
        raise_for_status(code, msg)  # the call itself was refused
    # a failed state's row is already NaN (pendula_rk4_batch writes NaN for it)
    # the caller's arrays themselves when given, as NumPy's out= returns them
    theta, omega = given or (theta.reshape(shape + (n_t,)), omega.reshape(shape + (n_t,)))
    return BatchResult(
        t=tt,
        theta=theta,
        omega=omega,
        codes=codes.astype(np.int64).reshape(shape),
        steps=steps.astype(np.int64).reshape(shape),
        code=code,
        message=_text(msg) if code else "",
        first_failed=first - 1,
    )


def cvode_batch(
    t,
    theta0,
    omega0,
    w0,
    gamma,
    rtol=CVODE_RTOL,
    atol=CVODE_ATOL,
    method=CVODE_METHOD,
    max_steps=CVODE_MAX_STEPS,
    threads=None,
    control=None,
    events=False,
    drive=None,
):
    """CVODE (as ``pendula.cvode``) for a batch of states over one output grid.

    t: strictly increasing, finite output times [s], 1-D, shared by every
    state.  theta0 [rad], omega0 [rad/s], w0 > 0, gamma >= 0 [1/s] and the
    tolerances rtol > 0, atol >= 0 broadcast together like NumPy to the batch
    shape; method ("adams" or "bdf") and the per-state step budget max_steps
    are shared.  Each state's theta, omega, stats and code are bit-identical
    to ``pendula.cvode`` for the same arguments (whose exception becomes the
    state's code; a failed state's outputs after its failure are NaN).
    threads, control: as ``rk4_batch`` (control[1] counts finished states).
    events: not supported in batch mode (ValueError for True: call
    ``pendula.cvode(..., events=True)`` per state).  drive: as ``rk4_batch``.

    Returns a ``CvodeBatchResult``.  Raises TypeError/ValueError for arguments
    that refuse the whole call (t, shapes, method, max_steps, threads,
    control, events), NotImplementedError when this build has no CVODE;
    per-state failures are reported in ``codes``, never raised.
    """
    if not isinstance(events, bool):
        raise TypeError(f"events must be True or False, got {type(events).__name__}")
    if events:
        raise ValueError(
            "events=True is not supported by cvode_batch: call pendula.cvode(..., events=True) "
            "for each state that needs its events"
        )
    tt = time_grid(t)
    shape, _, flats = broadcast_real(
        **_with_drive(dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, rtol=rtol, atol=atol), drive)
    )
    if not isinstance(method, str) or method.lower() not in CVODE_METHODS:
        raise ValueError(f"method = {method!r} is invalid: it must be 'adams' or 'bdf'")
    max_steps = integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True)
    nthreads = choose_threads(threads, cvode_work(tt, flats["w0"], flats["theta0"].size))
    control = _control(control)
    n = flats["theta0"].size
    states = tuple(flats[k] for k in ("theta0", "omega0", "w0", "gamma", "rtol", "atol"))
    settings = (CVODE_METHODS[method.lower()], float(min(max_steps, 2**62)), nthreads, control)
    if drive is None:

        def call():
            return _fortran.cvode_batch_f2py(tt, *states, *settings)
    else:

        def call():
            return _fortran.cvode_batch_drive_f2py(tt, *states, *_drives.kernel_args(flats), *settings)

    theta, omega, codes, stats, first, code, msg = _memory.guard(
        call,
        f"the outputs theta and omega of {n} states x {tt.size} times",
        _trajectory_bytes(n, tt.size),
    )
    code, first = int(code), int(first)
    if code != OK and first == 0 and code != ERR_CANCELLED:
        raise_for_status(code, msg)  # the call itself was refused
    n_t = tt.size
    # a failed state is NaN from its failure time (pendula_cvode_batch), a
    # cancelled one throughout
    theta, omega = theta.T, omega.T
    # stats has shape (7, n): row i is counter i of every state
    counts = {name: stats[i].astype(np.int64).reshape(shape) for i, name in enumerate(STAT_NAMES)}
    return CvodeBatchResult(
        t=tt,
        theta=theta.reshape(shape + (n_t,)),
        omega=omega.reshape(shape + (n_t,)),
        codes=codes.astype(np.int64).reshape(shape),
        steps=counts["steps"],
        code=code,
        message=_text(msg) if code else "",
        first_failed=first - 1,
        stats=counts,
        method=method.lower(),
    )


def _trajectory_bytes(n, n_t):
    """Bytes of a batch's theta and omega: n states x n_t times, float64 (the
    one prediction of a batch's output size: the batch calls and sweep use it)."""
    return 2 * 8 * n * n_t


def openmp():
    """True when this build runs the batch kernels on OpenMP threads."""
    return bool(_fortran.rk4_batch_openmp_f2py())
