"""The batch path of ``pendula.rk4`` and ``pendula.cvode`` (array states).

``rk4`` and ``cvode`` come here when theta0, omega0, w0 or gamma is an array
of one or more dimensions; they broadcast together like NumPy to the batch
shape.  The work goes to the Fortran batch kernels (``_batch``: OpenMP
threads, GIL released), each state bit-identical to the scalar call;
``cvode(..., events=True)`` runs the scalar call per state on a thread pool
(``_pool``).

Failure rules (documented in rk4/cvode):
- a value the scalar call refuses without integrating (NaN or infinite,
  w0 <= 0, gamma < 0, h <= 0, ...) raises ValueError for the whole call,
  naming the first bad state and the argument: it is a mistake in the input,
  found before any work by a pass over the states at t[0] alone;
- anything that fails for one state over the window (an RK4 step outside the
  stability region, more than max_steps steps, a CVODE failure, a non-finite
  state) is that state's code; the others keep their answers;
- when EVERY state of a non-empty batch failed, the call raises the first
  state's exception (there is no answer to return), message prefixed by
  "every state failed".
"""
from dataclasses import dataclass, field

import numpy as np

from . import _batch, _longcall, _pool, _tables
from ._errors import OK, raise_for_status

_BATCH_ARGS = ("theta0", "omega0", "w0", "gamma")


def is_batch(*values):
    """True when any value is an array (or list/tuple) of one or more dimensions:
    0-d arrays and scalars keep the scalar path and its result types."""
    for v in values:
        if type(v) is float:
            continue
        if isinstance(v, (list, tuple)) or getattr(v, "ndim", 0) > 0:
            return True
    return False


class BatchStatus:
    """Per-state status of a batch result (mixed into the result classes)."""

    @property
    def ok(self):
        """Boolean mask of the states that succeeded.

        Returns
        -------
        numpy.ndarray
            bool, shape batch_shape: True where the state's code is OK.

        Examples
        --------
        >>> import pendula
        >>> pendula.rk4([0.0, 1.0], [0.1, 0.2], 0.0, 1.0, 0.0, h=0.1).ok.tolist()
        [True, True]
        """
        return self.codes == OK

    @property
    def shape(self):
        """The batch shape.

        Returns
        -------
        tuple of int
            The broadcast shape of the batch's state arguments.

        Examples
        --------
        >>> import pendula
        >>> pendula.rk4([0.0, 1.0], [[0.1], [0.2]], 0.0, [1.0, 2.0, 3.0], 0.0, h=0.1).shape
        (2, 3)
        """
        return self.codes.shape


def summary(codes, messages):
    """(first_failed, message) of a batch from flat codes and per-state messages;
    raises the first state's exception when every state of a non-empty batch failed."""
    bad = np.flatnonzero(codes != OK)
    if not bad.size:
        return -1, ""
    first = int(bad[0])
    message = f"state {first + 1} of {codes.size} ({bad.size} failed, see codes): {messages[first]}"
    _all_failed(codes, int(codes[first]), message)
    return first, message


@dataclass(frozen=True, repr=False)
class BatchIntegrationResult(BatchStatus, _tables.Tabular):
    """Result of ``rk4`` / ``cvode`` over a batch of states.

    Parameters
    ----------
    t : numpy.ndarray
        Output times [s], shape (n_t,).
    theta, omega : numpy.ndarray
        [rad], [rad/s], shape batch_shape + (n_t,); a failed state's rows
        are zero (CVODE: what it reached before failing, zero after).
    stats : dict
        int64 arrays of shape batch_shape (the keys of the scalar result's
        stats).
    method : str
        "rk4", "adams" or "bdf".
    codes : numpy.ndarray
        int64 status per state (0 = ok, see ``pendula._codes``).
    message : str
        Summary ('' when every state succeeded; else the first failed
        state's index and the scalar call's message for it, states numbered
        from 1 in C order).
    first_failed : int
        Flat index of the first failed state, or -1.
    events : numpy.ndarray, optional
        For ``cvode(..., events=True)``, an object array of ``Events`` (None
        for a failed state), else None.

    Notes
    -----
    ``ok`` and ``shape`` come from the codes; ``repr`` is a few lines;
    ``to_pandas`` / ``to_xarray`` convert.

    Examples
    --------
    >>> import pendula
    >>> r = pendula.rk4([0.0, 1.0], [0.1, 0.2], 0.0, [1.0, 300.0], 0.0, h=0.1)
    >>> r.ok.tolist(), r.first_failed
    ([True, False], 1)
    """
    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    stats: dict
    method: str
    codes: np.ndarray
    message: str
    first_failed: int
    events: np.ndarray = field(default=None)

    def __repr__(self):
        good = self.ok
        steps = self.stats.get("steps")
        return _tables.block("BatchIntegrationResult", [
            f"method={self.method!r}, batch shape {self.shape}, " + _tables.series(self.t, {}),
            _tables.series(None, {"theta": self.theta[good], "omega": self.omega[good]}) + " (states that succeeded)",
            None if steps is None or not good.any() else f"steps per state in {_tables.span(steps[good])}",
            _tables.codes_line(self.codes, self.message)])

    def _table(self):
        return dict(t=self.t, fields={"theta": self.theta, "omega": self.omega}, shape=self.shape,
                    per_state={"code": self.codes}, attrs={"method": self.method})

