"""The batch path of ``pendula.rk4`` and ``pendula.cvode`` (array states).

``rk4`` and ``cvode`` come here when theta0, omega0, w0, gamma (or rk4's h)
is an array of one or more dimensions; they broadcast together like NumPy to
the batch shape.  The work goes to the Fortran batch kernels (``kernels``:
OpenMP threads, GIL released), each state bit-identical to the scalar call;
``cvode(..., events=True)`` runs the scalar call per state on a thread pool
(``pool``).

Failure rules (the package's one contract, docs/robustness.md):
- a value the scalar call refuses without integrating (NaN or infinite,
  w0 <= 0, gamma < 0, h <= 0, ...) raises ValueError for the whole call,
  naming the argument and the first bad state (``w0[2] = -1.0 ...``): it is
  a mistake in the input, found before any work by a pass over the states at
  t[0] alone;
- anything that fails for one state over the window (an RK4 step outside the
  stability region, more than max_steps steps, a CVODE failure, a non-finite
  state) is that state's code, and its outputs are NaN from the point it
  failed; the others keep their answers;
- when EVERY state of a non-empty batch failed, the call raises the first
  state's exception (there is no answer to return).
"""

from dataclasses import dataclass, field

import numpy as np

from .. import _longcall, _tables
from .._arrays import broadcast_real, integer_arg, output_pair
from .._defaults import CVODE_METHODS, POOL_STATE_WORK
from .._errors import OK, batch_summary, for_state, raise_if_all_failed
from . import kernels, pool

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


def summary(codes, messages, shape, names=None):
    """(first_failed, message) of a batch of ``shape`` from flat codes and
    per-state messages; raises the first state's exception when every state of
    a non-empty batch failed."""
    bad = np.flatnonzero(codes != OK)
    if not bad.size:
        return -1, ""
    first = int(bad[0])
    message = batch_summary(codes, messages[first], shape, names)
    raise_if_all_failed(codes, int(codes[first]), message)
    return first, message


@dataclass(frozen=True, repr=False)
class BatchIntegrationResult(BatchStatus, _tables.Tabular):
    """Result of ``rk4`` / ``cvode`` over a batch of states.

    Parameters
    ----------
    t : numpy.ndarray
        Output times [s], shape (n_t,).
    theta, omega : numpy.ndarray
        [rad], [rad/s], shape batch_shape + (n_t,); a failed state is NaN
        from the point it failed (RK4: its whole row; CVODE: what it
        reached before failing is kept).
    stats : dict
        int64 arrays of shape batch_shape (the keys of the scalar result's
        stats).
    method : str
        "rk4", "adams" or "bdf".
    codes : numpy.ndarray
        int64 status per state (0 = ok, see ``pendula._codes``).
    message : str
        Summary ('' when every state succeeded; else how many failed and
        the first one's message, naming it by its 0-based index in the
        batch, ``w0[2]`` or ``state [1, 0]``).
    first_failed : int
        Flat index of the first failed state, or -1.
    events : numpy.ndarray, optional
        For ``cvode(..., events=True)``, an object array of ``Events`` (None
        for a failed state), else None.
    inputs : dict, optional
        The per-state inputs broadcast to batch_shape (theta0, omega0, w0,
        gamma, and h or rtol, atol): the coordinates of ``to_xarray`` and
        columns of ``to_pandas``.

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
    inputs: dict = field(default=None)

    def __repr__(self):
        good = self.ok
        steps = self.stats.get("steps")
        return _tables.block(
            "BatchIntegrationResult",
            [
                f"method={self.method!r}, batch shape {self.shape}, " + _tables.series(self.t, {}),
                _tables.series(None, {"theta": self.theta[good], "omega": self.omega[good]})
                + " (states that succeeded)",
                None if steps is None or not good.any() else f"steps per state in {_tables.span(steps[good])}",
                _tables.codes_line(self.codes, self.message),
            ],
        )

    def _table(self):
        return dict(
            t=self.t,
            fields={"theta": self.theta, "omega": self.omega},
            shape=self.shape,
            per_state={"code": self.codes},
            attrs={"method": self.method},
            coords=self.inputs,
        )


def inputs(shape, **named):
    """The per-state inputs of a batch, each broadcast to ``shape``: read-only views of
    copies (the result never aliases, nor changes with, a user's array)."""
    return {k: np.broadcast_to(np.array(v, dtype=float), shape) for k, v in named.items()}


def _precheck(kernel, t, shape, **kw):
    # The kernel over t[0] alone: the per-state argument checks, no integration.
    res = kernel(t[:1], **kw)
    if res.code != OK:
        raise ValueError(for_state(res.message, res.first_failed, shape))


def _watched(run, n, per_state_work, long_work, progress):
    control = _longcall.new_control()
    long = n * per_state_work > long_work
    return _longcall.run(lambda: run(control), control, long, progress, total=n, unit="state")


def _summarised(res, shape):
    """The kernel result's message in the package's convention; raises when every state failed."""
    if res.first_failed < 0:
        return res.message
    message = batch_summary(res.codes, res.message, shape)
    raise_if_all_failed(res.codes, res.code, message)
    return message


def rk4_batch(tt, theta0, omega0, w0, gamma, h, max_steps, progress, threads, drive=None, out=None):
    # drive: None or its columns (pendula._many.drives.COLUMNS), which broadcast with the states;
    # out: None or the caller's (theta, omega), checked here before any work
    dcols = drive or {}
    shape, _, _ = broadcast_real(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, h=h, **dcols)  # names a bad one
    output_pair(out, shape + (tt.size,))
    args = dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, h=h, threads=threads)
    if drive is not None:
        args["drive"] = dcols
    _precheck(kernels.rk4_batch, tt, shape, **dict(args, threads=1))
    hmin = float(np.min(h, initial=np.inf))
    steps = (tt[-1] - tt[0]) / hmin + tt.size
    res = _watched(
        lambda c: kernels.rk4_batch(tt, control=c, max_steps=max_steps, out=out, **args),
        int(np.prod(shape, dtype=np.int64)),
        steps,
        _longcall.RK4_LONG_STEPS,
        progress,
    )
    message = _summarised(res, shape)
    zero = np.zeros(res.codes.shape, dtype=np.int64)
    stats = {
        "steps": res.steps,
        "rhs_evals": 4 * res.steps,
        "jac_evals": zero,
        "err_test_fails": zero.copy(),
        "nonlin_iters": zero.copy(),
        "nonlin_fails": zero.copy(),
        "root_evals": zero.copy(),
    }
    return BatchIntegrationResult(
        t=tt,
        theta=res.theta,
        omega=res.omega,
        stats=stats,
        method="rk4",
        codes=res.codes,
        message=message,
        first_failed=res.first_failed,
        inputs=inputs(shape, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, h=h, **dcols),
    )


