"""The table of pendula's public API for the bad-input tests: per public
callable, a call that must succeed and the kind of each argument, and the bad
cases generated from the kinds (``ALL_CASES``).  Shared by test_bad_input.py
(which checks each case raises a ValueError/TypeError naming the argument) and
test_threads.py (which runs the same cases concurrently); a helper module, not
a test module.
"""

from __future__ import annotations

import dataclasses
import inspect
import numbers
import warnings

import numpy as np
from helpers import HAVE_CVODE

import pendula

NAN = float("nan")
INF = float("inf")
# ---- argument kinds ---------------------------------------------------------
REAL = "real"  # any finite real (angles, velocities, a time)
POS = "positive"  # finite and > 0 (g, l, m, w0, h, rtol, tol, ...)
NONNEG = "nonneg"  # finite and >= 0 (gamma, b, atol, ...)
TIMES = "times"  # 1-D, non-empty, finite, strictly increasing
CHOICE = "choice"  # a string from a fixed set
COUNT = "count"  # a positive integer
OTHER = "other"  # checked by ``extra`` cases only


@dataclasses.dataclass
class Arg:
    kind: str
    # Names the message may use for this argument instead of the Python name
    # (the Fortran core writes the text's symbols: l, m, ...).
    aliases: tuple = ()
    # Accepts arrays (broadcast elementwise); scalar-only arguments get a
    # 1-element array as a wrong-shape case instead.
    array: bool = False
    # Extra bad values: (value, exception type) or (value, exception type,
    # {other argument: value}) for a case that needs another argument changed.
    extra: tuple = ()
    # Values of a finite real that are out of domain (ValueError).
    out_of_domain: tuple = ()
    # Extreme valid values to try instead of the kind's default set (a step
    # size of 1e-10 s is valid but would take hours of honest work).
    extremes: tuple = None
    # Other arguments to change for every case of this argument (e.g. drop
    # mass and b when trying bad gamma values on a Scene).
    others: dict = dataclasses.field(default_factory=dict)


@dataclasses.dataclass
class Entry:
    valid: dict
    args: dict
    nan: str = "raise"  # "propagate": NaN in -> NaN out (elliptic rule)
    needs_cvode: bool = False
    # Arguments of the signature deliberately not checked, with the reason.
    unchecked: dict = dataclasses.field(default_factory=dict)


# Public names that are not numerical entry points.
NOT_ENTRY_POINTS = {
    "PendulaSolverError": "exception class",
    "AngleWarning": "warning class (test_angle_warning.py)",
    "TradeoffTable": "result container built by tradeoff() from checked runs",
    "BatchIntegrationResult": "result container built by rk4()/cvode() for a batch of states",
    "TaylorResult": "result container built by taylor() for one state",
    "TaylorBatchResult": "result container built by taylor() for a batch of states",
    "SceneBatch": "built by Scene() for array parameters (its table entry covers them)",
    "SceneBatchResult": "result container built by solve()/run_model() for a SceneBatch",
    "build_info": "no arguments: build configuration",
    "have_cvode": "no arguments: build configuration",
    # a Figure is no result of numbers to walk; their bad input is tested in test_motion_plots.py
    "plot_motion": "plot helper: returns a matplotlib Figure",
    "plot_phase_portrait": "plot helper: returns a matplotlib Figure",
    "FitResult": "result container built by fit_period()/fit_motion() from checked data",
}

# threads= of the batch paths: None (the default: chosen from the predicted work), 0 (the
# OpenMP default: every core) or a count
THREADS = Arg(OTHER, extra=((-1, ValueError), (2.5, TypeError), ("2", TypeError), (True, TypeError)))

# The pendulum as g and length instead of w0, the damping as b and mass instead of
# gamma (pendula.physics' one convention): checked with w0 (gamma) left out.
PENDULUM = dict(g=Arg(POS, others=dict(w0=None)), length=Arg(POS, aliases=("l",), others=dict(w0=None)))
DAMPING = dict(
    b=Arg(NONNEG, others=dict(gamma=None, mass=0.1)), mass=Arg(POS, aliases=("m",), others=dict(gamma=None, b=0.05))
)

