"""The nonlinear damped pendulum theta'' + gamma theta' + w0**2 sin(theta) = 0
(text eq. 2.2, section 2.2) by classic RK4 and by SUNDIALS CVODE.

``rk4`` is the fixed-step method the text's section 2.2 listing means to
implement (without its line-67 typo; see ``pendula.textbook``), ``cvode`` the
adaptive Adams/BDF alternative with event location.  Both take an output grid
``t`` (strictly increasing, ``t[0]`` is the initial time) and return an
``IntegrationResult`` with theta and Omega exactly at those times.

Units: t and h in s, angles in rad, Omega in rad/s, w0 and gamma in 1/s.

Long runs keep memory proportional to the outputs only: ask for
``t=[0, t_end]`` to get the final state of a run of any length.

Constants
---------
TURNING_POINT : int
    ``Events.kind`` of a turning point: Omega = 0, theta at an extremum
    (the amplitude is abs(theta) there).
ZERO_CROSSING : int
    ``Events.kind`` of a zero crossing: theta = 0, the pendulum passes the
    vertical.

Both come from the Fortran core (``pendula._codes``).

Examples
--------
>>> import pendula
>>> ev = pendula.cvode([0.0, 7.0], 1.0, 0.0, 1.0, 0.0, events=True).events
>>> [int(k) == pendula.TURNING_POINT for k in ev.kind]
[False, True, False, True]
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from . import _drive_args, _fortran, _longcall, _memory
from ._arrays import check_size, integer_arg, output_pair, real_scalar, step_budget, time_grid
from ._codes import CVODE_ADAMS, EVENT_TURNING, EVENT_ZERO
from ._config import HAVE_CVODE
from ._defaults import (
    CVODE_ATOL,
    CVODE_MAX_STEPS,
    CVODE_METHOD,
    CVODE_METHODS,
    CVODE_RTOL,
    MAX_EVENTS,
    RK4_MAX_STEPS,
    THREADS,
    check_threads,
)
from ._errors import raise_for_status
from ._integrate_results import Events, IntegrationResult, quick_result, rk4_stats, stats_of
from ._many import ensemble as _ensemble
from ._many.ensemble import BatchIntegrationResult

TURNING_POINT = EVENT_TURNING
"""Event kind: Omega = 0 (theta at an extremum; the amplitude is abs(theta) there)."""
ZERO_CROSSING = EVENT_ZERO
"""Event kind: theta = 0 mod 2 pi (the pendulum passes the bottom; a rotation once per turn)."""

_METHODS = CVODE_METHODS
_grid = time_grid


def _real(x, name):
    # Plain floats (the common case) go straight through; everything else is
    # checked and converted by real_scalar.
    return x if type(x) is float else real_scalar(x, name)


def rk4(
    t: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike,
    w0: ArrayLike,
    gamma: ArrayLike,
    h: ArrayLike,
    max_steps: int = RK4_MAX_STEPS,
    progress: bool | Callable[[int, int | None], object] | None = None,
    threads: int | None = THREADS,
    drive: object | None = None,
    out: tuple[np.ndarray, np.ndarray] | None = None,
) -> IntegrationResult | BatchIntegrationResult:
    """Integrate theta'' + gamma theta' + w0**2 sin(theta) = 0 by classic RK4.

    Parameters
    ----------
    t : array_like
        Strictly increasing, finite output times [s], 1-D, at least one;
        t[0] is the initial time.
    theta0, omega0 : float or array_like
        Initial angle [rad] and angular velocity [rad/s] at t[0], finite.
    w0 : float or array_like
        Small-angle angular frequency sqrt(g/l) [1/s], > 0.
    gamma : float or array_like
        Damping rate [1/s], >= 0.
    h : float or array_like
        Largest step [s], > 0 and inside RK4's stability limit
        (``rk4_max_stable_step``).  Between consecutive output times RK4
        takes the fewest equal substeps of at most h (a spacing that is a
        multiple of h up to rounding counts as that multiple).  An array
        is a step per state, broadcast with the state arguments.
    max_steps : int
        Step budget (default 2e9, about a minute of CPU); a window that
        needs more steps is refused before any work.
    progress : bool or callable, optional
        True for a tqdm bar (needs tqdm), or a callable(done, total) called
        about every 20 ms with the steps taken.
    threads : int or None
        OpenMP threads of a batch: None (the default) chooses from the
        predicted work (one thread for a small batch), 0 asks for
        OMP_NUM_THREADS or every core; unused by a single state.
    drive : Drive or array_like of Drive, optional
        Integrate the driven pendulum (``pendula.Drive``: a torque
        F cos(Omega t + phi) or a vertically driven pivot) instead.  One
        Drive for every state, or an array of them, one per state, that
        broadcasts with the state arguments (a batch).  The steps are then
        T/N for the fewest N >= 8 with T/N <= h (T = 2 pi/Omega, N <=
        1e6), on a grid whose drive phase comes from integers: a million
        periods lose no phase.  The step must resolve the drive too:
        h max(sqrt(w0**2 + abs(a/l) Omega**2), gamma) <= 1.5 and
        abs(omega0) h <= 1.5; abs(theta0) < 1e15 rad.
    out : tuple of two ndarray, optional
        Arrays (theta, omega) for the results, as NumPy's ``out=``: float64,
        C-contiguous, writeable, not overlapping, of the result's shape
        (batch_shape + (len(t),)); the result's theta and omega are these
        arrays.  A batch writes into them directly, so repeated calls reuse
        their memory instead of fresh pages; one state is copied in.  A
        refused out is never written; after another exception its contents
        are unspecified.

    Returns
    -------
    IntegrationResult or BatchIntegrationResult
        theta [rad] and omega [rad/s] at t, stats (steps, rhs_evals = 4
        steps); a ``BatchIntegrationResult`` when a state argument or h is
        an array.

    Raises
    ------
    ValueError
        For bad arguments (naming them), more than max_steps steps, or a
        step outside RK4's stability region for the linearisation about
        theta = 0 (the message gives the largest stable h).
    TypeError
        For non-real input.
    MemoryError
        When the outputs cannot be allocated, before any work; the message
        names them, the size of t (or of the batch) and the bytes.
    KeyboardInterrupt
        Ctrl-C during a long run (over ~50 ms), raised within a
        millisecond or so; nothing is left half-done.

    Notes
    -----
    Global error O(h**4): for the text's scenario (w0 = sqrt(2), gamma =
    0.1, theta0 = 0, Omega0 = 2, t <= 30 s) h = 0.05 s gives about 3e-6 rad.

    Batches: theta0, omega0, w0, gamma and h broadcast together like NumPy
    to the batch shape; theta.shape == batch_shape + (len(t),), each state
    bit-identical to the scalar call (the Fortran batch kernel, GIL
    released).  A value refused without integrating (NaN, inf, out of
    domain) raises ValueError naming the argument and the first bad state
    (``w0[2] = -1.0 ...``); a state that fails over the window (unstable
    h, more than max_steps steps) gets its own code in ``result.codes``
    (``result.ok``, ``result.message``), NaN in its theta and omega, and
    the others keep their answers; when every state failed the call raises
    that exception (docs/robustness.md).  progress then counts finished states.  Scalars and
    0-d arrays take the scalar path.

    With a drive the states run on the driven pendulum's block kernel
    (``pendula.driven``'s), each batch state bit-identical to the scalar
    call; progress then counts finished states.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> r = pendula.rk4(np.linspace(0, 30, 601), 0.0, 2.0, np.sqrt(2), 0.1, h=0.05)
    >>> r.theta.shape, r.stats["steps"]
    ((601,), 600)
    >>> b = pendula.rk4([0.0, 1.0], [0.1, 0.2], 0.0, 1.0, 0.0, h=0.01)
    >>> b.theta.shape, bool(b.ok.all())
    ((2, 2), True)

    A driven pendulum (Baker & Gollub's chaotic one), and a sweep over the
    drive amplitude as an array of drives:

    >>> d = pendula.Drive("torque", 1.15, 2 / 3)
    >>> r = pendula.rk4([0.0, 3 * d.period], 0.2, 0.0, 1.0, 0.5, h=d.period / 100, drive=d)
    >>> r.stats["steps"]
    300
    >>> ds = [pendula.Drive("torque", f, 2 / 3) for f in (0.9, 1.07, 1.15)]
    >>> pendula.rk4([0.0, 10.0], 0.2, 0.0, 1.0, 0.5, h=0.05, drive=ds).theta.shape
    (3, 2)
    """
    if drive is not None:
        return _rk4_driven(t, theta0, omega0, w0, gamma, h, max_steps, progress, threads, drive, out)
    if _ensemble.is_batch(theta0, omega0, w0, gamma, h):
        return _ensemble.rk4_batch(_grid(t), theta0, omega0, w0, gamma, h, max_steps, progress, threads, out=out)
    if threads is not None:
        check_threads(threads)  # checked, unused: one state runs on one thread
    if type(t) is np.ndarray and t.dtype.char == "d" and t.ndim == 1 and t.size >= 1:
        check_size(t.size, "t")
        # the result keeps its own grid; Fortran gets a contiguous one
        tt = _memory.guard(t.copy, *_outputs(t.size, ("t", "theta", "omega")))
    else:
        tt = _grid(t)
    output_pair(out, tt.shape)
    outputs = _outputs(tt.size)
    hh = _real(h, "h")
    budget = max_steps if type(max_steps) is int and 1 <= max_steps <= 2**62 else _step_budget(max_steps)
    args = (
        tt,
        _real(theta0, "theta0"),
        _real(omega0, "omega0"),
        _real(w0, "w0"),
        _real(gamma, "gamma"),
        hh,
        float(budget),
    )
    # Predicted steps in plain float arithmetic (inf/NaN propagate without
    # warnings; h <= 0 or NaN gives no prediction: Fortran refuses it).
    steps = (tt.item(-1) - tt.item(0)) / hh + tt.size if hh > 0 else 0.0
    long = _longcall.RK4_LONG_STEPS < steps <= budget
    if not long and progress is None:
        theta, omega, stats, code, msg = _memory.guard(
            lambda: _fortran.rk4_f2py(*args, _longcall.scratch_control()), *outputs
        )
    else:
        control = _longcall.new_control()
        theta, omega, stats, code, msg = _longcall.run(
            lambda: _memory.guard(lambda: _fortran.rk4_f2py(*args, control), *outputs),
            control,
            long,
            progress,
            total=int(min(steps, 2**62)),
        )
    if code:
        raise_for_status(code, msg)
    return quick_result(tt, *_into(out, theta, omega), rk4_stats(stats), "rk4")


_step_budget = step_budget


def _into(out, theta, omega):
    """(theta, omega) of one state, copied into the caller's out when given."""
    if out is None:
        return theta, omega
    out[0][...] = theta
    out[1][...] = omega
    return out


def _outputs(n_t, fields=("theta", "omega"), events=0):
    """What a one-state call allocates before any work and its size in bytes,
    for ``_memory.guard``: the arrays ``fields`` (8 bytes per time each) over
    the ``n_t`` times of ``t``, plus ``events`` event slots (28 bytes each)."""
    what = f"the outputs {', '.join(fields[:-1])} and {fields[-1]} of {n_t} times (the size of t)"
    if events:
        what += f" and {events} event slots (max_events)"
    return what, 8 * n_t * len(fields) + 28 * events


def _rk4_driven(t, theta0, omega0, w0, gamma, h, max_steps, progress, threads, drive, out):
    """``rk4`` with a drive: the batch path for array states or drives, else one state."""
    if _drive_args.is_many(drive) or _ensemble.is_batch(theta0, omega0, w0, gamma, h):
        cols = _drive_args.columns(drive)  # TypeError naming drive for anything but Drives
        return _ensemble.rk4_batch(
            _grid(t), theta0, omega0, w0, gamma, h, max_steps, progress, threads, drive=cols, out=out
        )
    if threads is not None:
        check_threads(threads)  # checked, unused: one state runs on one thread
    tt = _grid(t)
    output_pair(out, tt.shape)
    hh = _real(h, "h")
    budget = _step_budget(max_steps)
    args = (
        tt,
        _real(theta0, "theta0"),
        _real(omega0, "omega0"),
        _real(w0, "w0"),
        _real(gamma, "gamma"),
        hh,
        float(budget),
        drive.code,
        drive.amplitude,
        drive.frequency,
        drive.phase,
    )
    steps = (tt.item(-1) - tt.item(0)) / hh + tt.size if hh > 0 else 0.0
    long = _longcall.RK4_LONG_STEPS < steps <= budget
    control = _longcall.new_control()
    # the driven kernel counts the finished state (1) as its progress
    theta, omega, stats, code, msg = _longcall.run(
        lambda: _memory.guard(lambda: _fortran.rk4_drive_f2py(*args, control), *_outputs(tt.size)),
        control,
        long,
        progress,
        total=1,
    )
    if code:
        raise_for_status(code, msg)
    return quick_result(tt, *_into(out, theta, omega), rk4_stats(stats), "rk4")


def rk4_max_stable_step(w0: float, gamma: float) -> float:
    """Largest RK4 step h [s] that is stable for the pendulum linearised about theta = 0.

    Parameters
    ----------
    w0 : float
        Small-angle angular frequency [1/s], > 0.
    gamma : float
        Damping rate [1/s], >= 0.

    Returns
    -------
    float
        The largest h [s] with abs(R(h lambda)) <= 1 for both eigenvalues
        lambda = -gamma/2 +- sqrt(gamma**2/4 - w0**2), where R(z) = 1 + z +
        z**2/2 + z**3/6 + z**4/24 is RK4's stability function.

    Raises
    ------
    ValueError
        For w0 <= 0, gamma < 0 or non-finite input.
    TypeError
        For non-real input.

    Notes
    -----
    2 sqrt(2)/w0 for gamma = 0; 2.7853/abs(lambda) on the real axis
    (overdamped).  A larger step makes ``rk4`` refuse the run.

    Examples
    --------
    >>> import pendula
    >>> round(pendula.rk4_max_stable_step(1.0, 0.0), 6)   # 2 sqrt(2)
    2.828427
    """
    h, code, msg = _fortran.rk4_max_stable_step_f2py(real_scalar(w0, "w0"), real_scalar(gamma, "gamma"))
    raise_for_status(code, msg)
    return float(h)


def cvode(
    t: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike,
    w0: ArrayLike,
    gamma: ArrayLike,
    rtol: float = CVODE_RTOL,
    atol: float = CVODE_ATOL,
    method: str = CVODE_METHOD,
    max_steps: int = CVODE_MAX_STEPS,
    events: bool = False,
    max_events: int = MAX_EVENTS,
    progress: bool | Callable[[int, int | None], object] | None = None,
    threads: int | None = THREADS,
    drive: object | None = None,
) -> IntegrationResult | BatchIntegrationResult:
    """Integrate theta'' + gamma theta' + w0**2 sin(theta) = 0 with SUNDIALS CVODE.

    Parameters
    ----------
    t : array_like
        Strictly increasing, finite output times [s], 1-D; t[0] is the
        initial time.  Windows as short as 5e-324 s, or one ulp at any t[0]
        (the ODE is autonomous: CVODE works in t - t[0]); t[-1] - t[0] must
        not overflow.
    theta0, omega0 : float or array_like
        Initial angle [rad] and angular velocity [rad/s] at t[0], finite.
    w0 : float or array_like
        Small-angle angular frequency [1/s], > 0.
    gamma : float or array_like
        Damping rate [1/s], >= 0.
    rtol : float
        Relative tolerance, > 0: CVODE keeps each local error below
        rtol abs(y) + atol (global errors are typically 1-100x that).
    atol : float
        Absolute tolerance, >= 0.  atol = 0 is pure relative control,
        normwise: the local error in theta stays below rtol S and in Omega
        below rtol w0 S, S = max(abs(theta), abs(Omega)/w0); it keeps its
        relative accuracy as damped motion decays.
    method : {"adams", "bdf"}
        Adams (non-stiff, default) or BDF (stiff, e.g. gamma >> w0); both
        use Newton iteration with a dense solver and the analytic Jacobian.
    max_steps : int
        Total step budget of the run, >= 1.
    events : bool
        Also locate turning points (Omega = 0) and zero crossings (passes
        through the bottom, theta = 0 mod 2 pi, as scenes count them) after t[0].
    max_events : int
        Events kept, 1 ... 10**7 (``result.events.truncated`` tells if
        more occurred).
    progress : bool or callable, optional
        True for a tqdm bar, or a callable(done, total) called about every
        20 ms with the right-hand-side evaluations so far (total None).
    threads : int or None
        Threads of a batch: None (the default) chooses from the predicted
        work, 0 asks for OMP_NUM_THREADS or every core; unused by a single
        state.
    drive : Drive or array_like of Drive, optional
        Integrate the driven pendulum (``pendula.Drive``) instead: one Drive
        for every state or an array of them broadcast with the states, as
        for ``rk4``.  The drive phase is Omega (t - t[0]) plus the phase at
        t[0] reduced once, as exact as CVODE's own time over any number of
        periods.

    Returns
    -------
    IntegrationResult or BatchIntegrationResult
        theta [rad], omega [rad/s] at t, CVODE's stats, events when asked.

    Raises
    ------
    ValueError
        For bad arguments (naming them).
    TypeError
        For non-real input (str, bool, complex), a non-integer max_steps or
        max_events, a non-bool events or a progress that is not callable.
    PendulaSolverError
        When CVODE fails or runs out of steps (a RuntimeError; the message
        gives CVODE's reason).
    NotImplementedError
        When this build has no CVODE (``pendula.build_info()["cvode"]``).
    MemoryError
        When the outputs (and event slots) cannot be allocated, before any
        work; the message names them, the size of t (or of the batch) and
        the bytes.
    KeyboardInterrupt
        Ctrl-C during a long run (the solver memory is freed).

    Notes
    -----
    Batches: theta0, omega0, w0 and gamma may be arrays, as for ``rk4``
    (same rules; a state's CVODE failure or exhausted max_steps is its
    code); the Fortran batch kernel reuses one solver per thread.  With
    events=True each state runs the scalar call on a pool of ``threads``
    Python threads (``result.events``: an object array of ``Events``).
    Use the events to measure the period and the decrement of the motion.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> r = pendula.cvode(np.linspace(0, 30, 601), 0.0, 2.0, np.sqrt(2), 0.1, rtol=1e-10, atol=0.0)
    >>> r.method, r.theta.shape
    ('adams', (601,))
    >>> e = pendula.cvode([0.0, 10.0], 1.0, 0.0, 1.0, 0.0, events=True).events
    >>> t_turn, theta_turn = e.turning_points
    >>> np.round(theta_turn, 6).tolist()
    [-1.0, 1.0]

    A small drive of a damped pendulum settles on the linear steady state
    (``pendula.driven_linear``):

    >>> d = pendula.Drive("torque", 1e-4, 0.5)
    >>> t = [0.0, 60.0]
    >>> r = pendula.cvode(t, 0.0, 0.0, 1.0, 0.5, rtol=1e-10, atol=1e-14, drive=d)
    >>> lin_theta, lin_omega = pendula.driven_linear(t, 0.0, 0.0, drive=d, w0=1.0, gamma=0.5)
    >>> bool(abs(r.theta[-1] - lin_theta[-1]) < 1e-9)
    True
    """
    if not HAVE_CVODE:
        # The Fortran stub says the same; checking here first keeps the
        # message independent of the other arguments.
        _, _, _, _, _, _, _, _, _, code, msg = _fortran.cvode_f2py(
            np.zeros(1), 0.0, 0.0, 1.0, 0.0, CVODE_RTOL, CVODE_ATOL, CVODE_ADAMS, 1.0, 0, _longcall.new_control()
        )
        raise_for_status(code, msg)
    tt = _grid(t)
    if _ensemble.is_batch(theta0, omega0, w0, gamma) or _drive_args.is_many(drive):
        if not isinstance(method, str):
            raise ValueError(f"method = {method!r} is invalid: it must be 'adams' or 'bdf'")
        if not isinstance(events, bool):
            raise TypeError(f"events must be True or False, got {type(events).__name__}")
        return _ensemble.cvode_batch(
            tt,
            theta0,
            omega0,
            w0,
            gamma,
            real_scalar(rtol, "rtol"),
            real_scalar(atol, "atol"),
            method,
            max_steps,
            events,
            max_events,
            progress,
            threads,
            _cvode_one,
            drive=None if drive is None else _drive_args.columns(drive),
            drive_each=None if drive is None else (lambda shape: _drive_args.per_state(drive, shape)),
        )
    if threads is not None:
        check_threads(threads)  # checked, unused: one state runs on one thread
    return _cvode_one(
        tt, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, events, max_events, progress, drive=drive
    )


def _cvode_one(
    tt,
    theta0,
    omega0,
    w0,
    gamma,
    rtol=CVODE_RTOL,
    atol=CVODE_ATOL,
    method=CVODE_METHOD,
    max_steps=CVODE_MAX_STEPS,
    events=False,
    max_events=MAX_EVENTS,
    progress=None,
    control=None,
    drive=None,
):
    """``cvode`` for one state on the checked grid tt; control: the caller's
    (a batch pool thread's) control array, watched by the caller; drive:
    None or one ``Drive``."""
    args = [
        real_scalar(x, name)
        for x, name in (
            (theta0, "theta0"),
            (omega0, "omega0"),
            (w0, "w0"),
            (gamma, "gamma"),
            (rtol, "rtol"),
            (atol, "atol"),
        )
    ]
    if not isinstance(method, str) or method.lower() not in _METHODS:
        raise ValueError(f"method = {method!r} is invalid: it must be 'adams' or 'bdf'")
    max_steps = integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True)
    if not isinstance(events, bool):
        raise TypeError(f"events must be True or False, got {type(events).__name__}")
    m = 0
    if events:
        # the event arrays are allocated up front: 28 bytes per event
        m = integer_arg(max_events, "max_events", 1, 10**7, scalar=True)
    watched = control is None
    control = _longcall.new_control() if watched else control
    call_args = (tt, *args, _METHODS[method.lower()], float(min(max_steps, 2**62)), m, control)
    # CVODE's step count is not known up front: any run that may take more
    # than ~50 ms (a long window in periods, or many outputs) runs watched.
    periods = abs(tt.item(-1) - tt.item(0)) * args[2] / (2 * np.pi)
    glue = _fortran.cvode_f2py
    if drive is not None:
        if _drive_args.is_many(drive):
            _drive_args.columns(drive)  # TypeError naming drive
        call_args = (*call_args[:-1], drive.code, drive.amplitude, drive.frequency, drive.phase, control)
        periods = max(periods, abs(tt.item(-1) - tt.item(0)) * drive.frequency / (2 * np.pi))
        glue = _fortran.cvode_drive_f2py
    long = watched and not periods * 50 + tt.size <= _longcall.CVODE_LONG_STEPS  # NaN/inf: long
    outputs = _outputs(tt.size, events=m)
    (theta, omega, stats, ev_t, ev_kind, ev_theta, ev_omega, n_ev, trunc, code, msg) = _longcall.run(
        lambda: _memory.guard(lambda: glue(*call_args), *outputs), control, long, progress, unit="rhs"
    )
    raise_for_status(code, msg)
    ev = None
    if events:
        n = int(n_ev)
        ev = Events(
            t=ev_t[:n].copy(),
            kind=ev_kind[:n].astype(np.int64),
            theta=ev_theta[:n].copy(),
            omega=ev_omega[:n].copy(),
            truncated=bool(trunc),
        )
    return IntegrationResult(t=tt, theta=theta, omega=omega, stats=stats_of(stats), method=method.lower(), events=ev)


__all__ = [
    "rk4",
    "rk4_max_stable_step",
    "cvode",
    "IntegrationResult",
    "BatchIntegrationResult",
    "Events",
    "TURNING_POINT",
    "ZERO_CROSSING",
]
