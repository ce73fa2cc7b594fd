"""The Lyapunov spectrum of the driven pendulum (public through pendula.chaos)."""

import dataclasses

import numpy as np

from . import _driven_call as _dc
from . import _tables
from ._chaos_base import _Outcome, _work
from ._codes import LYAPUNOV_BLOCKS, LYAPUNOV_DEFAULT_PERIODS, LYAPUNOV_DEFAULT_STEPS, LYAPUNOV_ORBITS
from ._defaults import CHUNK_STATES, THREADS
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
        95 % error bounds [1/s], same shape: Student's t times the standard
        error of the means of 16 blocks of the measured periods (of every
        copy, when the copies have parted by the end of the transient;
        else of the blocks averaged over the copies), combined with the
        part of half the gap between the means of the two halves that the
        noise does not explain (a running average still drifting).
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


@_dc.fill_doc
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
    periods=LYAPUNOV_DEFAULT_PERIODS,
    orbits=LYAPUNOV_ORBITS,
    steps_per_period=LYAPUNOV_DEFAULT_STEPS,
    threads=THREADS,
    progress=None,
    client=None,
    chunk_states=CHUNK_STATES,
):
    """Both Lyapunov exponents of driven pendulums, with 95 % error bounds.

    Two tangent vectors follow the derivative of the RK4 map and are
    re-orthonormalised (Gram-Schmidt) every drive period (Benettin et al.,
    Meccanica 15 (1980) 9); the exponents are the mean log stretchings per
    unit time over ``periods`` drive periods after ``transient``.  Each
    state runs as an ensemble of ``orbits`` copies in the SIMD lanes of one
    block (copy c starts at theta0 + c 1e-6 rad): on a chaotic attractor
    they part within the transient and sample it independently, so the
    eight cost about what one does; on a stable periodic orbit they meet.
    The defaults give the Baker-Gollub chaotic exponent (w0 = 1, gamma =
    0.5, F = 1.15, Omega = 2/3) to about +-0.0005 1/s in well under a
    second on one core (benchmarks/bench_driven.py).

    Parameters
    ----------
    theta0, omega0 : float or array_like
        Initial states at t = 0 [rad, rad/s]; broadcast with w0 and gamma.
    drive : Drive
        The drive.
    {pendulum}
    transient : int, optional
        Drive periods before the measurement (default 100).
    periods : int, optional
        Drive periods measured by each copy, >= 16 (default 50000).
    orbits : int, optional
        Copies of each state, in [1, 8] (default 8); 1 follows exactly the
        orbit from (theta0, omega0).
    steps_per_period : int, optional
        RK4 steps per drive period (default 64: the exponents are those of
        the RK4 map, and step halving shows this step's bias on the
        Baker-Gollub exponent well below the error bound).
    {threads}
    {progress}
    {dask}

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
    >>> r = pendula.lyapunov(0.2, 0.0, drive=d, w0=1.0, gamma=0.5)
    >>> bool(abs(r.exponents[0] - 0.0999) < 0.001 and r.errors[0] < 0.0006), round(float(r.exponents.sum()), 4)
    (True, -0.5)
    """
    call = _dc.prepare(
        locals(),
        transient=(transient, 0),
        periods=(periods, LYAPUNOV_BLOCKS),
        orbits=(orbits, 1, LYAPUNOV_ORBITS),
    )
    c = call.counts
    work = _work(call.n * c["orbits"], 3 * call.steps, c["transient"] + c["periods"])
    opts = dict(nsteps=call.steps, **c)
    (ly, le), res = _dc.run("lyapunov_f2py", call, work, progress, opts)
    ly, le = _dc.per_state(ly, call.shape), _dc.per_state(le, call.shape)
    _dc.nan_failed(res, ly, le)
    return LyapunovResult(ly, le, res.codes, res.message, call.inputs)