# ---- the table ----------------------------------------------------------------
# drive= of rk4, cvode and sweep: None, a pendula.Drive, or an array of them (pendula._many.drives)
# out= of rk4 for the valid call's 4 times: every way to get it wrong, refused before any write
_OUT4 = np.zeros(4)
_RK4_OUT_BAD = (
    ("out", TypeError),
    ([np.zeros(4), np.zeros(4)], TypeError),
    ((np.zeros(4),), ValueError),
    ((_OUT4, _OUT4), ValueError),
    ((np.zeros(4), np.zeros(5)), ValueError),
    ((np.zeros(4, dtype=np.float32), np.zeros(4)), TypeError),
    ((np.zeros(8)[::2], np.zeros(4)), ValueError),
    ((np.zeros(4), np.broadcast_to(0.0, (4,))), ValueError),
)
_INTEGRATOR_DRIVE = Arg(OTHER, extra=(((1.0, 1.0), TypeError), ("torque", TypeError), ({"F": 1.0}, TypeError)))

API: dict[str, Entry] = {
    # fits (fit.py): data arrays are whole records (array=False: a scalar or a
    # wrong-length array is refused, not broadcast into a different data set)
    "fit_period": Entry(
        valid=dict(
            theta0=[0.2, 0.8, 1.5, 2.5], period=2.0, sigma_period=1e-3, sigma_theta0=0.01, length=0.75, bob_radius=0.01
        ),
        args=dict(
            theta0=Arg(REAL, out_of_domain=(4.0,)),
            period=Arg(POS),
            sigma_period=Arg(POS),
            sigma_theta0=Arg(NONNEG),
            length=Arg(POS),
            g=Arg(POS, others=dict(length=None)),
            bob_radius=Arg(NONNEG),
            confidence=Arg(OTHER, extra=((1.0, ValueError), (0.0, ValueError), ("0.9", TypeError))),
        ),
    ),
    "fit_motion": Entry(
        valid=dict(
            t=np.linspace(0.0, 6.0, 40).tolist(),
            theta=(np.cos(3.0 * np.linspace(0.0, 6.0, 40)) * np.exp(-0.05 * np.linspace(0.0, 6.0, 40)) * 0.5).tolist(),
            sigma=1e-2,
            t_ref=0.0,
        ),
        args=dict(
            t=Arg(TIMES),
            theta=Arg(REAL),
            omega=Arg(REAL, others=dict(sigma_omega=0.1)),
            sigma=Arg(POS),
            sigma_omega=Arg(POS, others=dict(omega=(-1.5 * np.sin(3.0 * np.linspace(0.0, 6.0, 40))).tolist())),
            damping=Arg(OTHER, extra=(("quadratic", ValueError), (1.0, ValueError))),
            fit_offsets=Arg(OTHER, extra=(("yes", TypeError), (1, TypeError))),
            length=Arg(POS),
            g=Arg(POS),
            t_ref=Arg(REAL),
            p0=Arg(OTHER, extra=(([1.0], TypeError), ({"w1": 1.0}, ValueError), ({"w0": "x"}, TypeError))),
            loss=Arg(CHOICE),
            f_scale=Arg(POS),
            tol=Arg(POS),
            integrator=Arg(CHOICE),
            confidence=Arg(OTHER, extra=((1.5, ValueError), (None, TypeError))),
            max_nfev=Arg(COUNT),
        ),
    ),
    # physics (core)
    "natural_frequency": Entry(valid=dict(g=9.8, length=4.9), args=dict(g=Arg(POS), length=Arg(POS, aliases=("l",)))),
    "damping_rate": Entry(valid=dict(b=0.05, mass=0.1), args=dict(b=Arg(NONNEG), mass=Arg(POS, aliases=("m",)))),
    "small_angle_period": Entry(valid=dict(w0=1.5), args=dict(w0=Arg(POS, array=True), **PENDULUM)),
    "period_series": Entry(
        valid=dict(m=0.3, w0=1.5),
        args=dict(
            m=Arg(
                NONNEG,
                array=True,
                out_of_domain=(1 + 2**-52, 1.5, 1e10, 1e300),
                extremes=(0.0, 5e-324, 1e-300, 1 - 2**-53, 1.0),
            ),
            w0=Arg(POS, array=True),
            **PENDULUM,
        ),
    ),
    # linear damped (src/damped, linear.py)
    "linear_damped": Entry(
        valid=dict(t=1.5, theta0=0.1, omega0=0.5, w0=1.4, gamma=0.3),
        args=dict(
            t=Arg(NONNEG, array=True),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            gamma=Arg(NONNEG, array=True),
            **PENDULUM,
            **DAMPING,
        ),
    ),
    "linear_damped_envelope": Entry(
        valid=dict(t=1.5, theta0=0.1, omega0=0.5, w0=1.4, gamma=0.3),
        args=dict(
            t=Arg(NONNEG, array=True),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            gamma=Arg(NONNEG, array=True),
            **PENDULUM,
            **DAMPING,
        ),
    ),
    "damping_regime": Entry(
        valid=dict(w0=1.4, gamma=0.3), args=dict(w0=Arg(POS), gamma=Arg(NONNEG), **PENDULUM, **DAMPING)
    ),
    # elliptic (src/special, elliptic.py): NaN in -> NaN out, out of domain -> ValueError
    "ellipk": Entry(
        valid=dict(m=0.7), nan="propagate", args=dict(m=Arg(REAL, array=True, out_of_domain=(1.5, 1 + 2**-52, INF)))
    ),
    "ellipe": Entry(
        valid=dict(m=0.7), nan="propagate", args=dict(m=Arg(REAL, array=True, out_of_domain=(1.5, 1 + 2**-52, INF)))
    ),
    "ellipkm1": Entry(
        valid=dict(p=0.3), nan="propagate", args=dict(p=Arg(REAL, array=True, out_of_domain=(-0.5, -5e-324, -INF)))
    ),
    "ellipem1": Entry(
        valid=dict(p=0.3), nan="propagate", args=dict(p=Arg(REAL, array=True, out_of_domain=(-0.5, -5e-324, -INF)))
    ),
    "ellipf": Entry(
        valid=dict(phi=1.0, m=0.7),
        nan="propagate",
        args=dict(phi=Arg(REAL, array=True), m=Arg(REAL, array=True, out_of_domain=(2.0, INF))),
    ),
    "ellipkinc": Entry(
        valid=dict(phi=1.0, m=0.7),
        nan="propagate",
        args=dict(phi=Arg(REAL, array=True), m=Arg(REAL, array=True, out_of_domain=(2.0, INF))),
    ),
    "ellipfm1": Entry(
        valid=dict(phi=1.0, p=0.3),
        nan="propagate",
        args=dict(phi=Arg(REAL, array=True), p=Arg(REAL, array=True, out_of_domain=(-1.0, -INF))),
    ),
    "ellipj": Entry(
        valid=dict(u=0.8, m=0.7), nan="propagate", args=dict(u=Arg(REAL, array=True), m=Arg(REAL, array=True))
    ),
    "ellipjm1": Entry(
        valid=dict(u=0.8, p=0.3), nan="propagate", args=dict(u=Arg(REAL, array=True), p=Arg(REAL, array=True))
    ),
    # integrators (src/integrators, integrate.py); drive=: a pendula.Drive or an array of them
    "rk4": Entry(
        valid=dict(t=[0.0, 0.5, 1.0, 2.0], theta0=0.0, omega0=2.0, w0=1.4, gamma=0.1, h=0.05),
        args=dict(
            t=Arg(TIMES),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            gamma=Arg(NONNEG, array=True),
            threads=THREADS,
            # a step outside RK4's stability region is refused, not integrated into garbage;
            # an array is a step per state, broadcast like the state arguments
            h=Arg(
                POS,
                array=True,
                extremes=(1e300, 1e154, 1e-300, 5e-324),
                extra=((50.0, ValueError, dict(t=np.array([0.0, 100.0]))),),
            ),
            # a budget below the window's steps is refused up front
            max_steps=Arg(COUNT, extra=((3, ValueError),)),
            progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))),
            drive=_INTEGRATOR_DRIVE,
            # the caller's (theta, omega) result arrays, of the result's shape (4 times here)
            out=Arg(OTHER, extra=_RK4_OUT_BAD),
        ),
    ),
    # sweeps (sweep.py): inputs checked up front, before any chunk runs
    "sweep": Entry(
        valid=dict(t=[0.0, 0.5, 1.0], theta0=0.3, omega0=0.5, w0=1.4, gamma=0.1, h=0.05),
        args=dict(
            t=Arg(TIMES),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            gamma=Arg(NONNEG, array=True),
            h=Arg(POS, array=True, extremes=(1e300, 1e154, 1e-300, 5e-324)),
            want=Arg(CHOICE, extra=(("all", ValueError),)),
            method=Arg(CHOICE, extra=(("euler", ValueError),)),
            chunk_states=Arg(COUNT),
            progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))),
            client=Arg(OTHER, extra=(("tcp://x", TypeError),)),
            drive=_INTEGRATOR_DRIVE,
        ),
        unchecked=dict(
            rtol="CVODE only (method='cvode')",
            atol="CVODE only (method='cvode')",
            cvode_method="checked by cvode_batch",
            max_steps="checked by cvode_batch",
            threads="checked by _defaults.check_threads (test_sweep)",
        ),
    ),
    "rk4_max_stable_step": Entry(valid=dict(w0=1.4, gamma=0.1), args=dict(w0=Arg(POS), gamma=Arg(NONNEG))),
    "cvode": Entry(
        valid=dict(t=[0.0, 0.5, 1.0, 2.0], theta0=0.0, omega0=2.0, w0=1.4, gamma=0.1, max_steps=200_000),
        needs_cvode=True,
        args=dict(
            t=Arg(TIMES),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            gamma=Arg(NONNEG, array=True),
            threads=THREADS,
            rtol=Arg(POS),
            atol=Arg(NONNEG),
            method=Arg(CHOICE),
            max_steps=Arg(COUNT, extra=((3, pendula.PendulaSolverError, dict(t=np.array([0.0, 100.0]))),)),
            events=Arg(OTHER, extra=(("yes", TypeError), (None, TypeError), (1.0, TypeError))),
            # max_events matters only with events=True
            max_events=Arg(
                OTHER,
                extra=(
                    (0, ValueError, dict(events=True)),
                    (-1, ValueError, dict(events=True)),
                    (2.5, TypeError, dict(events=True)),
                    ("7", TypeError, dict(events=True)),
                    (2**40, ValueError, dict(events=True)),
                ),
            ),
            progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))),
            drive=_INTEGRATOR_DRIVE,
        ),
    ),
    # t may also decrease (backwards in time): its bad cases are listed here
    "taylor": Entry(
        valid=dict(t=[0.0, 0.5, 1.0, 2.0], theta0=0.0, omega0=2.0, w0=1.4, gamma=0.1),
        args=dict(
            t=Arg(
                OTHER,
                extra=(
                    (np.array([0.0, NAN]), ValueError),
                    (np.array([0.0, INF]), ValueError),
                    (np.array([]), ValueError),
                    (np.array([0.0, 1.0, 1.0]), ValueError),
                    (np.array([0.0, 1.0, 0.5]), ValueError),
                    (np.zeros((2, 2)), ValueError),
                    ("0", TypeError),
                ),
            ),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            gamma=Arg(NONNEG, array=True),
            threads=THREADS,
            tol=Arg(POS, array=True, out_of_domain=(1.5, 1e300)),
            max_steps=Arg(COUNT, extra=((3, pendula.PendulaSolverError, dict(t=np.array([0.0, 100.0]))),)),
            events=Arg(OTHER, extra=(("yes", TypeError), (None, TypeError), (1.0, TypeError))),
            max_events=Arg(
                OTHER,
                extra=(
                    (0, ValueError, dict(events=True)),
                    (-1, ValueError, dict(events=True)),
                    (2.5, TypeError, dict(events=True)),
                    (2**40, ValueError, dict(events=True)),
                ),
            ),
            progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))),
        ),
    ),
    # undamped (src/undamped, undamped.py): any real t, any real state, w0 > 0
    "undamped": Entry(
        valid=dict(t=1.3, theta0=1.0, omega0=0.2, w0=1.4),
        args=dict(
            t=Arg(REAL, array=True),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            **PENDULUM,
        ),
    ),
    "small_angle": Entry(
        valid=dict(t=1.3, theta0=0.1, omega0=0.2, w0=1.4),
        args=dict(
            t=Arg(REAL, array=True),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            **PENDULUM,
        ),
    ),
    "small_angle_error": Entry(
        valid=dict(tmax=10.0, theta0=0.1, omega0=0.2, w0=1.4),
        args=dict(
            tmax=Arg(REAL, array=True),
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            w0=Arg(POS, array=True),
            **PENDULUM,
        ),
    ),
    **{
        name: Entry(
            valid=dict(theta0=1.0, omega0=0.2, w0=1.4),
            args=dict(theta0=Arg(REAL, array=True), omega0=Arg(REAL, array=True), w0=Arg(POS, array=True), **PENDULUM),
        )
        for name in ("period", "amplitude", "elliptic_parameter", "regime")
    },
    "energy": Entry(
        valid=dict(theta=1.0, omega=0.2, w0=1.4),
        args=dict(theta=Arg(REAL, array=True), omega=Arg(REAL, array=True), w0=Arg(POS, array=True), **PENDULUM),
    ),
    "equilibria": Entry(
        valid=dict(n=3, w0=1.4),
        args=dict(
            n=Arg(
                OTHER,
                extra=(
                    (1.5, TypeError),
                    ("1", TypeError),
                    (None, TypeError),
                    (True, TypeError),
                    (np.array([1.0, 2.0]), TypeError),
                    (1 + 1j, TypeError),
                    (2**40, ValueError),
                    (np.array([[1, 2]]), ValueError, dict(w0=np.array([1.0, 2.0, 3.0]))),
                ),
            ),
            w0=Arg(POS, array=True),
            **PENDULUM,
        ),
    ),
    # scenes (src/scene, scene.py)
    "Scene": Entry(
        valid=dict(
            theta0=0.3, omega0=0.1, t=[0.0, 1.0, 2.0], g=9.8, length=4.9, mass=0.1, b=0.01, tol=1e-6, want="state"
        ),
        args=dict(
            theta0=Arg(REAL, array=True),
            omega0=Arg(REAL, array=True),
            g=Arg(POS, array=True),
            length=Arg(POS, aliases=("l",), array=True),
            mass=Arg(POS, aliases=("m",), array=True),
            b=Arg(NONNEG, array=True),
            tol=Arg(POS, array=True),
            want=Arg(CHOICE),
            gamma=Arg(NONNEG, others=dict(mass=None, b=None), array=True),
            t=Arg(TIMES, extra=((np.array([-1.0, 0.0, 1.0]), ValueError), (np.array([]), ValueError))),
            drive=Arg(OTHER, extra=(((1.0, 2.0), TypeError), ("torque", TypeError))),
        ),
    ),
    "solve": Entry(
        valid=dict(scene="SCENE", model=None),
        args=dict(
            scene=Arg(OTHER, extra=(("scene", TypeError), (None, TypeError), (1.0, TypeError))),
            model=Arg(CHOICE, extra=(("exact", ValueError, dict(scene="DAMPED")),)),
            max_steps=Arg(COUNT),
            threads=THREADS,
            progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))),
        ),
    ),
    "run_model": Entry(
        valid=dict(scene="SCENE", model="rk4", setting=0.01),
        args=dict(
            scene=Arg(OTHER, extra=(("scene", TypeError), (None, TypeError))),
            model=Arg(CHOICE, extra=(("auto", ValueError),)),
            setting=Arg(POS, aliases=("h",), extremes=(1e300, 1e154, 1e-300, 5e-324)),
            max_steps=Arg(COUNT, extra=((3, ValueError),)),
            threads=THREADS,
            progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))),
        ),
    ),
    "tradeoff": Entry(
        valid=dict(scene="SCENE", models=["small_angle", "rk4"], rk4_steps=[0.1, 0.05], cvode_rtols=[1e-6], repeat=1),
        args=dict(
            scene=Arg(OTHER, extra=(("scene", TypeError), (None, TypeError))),
            models=Arg(OTHER, extra=((["nope"], ValueError), (["linear"], ValueError), ("rk4", ValueError))),
            rk4_steps=Arg(OTHER, extra=(([NAN], ValueError), ([-0.1], ValueError), ([0.0], ValueError))),
            cvode_rtols=Arg(
                OTHER,
                extra=(
                    (([NAN], ValueError, dict(models=["cvode"])), ([-1e-6], ValueError, dict(models=["cvode"])))
                    if HAVE_CVODE
                    else ()
                ),
            ),
            repeat=Arg(COUNT),
            # max_steps bounds the automatic RK4 sweep (rk4_steps=None)
            max_steps=Arg(COUNT, others=dict(rk4_steps=None)),
            scipy=Arg(OTHER, extra=((["Euler"], ValueError), ("RK45", ValueError), ([1], TypeError), (1, TypeError))),
            scipy_rtols=Arg(OTHER, extra=(([NAN], ValueError), ([-1e-3], ValueError), ([0.0], ValueError))),
        ),
        unchecked=dict(csv="output path (file I/O)", plot="output path (file I/O)"),
    ),
}
# the driven pendulum (driven.py, chaos.py): the drive is a pendula.Drive, checked by its constructor
# (a dataclass, so not an entry here: tests/python/test_driven.py checks its refusals)
_DRIVE = Arg(OTHER, extra=(((1.0, 1.0), TypeError), (None, TypeError), ("torque", TypeError)))
_PROGRESS = Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError)))
_TRANSIENT = Arg(OTHER, extra=((-1, ValueError), (2.5, TypeError), ("3", TypeError)))
_STATES = dict(
    theta0=Arg(REAL, array=True),
    omega0=Arg(REAL, array=True),
    w0=Arg(POS, array=True),
    gamma=Arg(NONNEG, array=True),
    drive=_DRIVE,
    steps_per_period=Arg(COUNT, extra=((7, ValueError),)),
    threads=THREADS,
)
_DASK = dict(chunk_states=Arg(COUNT), client=Arg(OTHER, extra=(("tcp://x", TypeError),)))
_CHAOS = dict(theta0=0.2, omega0=0.0, w0=1.0, gamma=0.5, drive=pendula.Drive("torque", 0.9, 2 / 3), steps_per_period=32)
API.update(
    {
        "driven": Entry(
            valid=dict(t=[0.0, 1.0, 2.5], **_CHAOS),
            args=dict(t=Arg(TIMES), error=Arg(OTHER, extra=(("yes", TypeError),)), progress=_PROGRESS, **_STATES),
        ),
        "poincare": Entry(
            valid=dict(transient=2, points=3, **_CHAOS),
            args=dict(transient=_TRANSIENT, points=Arg(COUNT), section_phase=Arg(REAL), progress=_PROGRESS, **_STATES),
        ),
        "bifurcation": Entry(
            valid=dict(parameter="amplitude", values=[0.9, 1.0], transient=2, points=3, **_CHAOS),
            args=dict(
                parameter=Arg(CHOICE),
                values=Arg(OTHER, extra=(([NAN], ValueError), ([], ValueError))),
                theta0=Arg(REAL),
                omega0=Arg(REAL),
                w0=Arg(POS),
                gamma=Arg(NONNEG),
                drive=_DRIVE,
                transient=_TRANSIENT,
                points=Arg(COUNT),
                section_phase=Arg(REAL),
                steps_per_period=Arg(COUNT),
                threads=THREADS,
                progress=_PROGRESS,
                **_DASK,
            ),
        ),
        "lyapunov": Entry(
            valid=dict(transient=2, periods=16, **_CHAOS),
            args=dict(
                transient=_TRANSIENT,
                periods=Arg(COUNT, extra=((15, ValueError),)),
                orbits=Arg(COUNT, extra=((9, ValueError),)),
                progress=_PROGRESS,
                **_DASK,
                **_STATES,
            ),
        ),
        "periodic_orbits": Entry(
            valid=dict(transient=5, nmax=2, tol=1e-3, **_CHAOS),
            args=dict(
                transient=_TRANSIENT,
                nmax=Arg(COUNT, extra=((65, ValueError),)),
                tol=Arg(POS),
                progress=_PROGRESS,
                **_DASK,
                **_STATES,
            ),
        ),
        "find_periodic_orbit": Entry(
            valid=dict(period=1, **_CHAOS), args=dict(period=Arg(COUNT, extra=((65, ValueError),)), **_STATES)
        ),
        "basins": Entry(
            valid=dict(transient=5, nmax=2, tol=1e-3, max_attractors=4, **_CHAOS),
            args=dict(
                transient=_TRANSIENT,
                nmax=Arg(COUNT),
                tol=Arg(POS),
                max_attractors=Arg(COUNT),
                progress=_PROGRESS,
                **_DASK,
                **_STATES,
            ),
        ),
        "driven_linear": Entry(
            valid=dict(
                t=[0.0, 1.0, 2.0], theta0=0.01, omega0=0.0, w0=1.0, gamma=0.2, drive=pendula.Drive("torque", 0.01, 1.3)
            ),
            args=dict(
                t=Arg(OTHER, extra=(([NAN], ValueError), ([-1.0], ValueError))),
                theta0=Arg(REAL),
                omega0=Arg(REAL),
                w0=Arg(POS),
                gamma=Arg(NONNEG),
                drive=_DRIVE,
            ),
        ),
        "resonance_curve": Entry(
            valid=dict(frequency=1.3, w0=1.0, gamma=0.2),
            args=dict(frequency=Arg(POS, array=True), w0=Arg(POS, array=True), gamma=Arg(NONNEG, array=True)),
        ),
    }
)
# errors= of the elliptic functions: 'raise' or 'nan' (test_elliptic_errors.py)
for _name in ("ellipk", "ellipe", "ellipkm1", "ellipem1", "ellipf", "ellipkinc", "ellipfm1", "ellipj", "ellipjm1"):
    API[_name].args["errors"] = Arg(CHOICE)