def cvode_batch(
    tt,
    theta0,
    omega0,
    w0,
    gamma,
    rtol,
    atol,
    method,
    max_steps,
    events,
    max_events,
    progress,
    threads,
    scalar_cvode,
    drive=None,
    drive_each=None,
):
    # drive: None or its columns (as rk4_batch); drive_each(shape): the Drive of each
    # flat state, for the scalar calls of events=True
    # the call's own arguments first, as the scalar call checks them: ValueError for the whole call
    if not isinstance(method, str) or method.lower() not in CVODE_METHODS:
        raise ValueError(f"method = {method!r} is invalid: it must be 'adams' or 'bdf'")
    integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True)
    if events:
        integer_arg(max_events, "max_events", 1, 10**7, scalar=True)
    dcols = drive or {}
    shape, _, _ = broadcast_real(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, **dcols)  # names a bad one
    args = dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, rtol=rtol, atol=atol, method=method, threads=threads)
    if drive is not None:
        args["drive"] = dcols
    _precheck(kernels.cvode_batch, tt, shape, **dict(args, threads=1))
    n = int(np.prod(shape, dtype=np.int64))
    periods = abs(tt[-1] - tt[0]) * float(np.max(w0, initial=0.0)) / (2 * np.pi)
    if drive is not None:
        # the drive sets the pace too: ~50 steps a drive period of the fastest drive
        periods = max(periods, abs(tt[-1] - tt[0]) * float(np.max(dcols["drive_frequency"], initial=0.0)) / (2 * np.pi))
    given = inputs(shape, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma, rtol=rtol, atol=atol, **dcols)
    if not events:
        res = _watched(
            lambda c: kernels.cvode_batch(tt, control=c, max_steps=max_steps, **args),
            n,
            periods * 50 + tt.size,
            _longcall.CVODE_LONG_STEPS,
            progress,
        )
        message = _summarised(res, shape)
        return BatchIntegrationResult(
            t=tt,
            theta=res.theta,
            omega=res.omega,
            stats=res.stats,
            method=res.method,
            codes=res.codes,
            message=message,
            first_failed=res.first_failed,
            inputs=given,
        )
    # events: the scalar call per state (its event arrays differ in length)
    flat = [np.broadcast_to(np.asarray(v, dtype=float), shape).reshape(-1) for v in (theta0, omega0, w0, gamma)]
    each = None if drive is None else drive_each(shape)

    def one(i, control):
        return scalar_cvode(
            tt,
            float(flat[0][i]),
            float(flat[1][i]),
            float(flat[2][i]),
            float(flat[3][i]),
            rtol=rtol,
            atol=atol,
            method=method,
            max_steps=max_steps,
            events=True,
            max_events=max_events,
            control=control,
            drive=None if each is None else each[i],
        )

    work = kernels.cvode_work(tt, w0, n) + n * POOL_STATE_WORK
    values, codes, messages = pool.map_states(one, n, threads, progress, work=work, shape=shape, names=_BATCH_ARGS)
    return _from_states(tt, shape, values, codes, messages, method.lower(), given)


def _from_states(tt, shape, values, codes, messages, method, given):
    n = len(values)
    theta = np.full((n, tt.size), np.nan)
    omega = np.full((n, tt.size), np.nan)
    stats = {}
    ev = np.empty(n, dtype=object)
    for i, r in enumerate(values):
        if r is None:
            continue
        theta[i], omega[i], ev[i] = r.theta, r.omega, r.events
        for k, v in r.stats.items():
            stats.setdefault(k, np.zeros(n, dtype=np.int64))[i] = v
    first, message = summary(codes, messages, shape, _BATCH_ARGS)
    codes = codes.reshape(shape)
    return BatchIntegrationResult(
        t=tt,
        theta=theta.reshape(shape + (tt.size,)),
        omega=omega.reshape(shape + (tt.size,)),
        stats={k: v.reshape(shape) for k, v in stats.items()},
        method=method,
        codes=codes,
        message=message,
        first_failed=first,
        events=ev.reshape(shape),
        inputs=given,
    )
