"""Sweeps: many pendulums over a grid of states or parameters, in chunks,
on this machine or on a Dask cluster.

``sweep`` broadcasts theta0, omega0, w0, gamma (and the RK4 step h or the
CVODE tolerances) like NumPy -- ``theta0[:, None]`` and ``omega0[None, :]``
give a theta0 x omega0 grid -- splits the flattened states into chunks and
runs each chunk through the batch kernels of ``pendula._batch`` (RK4 or
CVODE), or through the closed-form period for an undamped sweep.  Each
state's answer is bit-identical to the direct batch call (and so to
``pendula.rk4`` / ``pendula.cvode``): states are independent, and chunking
only changes which call computes them.

Locally, each chunk runs in a worker thread that Ctrl-C cancels within
milliseconds (``pendula._longcall``); progress is reported per state.  With
``client=`` (a ``dask.distributed.Client``) the chunks become Dask tasks
mapped to the same batch kernel on the workers; results come back as NumPy
arrays assembled in place (each chunk exactly once).  Dask is imported only
there: importing pendula never imports dask (optional extra ``cluster``).
"""
import math
import re
from dataclasses import dataclass

import numpy as np

from . import _batch, _fortran, _longcall, _memory, _tables
from ._arrays import broadcast_real, integer_arg
from ._errors import OK
from .undamped import REGIMES, _state_property, period as _period

WANTS = ("final", "trajectory", "period")
METHODS = ("rk4", "cvode")
#: Default states per chunk: ~0.1-0.5 s of RK4 work for a few hundred steps.
CHUNK_STATES = 4096
# The batch kernels' summary prefix, renumbered by _assemble.
_PREFIX = re.compile(r"^state \d+ of \d+ \(\d+ failed, see codes\): ")
# Poll interval of the Dask wait loop: Ctrl-C and progress are seen this often.
_DASK_POLL_SECONDS = 0.1


@dataclass(frozen=True, repr=False)
class SweepResult(_tables.Tabular):
    """Result of ``sweep``; every array has the broadcast batch shape in front.

    Parameters
    ----------
    want : str
        "final", "trajectory" or "period".
    t : numpy.ndarray or None
        The output times [s] (None for "period").
    theta, omega : numpy.ndarray or None
        [rad], [rad/s]: the state at t[-1] (shape batch_shape) for "final",
        the whole series (batch_shape + (n_t,)) for "trajectory", None for
        "period".
    period : numpy.ndarray or None
        For "period" [s]: the libration period, or the time of one turn of a
        rotation (+inf on the separatrix); else None.
    codes : numpy.ndarray
        Status per state (0 = ok; see ``pendula._errors``).
    code, message
        The first failure's code and message, or 0 and ''.
    n_chunks : int
        The chunks the sweep ran in.

    Notes
    -----
    ``repr`` is a few lines; ``to_pandas`` / ``to_xarray`` convert.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> r = pendula.sweep([0.0, 5.0], np.array([0.5, 1.0]), w0=1.0, h=0.01)
    >>> r.want, r.theta.shape, r.n_chunks
    ('final', (2,), 1)
    """
    want: str
    t: object
    theta: object
    omega: object
    period: object
    codes: np.ndarray
    code: int
    message: str
    n_chunks: int

    @property
    def ok(self):
        """Boolean mask of the states that succeeded.

        Returns
        -------
        numpy.ndarray
            bool, the batch shape: True where the state's code is OK.

        Examples
        --------
        >>> import numpy as np, pendula
        >>> pendula.sweep([0.0, 1.0], np.array([0.5, 1.0]), h=0.01).ok.tolist()
        [True, True]
        """
        return self.codes == OK

    def _fields(self):
        return {"theta": self.theta, "omega": self.omega, "period": self.period}

    def _table(self):
        # final and period: one value per state (no t dimension); attrs["t"]: the time of a final state
        attrs = {"want": self.want}
        if self.want == "final":
            attrs["t"] = float(self.t[-1])
        return dict(t=self.t if self.want == "trajectory" else None, fields=self._fields(),
                    shape=self.codes.shape, per_state={"code": self.codes}, attrs=attrs)

    def __repr__(self):
        good = self.ok
        fields = {k: None if v is None else v[good] for k, v in self._fields().items()}
        at = "" if self.t is None else f" at t={self.t[-1]:.4g} s" if self.want == "final" else ""
        return _tables.block("SweepResult", [
            f"want={self.want!r}, batch shape {self.codes.shape}, {self.n_chunks} chunks"
            + ("" if self.t is None else f", t[{self.t.size}] in {_tables.span(self.t, 's')}"),
            _tables.series(None, fields) + at + " (states that succeeded)",
            _tables.codes_line(self.codes, self.message)])

    def _final(self):
        if self.want == "period":
            raise ValueError("a sweep with want='period' has no final state: use want='final'")
        if self.want == "final":
            return self.theta, self.omega
        return self.theta[..., -1], self.omega[..., -1]

    def rotating(self, w0):
        """True where the state at t[-1] is above the separatrix energy 2 w0^2.

        Parameters
        ----------
        w0 : float or array_like
            The sweep's w0 [1/s], > 0 (broadcast against the batch).

        Returns
        -------
        numpy.ndarray
            bool, the batch shape: still going over the top at t[-1].

        Raises
        ------
        ValueError
            For want="period" (no final state) or a bad w0.

        Examples
        --------
        >>> import numpy as np, pendula
        >>> r = pendula.sweep([0.0, 1.0], 0.0, np.array([1.0, 3.0]), w0=1.0, h=0.01)
        >>> r.rotating(1.0).tolist()
        [False, True]
        """
        theta, omega = self._final()
        shape, _, (reg,) = _state_property(_fortran.regime_f2py, 1, theta, omega, w0)
        rotation = next(code for code, name in REGIMES.items() if name == "rotation")
        return (np.asarray(reg) == rotation).reshape(shape)

    @property
    def well(self):
        """The well each state ends in: the integer k nearest theta(t[-1])/(2 pi).

        Returns
        -------
        numpy.ndarray
            int64, the batch shape: the number of full turns made before the
            damping caught the pendulum (the basin map colours starts by it).

        Raises
        ------
        ValueError
            For want="period" (no final state).

        Examples
        --------
        >>> import numpy as np, pendula
        >>> r = pendula.sweep([0.0, 40.0], 0.0, np.array([1.0, 3.0]), w0=1.0, gamma=0.2, h=0.01)
        >>> r.well.tolist()
        [0, 1]
        """
        theta, _ = self._final()
        return np.rint(np.asarray(theta) / (2 * math.pi)).astype(np.int64)


