"""Periodic orbits of the stroboscopic map and basins of attraction of the driven
pendulum (public through pendula.chaos)."""

import dataclasses
import math

import numpy as np

from . import _driven_call as _dc
from . import _fortran
from ._chaos_base import _Outcome, _positive, _work
from ._codes import BASIN_UNSETTLED, DRIVEN_DEFAULT_STEPS, OK, ORBIT_MAX_PERIOD
from ._defaults import CHUNK_STATES, THREADS, WELL_NONE
from ._errors import raise_for_status
from .driven import _state_columns

UNSETTLED = BASIN_UNSETTLED
"""Basin label of a state that settled on no periodic attractor of period <= nmax
(chaotic, or still settling); attractor labels count from 1."""

FAILED = WELL_NONE
"""The integer fields (basin ``labels``, ``period``, ``winding``) of a state
that failed: -2**31, never a label, a period or a number of turns (the
``codes`` of the result say why; ``ok`` is the mask of the others)."""


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


def _failed_ints(res, *arrays):
    """The integer fields (shaped like the states): FAILED where the state failed."""
    return tuple(np.where(res.codes != OK, FAILED, a) for a in arrays)


def _orbits(call, period_in, transient, nmax, tol, progress):
    n, shape, args = call.n, call.shape, call.args
    work = _work(n, 3 * call.steps, transient + 2 * nmax + 40 * max(period_in, nmax))
    opts = dict(
        period_in=np.array([period_in], dtype=np.int32), nsteps=call.steps, transient=transient, nmax=nmax, tol=tol
    )
    (per, wnd, tp, op, mult, resid), res = _dc.run("orbits_f2py", call, work, progress, opts)
    mu = (mult[0::2] + 1j * mult[1::2]).T.reshape(shape + (2,))
    per = per.reshape(shape)
    T = 2 * math.pi / np.broadcast_to(args["freq"], (n,)).reshape(shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        fe = np.where(per[..., None] > 0, np.log(np.abs(mu)) / (np.maximum(per, 1) * T)[..., None], 0.0)
    stable = (per > 0) & (np.abs(mu[..., 0]) < 1)
    wnd, tp, op, resid = wnd.reshape(shape), tp.reshape(shape), op.reshape(shape), resid.reshape(shape)
    _dc.nan_failed(res, tp, op, mu, fe, resid)
    per, wnd = _failed_ints(res, per, wnd)
    return PeriodicOrbits(
        per, wnd, tp, op, mu, stable & (res.codes == OK), fe, resid, res.codes, res.message, call.inputs
    )


@_dc.fill_doc
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
    client=None,
    chunk_states=CHUNK_STATES,
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
    {pendulum}
    transient : int, optional
        Drive periods before detection (default 200).
    nmax : int, optional
        Largest period searched, in [1, 64] (default 8).
    tol : float, optional
        Detection tolerance on strobe points, > 0 (default 1e-6).
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    {threads}
    {progress}
    {dask}

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
    call = _dc.prepare(
        locals(),
        checks=[lambda: _positive(tol, "tol")],
        transient=(transient, 0),
        nmax=(nmax, 1, ORBIT_MAX_PERIOD),
    )
    tol = _positive(tol, "tol")
    return _orbits(call, 0, call.counts["transient"], call.counts["nmax"], tol, progress)


@_dc.fill_doc
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
    {pendulum}
    steps_per_period : int, optional
        RK4 steps per drive period (default 128).
    {threads}

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
    call = _dc.prepare(
        locals(),
        period=(period, 1, ORBIT_MAX_PERIOD),
    )
    return _orbits(call, call.counts["period"], 0, 1, 1e-6, None)


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


@_dc.fill_doc
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
    {pendulum}
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
    {threads}
    {progress}

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
    call = _dc.prepare(
        locals(),
        checks=[lambda: _positive(tol, "tol")],
        transient=(transient, 0),
        nmax=(nmax, 1, ORBIT_MAX_PERIOD),
        max_attractors=(max_attractors, 1, 100_000),
    )
    tol = _positive(tol, "tol")
    c, shape = call.counts, call.shape
    work = _work(call.n, call.steps, c["transient"] + 2 * c["nmax"])
    opts = dict(nsteps=call.steps, tol=tol, transient=c["transient"], nmax=c["nmax"], cap=c["max_attractors"])
    # on Dask each chunk returns its states' periods, windings and strobe cycles (a table
    # of capacity 1, ncyc = its states); the table is then built from all of them in state
    # order by the same Fortran (basin_table), as the local call builds it
    out, res = _dc.run(
        "basins_f2py",
        call,
        work,
        progress,
        dict(opts, ncyc=1),
        chunk_opts=dict(opts, cap=1),
        per_chunk=lambda chunk: dict(ncyc=len(chunk["theta0"])),
    )
    if call.client is None:
        lab, per, wnd, natt, ap, aw, at, ao, am, _ = out
    else:
        per, wnd, cyc = out[1], out[2], out[9]
        lab, natt, ap, aw, at, ao, am, code, msg = _fortran.basin_table_f2py(
            cap=c["max_attractors"], period=per, winding=wnd, cyc=cyc, freq=call.args["freq"], tol=tol
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
    lab, per, wnd = _failed_ints(res, *(np.asarray(a).reshape(shape) for a in (lab, per, wnd)))
    return Basins(lab, per, wnd, table, res.codes, res.message, call.inputs)
