"""The driven damped pendulum: the drive, the integrator and the linear closed form.

The model (Fortran module pendula_drive)::

    torque:  theta'' + gamma theta' + w0^2 sin(theta) = F cos(Omega t + phi)
    pivot:   theta'' + gamma theta' + (w0^2 + (a/l) Omega^2 cos(Omega t + phi)) sin(theta) = 0

(F in rad/s^2; the pivot's a/l is dimensionless: Kapitza's pendulum).  The
integrator is fixed-step RK4 with an integer number N of steps per drive
period, so the drive phase at every step is computed from integers and a
million periods lose none of it.  The chaos tools (Poincare sections,
bifurcation diagrams, Lyapunov exponents, periodic orbits, basins) are in
pendula.chaos.
"""

import dataclasses
import math

import numpy as np

from . import _driven_call as _dc
from . import _fortran, _tables
from ._arrays import as_real, broadcast_real, real_scalar
from ._codes import DRIVE_PIVOT, DRIVE_TORQUE, DRIVEN_DEFAULT_STEPS, OK
from ._defaults import THREADS
from ._errors import raise_for_status

__all__ = ["Drive", "DrivenResult", "driven", "driven_linear", "resonance_curve"]

_KINDS = {"torque": DRIVE_TORQUE, "pivot": DRIVE_PIVOT}


@dataclasses.dataclass(frozen=True)
class Drive:
    """A periodic drive of the pendulum: a torque or a vertically oscillating pivot.

    Parameters
    ----------
    kind : {'torque', 'pivot'}
        ``'torque'``: F cos(Omega t + phi) on the right-hand side, F in rad/s^2.
        ``'pivot'``: the pivot moves as a cos(Omega t + phi), which adds
        (a/l) Omega^2 cos(Omega t + phi) to w0^2 (Kapitza's pendulum).
    amplitude : float
        F [rad/s^2] for a torque, a/l (dimensionless) for a pivot; finite.
    frequency : float
        Omega [rad/s], finite and > 0.
    phase : float, optional
        phi [rad], finite (default 0).

    Raises
    ------
    ValueError
        For an unknown kind, a non-finite amplitude or phase, or frequency <= 0
        (the message names the argument).
    TypeError
        When a value is not a real number.

    Examples
    --------
    >>> d = pendula.Drive("torque", 1.15, 2/3)
    >>> round(d.period, 6)
    9.424778
    >>> pendula.Drive("pivot", 0.1, -1.0)
    Traceback (most recent call last):
    ...
    ValueError: frequency = -1.0 is out of range: it must be finite and > 0
    """

    kind: str
    amplitude: float
    frequency: float
    phase: float = 0.0

    def __post_init__(self):
        if self.kind not in _KINDS:
            raise ValueError(f"kind = {self.kind!r} is not a drive kind: it must be 'torque' or 'pivot'")
        for name in ("amplitude", "frequency", "phase"):
            v = real_scalar(getattr(self, name), name)
            if not math.isfinite(v):
                raise ValueError(f"{name} = {v!r} is invalid: it must be finite")
            object.__setattr__(self, name, v)
        if not self.frequency > 0:
            raise ValueError(f"frequency = {self.frequency!r} is out of range: it must be finite and > 0")

    @property
    def period(self):
        """The drive period 2 pi/Omega [s]."""
        return 2 * math.pi / self.frequency

    @property
    def code(self):
        """The Fortran kind code (DRIVE_TORQUE or DRIVE_PIVOT of pendula_drive)."""
        return _KINDS[self.kind]