def _chunk(kind, t, cols, opts, want, threads):
    """One chunk: the batch kernel on the states ``cols`` (dict of 1-D
    arrays), reduced to what ``want`` keeps.  Runs locally or on a Dask
    worker; a pure function of its arguments (Dask may run it twice)."""
    if want == "period":
        per = np.asarray(_period(cols["theta0"], cols["omega0"], cols["w0"]), dtype=float).reshape(-1)
        return {"period": per, "codes": np.zeros(per.size, dtype=np.int64), "code": 0, "message": ""}
    control = opts.pop("control", None)
    if kind == "rk4":
        r = _batch.rk4_batch(t, cols["theta0"], cols["omega0"], cols["w0"], cols["gamma"], cols["h"],
                             threads=threads, control=control)
    else:
        r = _batch.cvode_batch(t, cols["theta0"], cols["omega0"], cols["w0"], cols["gamma"], cols["rtol"],
                               cols["atol"], threads=threads, control=control, **opts)
    keep = (lambda a: a) if want == "trajectory" else (lambda a: np.ascontiguousarray(a[:, -1]))
    return {"theta": keep(r.theta), "omega": keep(r.omega), "codes": r.codes, "code": r.code,
            "message": r.message}


def _check(flats, method, want):
    """Refuse non-finite or out-of-domain inputs up front, naming the argument."""
    for name, a in flats.items():
        if not np.isfinite(a).all():
            raise ValueError(f"{name} has a non-finite element (NaN or +-inf): every element must be finite")
    rules = {"w0": (lambda a: a > 0, "> 0"), "gamma": (lambda a: a >= 0, ">= 0"), "h": (lambda a: a > 0, "> 0"),
             "rtol": (lambda a: a > 0, "> 0"), "atol": (lambda a: a >= 0, ">= 0")}
    for name, (good, rng) in rules.items():
        if name in flats and not good(flats[name]).all():
            bad = flats[name][~good(flats[name])][0]
            raise ValueError(f"{name} = {bad!r} is out of range: every element must be {rng}")
    if want == "period" and (flats["gamma"] != 0).any():
        raise ValueError("want='period' needs gamma = 0 everywhere (the closed-form period is undamped)")


