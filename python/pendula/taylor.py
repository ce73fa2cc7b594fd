"""The nonlinear damped pendulum theta'' + gamma theta' + w0**2 sin(theta) = 0
(text eq. 2.2) by an adaptive Taylor-series method (Jorba & Zou 2005).

``taylor`` takes the accuracy the user wants at the outputs (``tol``,
absolute: theta in rad, Omega/w0 in rad) and nothing else: the order and the
steps follow from it, the output grid costs no steps (dense output from the
step polynomials), a decreasing ``t`` integrates backwards, and every output
carries an error estimate (``result.error``).

Examples
--------
>>> import numpy as np, pendula
>>> r = pendula.taylor(np.linspace(0, 30, 31), 2.5, 0.0, np.sqrt(2), 0.1, tol=1e-12)
>>> r.method, bool(r.error.max() <= 1e-12)
('taylor', True)
"""

import math
from dataclasses import dataclass, field

import numpy as np

from . import _fortran, _longcall
from ._arrays import broadcast_real, integer_arg, real_scalar, time_grid
from ._defaults import (
    MAX_EVENTS,
    POOL_STATE_WORK,
    STAT_NAMES,
    TAYLOR_MAX_STEPS,
    TAYLOR_TOL,
    THREADS,
    check_threads,
    choose_threads,
)
from ._errors import ERR_CANCELLED, OK, _text, batch_summary, for_state, raise_for_status, raise_if_all_failed
from ._many import pool
from ._many.ensemble import BatchIntegrationResult, inputs, is_batch, summary
from .driven import Drive
from .integrate import Events, IntegrationResult

_BATCH_ARGS = ("theta0", "omega0", "w0", "gamma", "tol")

# The counters a Taylor run does not use (the series has no Jacobian, no
# error-test failures, no nonlinear solves, no root function).
_NO_STATS = dict.fromkeys(STAT_NAMES[2:], 0)

# Steps per unit w0 t that a run takes at most (for deciding when a call is
# long enough to run watched: cancellable, with progress).
_STEPS_PER_RADIAN = 4.0


@dataclass(frozen=True, repr=False)
class TaylorResult(IntegrationResult):
    """``IntegrationResult`` of ``taylor``, with its error estimate.

    Parameters
    ----------
    t : numpy.ndarray
        Output times [s], shape (n_t,).
    theta, omega : numpy.ndarray
        Angle [rad] and angular velocity [rad/s] at t.
    stats : dict
        Work counters (see Notes).
    method : str
        "taylor".
    events : Events, optional
        For ``taylor(..., events=True)``, else None.
    error : numpy.ndarray
        Estimated bound on the absolute error at each output [rad]: the
        larger of theta's and of Omega/w0's; ``error[0] == 0``.
    tol : float
        The accuracy asked for.

    Notes
    -----
    ``stats`` has the keys of the other integrators plus ``order``, the
    series order (``rhs_evals`` = steps x order series terms).

    Examples
    --------
    >>> import pendula
    >>> r = pendula.taylor([0.0, 1.0], 1.0, 0.0, 1.0, 0.0, tol=1e-10)
    >>> r.stats["order"] >= 10, bool(r.error[-1] < 1e-10)
    (True, True)
    """

    error: np.ndarray = field(default=None)
    tol: float = field(default=None)

    def __repr__(self):
        return (
            IntegrationResult.__repr__(self)[:-1] + f"\n  order={self.stats.get('order')}, "
            f"error estimate <= {float(np.max(self.error)):.3g} rad (tol {self.tol:.3g}))"
        )


