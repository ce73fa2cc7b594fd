"""The results of one integration: ``Events`` (turning points and zero
crossings) and ``IntegrationResult`` (theta and omega at the output times),
with the step statistics they carry; made by ``rk4``, ``cvode`` and ``taylor``."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import _tables
from ._codes import EVENT_TURNING, EVENT_ZERO
from ._defaults import STAT_NAMES


@dataclass(frozen=True, repr=False)
class Events:
    """Events of the motion, in time order: turning points and zero crossings.

    Made by ``cvode(..., events=True)`` and by scenes with ``want="events"``.

    Parameters
    ----------
    t : numpy.ndarray
        Event times [s].
    kind : numpy.ndarray
        ``TURNING_POINT`` (Omega = 0) or ``ZERO_CROSSING`` (a pass through
        the bottom, theta = 0 mod 2 pi; a rotation gives one per turn) per event.
    theta, omega : numpy.ndarray
        The state at each event [rad], [rad/s].
    truncated : bool
        True when more events occurred than ``max_events`` (only the first
        are kept).

    Notes
    -----
    Successive abs(theta) at turning points give the decrement; every
    second zero crossing of a swing is a full period, each one of a
    rotation a full turn.

    Examples
    --------
    >>> import pendula
    >>> ev = pendula.cvode([0.0, 7.0], 1.0, 0.0, 1.0, 0.0, events=True).events
    >>> ev
    Events(4 events (2 turning points, 2 zero crossings), t in [1.675, 6.7] s)
    """

    t: np.ndarray
    kind: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    truncated: bool

    @property
    def turning_points(self):
        """(t [s], theta [rad]) at the turning points (Omega = 0).

        Returns
        -------
        tuple of numpy.ndarray
            Times and angles of the turning points; successive abs(theta)
            give the decrement.

        Examples
        --------
        >>> import pendula
        >>> t, th = pendula.cvode([0.0, 7.0], 1.0, 0.0, 1.0, 0.0, events=True).events.turning_points
        >>> [round(float(x), 6) for x in th]
        [-1.0, 1.0]
        """
        m = self.kind == EVENT_TURNING
        return self.t[m], self.theta[m]

    @property
    def zero_crossings(self):
        """(t [s], omega [rad/s]) at the zero crossings (theta = 0 mod 2 pi).

        Returns
        -------
        tuple of numpy.ndarray
            Times and angular velocities of the zero crossings; every second
            one of a swing is a full period later, each one of a rotation a turn.

        Examples
        --------
        >>> import pendula
        >>> t, om = pendula.cvode([0.0, 7.0], 1.0, 0.0, 1.0, 0.0, events=True).events.zero_crossings
        >>> round(float(t[1] - t[0]), 4)   # half the period 6.70 s of amplitude 1 rad at w0 = 1
        3.35
        """
        m = self.kind == EVENT_ZERO
        return self.t[m], self.omega[m]

    def summary(self):
        """One line: how many events of each kind, over which times.

        Returns
        -------
        str
            The counts, the time range [s], and whether the list was truncated.

        Examples
        --------
        >>> import pendula
        >>> pendula.cvode([0.0, 7.0], 1.0, 0.0, 1.0, 0.0, events=True).events.summary()
        '4 events (2 turning points, 2 zero crossings), t in [1.675, 6.7] s'
        """
        n_turn = int(np.count_nonzero(self.kind == EVENT_TURNING))
        text = (
            f"{self.t.size} events ({n_turn} turning points, {self.t.size - n_turn} zero crossings), "
            f"t in {_tables.span(self.t, 's')}"
        )
        return text + (", truncated at max_events" if self.truncated else "")

    def __repr__(self):
        return f"Events({self.summary()})"

    def to_pandas(self):
        """The events as a pandas DataFrame, one row per event in time order.

        Returns
        -------
        pandas.DataFrame
            Columns t [s], kind (``"turning_point"`` or ``"zero_crossing"``),
            theta [rad], omega [rad/s]; index: the event number.

        Raises
        ------
        ImportError
            When pandas is not installed.

        Notes
        -----
        ``attrs["truncated"]`` says whether events were left out (``max_events``).

        Examples
        --------
        >>> import pendula
        >>> r = pendula.cvode([0.0, 3.0], 1.0, 0.0, 2 ** 0.5, 0.0, events=True)
        >>> list(r.events.to_pandas().kind)
        ['zero_crossing', 'turning_point']
        """
        pd = _tables.optional("pandas")
        kind = np.where(self.kind == EVENT_TURNING, "turning_point", "zero_crossing")
        out = pd.DataFrame(
            {"t": self.t, "kind": kind, "theta": self.theta, "omega": self.omega},
            index=pd.RangeIndex(self.t.size, name="event"),
        )
        out.attrs["truncated"] = bool(self.truncated)
        return out


@dataclass(frozen=True, repr=False)
class IntegrationResult(_tables.Tabular):
    """theta [rad] and omega [rad/s] of one integration at the output times t [s].

    Returned by ``rk4`` and ``cvode`` for a single state.

    Parameters
    ----------
    t : numpy.ndarray
        Output times [s], shape (n_t,).
    theta, omega : numpy.ndarray
        Angle [rad] and angular velocity [rad/s] at t, shape (n_t,).
    stats : dict
        Work counters: steps, rhs_evals (both integrators), jac_evals,
        err_test_fails, nonlin_iters, nonlin_fails, root_evals (CVODE;
        zero for RK4).
    method : str
        "rk4", "adams" or "bdf".
    events : Events, optional
        For ``cvode(..., events=True)``, else None.

    Notes
    -----
    ``repr`` is a few lines (sizes, ranges, work); ``to_pandas`` and
    ``to_xarray`` convert (pandas / xarray are optional dependencies).

    Examples
    --------
    >>> import pendula
    >>> pendula.rk4([0.0, 1.0, 2.0], 0.1, 0.0, 1.0, 0.0, h=0.1)   # doctest: +ELLIPSIS
    IntegrationResult(method='rk4', t[3] in [0, 2] s
      theta in [...] rad, omega in [...] rad/s
      stats: steps=20, rhs_evals=80)
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    stats: dict
    method: str
    events: Events = field(default=None)

    def __repr__(self):
        st = self.stats
        return _tables.block(
            "IntegrationResult",
            [
                f"method={self.method!r}, " + _tables.series(self.t, {}),
                _tables.series(None, {"theta": self.theta, "omega": self.omega}),
                f"stats: steps={st.get('steps')}, rhs_evals={st.get('rhs_evals')}",
                None if self.events is None else "events: " + self.events.summary(),
            ],
        )

    def _table(self):
        return dict(t=self.t, fields={"theta": self.theta, "omega": self.omega}, attrs={"method": self.method})


def stats_of(raw):
    return {name: int(v) for name, v in zip(STAT_NAMES, raw)}


def rk4_stats(raw):
    # RK4 fills only steps and rhs_evals (the others are zero by definition);
    # reading two values keeps this off the cost of short runs.
    return {
        "steps": int(raw.item(0)),
        "rhs_evals": int(raw.item(1)),
        "jac_evals": 0,
        "err_test_fails": 0,
        "nonlin_iters": 0,
        "nonlin_fails": 0,
        "root_evals": 0,
    }


def quick_result(t, theta, omega, stats, method):
    # Same object as IntegrationResult(t, theta, omega, stats, method), built
    # without the frozen dataclass's per-field __setattr__ calls (a visible
    # share of a short rk4 call).
    r = object.__new__(IntegrationResult)
    r.__dict__.update(t=t, theta=theta, omega=omega, stats=stats, method=method, events=None)
    return r
