"""The Lyapunov spectrum of the driven pendulum (public through pendula.chaos)."""

import dataclasses

import numpy as np

from . import _driven_call as _dc
from . import _fortran, _tables
from ._chaos_base import _chunk_args, _Outcome, _work
from ._codes import DRIVEN_DEFAULT_STEPS, LYAPUNOV_BLOCKS
from ._defaults import CHUNK_STATES, THREADS, check_threads
from .driven import _state_columns


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