# ---- helpers ----------------------------------------------------------------------


def _walk_numbers(result):
    """Every float/complex found in a result (arrays, tuples, dicts, objects)."""
    if result is None or isinstance(result, (str, bytes, bool)):
        return
    if isinstance(result, numbers.Number):
        yield result
    elif isinstance(result, np.ndarray):
        if result.dtype.kind in "fc":
            yield from result.ravel().tolist()
        elif result.dtype == object:
            for x in result.ravel():
                yield from _walk_numbers(x)
    elif isinstance(result, dict):
        for v in result.values():
            yield from _walk_numbers(v)
    elif isinstance(result, (list, tuple)):
        for v in result:
            yield from _walk_numbers(v)
    elif dataclasses.is_dataclass(result):
        for f in dataclasses.fields(result):
            yield from _walk_numbers(getattr(result, f.name))
    elif hasattr(result, "__dict__"):
        for k, v in vars(result).items():
            if not k.startswith("_"):
                yield from _walk_numbers(v)


def _as_array_arg(value):
    if isinstance(value, np.ndarray):
        return value
    return np.array([value, value], dtype=float)


# ---- case generation ----------------------------------------------------------------
@dataclasses.dataclass
class Case:
    func: str
    arg: str
    label: str
    value: object
    expect: object  # exception type, or "nan" (NaN out), or "error-or-empty"
    others: dict = dataclasses.field(default_factory=dict)  # overrides of other args

    @property
    def id(self):
        return f"{self.func}-{self.arg}-{self.label}"