@dataclasses.dataclass
class DrivenResult:
    """theta(t) and Omega(t) of driven pendulums (built by :func:`driven`).

    Attributes
    ----------
    t : numpy.ndarray
        Output times [s].
    theta : numpy.ndarray
        Angles [rad], shape ``state_shape + (len(t),)``.
    omega : numpy.ndarray
        Angular velocities [rad/s], same shape.
    theta_err, omega_err : numpy.ndarray or None
        Richardson error estimates (``error=True``), same shape.
    codes : numpy.ndarray
        Status code of each state (0: OK); a failed state is NaN throughout.
    message : str
        '' when every state succeeded, else how many failed and the first.
    inputs : dict
        theta0, omega0, w0, gamma (broadcast to the states' shape) and the
        drive's kind, amplitude, frequency and phase.

    Examples
    --------
    >>> r = pendula.driven([0.0, 1.0], 0.1, 0.0, drive=pendula.Drive("torque", 0.5, 2/3))
    >>> r.theta.shape, r.theta_err is None
    ((2,), True)
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    theta_err: np.ndarray = None
    omega_err: np.ndarray = None
    codes: np.ndarray = None
    message: str = ""
    inputs: dict = None

    @property
    def ok(self):
        """Mask of the states that succeeded."""
        return np.asarray(self.codes) == OK

    def to_pandas(self):
        """The result as a long table, one row per state and time.

        Returns
        -------
        pandas.DataFrame
            Columns ``state``, ``t``, ``theta``, ``omega`` (and the error
            estimates when computed), then each state's inputs ``theta0``,
            ``omega0``, ``w0``, ``gamma`` and ``code``.

        Examples
        --------
        >>> r = pendula.driven([0.0, 1.0], 0.1, 0.0, drive=pendula.Drive("torque", 0.5, 2/3))
        >>> list(r.to_pandas().columns)
        ['state', 't', 'theta', 'omega', 'theta0', 'omega0', 'w0', 'gamma', 'code']
        """
        import pandas as pd

        th = self.theta.reshape(-1, len(self.t))
        cols = {
            "state": np.repeat(np.arange(th.shape[0]), len(self.t)),
            "t": np.tile(self.t, th.shape[0]),
            "theta": th.ravel(),
            "omega": self.omega.reshape(-1, len(self.t)).ravel(),
        }
        if self.theta_err is not None:
            cols["theta_err"] = self.theta_err.ravel()
            cols["omega_err"] = self.omega_err.ravel()
        return pd.DataFrame({**cols, **_state_columns(self, len(self.t))})

    def to_xarray(self):
        """The result as an xarray Dataset.

        Returns
        -------
        xarray.Dataset
            theta and omega (and the error estimates) over (batch dims, t);
            ``codes`` over the batch dims; the inputs theta0, omega0, w0,
            gamma as coordinates and the drive's parameters as attributes.

        Examples
        --------
        >>> r = pendula.driven([0.0, 1.0], [0.1, 0.2], 0.0, drive=pendula.Drive("torque", 0.5, 2/3), w0=1.0)
        >>> ds = r.to_xarray()
        >>> ds["theta"].dims, ds["w0"].values.tolist()
        (('batch', 't'), [1.0, 1.0])
        """
        fields = {"theta": self.theta, "omega": self.omega, "theta_err": self.theta_err, "omega_err": self.omega_err}
        coords = {k: v for k, v in (self.inputs or {}).items() if k in ("theta0", "omega0", "w0", "gamma")}
        attrs = {k: v for k, v in (self.inputs or {}).items() if k in ("kind", "amplitude", "frequency", "phase")}
        return _tables.dataset(
            self.t, fields, np.shape(self.codes), per_state={"codes": self.codes}, attrs=attrs, coords=coords
        )


def _state_columns(result, repeat=1):
    """Each state's inputs and code as table columns, each value repeated ``repeat`` times."""
    cols = {}
    for k in ("theta0", "omega0", "w0", "gamma"):
        if result.inputs is not None and k in result.inputs:
            cols[k] = np.repeat(np.asarray(result.inputs[k], dtype=float).reshape(-1), repeat)
    if result.codes is not None:
        cols["code"] = np.repeat(np.asarray(result.codes).reshape(-1), repeat)
    return cols