def _all_failed(codes, code, message):
    if codes.size and not (codes == OK).any():
        raise_for_status(code, "every state failed; " + message)


def _precheck(kernel, t, **kw):
    # The kernel over t[0] alone: the per-state argument checks, no integration.
    res = kernel(t[:1], **kw)
    if res.code != OK:
        raise ValueError(res.message)


def _watched(run, n, per_state_work, long_work, progress):
    control = _longcall.new_control()
    long = n * per_state_work > long_work
    return _longcall.run(lambda: run(control), control, long, progress, total=n, unit="state")


def rk4_batch(tt, theta0, omega0, w0, gamma, h, max_steps, progress, threads):
    args = dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, h=h, threads=threads)
    _precheck(_batch.rk4_batch, tt, **args)
    steps = (tt[-1] - tt[0]) / float(h) + tt.size
    res = _watched(lambda c: _batch.rk4_batch(tt, control=c, max_steps=max_steps, **args),
                   int(res_size(theta0, omega0, w0, gamma)), steps, _longcall.RK4_LONG_STEPS, progress)
    _all_failed(res.codes, res.code, res.message)
    zero = np.zeros(res.codes.shape, dtype=np.int64)
    stats = {"steps": res.steps, "rhs_evals": 4 * res.steps, "jac_evals": zero, "err_test_fails": zero.copy(),
             "nonlin_iters": zero.copy(), "nonlin_fails": zero.copy(), "root_evals": zero.copy()}
    return BatchIntegrationResult(t=tt, theta=res.theta, omega=res.omega, stats=stats, method="rk4",
                                  codes=res.codes, message=res.message, first_failed=res.first_failed)


def res_size(*values):
    """Number of states of the broadcast of ``values``."""
    return int(np.prod(np.broadcast_shapes(*(np.shape(v) for v in values)), dtype=np.int64))


def cvode_batch(tt, theta0, omega0, w0, gamma, rtol, atol, method, max_steps, events, max_events, progress,
                threads, scalar_cvode):
    args = dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, rtol=rtol, atol=atol, method=method,
                threads=threads)
    _precheck(_batch.cvode_batch, tt, **args)
    n = res_size(theta0, omega0, w0, gamma)
    periods = abs(tt[-1] - tt[0]) * float(np.max(w0, initial=0.0)) / (2 * np.pi)
    if not events:
        res = _watched(lambda c: _batch.cvode_batch(tt, control=c, max_steps=max_steps, **args), n,
                       periods * 50 + tt.size, _longcall.CVODE_LONG_STEPS, progress)
        _all_failed(res.codes, res.code, res.message)
        return BatchIntegrationResult(t=tt, theta=res.theta, omega=res.omega, stats=res.stats, method=res.method,
                                      codes=res.codes, message=res.message, first_failed=res.first_failed)
    # events: the scalar call per state (its event arrays differ in length)
    shape = np.broadcast_shapes(*(np.shape(v) for v in (theta0, omega0, w0, gamma)))
    flat = [np.broadcast_to(np.asarray(v, dtype=float), shape).reshape(-1) for v in (theta0, omega0, w0, gamma)]

    def one(i, control):
        return scalar_cvode(tt, float(flat[0][i]), float(flat[1][i]), float(flat[2][i]), float(flat[3][i]),
                            rtol=rtol, atol=atol, method=method, max_steps=max_steps, events=True,
                            max_events=max_events, control=control)
    values, codes, messages = _pool.map_states(one, n, threads, progress)
    return _from_states(tt, shape, values, codes, messages, method.lower())


def _from_states(tt, shape, values, codes, messages, method):
    n = len(values)
    theta = np.zeros((n, tt.size))
    omega = np.zeros((n, tt.size))
    stats = {}
    ev = np.empty(n, dtype=object)
    for i, r in enumerate(values):
        if r is None:
            continue
        theta[i], omega[i], ev[i] = r.theta, r.omega, r.events
        for k, v in r.stats.items():
            stats.setdefault(k, np.zeros(n, dtype=np.int64))[i] = v
    first, message = summary(codes, messages)
    codes = codes.reshape(shape)
    return BatchIntegrationResult(t=tt, theta=theta.reshape(shape + (tt.size,)),
                                  omega=omega.reshape(shape + (tt.size,)),
                                  stats={k: v.reshape(shape) for k, v in stats.items()}, method=method,
                                  codes=codes, message=message, first_failed=first, events=ev.reshape(shape))
