"""Poincare (stroboscopic) sections and bifurcation diagrams of the driven pendulum
(public through pendula.chaos)."""

import dataclasses
import math

import numpy as np

from . import _driven_call as _dc
from ._arrays import as_real, real_scalar
from ._chaos_base import _PARAMS, _Outcome, _work
from ._codes import DRIVEN_DEFAULT_STEPS
from ._defaults import CHUNK_STATES, THREADS, check_threads
from ._errors import number
from .driven import _state_columns


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


def _section_call(call, section_phase, progress):
    n, shape, c = call.n, call.shape, call.counts
    work = _work(n, call.steps, c["transient"] + c["points"] + 1)
    opts = dict(nsteps=call.steps, section_phase=section_phase, transient=c["transient"], nrec=c["points"])
    (ts, os_, mo), res = _dc.run("poincare_f2py", call, work, progress, opts)
    theta, omega = _dc.per_state(ts, shape), _dc.per_state(os_, shape)
    mo = mo.reshape(shape)
    rot = mo / np.broadcast_to(call.args["freq"], (n,)).reshape(shape)
    _dc.nan_failed(res, theta, omega, mo, rot)
    return theta, omega, mo, rot, res


def _phase(section_phase, drive):
    ph = drive.phase if section_phase is None else real_scalar(section_phase, "section_phase")
    if not math.isfinite(ph):
        raise ValueError(f"section_phase = {ph!r} is invalid: it must be finite")
    return ph


@_dc.fill_doc
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
    {pendulum}
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
    {threads}
    {progress}

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
    call = _dc.prepare(
        locals(),
        transient=(transient, 0),
        points=(points, 1),
    )
    theta, omega, mo, rot, res = _section_call(call, _phase(section_phase, call.drive), progress)
    return Section(theta, omega, mo, rot, None, None, res.codes, res.message, call.inputs)


@_dc.fill_doc
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
    {pendulum}
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
    {threads}
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
    counts = dict(transient=_dc.count_arg(transient, "transient", 0), points=_dc.count_arg(points, "points", 1))
    check_threads(threads)
    _dc.check_client(client)
    chunk_states = _dc.count_arg(chunk_states, "chunk_states", 1)
    ph = _phase(section_phase, drive)
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
    call = _dc.Call(drive, steps, counts, threads, client, chunk_states, (vals.size,), args, inputs)
    theta, omega, mo, rot, res = _section_call(call, ph, progress)
    return Section(theta, omega, mo, rot, vals, parameter, res.codes, res.message, inputs)