class _Obj:
    pass


def _defaults(fname):
    sig = inspect.signature(getattr(pendula, fname))
    return {p.name: p.default for p in sig.parameters.values() if p.default is not p.empty}


def _cases_for(fname, entry):
    cases = []
    defaults = _defaults(fname) if hasattr(pendula, fname) else {}
    for aname, spec in entry.args.items():
        v = entry.valid[aname] if aname in entry.valid else defaults.get(aname)
        add = lambda label, value, expect, others=None: cases.append(  # noqa: E731
            Case(fname, aname, label, value, expect, {**spec.others, **(others or {})})
        )
        if v is None:
            v = 1.0  # an optional real left at None in the valid call
        if spec.kind in (REAL, POS, NONNEG, TIMES):
            # non-finite values
            if spec.kind == TIMES:
                base = np.asarray(v, dtype=float)
                for label, bad in (("nan", NAN), ("inf", INF), ("-inf", -INF)):
                    t = base.copy()
                    t[-1] = bad
                    add(label, t, ValueError)
            else:
                nan_expect = "nan" if entry.nan == "propagate" else ValueError
                add("nan", NAN, nan_expect)
                # Elliptic rule: +-Inf is either out of domain (ValueError) or
                # has a defined value; never NaN.
                if INF not in spec.out_of_domain:
                    add("inf", INF, ValueError if entry.nan == "raise" else "error-or-defined")
                if -INF not in spec.out_of_domain:
                    add("-inf", -INF, ValueError if entry.nan == "raise" else "error-or-defined")
                if spec.array:
                    add("array-with-nan", np.array([v, NAN]), "nan-element" if entry.nan == "propagate" else ValueError)
                    add(
                        "array-with-inf", np.array([v, INF]), ValueError if entry.nan == "raise" else "error-or-defined"
                    )
                    add("empty-array", np.array([], dtype=float), "error-or-empty")
                    add("object-array", np.array([v, _Obj()], dtype=object), TypeError)
                    add("string-array", np.array(["1.0", "2.0"]), TypeError)
                    add("complex-array", np.array([v + 1j, v]), TypeError)
                else:
                    add("1-element-array", np.array([v]), (ValueError, TypeError))
                    add("2-element-array", np.array([v, v]), (ValueError, TypeError))
            # wrong signs
            if spec.kind == POS:
                add("zero", 0.0, ValueError)
                add("negative", -abs(v) if v else -1.0, ValueError)
                add("-0.0", -0.0, ValueError)
            elif spec.kind == NONNEG:
                add("negative", -1.0, ValueError)
                add("tiny-negative", -5e-324, ValueError)
            for i, bad in enumerate(spec.out_of_domain):
                add(f"out-of-domain-{i}", bad, ValueError)
            # wrong types
            add("string", "1.0", TypeError)
            if defaults.get(aname, "") is not None:  # None is valid for optional arguments
                add("None", None, TypeError)
            add("complex", complex(float(np.ravel(v)[0]), 1.0), TypeError)
            add("object", _Obj(), TypeError)
            add("list-of-strings", ["a", "b"], TypeError)
            # one validation path: the same answer on every route (scalar, array, plan)
            x = float(np.ravel(v)[0])
            add("ragged", [[x], [x, x]], ValueError)
            add("timedelta64", np.timedelta64(1, "s"), TypeError)
            add("datetime64", np.datetime64("2020-01-01"), TypeError)
            add("bool", True, TypeError)
            add("numpy-bool", np.bool_(False), TypeError)
            if spec.array or spec.kind == TIMES:
                add("bool-array", np.array([True, False] * 40), TypeError)
                add("timedelta-array", np.array([1, 2], dtype="m8[s]"), TypeError)
                # f2py passes sizes as 4-byte integers: a clear refusal, not a wrapped size
                # (a zero-stride view: no 2**31 elements are ever allocated)
                add("2**31-elements", np.broadcast_to(np.float64(x), (2**31 + 8,)), ValueError)
            if spec.kind == TIMES:
                base = np.asarray(v, dtype=float)
                add("empty", np.array([], dtype=float), ValueError)
                rep = base.copy()
                rep[-1] = rep[-2]
                add("repeated", rep, ValueError)
                add("decreasing", base[::-1].copy(), ValueError)
                add("2-D", np.stack([base, base + 1]), ValueError)
        elif spec.kind == CHOICE:
            add("unknown", "no-such-choice", ValueError)
            if defaults.get(aname, "") is not None:
                add("None", None, (TypeError, ValueError))
            add("number", 1.0, (TypeError, ValueError))
        elif spec.kind == COUNT:
            add("zero", 0, ValueError)
            add("negative", -3, ValueError)
            add("float", 2.5, (TypeError, ValueError))
            add("string", "10", TypeError)
            if defaults.get(aname, "") is not None:
                add("None", None, TypeError)
        for i, ex in enumerate(spec.extra):
            add(f"extra-{i}", ex[0], ex[1], ex[2] if len(ex) > 2 else None)
    # incompatible shapes between two array arguments
    arr = [a for a, s in entry.args.items() if s.array and s.kind in (REAL, POS, NONNEG)]
    if len(arr) >= 2:
        a, b = arr[:2]
        cases.append(
            Case(
                fname,
                a,
                f"shape-mismatch-with-{b}",
                np.full(2, entry.valid[a], dtype=float),
                ValueError,
                {b: np.full(3, entry.valid[b], dtype=float)},
            )
        )
    return cases


ALL_CASES = [c for f, e in API.items() for c in _cases_for(f, e)]


_PLACEHOLDERS = {
    "SCENE": lambda: pendula.Scene(theta0=0.3, omega0=0.1, t=np.linspace(0.0, 2.0, 5), tol=1e-6),
    "DAMPED": lambda: pendula.Scene(theta0=0.3, omega0=0.1, t=np.linspace(0.0, 2.0, 5), gamma=0.1, tol=1e-6),
}


def _materialise(v):
    """Lists of numbers in the table become float arrays (to check they stay unmodified)."""
    if isinstance(v, (list, tuple)) and all(isinstance(x, numbers.Real) for x in v):
        return np.array(v, dtype=float)
    return v


def _call(fname, kwargs):
    for k, v in list(kwargs.items()):
        if isinstance(v, str) and v in _PLACEHOLDERS:
            kwargs[k] = _PLACEHOLDERS[v]()
    with warnings.catch_warnings():
        # the extreme angles here are meant (tests/python/test_angle_warning.py tests the warning)
        warnings.simplefilter("ignore", pendula.AngleWarning)
        return getattr(pendula, fname)(**kwargs)
