"""Chaos tools of the driven pendulum: Poincare sections, bifurcation diagrams,
Lyapunov exponents, periodic orbits and basins of attraction.

Every tool is a Fortran batch (src/driven: many initial states or parameter
values per call, blocks of SIMD lanes on every core), started at t = 0 and
sampled stroboscopically on the RK4 grid of N steps per drive period
(pendula.driven); each takes ``threads`` and ``progress`` and stops on
Ctrl-C.  See docs/guide/driven.md.
"""

import dataclasses
import math

import numpy as np

from . import _driven_call as _dc
from . import _fortran, _tables
from ._arrays import as_real, real_scalar
from ._codes import BASIN_UNSETTLED, DRIVEN_DEFAULT_STEPS, LYAPUNOV_BLOCKS, OK, ORBIT_MAX_PERIOD
from ._defaults import CHUNK_STATES, THREADS, WELL_NONE, check_threads
from ._errors import number, raise_for_status
from .driven import _state_columns

__all__ = [
    "Section",
    "poincare",
    "bifurcation",
    "LyapunovResult",
    "lyapunov",
    "PeriodicOrbits",
    "periodic_orbits",
    "find_periodic_orbit",
    "Basins",
    "basins",
    "UNSETTLED",
    "FAILED",
]

UNSETTLED = BASIN_UNSETTLED
"""Basin label of a state that settled on no periodic attractor of period <= nmax
(chaotic, or still settling); attractor labels count from 1."""

FAILED = WELL_NONE
"""The integer fields (basin ``labels``, ``period``, ``winding``) of a state
that failed: -2**31, never a label, a period or a number of turns (the
``codes`` of the result say why; ``ok`` is the mask of the others)."""

_PARAMS = ("amplitude", "frequency", "phase", "gamma", "w0")


class _Outcome:
    """The batch contract's fields of a result: codes, message, inputs and the ok mask."""

    @property
    def ok(self):
        """Mask of the states that succeeded."""
        return np.asarray(self.codes) == OK


def _work(n, steps, periods):
    return n * steps * periods


@dataclasses.dataclass
class Section(_Outcome):
    """Stroboscopic (Poincare) section points (built by :func:`poincare` and :func:`bifurcation`).

    Attributes
    ----------
    theta : numpy.ndarray
        Section angles wrapped to (-pi, pi] [rad], shape ``shape + (points,)``.
    omega : numpy.ndarray
        Section angular velocities [rad/s], same shape.
    mean_omega : numpy.ndarray
        Mean angular velocity over the recorded periods [rad/s], shape ``shape``.
    rotation_number : numpy.ndarray
        ``mean_omega / Omega``: turns per drive period (0 for oscillations).
    values : numpy.ndarray or None
        The parameter values of a bifurcation diagram (its first axis).
    parameter : str or None
        The parameter varied in a bifurcation diagram.
    codes : numpy.ndarray
        Status code of each state or value (0: OK); a failed one is NaN in
        every real field.
    message : str
        '' when every state succeeded, else how many failed and the first.
    inputs : dict
        theta0, omega0, w0, gamma (broadcast to the states' shape) and the
        drive's kind, amplitude, frequency and phase.

    Examples
    --------
    >>> s = pendula.poincare([0.2, 0.3], 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5, points=3)
    >>> s.theta.shape, s.rotation_number.shape
    ((2, 3), (2,))
    """

    theta: np.ndarray
    omega: np.ndarray
    mean_omega: np.ndarray
    rotation_number: np.ndarray
    values: np.ndarray = None
    parameter: str = None
    codes: np.ndarray = None
    message: str = ""
    inputs: dict = None

    def to_pandas(self):
        """The section points as a long table.

        Returns
        -------
        pandas.DataFrame
            Columns ``state`` (or the parameter's name), ``k`` (point index),
            ``theta``, ``omega``, then each state's inputs and ``code``.

        Examples
        --------
        >>> s = pendula.poincare(0.2, 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5,
        ...                      transient=50, points=3)
        >>> len(s.to_pandas())
        3
        """
        import pandas as pd

        th = self.theta.reshape(-1, self.theta.shape[-1])
        m, k = th.shape
        first = np.repeat(self.values if self.values is not None else np.arange(m), k)
        return pd.DataFrame(
            {
                self.parameter or "state": first,
                "k": np.tile(np.arange(k), m),
                "theta": th.ravel(),
                "omega": self.omega.reshape(-1, k).ravel(),
                **_state_columns(self, k),
            }
        )