@dataclass(frozen=True, repr=False)
class TaylorBatchResult(BatchIntegrationResult):
    """``BatchIntegrationResult`` of ``taylor``, with its error estimates.

    Parameters
    ----------
    t : numpy.ndarray
        Output times [s], shape (n_t,).
    theta, omega : numpy.ndarray
        [rad], [rad/s], shape batch_shape + (n_t,); NaN for a failed state.
    stats : dict
        int64 arrays of shape batch_shape: the scalar result's stats, with ``order``.
    method : str
        "taylor".
    codes : numpy.ndarray
        int64 status per state (0 = ok).
    message : str
        '' when every state succeeded, else the first failed state's message.
    first_failed : int
        Flat index of the first failed state, or -1.
    events : numpy.ndarray, optional
        With events=True, an object array of ``Events`` (None for a failed state).
    error : numpy.ndarray
        Estimated error bound of each output [rad], shape batch_shape +
        (n_t,) (NaN for a failed state).
    tol : numpy.ndarray
        The accuracy asked for, per state (batch_shape).

    Examples
    --------
    >>> import pendula
    >>> b = pendula.taylor([0.0, 1.0], [0.5, 1.0], 0.0, 1.0, 0.0, tol=1e-10)
    >>> b.error.shape, bool(b.ok.all())
    ((2, 2), True)
    """

    error: np.ndarray = field(default=None)
    tol: np.ndarray = field(default=None)