def driven(
    t,
    theta0,
    omega0,
    *,
    drive,
    w0=None,
    gamma=None,
    g=None,
    length=None,
    b=None,
    mass=None,
    steps_per_period=DRIVEN_DEFAULT_STEPS,
    error=False,
    threads=THREADS,
    progress=None,
):
    """Integrate driven damped pendulums by RK4 with a whole number of steps per drive period.

    Parameters
    ----------
    t : array_like
        Output times [s], finite, strictly increasing; ``t[0]`` is the start
        time, where the state is (theta0, omega0).  A time between grid
        times is reached by one shorter RK4 step (the grid is not moved).
    theta0, omega0 : float or array_like
        Initial angle [rad] and angular velocity [rad/s]; broadcast with w0
        and gamma (one trajectory per element).
    drive : Drive
        The drive (its kind, amplitude, frequency and phase).
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length) (the text's
        value for the one not given; with w0 only when they agree).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
    steps_per_period : int, optional
        RK4 steps per drive period N (default 128); h = T/N.  Error O(h^4).
    error : bool, optional
        Also estimate the error by Richardson extrapolation (a second run
        with 2 N steps: ``|x_N - x_2N| 16/15``).
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.
    progress : bool or callable, optional
        True for a tqdm bar, or ``callable(done, total)`` (states).

    Returns
    -------
    DrivenResult
        ``theta`` and ``omega`` of shape ``broadcast_shape + (len(t),)``; a
        state that failed (too few steps per period for its w0, gamma and the
        drive, or a state that overflowed) has its code in ``codes`` and NaN
        throughout.

    Raises
    ------
    ValueError
        Bad times or parameters (the message names the argument and, in a
        batch, the state: ``w0[1] = -1.0 ...``).
    PendulaSolverError
        Only when every state failed (the first state's error).
    TypeError
        Non-real input, or a drive that is not a pendula.Drive.

    Examples
    --------
    The dimensionless pendulum of Baker and Gollub (w0 = 1, gamma = 0.5,
    Omega = 2/3):

    >>> d = pendula.Drive("torque", 1.15, 2/3)
    >>> r = pendula.driven(np.linspace(0.0, 30.0, 4), [0.2, 0.3], 0.0, drive=d, w0=1.0, gamma=0.5, error=True)
    >>> r.theta.shape
    (2, 4)
    >>> bool(np.all(r.theta_err < 1e-4))
    True
    """
    drive = _dc.drive_arg(drive)
    tt = _dc.times_arg(t)
    steps = _dc.steps_arg(steps_per_period)
    if not isinstance(error, bool):
        raise TypeError(f"error must be True or False, got {type(error).__name__}")
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    shape, scalar, args, inputs = _dc.states(drive, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    n = args["theta0"].size
    work = n * steps * max(tt[-1] - tt[0], 0.0) / drive.period if tt.size else 0
    th = _dc.threads_arg(threads, work)
    (theta, omega, et, eo), res = _dc.watched(
        _fortran.driven_f2py,
        work * (3 if error else 1),
        n,
        progress,
        shape,
        t=tt,
        nsteps=steps,
        richardson=int(error),
        threads=th,
        **args,
    )
    out = [np.ascontiguousarray(a.T).reshape(shape + (tt.size,)) for a in (theta, omega, et, eo)]
    if not error:
        out[2] = out[3] = None
    _dc.nan_failed(res, *out)
    return DrivenResult(tt, out[0], out[1], out[2], out[3], res.codes, res.message, inputs)


def driven_linear(t, theta0, omega0, *, drive, w0=None, gamma=None, g=None, length=None, b=None, mass=None):
    """The linearised torque-driven damped oscillator in closed form.

    theta'' + gamma theta' + w0^2 theta = F cos(Omega t + phi): the steady
    state A cos(Omega t + phi - delta) (see :func:`resonance_curve`) plus the
    free damped motion that carries the initial state's difference from it
    (the transient).  A model of the pendulum to relative O(theta^2/8).

    Parameters
    ----------
    t : array_like
        Times [s], finite, >= 0 (any order); the initial state is at t = 0.
    theta0, omega0 : float
        Initial angle [rad] and angular velocity [rad/s].
    drive : Drive
        A torque drive (a pivot's linearisation, Mathieu's equation, has no
        closed form).
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length) (the text's
        value for the one not given; with w0 only when they agree).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).

    Returns
    -------
    theta, omega : numpy.ndarray
        theta(t) [rad] and Omega(t) [rad/s], shaped like t.

    Raises
    ------
    ValueError
        Bad times or parameters, a pivot drive, or undamped exact resonance.
    TypeError
        Non-real input, or a drive that is not a pendula.Drive.

    Examples
    --------
    >>> d = pendula.Drive("torque", 0.01, 1.2)
    >>> th, om = pendula.driven_linear([0.0, 50.0], 0.0, 0.0, drive=d, gamma=0.3)
    >>> float(th[0])
    0.0
    """
    drive = _dc.drive_arg(drive)
    tt = as_real(t, "t")
    th0 = real_scalar(theta0, "theta0")
    om0 = real_scalar(omega0, "omega0")
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    w = real_scalar(w0, "w0")
    g = real_scalar(gamma, "gamma")
    if drive.kind != "torque":
        raise ValueError("drive kind is 'pivot': the linear closed form exists for a torque drive only")
    theta, omega, code, msg = _fortran.driven_linear_f2py(
        tt.reshape(-1), th0, om0, w, g, drive.amplitude, drive.frequency, drive.phase
    )
    raise_for_status(code, msg)
    return theta.reshape(tt.shape), omega.reshape(tt.shape)


def resonance_curve(frequency, *, w0=None, gamma=None, g=None, length=None, b=None, mass=None):
    """Steady-state gain and phase lag of the linear oscillator driven at a frequency.

    For theta'' + gamma theta' + w0^2 theta = F cos(Omega t) the steady
    amplitude is A = F gain with gain = 1/sqrt((w0^2 - Omega^2)^2 + (gamma Omega)^2)
    and the response lags the drive by delta = atan2(gamma Omega, w0^2 - Omega^2)
    in [0, pi] (Taylor, Classical Mechanics, eqs. 5.64-5.65).

    Parameters
    ----------
    frequency : float or array_like
        Drive frequency Omega [rad/s], finite and > 0.
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length) (the text's
        value for the one not given; with w0 only when they agree).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).

    Returns
    -------
    gain : numpy.ndarray or float
        A/F [s^2] (+inf at undamped resonance).
    lag : numpy.ndarray or float
        delta [rad].

    Raises
    ------
    ValueError
        A non-finite or out-of-range argument (named).
    TypeError
        Non-real input.

    Examples
    --------
    >>> gain, lag = pendula.resonance_curve(1.0, w0=1.0, gamma=0.2)
    >>> round(gain, 12), round(lag, 12)
    (5.0, 1.570796326795)
    """
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    shape, scalar, f = broadcast_real(frequency=frequency, w0=w0, gamma=gamma)
    for name, lo_ok in (("frequency", lambda x: x > 0), ("w0", lambda x: x > 0), ("gamma", lambda x: x >= 0)):
        a = f[name]
        bad = ~(np.isfinite(a) & lo_ok(np.where(np.isfinite(a), a, 1.0)))
        if bad.any():
            v = a[np.argmax(bad)]
            rng = ">= 0" if name == "gamma" else "> 0"
            raise ValueError(f"{name} = {v!r} is out of range: it must be finite and {rng}")
    if f["w0"].size == 0:
        return np.empty(shape), np.empty(shape)
    gain, lag = _fortran.driven_response_f2py(f["w0"], f["gamma"], f["frequency"])
    if scalar:
        return float(gain[0]), float(lag[0])
    return gain.reshape(shape), lag.reshape(shape)
