"""Batches of scenes: ``Scene(...)`` with array parameters, and its solves.

``Scene`` returns a ``SceneBatch`` when theta0, omega0, g, length, gamma,
mass, b or tol is an array of one or more dimensions (they broadcast like
NumPy; t and want are shared).  ``solve``, ``run_model`` and ``tradeoff``
of a SceneBatch answer every scene of it.

Why a thread pool over the scalar solve (``pool``), not a Fortran loop: each
scene picks its own model, setting and verification runs, and its answer
must be bit-identical to ``solve`` of that scene alone, which the scalar
Fortran solve is by construction; the f2py call releases the GIL, so with one
thread per core every core runs Fortran while the Python overhead (~30 us
a scene) is small against a scene's integration.  tradeoff of a batch runs
the scenes one after another: its wall times must not compete for cores.

Failure rules (as rk4/cvode batches, docs/robustness.md): a scene that
cannot be built (a bad value in one state) raises ValueError naming the
argument and the state (``gamma[1] = -1 ...``); a scene whose solve fails
gets its code and message, NaN in its real quantities and '' as its model;
when every scene failed, the call raises the first one's exception.

This layer knows nothing of ``pendula.scene``: the scene class and the
one-scene solve are handed in (``make``, ``one``), so imports run one way.
"""

from dataclasses import dataclass

import numpy as np

from .. import _memory, _tables
from .._arrays import SharedTimes, broadcast_real
from .._errors import for_state
from . import pool
from .ensemble import BatchStatus, summary

_PARAMS = ("theta0", "omega0", "g", "length", "gamma", "mass", "b", "tol")


class SceneBatch:
    """Scenes over a batch of parameters: what ``Scene`` returns for array parameters.

    Parameters
    ----------
    theta0, omega0, t, g, length, gamma, mass, b, tol, want
        As for ``Scene``; the numeric ones (not t, want) broadcast like NumPy.
    make : type
        The one-scene class, ``pendula.Scene``, which hands itself in (this
        layer does not import it).

    Attributes
    ----------
    shape : tuple of int
        The batch shape.
    scenes : numpy.ndarray
        Object array of ``Scene`` of that shape.
    t, want
        Shared by every scene (t [s], read-only: one array that every
        scene of the batch refers to, not a copy per scene).
    theta0, omega0, w0, gamma, tol : numpy.ndarray
        Float arrays of the batch shape ([rad], [rad/s], [1/s], [1/s], [rad]).

    Raises
    ------
    ValueError
        For a bad value in one state, naming the state and the argument.

    Examples
    --------
    >>> import pendula
    >>> batch = pendula.Scene([0.1, 0.5, 1.0], t=[0.0, 1.0])
    >>> batch
    SceneBatch(shape=(3,), want='state', t[2])
    >>> batch.theta0.tolist()
    [0.1, 0.5, 1.0]
    """

    def __init__(self, theta0, omega0, t, g, length, gamma, mass, b, tol, want, *, make):
        # make: the one-scene class (pendula.Scene), handed in by it
        given = {k: v for k, v in zip(_PARAMS, (theta0, omega0, g, length, gamma, mass, b, tol)) if v is not None}
        shape, _, flats = broadcast_real(**given)
        n = int(np.prod(shape, dtype=np.int64))
        probe = make(0.0, 0.0, t=t, want=want)  # t and want, also for an empty batch
        shared = SharedTimes(probe.t)  # one time grid for every scene, not a copy each
        scenes = np.empty(n, dtype=object)
        for i in range(n):
            kw = {k: float(v[i]) for k, v in flats.items()}
            try:
                scenes[i] = make(t=shared, want=want, **kw)
            except ValueError as exc:
                raise ValueError(for_state(exc, i, shape, _PARAMS)) from None
        self.shape = shape
        self.scenes = scenes.reshape(shape)
        self.t = probe.t
        self.want = probe.want
        for name in ("theta0", "omega0", "w0", "gamma", "tol"):
            setattr(self, name, np.array([getattr(s, name) for s in scenes], dtype=float).reshape(shape))

    def __len__(self):
        return self.shape[0] if self.shape else 1

    def __repr__(self):
        return f"SceneBatch(shape={self.shape}, want={self.want!r}, t[{self.t.size}])"