def taylor(
    t,
    theta0,
    omega0,
    w0,
    gamma,
    *,
    tol=TAYLOR_TOL,
    events=False,
    max_events=MAX_EVENTS,
    max_steps=TAYLOR_MAX_STEPS,
    progress=None,
    threads=THREADS,
    drive=None,
):
    """Integrate theta'' + gamma theta' + w0**2 sin(theta) = 0 by a Taylor method to accuracy tol.

    Parameters
    ----------
    t : array_like
        Strictly monotonic, finite output times [s], 1-D, at least one;
        t[0] is the initial time.  Decreasing times integrate backwards.
    theta0, omega0 : float or array_like
        Initial angle [rad] and angular velocity [rad/s] at t[0], finite.
    w0 : float or array_like
        Small-angle angular frequency sqrt(g/l) [1/s], > 0.
    gamma : float or array_like
        Damping rate [1/s], >= 0.
    tol : float or array_like
        Absolute accuracy wanted at every output, in (0, 1]: theta in rad,
        Omega/w0 in rad.  Not a per-step tolerance: the steps' own target
        is set from it and the length of the window.
    events : bool
        Also locate turning points (Omega = 0) and passes through the
        bottom (theta = 0 mod 2 pi) after t[0], by root finding on the step
        polynomials (times to a few ulps of the step).
    max_events : int
        Events kept, 1 ... 10**7 (``result.events.truncated`` tells if more
        occurred).
    max_steps : int
        Step budget per state, >= 1.
    progress : bool or callable, optional
        True for a tqdm bar, or a callable(done, total) (steps, or states of
        a batch).
    threads : int or None
        OpenMP threads of a batch: None (the default) chooses from the
        predicted work, 0 asks for the OpenMP default (OMP_NUM_THREADS or
        every core), a count is used as given.
    drive : Drive, optional
        A periodic drive (:class:`pendula.Drive`: a torque
        F cos(Omega t + phi) or a vertically driven pivot), the same for
        every state of a batch; its phase holds at t = 0.  The error
        estimate then grows by Gronwall's bound (no shear model: the driven
        pendulum may be chaotic), so long driven windows report large
        estimates honestly.

    Returns
    -------
    TaylorResult or TaylorBatchResult
        theta [rad], omega [rad/s] at t, ``error`` (the estimated error
        bound per output [rad]), stats (steps, order), events when asked.
        Subclasses of ``IntegrationResult`` / ``BatchIntegrationResult``.

    Raises
    ------
    ValueError
        For bad arguments (naming them).
    TypeError
        For non-real input, a non-bool events or a non-integer max_steps.
    PendulaSolverError
        When max_steps is exhausted or the state stops being finite.
    KeyboardInterrupt
        Ctrl-C during a long run.

    Notes
    -----
    The series come from the automatic-differentiation recurrences of
    sin and cos; the steps follow from a per-step target eps (Jorba & Zou
    2005) and the order from this code's cost per step,
    p = ceil(0.8 ln(1/eps)) + 2 (Jorba & Zou's ceil(ln(1/eps)/2) + 1 for
    rounding-limited windows, whose rounding grows with the step).  The state and time are
    carried in double-double, so rounding grows with the size of the
    increments, not with the number of steps.  ``error`` propagates the
    local truncation and rounding bounds with the pendulum's phase shear
    (linear in time; large near the separatrix, where it says so) and is
    checked against mpmath and the exact elliptic solution in the tests.
    About 0.35-0.45 us a step at order 25-36; 0.5-3 steps per radian of w0 t.

    Batches: theta0, omega0, w0, gamma and tol broadcast like NumPy (as
    for ``rk4``); each state is bit-identical to the scalar call; a bad
    value raises ValueError naming the first bad state; a state that fails
    over the window gets its own code.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> t = np.linspace(0.0, 20.0, 201)
    >>> r = pendula.taylor(t, 2.0, 0.0, 1.0, 0.0, tol=1e-13)
    >>> exact, _ = pendula.undamped(t, 2.0, 0.0, 1.0)
    >>> bool(np.max(abs(r.theta - exact)) <= r.error.max() <= 1e-13)
    True
    >>> back = pendula.taylor(t[::-1], r.theta[-1], r.omega[-1], 1.0, 0.0, tol=1e-13)
    >>> bool(abs(back.theta[-1] - 2.0) < 1e-13)
    True
    >>> ev = pendula.taylor([0.0, 7.0], 1.0, 0.0, 1.0, 0.0, events=True).events
    >>> ev
    Events(4 events (2 turning points, 2 zero crossings), t in [1.675, 6.7] s)
    """
    if not isinstance(events, bool):
        raise TypeError(f"events must be True or False, got {type(events).__name__}")
    if drive is not None and not isinstance(drive, Drive):
        raise TypeError(f"drive must be a pendula.Drive or None, got {type(drive).__name__}")
    dargs = (0, 0.0, 1.0, 0.0) if drive is None else (drive.code, drive.amplitude, drive.frequency, drive.phase)
    if type(t) is np.ndarray and t.dtype.char == "d" and t.ndim == 1 and 1 <= t.size < 2**31:
        tt = t.copy()  # the result keeps its own grid
    else:
        tt = time_grid(t)
    if type(max_steps) is int and 1 <= max_steps <= 2**62:
        budget = float(max_steps)
    else:
        budget = float(min(integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True), 2**62))
    m = integer_arg(max_events, "max_events", 1, 10**7, scalar=True) if events else 0
    if type(theta0) is float and type(omega0) is float and type(w0) is float and type(gamma) is float:
        if type(tol) is float:  # one state given as Python floats: nothing to convert
            check_threads(threads)
            return _one(tt, theta0, omega0, w0, gamma, tol, budget, m, progress, dargs=dargs)
    if is_batch(theta0, omega0, w0, gamma, tol):
        return _batch(tt, theta0, omega0, w0, gamma, tol, budget, m, progress, threads, dargs)
    check_threads(threads)  # checked, unused: one state runs on one thread
    args = [
        x if type(x) is float else real_scalar(x, name)
        for x, name in ((theta0, "theta0"), (omega0, "omega0"), (w0, "w0"), (gamma, "gamma"), (tol, "tol"))
    ]
    return _one(tt, *args, budget, m, progress, dargs=dargs)