def sweep(t, theta0, omega0=0.0, w0=1.0, gamma=0.0, *, want="final", method="rk4", h=0.01, rtol=1e-8,
          atol=1e-10, cvode_method="adams", max_steps=10_000_000, chunk_states=CHUNK_STATES, threads=None,
          progress=None, client=None):
    """Integrate (or, for want="period", answer in closed form) every state of a sweep.

    Parameters
    ----------
    t : array_like or None
        Strictly increasing output times [s], shared by every state (None
        for want="period").
    theta0, omega0 : float or array_like
        Initial angle [rad] and angular velocity [rad/s]; with w0, gamma and
        h (or rtol, atol) they broadcast like NumPy: pass
        ``theta0[:, None]`` and ``omega0[None, :]`` for a grid.
    w0 : float or array_like
        [1/s], > 0.
    gamma : float or array_like
        [1/s], >= 0 (0 everywhere for want="period").
    want : {"final", "trajectory", "period"}
        theta, omega at t[-1]; the whole series; or the closed-form period
        (undamped only, ``pendula.period``).
    method : {"rk4", "cvode"}
        The integrator.
    h : float or array_like
        RK4 step [s], > 0 (method="rk4").
    rtol, atol : float or array_like
        CVODE tolerances, rtol > 0, atol >= 0 (method="cvode").
    cvode_method, max_steps
        As ``pendula.cvode``'s method and max_steps.
    chunk_states : int
        States per chunk, >= 1 (fewer when a chunk's trajectories would
        pass 256 MiB: long grids run in smaller chunks).
    threads : int, optional
        OpenMP threads per chunk (None: the OpenMP default locally, 1 on
        Dask workers, whose own threads give the parallelism).
    progress : bool or callable, optional
        True (tqdm bar; tqdm is optional) or callable(done, total) in states.
    client : dask.distributed.Client, optional
        Run the chunks as Dask tasks on its workers (a worker lost mid-sweep
        has its chunks rerun by Dask; each chunk is placed exactly once).

    Returns
    -------
    SweepResult
        Arrays with the batch shape in front; per-state solver failures are
        reported in ``codes``.

    Raises
    ------
    ValueError
        For bad arguments, naming them.
    TypeError
        For a client that is not a Dask client, or bad types.
    MemoryError
        Up front, before any work, when the outputs of want="trajectory"
        (2 x 8 bytes x states x times) cannot be allocated; the message
        gives the size.
    KeyboardInterrupt
        Ctrl-C: a local sweep stops within ~0.1 s, a Dask one within
        ~0.1 s plus the cancellation of its tasks.

    Notes
    -----
    Each state's answer is bit-identical to the direct batch call (and so
    to ``pendula.rk4`` / ``pendula.cvode``): chunking only changes which
    call computes it.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> r = pendula.sweep([0.0, 10.0], np.linspace(0, 3, 4)[:, None], np.zeros(2)[None, :], w0=1.0)
    >>> r.theta.shape, bool(r.ok.all())
    ((4, 2), True)
    >>> np.round(pendula.sweep(None, np.array([0.1, 1.0]), want="period").period, 3).tolist()
    [6.287, 6.7]
    """
    if not isinstance(want, str) or want not in WANTS:
        raise ValueError(f"want = {want!r} is invalid: it must be one of {', '.join(WANTS)}")
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"method = {method!r} is invalid: it must be 'rk4' or 'cvode'")
    chunk_states = integer_arg(chunk_states, "chunk_states", 1, 2**31 - 1, scalar=True)
    if client is not None and not callable(getattr(client, "submit", None)):
        raise TypeError(f"client must be a dask.distributed Client (or None), got {type(client).__name__}")
    if threads is not None:
        _batch._threads(threads)   # validates the type and range
    named = dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    opts = {}
    if want == "period":
        tt = None
    else:
        tt = _batch._grid(t)
        if not np.isfinite(tt).all() or (np.diff(tt) <= 0).any():
            raise ValueError("t must be finite and strictly increasing (the output times in s)")
        if method == "rk4":
            named["h"] = h
        else:
            named.update(rtol=rtol, atol=atol)
            opts = dict(method=cvode_method, max_steps=max_steps)
    shape, _, flats = broadcast_real(**named)
    _check(flats, method, want)
    n = int(np.prod(shape, dtype=np.int64)) if shape else 1
    out = None
    if tt is not None:
        # a chunk's trajectories (also for "final": the kernels return them) stay within
        # _memory.CHUNK_BYTES; the whole output of "trajectory" is allocated (or refused) now
        chunk_states = min(chunk_states, max(1, _memory.CHUNK_BYTES // _batch._trajectory_bytes(1, tt.size)))
        if want == "trajectory":
            what = f"the outputs theta and omega of {n} states x {tt.size} times"
            both = _memory.empty((2, n, tt.size), what)
            out = {"theta": both[0], "omega": both[1]}
    starts = list(range(0, n, chunk_states))
    chunks = [{k: v[s:s + chunk_states] for k, v in flats.items()} for s in starts]
    update, close = _longcall._progress_sink(progress, n, "state")
    try:
        if client is None:
            parts = _run_local(method, tt, chunks, opts, want, 0 if threads is None else threads, update,
                               out, starts)
        else:
            parts = _run_dask(client, method, tt, chunks, opts, want, 1 if threads is None else threads, update,
                              out, starts)
    finally:
        if close is not None:
            close()
    return _assemble(parts, shape, tt, want, len(chunks), out)


def _store(part, out, start):
    """Move a trajectory chunk's series into the sweep's outputs (allocated up
    front), so that no chunk's copy outlives its arrival."""
    if out is not None:
        for k in ("theta", "omega"):
            out[k][start:start + len(part[k])] = part[k]
            part[k] = None
    return part


def _run_local(method, tt, chunks, opts, want, threads, update, out=None, starts=()):
    parts, done = [], 0
    for i, cols in enumerate(chunks):
        size = len(cols["theta0"])
        if want == "period":
            parts.append(_chunk(method, tt, cols, dict(opts), want, threads))
        else:
            control = _longcall.new_control()
            sink = None if update is None else (lambda k, _tot, d=done: update(d + k))
            parts.append(_store(_longcall.run(lambda: _chunk(method, tt, cols, dict(opts, control=control), want,
                                                             threads), control, long=True, progress=sink),
                                out, starts[i] if out is not None else 0))
        done += size
        if update is not None:
            update(done)
    return parts


def _run_dask(client, method, tt, chunks, opts, want, threads, update, out=None, starts=()):
    from distributed import wait   # optional dependency: imported only here
    futures = [client.submit(_chunk, method, tt, cols, dict(opts), want, threads, pure=False,
                             key=f"pendula-sweep-{i}-{id(chunks)}") for i, cols in enumerate(chunks)]
    index = {f.key: i for i, f in enumerate(futures)}
    parts = [None] * len(chunks)
    arrivals = np.zeros(len(chunks), dtype=np.int64)
    pending, done = set(futures), 0
    try:
        while pending:
            finished, pending = _wait_some(wait, pending)
            for f in finished:
                i = index[f.key]
                parts[i] = _store(f.result(), out, starts[i] if out is not None else 0)
                arrivals[i] += 1
                done += len(chunks[i]["theta0"])
            if update is not None and finished:
                update(done)
    except BaseException:
        client.cancel(futures)
        raise
    if not (arrivals == 1).all():   # never expected: Dask resolves each future once
        raise RuntimeError(f"sweep: chunks placed {arrivals.tolist()} times, expected each exactly once")
    return parts


def _wait_some(wait, pending):
    """Wait up to _DASK_POLL_SECONDS for some futures; (finished, still pending)."""
    try:
        res = wait(list(pending), timeout=_DASK_POLL_SECONDS, return_when="FIRST_COMPLETED")
    except TimeoutError:
        return set(), pending
    return set(res.done), set(res.not_done)


def _assemble(parts, shape, tt, want, n_chunks, out=None):
    codes = np.concatenate([p["codes"] for p in parts]) if parts else np.zeros(0, dtype=np.int64)
    code, message = OK, ""
    failed = np.flatnonzero(codes != OK)
    if failed.size:
        # the first failed chunk's message, renumbered for the whole sweep (as the direct batch call says it)
        first = next(p for p in parts if p["code"] != OK)
        detail = _PREFIX.sub("", first["message"], count=1)
        code = first["code"]
        message = f"state {failed[0] + 1} of {codes.size} ({failed.size} failed, see codes): {detail}"
    if want == "period":
        per = np.concatenate([p["period"] for p in parts]) if parts else np.zeros(0)
        return SweepResult(want, None, None, None, per.reshape(shape), codes.reshape(shape), code, message,
                           n_chunks)
    tail = (tt.size,) if want == "trajectory" else ()
    join = (lambda key: np.concatenate([p[key] for p in parts]).reshape(shape + tail)) if parts \
        else (lambda key: np.zeros(shape + tail))
    if out is not None:   # the trajectories, already in place
        join = (lambda key: out[key].reshape(shape + tail))
    return SweepResult(want, tt, join("theta"), join("omega"), None, codes.reshape(shape), code, message,
                       n_chunks)


__all__ = ["sweep", "SweepResult"]