@dataclass(frozen=True, repr=False)
class SceneBatchResult(BatchStatus, _tables.Tabular):
    """The answers to a ``SceneBatch`` (``solve`` / ``run_model`` of array scenes).

    Parameters
    ----------
    results : numpy.ndarray
        Object array (batch shape) of ``SceneResult`` (None for a failed
        scene).
    codes : numpy.ndarray
        int64 status per scene (0 = ok).
    messages : numpy.ndarray
        The failed scenes' messages ('' for the others).
    message : str
        Summary ('' when every scene succeeded).
    first_failed : int
        Flat index of the first failed scene, or -1.
    model, error_estimate, tol_met : numpy.ndarray
        Per scene: model name ('' when failed), error estimate [rad] (NaN
        when failed), tol met (False when failed).
    t, theta, omega, energy, period, event_time_error : numpy.ndarray or None
        The per-scene quantities stacked with the batch shape in front
        (theta.shape == batch_shape + (len(t),); batch_shape + (1,) for want
        "final"), NaN for a failed scene; None when not asked for.
    inputs : dict
        The scenes' theta0 [rad], omega0 [rad/s], w0 [1/s], gamma [1/s] and
        tol [rad] (batch shape): the coordinates of ``to_xarray`` and columns
        of ``to_pandas``.

    Notes
    -----
    ``ok`` (mask of the scenes that succeeded) and ``shape`` come with it;
    ``repr`` is a few lines; ``to_pandas`` / ``to_xarray`` convert.

    Examples
    --------
    >>> import pendula
    >>> r = pendula.solve(pendula.Scene([0.1, 3.0], t=[0.0, 1.0]))
    >>> r.shape, list(r.model), bool(r.tol_met.all())
    ((2,), ['exact', 'exact'], True)
    """

    results: np.ndarray
    codes: np.ndarray
    messages: np.ndarray
    message: str
    first_failed: int
    model: np.ndarray
    error_estimate: np.ndarray
    tol_met: np.ndarray
    t: object = None
    theta: object = None
    omega: object = None
    energy: object = None
    period: object = None
    event_time_error: object = None
    inputs: dict = None

    def _series(self):
        return {"theta": self.theta, "omega": self.omega, "energy": self.energy}

    def _t(self):
        # t is stacked like the series; every scene shares it (a failed scene's row is NaN)
        if self.t is None:
            return None
        return self.t.reshape(-1, self.t.shape[-1])[int(np.argmax(self.ok.reshape(-1)))]

    def _table(self):
        if self.t is None and self.period is None:
            raise ValueError("a batch of want='events' scenes has no table: convert results[i].events one by one")
        return dict(
            t=self._t(),
            fields=self._series(),
            shape=self.shape,
            per_state={
                "code": self.codes,
                "model": self.model,
                "error_estimate": self.error_estimate,
                "tol_met": self.tol_met,
                "period": self.period,
            },
            coords=self.inputs,
        )

    def __repr__(self):
        good = self.ok
        series = {k: None if v is None else v[good] for k, v in self._series().items()}
        quantities = _tables.series(self._t(), series) if self.t is not None else ""
        if self.period is not None:
            quantities = f"period in {_tables.span(self.period[good], 's')}"
        return _tables.block(
            "SceneBatchResult",
            [
                f"batch shape {self.shape}, models: {_tables.counts(self.model)}",
                f"error_estimate in {_tables.span(self.error_estimate[good], 'rad')}, "
                f"tol met by {int(np.count_nonzero(self.tol_met))} of {self.codes.size}",
                quantities + (" (scenes that succeeded)" if quantities else ""),
                _tables.codes_line(self.codes, self.message),
            ],
        )


def _stack(values, shape, name):
    good = [getattr(v, name) for v in values if v is not None]
    if not good or good[0] is None:
        return None
    out = np.full((len(values),) + np.shape(good[0]), np.nan)
    for i, v in enumerate(values):
        if v is not None:
            out[i] = getattr(v, name)
    return out.reshape(shape + np.shape(good[0]))


def _collect(batch, values, codes, messages):
    shape, n = batch.shape, len(values)
    first, message = summary(codes, messages, shape, _PARAMS)
    res = np.empty(n, dtype=object)
    res[:] = values
    return SceneBatchResult(
        results=res.reshape(shape),
        codes=codes.reshape(shape),
        messages=np.array(messages, dtype=object).reshape(shape),
        message=message,
        first_failed=first,
        model=np.array([v.model if v is not None else "" for v in values], dtype=object).reshape(shape),
        error_estimate=np.array([v.error_estimate if v is not None else np.nan for v in values], dtype=float).reshape(
            shape
        ),
        tol_met=np.array([v is not None and v.tol_met for v in values], dtype=bool).reshape(shape),
        inputs={k: getattr(batch, k) for k in ("theta0", "omega0", "w0", "gamma", "tol")},
        **{k: _stack(values, shape, k) for k in ("t", "theta", "omega", "energy", "period", "event_time_error")},
    )


def run(batch, one, progress, threads, work):
    """``one(scene, control)`` (a solve or run_model of one scene) for every
    scene of ``batch`` on ``threads`` threads (None: chosen from ``work``, the
    predicted work of the batch in RK4 steps)."""
    scenes = batch.scenes.reshape(-1)
    # up front, before any solve: each scene's series (t, theta, omega, energy:
    # at most 4 of len(t)) in its result and again stacked in the batch's
    n_t = 1 if batch.want == "final" else batch.t.size if batch.want in ("state", "theta", "energy") else 0
    _memory.reserve(
        2 * 4 * 8 * scenes.size * n_t,
        f"the results of {scenes.size} scenes x {n_t} output times (4 series, per scene and stacked)",
    )
    values, codes, messages = pool.map_states(
        lambda i, control: one(scenes[i], control),
        scenes.size,
        threads,
        progress,
        work=work,
        shape=batch.shape,
        names=_PARAMS,
    )
    return _collect(batch, values, codes, messages)