def _one(tt, theta0, omega0, w0, gamma, tol, budget, m, progress, control=None, dargs=(0, 0.0, 1.0, 0.0)):
    watched = control is None
    # in Python floats (no NumPy scalars, no errstate: this is most of a short
    # call's cost); an overflow gives inf, a NaN compares False
    steps = abs(tt.item(-1) - tt.item(0)) * (w0 + gamma) * _STEPS_PER_RADIAN if w0 > 0 else 0.0
    if not steps < math.inf:
        steps = 0.0  # a bad t, w0 or gamma: refused by the Fortran checks
    long = watched and steps > _longcall.RK4_LONG_STEPS / 20
    if watched and not long and progress is None and not m and not dargs[0]:
        theta, omega, err, work, code, msg = _fortran.taylor_plain_f2py(
            tt, theta0, omega0, w0, gamma, tol, budget, _longcall.scratch_control()
        )
        if code:
            raise_for_status(code, msg)
        n_steps, order = work.tolist()
        n_steps, order = int(n_steps), int(order)
        st = {"steps": n_steps, "rhs_evals": n_steps * order}
        st.update(_NO_STATS)
        st["order"] = order
        r = object.__new__(TaylorResult)
        r.__dict__.update(t=tt, theta=theta, omega=omega, stats=st, method="taylor", events=None, error=err, tol=tol)
        return r
    if watched and not long and progress is None:
        (theta, omega, err, stats, order, ev_t, ev_kind, ev_theta, ev_omega, n_ev, trunc, code, msg) = (
            _fortran.taylor_f2py(tt, theta0, omega0, w0, gamma, tol, budget, m, _longcall.scratch_control(), *dargs)
        )
    else:
        control = _longcall.new_control() if watched else control
        call = (tt, theta0, omega0, w0, gamma, tol, budget, m, control, *dargs)
        (theta, omega, err, stats, order, ev_t, ev_kind, ev_theta, ev_omega, n_ev, trunc, code, msg) = _longcall.run(
            lambda: _fortran.taylor_f2py(*call), control, long, progress, total=int(min(steps, 2**62))
        )
    ev = None
    if m:
        n = int(n_ev)
        ev = Events(
            t=ev_t[:n].copy(),
            kind=ev_kind[:n].astype(np.int64),
            theta=ev_theta[:n].copy(),
            omega=ev_omega[:n].copy(),
            truncated=bool(trunc),
        )
    if code:
        raise_for_status(code, msg)
    st = dict(zip(STAT_NAMES, map(int, stats.tolist())))
    st["order"] = int(order)
    # as TaylorResult(...), without the frozen dataclass's per-field __setattr__
    r = object.__new__(TaylorResult)
    r.__dict__.update(t=tt, theta=theta, omega=omega, stats=st, method="taylor", events=ev, error=err, tol=tol)
    return r