def _section_call(drive, args, shape, steps, section_phase, transient, points, threads, progress):
    n = args["theta0"].size
    work = _work(n, steps, transient + points + 1)
    (ts, os_, mo), res = _dc.watched(
        _fortran.poincare_f2py,
        work,
        n,
        progress,
        shape,
        nsteps=steps,
        section_phase=section_phase,
        transient=transient,
        nrec=points,
        threads=_dc.threads_arg(threads, work),
        **args,
    )
    theta = np.ascontiguousarray(ts.T).reshape(shape + (points,))
    omega = np.ascontiguousarray(os_.T).reshape(shape + (points,))
    mo = mo.reshape(shape)
    freq = np.broadcast_to(args["freq"], (n,)).reshape(shape)
    rot = mo / freq
    _dc.nan_failed(res, theta, omega, mo, rot)
    return theta, omega, mo, rot, res


def poincare(
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
    transient=300,
    points=200,
    section_phase=None,
    steps_per_period=DRIVEN_DEFAULT_STEPS,
    threads=THREADS,
    progress=None,
):
    """Poincare (stroboscopic) sections of driven pendulums after a transient.

    Parameters
    ----------
    theta0, omega0 : float or array_like
        Initial states at t = 0 [rad, rad/s]; broadcast with w0 and gamma.
    drive : Drive
        The drive.
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
    transient : int, optional
        Drive periods discarded first (default 300).
    points : int, optional
        Section points recorded per state, >= 1 (default 200).
    section_phase : float, optional
        The drive phase Omega t + phi of the section [rad] (default: the
        drive's phase, i.e. t = k T); rounded to the nearest of the N grid
        phases of a period.
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.
    progress : bool or callable, optional
        True for a tqdm bar, or ``callable(done, total)`` (states).

    Returns
    -------
    Section
        theta wrapped to (-pi, pi], omega, the mean angular velocity and the
        rotation number.

    Raises
    ------
    ValueError
        A bad parameter or count (named).
    TypeError
        Non-real input, non-integer counts, or a drive that is not a pendula.Drive.

    Examples
    --------
    >>> d = pendula.Drive("torque", 1.07, 2/3)
    >>> s = pendula.poincare(0.2, 0.0, drive=d, w0=1.0, gamma=0.5, transient=300, points=4)
    >>> bool(abs(s.theta[2] - s.theta[0]) < 1e-6 < abs(s.theta[1] - s.theta[0]))   # period 2
    True
    """
    drive = _dc.drive_arg(drive)
    steps = _dc.steps_arg(steps_per_period)
    transient = _dc.count_arg(transient, "transient", 0)
    points = _dc.count_arg(points, "points", 1)
    check_threads(threads)
    ph = drive.phase if section_phase is None else real_scalar(section_phase, "section_phase")
    if not math.isfinite(ph):
        raise ValueError(f"section_phase = {ph!r} is invalid: it must be finite")
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    shape, scalar, args, inputs = _dc.states(drive, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    theta, omega, mo, rot, res = _section_call(drive, args, shape, steps, ph, transient, points, threads, progress)
    return Section(theta, omega, mo, rot, None, None, res.codes, res.message, inputs)


def bifurcation(
    parameter,
    values,
    *,
    drive,
    w0=None,
    gamma=None,
    g=None,
    length=None,
    b=None,
    mass=None,
    theta0=0.2,
    omega0=0.0,
    transient=300,
    points=200,
    section_phase=None,
    steps_per_period=DRIVEN_DEFAULT_STEPS,
    threads=THREADS,
    progress=None,
    client=None,
    chunk_states=CHUNK_STATES,
):
    """A bifurcation diagram: Poincare section points over values of one parameter.

    Every value starts from the same (theta0, omega0) at t = 0 (no
    continuation), so coexisting attractors show as the basin of that start
    selects them.

    Parameters
    ----------
    parameter : {'amplitude', 'frequency', 'phase', 'gamma', 'w0'}
        The parameter varied (amplitude, frequency and phase of the drive).
    values : array_like
        Its values (1-D).
    drive : Drive
        The drive supplying the other drive parameters.
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
    theta0, omega0 : float, optional
        The initial state [rad, rad/s] (default 0.2, 0).
    transient : int, optional
        Drive periods discarded (default 300).
    points : int, optional
        Section points per value (default 200).
    section_phase : float, optional
        Drive phase of the section [rad] (default: the drive's phase).
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.
    progress : bool or callable, optional
        True for a tqdm bar, or ``callable(done, total)`` (values).
    client : dask.distributed.Client, optional
        Run on Dask in chunks of ``chunk_states`` values (one thread each);
        the answer is bit for bit the local one.
    chunk_states : int, optional
        Values per Dask chunk (default ``pendula._defaults.CHUNK_STATES``).

    Returns
    -------
    Section
        ``theta`` and ``omega`` of shape ``(len(values), points)``, with
        ``values`` and ``parameter`` set; a value whose run failed has its
        code in ``codes`` and NaN in every real field.

    Raises
    ------
    ValueError
        An unknown parameter, or a bad value or count (named).
    TypeError
        Non-real input, or a drive that is not a pendula.Drive.

    Examples
    --------
    >>> d = pendula.Drive("torque", 1.0, 2/3)
    >>> b = pendula.bifurcation("amplitude", [0.9, 1.07], drive=d, w0=1.0, gamma=0.5, points=4)
    >>> b.theta.shape
    (2, 4)
    """
    drive = _dc.drive_arg(drive)
    if parameter not in _PARAMS:
        raise ValueError(f"parameter = {parameter!r} is not a parameter: it must be one of {', '.join(_PARAMS)}")
    vals = as_real(values, "values").reshape(-1)
    if vals.size == 0:
        raise ValueError("values is empty: it needs at least one value")
    if not np.all(np.isfinite(vals)):
        raise ValueError(f"values[{int(np.argmax(~np.isfinite(vals)))}] is invalid: every value must be finite")
    rule = {
        "w0": (lambda v: v > 0, "> 0"),
        "frequency": (lambda v: v > 0, "> 0"),
        "gamma": (lambda v: v >= 0, ">= 0"),
    }.get(parameter)
    if rule is not None and not rule[0](vals).all():
        i = int(np.argmax(~rule[0](vals)))
        raise ValueError(f"values[{i}] = {number(vals[i])} is out of range: {parameter} must be {rule[1]}")
    steps = _dc.steps_arg(steps_per_period)
    transient = _dc.count_arg(transient, "transient", 0)
    points = _dc.count_arg(points, "points", 1)
    check_threads(threads)
    _dc.check_client(client)
    chunk_states = _dc.count_arg(chunk_states, "chunk_states", 1)
    ph = drive.phase if section_phase is None else real_scalar(section_phase, "section_phase")
    if not math.isfinite(ph):
        raise ValueError(f"section_phase = {ph!r} is invalid: it must be finite")
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    base = dict(
        theta0=real_scalar(theta0, "theta0"),
        omega0=real_scalar(omega0, "omega0"),
        w0=real_scalar(w0, "w0"),
        gamma=real_scalar(gamma, "gamma"),
    )
    _dc.check_states({k: np.array([v]) for k, v in base.items()}, ())
    args = dict(
        theta0=np.full(vals.size, base["theta0"]),
        omega0=np.array([base["omega0"]]),
        w0=np.array([base["w0"]]),
        gamma=np.array([base["gamma"]]),
        kind=drive.code,
        amp=np.array([drive.amplitude]),
        freq=np.array([drive.frequency]),
        phase=np.array([drive.phase]),
    )
    key = {"amplitude": "amp", "frequency": "freq", "phase": "phase", "gamma": "gamma", "w0": "w0"}[parameter]
    args[key] = vals.copy()
    flats = {k: np.broadcast_to(args[k], vals.shape) for k in ("theta0", "omega0", "w0", "gamma")}
    inputs = _dc.inputs(drive, (vals.size,), flats)
    if parameter in ("amplitude", "frequency", "phase"):
        inputs[parameter] = vals.copy()
    if client is None:
        theta, omega, mo, rot, res = _section_call(
            drive, args, (vals.size,), steps, ph, transient, points, threads, progress
        )
        return Section(theta, omega, mo, rot, vals, parameter, res.codes, res.message, inputs)
    n = vals.size
    chunks = [
        _chunk_args(
            args, s0, chunk_states, n, nsteps=steps, section_phase=ph, transient=transient, nrec=points, threads=1
        )
        for s0 in range(0, n, chunk_states)
    ]
    (ts, os_, mo), res = _dc.settle(_dc.dask_chunks(client, "poincare_f2py", chunks, progress, n), (n,))
    theta, omega = np.ascontiguousarray(ts.T), np.ascontiguousarray(os_.T)
    rot = mo / np.broadcast_to(args["freq"], (n,))
    _dc.nan_failed(res, theta, omega, mo, rot)
    return Section(theta, omega, mo, rot, vals, parameter, res.codes, res.message, inputs)


def _chunk_args(args, start, size, n, **extra):
    """The glue's kwargs for states [start, start + size): per-state arrays sliced, the others as they are."""
    out = {
        k: (v[start : start + size] if isinstance(v, np.ndarray) and v.size == n and n > 1 else v)
        for k, v in args.items()
    }
    out.update(extra)
    return out


@dataclasses.dataclass
class LyapunovResult(_Outcome):
    """Lyapunov exponents with error estimates (built by :func:`lyapunov`).

    Attributes
    ----------
    exponents : numpy.ndarray
        [1/s], shape ``shape + (2,)``, the largest first; they sum to -gamma
        (up to the RK4 error of the tangent map, O(h^4)).
    errors : numpy.ndarray
        Error estimates [1/s], same shape: the standard error of the means of
        16 blocks of the measured periods, combined with half the gap between
        the means of the two halves (a running average still drifting).
    codes : numpy.ndarray
        Status code of each state (0: OK); a failed state is NaN.
    message : str
        '' when every state succeeded, else how many failed and the first.
    inputs : dict
        theta0, omega0, w0, gamma (broadcast to the states' shape) and the
        drive's kind, amplitude, frequency and phase.

    Examples
    --------
    >>> r = pendula.lyapunov(0.2, 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5, periods=32)
    >>> r.exponents.shape, r.errors.shape
    ((2,), (2,))
    """

    exponents: np.ndarray
    errors: np.ndarray
    codes: np.ndarray = None
    message: str = ""
    inputs: dict = None

    def to_pandas(self):
        """The exponents as a table, one row per state.

        Returns
        -------
        pandas.DataFrame
            Columns ``lambda1``, ``lambda1_err``, ``lambda2``, ``lambda2_err``,
            then each state's inputs and ``code``.

        Examples
        --------
        >>> r = pendula.lyapunov(0.2, 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5, periods=32)
        >>> list(r.to_pandas().columns)
        ['lambda1', 'lambda1_err', 'lambda2', 'lambda2_err', 'theta0', 'omega0', 'w0', 'gamma', 'code']
        """
        import pandas as pd

        e = self.exponents.reshape(-1, 2)
        s = self.errors.reshape(-1, 2)
        return pd.DataFrame(
            {
                "lambda1": e[:, 0],
                "lambda1_err": s[:, 0],
                "lambda2": e[:, 1],
                "lambda2_err": s[:, 1],
                **_state_columns(self),
            }
        )

    def to_xarray(self):
        """The exponents as an xarray Dataset.

        Returns
        -------
        xarray.Dataset
            ``lambda1``, ``lambda1_err``, ``lambda2``, ``lambda2_err`` [1/s] and
            ``codes`` over the batch dims; the inputs theta0, omega0, w0, gamma
            as coordinates and the drive's parameters as attributes.

        Examples
        --------
        >>> r = pendula.lyapunov([0.2, 0.3], 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5,
        ...                      periods=32)
        >>> r.to_xarray()["gamma"].values.tolist()
        [0.5, 0.5]
        """
        shape = np.shape(self.codes)
        per_state = {
            "lambda1": self.exponents[..., 0],
            "lambda1_err": self.errors[..., 0],
            "lambda2": self.exponents[..., 1],
            "lambda2_err": self.errors[..., 1],
            "codes": self.codes,
        }
        coords = {k: v for k, v in (self.inputs or {}).items() if k in ("theta0", "omega0", "w0", "gamma")}
        attrs = {k: v for k, v in (self.inputs or {}).items() if k in ("kind", "amplitude", "frequency", "phase")}
        return _tables.dataset(None, {}, shape, per_state=per_state, attrs=attrs, coords=coords)


def lyapunov(
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
    transient=100,
    periods=2000,
    steps_per_period=DRIVEN_DEFAULT_STEPS,
    threads=THREADS,
    progress=None,
    client=None,
    chunk_states=CHUNK_STATES,
):
    """Both Lyapunov exponents of driven pendulums, with error estimates.

    Two tangent vectors follow the derivative of the RK4 map and are
    re-orthonormalised (Gram-Schmidt) every drive period (Benettin et al.,
    Meccanica 15 (1980) 9); the exponents are the mean log stretchings per
    unit time over ``periods`` drive periods after ``transient``.

    Parameters
    ----------
    theta0, omega0 : float or array_like
        Initial states at t = 0 [rad, rad/s]; broadcast with w0 and gamma.
    drive : Drive
        The drive.
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
    transient : int, optional
        Drive periods before the measurement (default 100).
    periods : int, optional
        Drive periods measured, >= 16 (default 2000).
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.
    progress : bool or callable, optional
        True for a tqdm bar, or ``callable(done, total)`` (states).

    client : dask.distributed.Client, optional
        Run on Dask in chunks of ``chunk_states`` states (one thread each);
        the answer is bit for bit the local one.
    chunk_states : int, optional
        States per Dask chunk (default ``pendula._defaults.CHUNK_STATES``).

    Returns
    -------
    LyapunovResult
        ``exponents`` and ``errors`` of shape ``shape + (2,)``; a failed
        state has its code in ``codes`` and NaN.

    Raises
    ------
    ValueError
        A bad parameter or count (named).
    TypeError
        Non-real input, non-integer counts, or a drive that is not a pendula.Drive.

    Examples
    --------
    >>> d = pendula.Drive("torque", 1.15, 2/3)
    >>> r = pendula.lyapunov(0.2, 0.0, drive=d, w0=1.0, gamma=0.5, periods=2000)
    >>> bool(r.exponents[0] > 0), round(float(r.exponents.sum()), 4)
    (True, -0.5)
    """
    drive = _dc.drive_arg(drive)
    steps = _dc.steps_arg(steps_per_period)
    transient = _dc.count_arg(transient, "transient", 0)
    periods = _dc.count_arg(periods, "periods", LYAPUNOV_BLOCKS)
    check_threads(threads)
    _dc.check_client(client)
    chunk_states = _dc.count_arg(chunk_states, "chunk_states", 1)
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    shape, scalar, args, inputs = _dc.states(drive, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    n = args["theta0"].size
    work = _work(n, 3 * steps, transient + periods)
    opts = dict(nsteps=steps, transient=transient, periods=periods)
    if client is None:
        (ly, le), res = _dc.watched(
            _fortran.lyapunov_f2py, work, n, progress, shape, threads=_dc.threads_arg(threads, work), **opts, **args
        )
    else:
        chunks = [_chunk_args(args, s0, chunk_states, n, threads=1, **opts) for s0 in range(0, n, chunk_states)]
        (ly, le), res = _dc.settle(_dc.dask_chunks(client, "lyapunov_f2py", chunks, progress, n), shape)
    ly = np.ascontiguousarray(ly.T).reshape(shape + (2,))
    le = np.ascontiguousarray(le.T).reshape(shape + (2,))
    _dc.nan_failed(res, ly, le)
    return LyapunovResult(ly, le, res.codes, res.message, inputs)


@dataclasses.dataclass
class PeriodicOrbits(_Outcome):
    """Periodic orbits of the stroboscopic map (built by :func:`periodic_orbits`).

    Attributes
    ----------
    period : numpy.ndarray
        Period in drive periods (0: none found, or Newton failed).
    winding : numpy.ndarray
        Turns made per period (0 for an oscillation).
    theta, omega : numpy.ndarray
        The orbit's strobe point at t = k T: angle in (-pi, pi] [rad] and
        angular velocity [rad/s].
    multipliers : numpy.ndarray
        Floquet multipliers (complex), shape ``shape + (2,)``, the largest
        modulus first.
    stable : numpy.ndarray
        True where the largest multiplier's modulus is < 1.
    floquet_exponents : numpy.ndarray
        ``ln|mu| / (period T)`` [1/s]: a stable orbit's Lyapunov exponents
        (0 where ``period`` is 0).
    residual : numpy.ndarray
        Newton's final residual (<= 1e-10 when found).
    codes : numpy.ndarray
        Status code of each state (0: OK); a failed state has ``period`` and
        ``winding`` ``FAILED`` and NaN in every real field.
    message : str
        '' when every state succeeded, else how many failed and the first.
    inputs : dict
        theta0, omega0, w0, gamma (broadcast to the states' shape) and the
        drive's kind, amplitude, frequency and phase.

    Examples
    --------
    >>> o = pendula.periodic_orbits(0.2, 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5)
    >>> int(o.period), o.multipliers.shape
    (1, (2,))
    """

    period: np.ndarray
    winding: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    multipliers: np.ndarray
    stable: np.ndarray
    floquet_exponents: np.ndarray
    residual: np.ndarray
    codes: np.ndarray = None
    message: str = ""
    inputs: dict = None

    def to_pandas(self):
        """The orbits as a table, one row per state.

        Returns
        -------
        pandas.DataFrame
            period, winding, theta, omega, |mu1|, |mu2|, stable, then each
            state's inputs and ``code``.

        Examples
        --------
        >>> o = pendula.periodic_orbits(0.2, 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5)
        >>> int(o.to_pandas()["period"][0])
        1
        """
        import pandas as pd

        mu = np.abs(self.multipliers.reshape(-1, 2))
        return pd.DataFrame(
            {
                "period": self.period.ravel(),
                "winding": self.winding.ravel(),
                "theta": self.theta.ravel(),
                "omega": self.omega.ravel(),
                "abs_mu1": mu[:, 0],
                "abs_mu2": mu[:, 1],
                "stable": self.stable.ravel(),
                **_state_columns(self),
            }
        )


def _orbits(drive, args, inputs, shape, period_in, steps, transient, nmax, tol, threads, progress):
    n = args["theta0"].size
    per_in = np.asarray(period_in, dtype=np.int32).reshape(-1)
    work = _work(n, 3 * steps, transient + 2 * nmax + 40 * max(int(per_in.max()), nmax))
    (per, wnd, tp, op, mult, resid), res = _dc.watched(
        _fortran.orbits_f2py,
        work,
        n,
        progress,
        shape,
        period_in=per_in,
        nsteps=steps,
        transient=transient,
        nmax=nmax,
        tol=tol,
        threads=_dc.threads_arg(threads, work),
        **args,
    )
    mu = (mult[0::2] + 1j * mult[1::2]).T.reshape(shape + (2,))
    per = per.reshape(shape)
    T = 2 * math.pi / np.broadcast_to(args["freq"], (n,)).reshape(shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        fe = np.where(per[..., None] > 0, np.log(np.abs(mu)) / (np.maximum(per, 1) * T)[..., None], 0.0)
    stable = (per > 0) & (np.abs(mu[..., 0]) < 1)
    wnd, tp, op, resid = wnd.reshape(shape), tp.reshape(shape), op.reshape(shape), resid.reshape(shape)
    _dc.nan_failed(res, tp, op, mu, fe, resid)
    bad = res.codes != OK
    per, wnd = np.where(bad, FAILED, per), np.where(bad, FAILED, wnd)
    return PeriodicOrbits(per, wnd, tp, op, mu, stable & ~bad, fe, resid, res.codes, res.message, inputs)


def periodic_orbits(
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
    transient=200,
    nmax=8,
    tol=1e-6,
    steps_per_period=DRIVEN_DEFAULT_STEPS,
    threads=THREADS,
    progress=None,
):
    """Detect the periodic attractor each state settles on and locate it by Newton's method.

    After ``transient`` periods the strobe points (t = k T) are tested for a
    period n <= nmax (points repeating within ``tol``, theta modulo 2 pi);
    the orbit is then solved from there by Newton on P^n(x) - x - (2 pi m, 0)
    with the monodromy matrix from the variational equations, which gives
    its Floquet multipliers.

    Parameters
    ----------
    theta0, omega0 : float or array_like
        Initial states at t = 0 [rad, rad/s]; broadcast with w0 and gamma.
    drive : Drive
        The drive.
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
    transient : int, optional
        Drive periods before detection (default 200).
    nmax : int, optional
        Largest period searched, in [1, 64] (default 8).
    tol : float, optional
        Detection tolerance on strobe points, > 0 (default 1e-6).
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.
    progress : bool or callable, optional
        True for a tqdm bar, or ``callable(done, total)`` (states).

    Returns
    -------
    PeriodicOrbits
        Period 0 where no attractor of period <= nmax was found (chaos).

    Raises
    ------
    ValueError
        A bad parameter, count or tolerance (named).
    TypeError
        Non-real input, non-integer counts, or a drive that is not a pendula.Drive.

    Examples
    --------
    >>> d = pendula.Drive("torque", 1.07, 2/3)
    >>> o = pendula.periodic_orbits(0.2, 0.0, drive=d, w0=1.0, gamma=0.5)
    >>> int(o.period), bool(o.stable)
    (2, True)
    """
    drive = _dc.drive_arg(drive)
    steps = _dc.steps_arg(steps_per_period)
    transient = _dc.count_arg(transient, "transient", 0)
    nmax = _dc.count_arg(nmax, "nmax", 1, ORBIT_MAX_PERIOD)
    tol = _positive(tol, "tol")
    check_threads(threads)
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    shape, scalar, args, inputs = _dc.states(drive, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    return _orbits(drive, args, inputs, shape, [0], steps, transient, nmax, tol, threads, progress)


def find_periodic_orbit(
    theta0,
    omega0,
    *,
    drive,
    period=1,
    w0=None,
    gamma=None,
    g=None,
    length=None,
    b=None,
    mass=None,
    steps_per_period=DRIVEN_DEFAULT_STEPS,
    threads=THREADS,
):
    """Locate a periodic orbit of a given period by Newton's method from a guess (stable or not).

    Parameters
    ----------
    theta0, omega0 : float or array_like
        The guess of the orbit's strobe point at t = 0 [rad, rad/s].
    drive : Drive
        The drive.
    period : int, optional
        The period in drive periods, in [1, 64] (default 1).
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.

    Returns
    -------
    PeriodicOrbits
        ``period`` 0 where Newton did not converge.

    Raises
    ------
    ValueError
        A bad parameter or period (named).
    TypeError
        Non-real input, a non-integer period, or a drive that is not a pendula.Drive.

    Examples
    --------
    Kapitza's pendulum: the inverted state under a fast pivot (a/l = 0.1,
    Omega = 20 w0) is stable:

    >>> d = pendula.Drive("pivot", 0.1, 20.0)
    >>> o = pendula.find_periodic_orbit(np.pi, 0.0, drive=d, w0=1.0, gamma=0.1)
    >>> bool(o.stable)
    True
    """
    drive = _dc.drive_arg(drive)
    steps = _dc.steps_arg(steps_per_period)
    period = _dc.count_arg(period, "period", 1, ORBIT_MAX_PERIOD)
    check_threads(threads)
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    shape, scalar, args, inputs = _dc.states(drive, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    return _orbits(drive, args, inputs, shape, [period], steps, 0, 1, 1e-6, threads, None)


def _positive(x, name):
    v = real_scalar(x, name)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} = {v!r} is out of range: it must be finite and > 0")
    return v


@dataclasses.dataclass
class Basins(_Outcome):
    """Basins of attraction (built by :func:`basins`).

    Attributes
    ----------
    labels : numpy.ndarray
        The attractor of each initial state: 1..len(attractors), or
        ``UNSETTLED`` (0) for a state with no periodic attractor of period
        <= nmax (chaotic or still settling), or ``BASIN_UNLISTED`` (-1, in
        ``pendula._codes``) for an attractor beyond the table's capacity.
    period, winding : numpy.ndarray
        Each state's attractor's period and turns per period.
    attractors : dict of numpy.ndarray
        The table: ``period``, ``winding``, ``theta`` and ``omega`` (the
        strobe point of smallest angle) and ``mean_omega`` [rad/s] (running
        orbits: 2 pi winding / (period T)); entry k - 1 is label k.
    codes : numpy.ndarray
        Status code of each state (0: OK); a failed state has ``labels``,
        ``period`` and ``winding`` ``FAILED`` (-2**31) and ``ok`` False.
    message : str
        '' when every state succeeded, else how many failed and the first.
    inputs : dict
        theta0, omega0, w0, gamma (broadcast to the states' shape) and the
        drive's kind, amplitude, frequency and phase.

    Examples
    --------
    >>> b = pendula.basins([0.0, 1.0], 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5)
    >>> b.labels.tolist(), b.attractors["period"].tolist()
    ([1, 1], [1])
    """

    labels: np.ndarray
    period: np.ndarray
    winding: np.ndarray
    attractors: dict
    codes: np.ndarray = None
    message: str = ""
    inputs: dict = None

    def to_pandas(self):
        """The attractor table.

        Returns
        -------
        pandas.DataFrame
            One row per attractor, indexed by label.

        Examples
        --------
        >>> b = pendula.basins([0.0, 2.0], 0.0, drive=pendula.Drive("torque", 0.9, 2/3), w0=1.0, gamma=0.5)
        >>> b.to_pandas().index.name
        'label'
        """
        import pandas as pd

        df = pd.DataFrame(self.attractors)
        df.index = pd.RangeIndex(1, len(df) + 1, name="label")
        return df


def basins(
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
    transient=200,
    nmax=8,
    tol=1e-6,
    max_attractors=64,
    steps_per_period=DRIVEN_DEFAULT_STEPS,
    threads=THREADS,
    progress=None,
    client=None,
    chunk_states=CHUNK_STATES,
):
    """Which attractor each initial state settles on: a basin map.

    Parameters
    ----------
    theta0, omega0 : float or array_like
        Initial states at t = 0 [rad, rad/s]; broadcast with w0 and gamma
        (e.g. a column and a row for a grid).
    drive : Drive
        The drive.
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
    transient : int, optional
        Drive periods before classification (default 200).
    nmax : int, optional
        Largest period recognised, in [1, 64] (default 8).
    tol : float, optional
        Settling tolerance on strobe points, > 0 (default 1e-6); attractors
        match when a strobe point lies within 10 tol.
    max_attractors : int, optional
        Capacity of the attractor table (default 64).
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.
    progress : bool or callable, optional
        True for a tqdm bar, or ``callable(done, total)`` (states).

    client : dask.distributed.Client, optional
        Run on Dask in chunks of ``chunk_states`` states (one thread each);
        the chunks return each state's attractor and the table is built from
        them in state order as the local call builds it, so the map is bit
        for bit the local one.
    chunk_states : int, optional
        States per Dask chunk (default ``pendula._defaults.CHUNK_STATES``).

    Returns
    -------
    Basins
        Labels (``UNSETTLED`` = 0 for states with no periodic attractor) and
        the attractor table.

    Raises
    ------
    ValueError
        A bad parameter, count or tolerance (named).
    TypeError
        Non-real input, non-integer counts, or a drive that is not a pendula.Drive.

    Examples
    --------
    >>> d = pendula.Drive("torque", 0.9, 2/3)
    >>> b = pendula.basins(np.linspace(-3, 3, 4)[:, None], np.linspace(-2, 2, 3)[None, :], drive=d, w0=1.0, gamma=0.5)
    >>> b.labels.shape
    (4, 3)
    """
    drive = _dc.drive_arg(drive)
    steps = _dc.steps_arg(steps_per_period)
    transient = _dc.count_arg(transient, "transient", 0)
    nmax = _dc.count_arg(nmax, "nmax", 1, ORBIT_MAX_PERIOD)
    cap = _dc.count_arg(max_attractors, "max_attractors", 1, 100_000)
    tol = _positive(tol, "tol")
    check_threads(threads)
    _dc.check_client(client)
    chunk_states = _dc.count_arg(chunk_states, "chunk_states", 1)
    w0, gamma = _dc.pendulum(w0, gamma, g, length, b, mass)
    shape, scalar, args, inputs = _dc.states(drive, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    n = args["theta0"].size
    work = _work(n, steps, transient + 2 * nmax)
    opts = dict(cap=cap, nsteps=steps, transient=transient, nmax=nmax, tol=tol)
    if client is None:
        out, res = _dc.watched(
            _fortran.basins_f2py,
            work,
            n,
            progress,
            shape,
            ncyc=1,
            threads=_dc.threads_arg(threads, work),
            **opts,
            **args,
        )
        lab, per, wnd, natt, ap, aw, at, ao, am, _ = out
    else:
        # each chunk returns its states' periods, windings and strobe cycles; the table
        # is then built from all of them in state order by the same Fortran (basin_table)
        chunks = [
            _chunk_args(args, s0, chunk_states, n, threads=1, **dict(opts, cap=1)) for s0 in range(0, n, chunk_states)
        ]
        for c in chunks:
            c["ncyc"] = len(c["theta0"])
        out, res = _dc.settle(_dc.dask_chunks(client, "basins_f2py", chunks, progress, n), shape)
        per, wnd, cyc = out[1], out[2], out[9]
        lab, natt, ap, aw, at, ao, am, code, msg = _fortran.basin_table_f2py(
            cap=cap, period=per, winding=wnd, cyc=cyc, freq=args["freq"], tol=tol
        )
        raise_for_status(code, msg)
    natt = int(natt)
    table = dict(
        period=ap[:natt].copy(),
        winding=aw[:natt].copy(),
        theta=at[:natt].copy(),
        omega=ao[:natt].copy(),
        mean_omega=am[:natt].copy(),
    )
    bad = res.codes != OK
    lab, per, wnd = (np.where(bad, FAILED, np.asarray(a).reshape(shape)) for a in (lab, per, wnd))
    return Basins(lab, per, wnd, table, res.codes, res.message, inputs)