def _batch(tt, theta0, omega0, w0, gamma, tol, budget, m, progress, threads, dargs):
    check_threads(threads)
    shape, _, flats = broadcast_real(size1=True, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, tol=tol)
    n = int(np.prod(shape, dtype=np.int64))
    given = inputs(shape, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, tol=tol)
    if n == 0:
        empty = np.zeros(shape + (tt.size,))
        return TaylorBatchResult(
            t=tt,
            theta=empty,
            omega=empty.copy(),
            stats={},
            method="taylor",
            codes=np.zeros(shape, dtype=np.int64),
            message="",
            first_failed=-1,
            error=empty.copy(),
            tol=np.zeros(shape),
            inputs=given,
        )
    th0 = np.ascontiguousarray(
        np.broadcast_to(flats["theta0"], (n,)) if flats["theta0"].size == 1 and n != 1 else flats["theta0"]
    )
    rest = [flats[k] for k in ("omega0", "w0", "gamma", "tol")]
    # the per-state checks alone (t[0]): a bad value is a mistake in the input
    _, _, _, codes, _, _, first, code, msg = _fortran.taylor_batch_f2py(
        tt[:1], th0, *rest, budget, 1, _longcall.new_control(), *dargs
    )
    if int(code) != OK:
        if int(first) > 0:  # a bad value in one state: a mistake in the input, for the whole call
            raise ValueError(for_state(_text(msg), int(first) - 1, shape))
        raise_for_status(int(code), _text(msg))
    with np.errstate(all="ignore"):
        work = float(abs(tt[-1] - tt[0]) * float(np.max(rest[1] + rest[2])) * _STEPS_PER_RADIAN * n)
    if not np.isfinite(work):
        work = float("nan")
    if m:

        def one(i, control):
            state = (float(a[i if a.size > 1 else 0]) for a in [th0] + rest)
            return _one(tt, *state, budget, m, None, control, dargs=dargs)

        values, codes, messages = pool.map_states(
            one, n, threads, progress, work=work + n * POOL_STATE_WORK, shape=shape, names=_BATCH_ARGS
        )
        return _from_states(tt, shape, values, codes, messages, flats["tol"], given)
    nthreads = choose_threads(threads, work)
    control = _longcall.new_control()
    long = bool(work > _longcall.RK4_LONG_STEPS / 20)
    theta, omega, err, codes, steps, order, first, code, msg = _longcall.run(
        lambda: _fortran.taylor_batch_f2py(tt, th0, *rest, budget, nthreads, control, *dargs),
        control,
        long,
        progress,
        total=n,
        unit="state",
    )
    code = int(code)
    if code == ERR_CANCELLED:
        raise_for_status(code, _text(msg))
    codes = codes.astype(np.int64)
    message = ""
    if code:
        message = batch_summary(codes, _text(msg), shape, _BATCH_ARGS)
        raise_if_all_failed(codes, int(codes[int(first) - 1]) if int(first) > 0 else code, message)
    # (n_t, n) in Fortran order: the transposes are C-contiguous (n, n_t) already, no copy
    theta, omega, err = theta.T, omega.T, err.T
    bad = codes != OK
    theta[bad], omega[bad], err[bad] = np.nan, np.nan, np.nan  # a failed state is never a plausible number
    n_t = tt.size
    steps = steps.astype(np.int64)
    zero = np.zeros(n, dtype=np.int64)
    stats = {
        "steps": steps,
        "rhs_evals": steps * order,
        "jac_evals": zero,
        "err_test_fails": zero.copy(),
        "nonlin_iters": zero.copy(),
        "nonlin_fails": zero.copy(),
        "root_evals": zero.copy(),
        "order": order.astype(np.int64),
    }
    return TaylorBatchResult(
        t=tt,
        theta=theta.reshape(shape + (n_t,)),
        omega=omega.reshape(shape + (n_t,)),
        stats={k: v.reshape(shape) for k, v in stats.items()},
        method="taylor",
        codes=codes.reshape(shape),
        message=message,
        first_failed=int(first) - 1,
        error=err.reshape(shape + (n_t,)),
        tol=np.broadcast_to(flats["tol"], (n,)).reshape(shape).copy(),
        inputs=given,
    )


def _from_states(tt, shape, values, codes, messages, tol, given):
    n = len(values)
    out = {k: np.full((n, tt.size), np.nan) for k in ("theta", "omega", "error")}
    stats = {}
    ev = np.empty(n, dtype=object)
    for i, r in enumerate(values):
        if r is None:
            continue
        out["theta"][i], out["omega"][i], out["error"][i], ev[i] = r.theta, r.omega, r.error, r.events
        for k, v in r.stats.items():
            stats.setdefault(k, np.zeros(n, dtype=np.int64))[i] = v
    first, message = summary(codes, messages, shape, _BATCH_ARGS)
    return TaylorBatchResult(
        t=tt,
        theta=out["theta"].reshape(shape + (tt.size,)),
        omega=out["omega"].reshape(shape + (tt.size,)),
        stats={k: v.reshape(shape) for k, v in stats.items()},
        method="taylor",
        codes=codes.reshape(shape),
        message=message,
        first_failed=first,
        events=ev.reshape(shape),
        error=out["error"].reshape(shape + (tt.size,)),
        tol=np.broadcast_to(tol, (n,)).reshape(shape).copy(),
        inputs=given,
    )


__all__ = ["taylor", "TaylorResult", "TaylorBatchResult"]
