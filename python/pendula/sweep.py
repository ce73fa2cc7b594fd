"""Sweeps: many pendulums over a grid of states or parameters, in chunks,
on this machine or on a Dask cluster.

``sweep`` broadcasts theta0, omega0, w0, gamma (and the RK4 step h or the
CVODE tolerances) like NumPy -- ``theta0[:, None]`` and ``omega0[None, :]``
give a theta0 x omega0 grid -- splits the flattened states into chunks and
runs each chunk through the batch kernels of ``pendula._many.kernels`` (RK4
or CVODE), or through the closed-form period for an undamped sweep.  Each
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

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from . import _drive_args, _fortran, _longcall, _memory, _tables
from ._arrays import broadcast_real, integer_arg, time_grid
from ._defaults import (
    CHUNK_STATES,
    CVODE_ATOL,
    CVODE_MAX_STEPS,
    CVODE_METHOD,
    CVODE_METHODS,
    CVODE_RTOL,
    SETTLE_MARGIN,
    SWEEP_H,
    THREADS,
    check_threads,
)
from ._defaults import WELL_NONE as _WELL_NONE
from ._errors import OK, batch_summary, for_state, number, raise_if_all_failed
from ._many import drives as _drives
from ._many import kernels
from .physics import pendulum_gamma, pendulum_w0
from .undamped import REGIMES, _state_property
from .undamped import period as _period

WANTS = ("final", "trajectory", "period")
METHODS = ("rk4", "cvode")
WELL_NONE = _WELL_NONE
"""The ``well`` of a state that has none: it failed, or it is not ``settled``
at t[-1] (still going over the top, or at it).  -2**31, never a number of
turns (``pendula._defaults``)."""
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
        "period"; NaN for a failed state (from the point it failed).
    period : numpy.ndarray or None
        For "period" [s]: the libration period, or the time of one turn of a
        rotation (+inf on the separatrix); else None.
    codes : numpy.ndarray
        Status per state (0 = ok; see ``pendula._errors``).
    code, message
        The first failure's code and message, or 0 and ''.
    n_chunks : int
        The chunks the sweep ran in.
    inputs : dict
        The per-state inputs broadcast to the batch shape: theta0 [rad],
        omega0 [rad/s], w0 [1/s], gamma [1/s], and h [s] (rk4) or rtol,
        atol (cvode): the coordinates of ``to_xarray`` and columns of
        ``to_pandas``.

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
    inputs: dict = field(default=None)

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
        per_state = {"code": self.codes}
        if self.want != "period" and not self._driven():
            per_state.update(well=self.well, settled=self.settled)
        return dict(
            t=self.t if self.want == "trajectory" else None,
            fields=self._fields(),
            shape=self.codes.shape,
            per_state=per_state,
            attrs=attrs,
            coords=self.inputs,
        )

    def __repr__(self):
        good = self.ok
        fields = {k: None if v is None else v[good] for k, v in self._fields().items()}
        at = "" if self.t is None else f" at t={self.t[-1]:.4g} s" if self.want == "final" else ""
        return _tables.block(
            "SweepResult",
            [
                f"want={self.want!r}, batch shape {self.codes.shape}, {self.n_chunks} chunks"
                + ("" if self.t is None else f", t[{self.t.size}] in {_tables.span(self.t, 's')}"),
                _tables.series(None, fields) + at + " (states that succeeded)",
                _tables.codes_line(self.codes, self.message),
            ],
        )

    def _driven(self):
        """True when some state has a drive of nonzero amplitude."""
        amplitude = (self.inputs or {}).get("drive_amplitude")
        return amplitude is not None and bool(np.any(np.asarray(amplitude) != 0))

    def _undriven(self, name):
        """Refuse ``name`` (settled, well) for a driven sweep: the energy rule behind
        them holds only without a drive."""
        if self._driven():
            raise ValueError(
                f"{name} is not defined for a driven sweep: a drive can pump energy into the pendulum "
                "and carry it over the top again, so no energy at t[-1] traps it in a well; use "
                "rotating() for the energy at t[-1], or pendula.basins / pendula.periodic_orbits "
                "for the attractor a driven state settles on"
            )

    def _final(self):
        if self.want == "period":
            raise ValueError("a sweep with want='period' has no final state: use want='final'")
        if self.want == "final":
            return self.theta, self.omega
        return self.theta[..., -1], self.omega[..., -1]

    def rotating(self, w0=None):
        """True where the state at t[-1] is above the separatrix energy 2 w0^2.

        Parameters
        ----------
        w0 : float or array_like, optional
            [1/s], > 0 (broadcast against the batch); default: the sweep's
            own w0 (``inputs["w0"]``).

        Returns
        -------
        numpy.ndarray
            bool, the batch shape: still going over the top at t[-1]
            (False for a failed state).

        Raises
        ------
        ValueError
            For want="period" (no final state) or a bad w0.

        Examples
        --------
        >>> import numpy as np, pendula
        >>> r = pendula.sweep([0.0, 1.0], 0.0, np.array([1.0, 3.0]), w0=1.0, h=0.01)
        >>> r.rotating().tolist()
        [False, True]
        """
        theta, omega = self._final()
        w0 = self.inputs["w0"] if w0 is None else w0
        good = self.ok
        # a failed state has no regime: a placeholder state, reported False
        theta, omega = np.where(good, theta, 0.0), np.where(good, omega, 0.0)
        shape, _, (reg,) = _state_property(_fortran.regime_f2py, 1, theta, omega, w0)
        rotation = next(code for code, name in REGIMES.items() if name == "rotation")
        return (np.asarray(reg) == rotation).reshape(shape) & np.broadcast_to(good, shape)

    @property
    def settled(self):
        """True where the state at t[-1] is trapped in its well.

        Returns
        -------
        numpy.ndarray
            bool, the batch shape: the state succeeded and its energy
            omega^2/2 + w0^2 (1 - cos theta) is below the separatrix energy
            2 w0^2 by more than ``SETTLE_MARGIN`` of it, so the damped
            pendulum can never leave the well again.  False for a state
            still going over the top or near it.

        Raises
        ------
        ValueError
            For want="period" (no final state), or a driven sweep (a drive
            of nonzero amplitude can carry the pendulum out of any well, so
            no energy traps it; ``pendula.basins`` finds where a driven
            state settles).  A drive of zero amplitude is the undriven rule.

        Examples
        --------
        >>> import numpy as np, pendula
        >>> r = pendula.sweep([0.0, 40.0], 0.0, np.array([1.0, 3.0, 5.0]), w0=1.0, gamma=0.2, h=0.01)
        >>> r.settled.tolist()
        [True, True, True]
        >>> pendula.sweep([0.0, 1.0], 0.0, 5.0, w0=1.0, h=0.01).settled.tolist()
        False
        """
        theta, omega = self._final()
        self._undriven("settled")
        w0 = self.inputs["w0"]
        with np.errstate(invalid="ignore"):
            energy = 0.5 * omega**2 + w0**2 * (1 - np.cos(theta))
            return self.ok & (energy < 2 * w0**2 * (1 - SETTLE_MARGIN))

    @property
    def well(self):
        """The well each state ends in: the integer k nearest theta(t[-1])/(2 pi).

        Returns
        -------
        numpy.ndarray
            int64, the batch shape: the number of full turns made before the
            damping caught the pendulum (the basin map colours starts by it);
            ``pendula.WELL_NONE`` (-2**31, never a number of turns) where
            the state failed or is not ``settled`` at t[-1].

        Raises
        ------
        ValueError
            For want="period" (no final state) or a driven sweep (as
            ``settled``).

        Examples
        --------
        >>> import numpy as np, pendula
        >>> r = pendula.sweep([0.0, 40.0], 0.0, np.array([1.0, 3.0]), w0=1.0, gamma=0.2, h=0.01)
        >>> r.well.tolist()
        [0, 1]
        >>> int(pendula.sweep([0.0, 1.0], 0.0, 5.0, w0=1.0, h=0.01).well) == pendula.WELL_NONE
        True
        """
        theta, _ = self._final()
        self._undriven("well")
        settled = self.settled
        k = np.rint(np.where(settled, theta, 0.0) / (2 * math.pi)).astype(np.int64)
        return np.where(settled, k, WELL_NONE)


def _chunk(kind, t, cols, opts, want, threads):
    """One chunk: the batch kernel on the states ``cols`` (dict of 1-D
    arrays), reduced to what ``want`` keeps.  Runs locally or on a Dask
    worker; a pure function of its arguments (Dask may run it twice)."""
    if want == "period":
        per = np.asarray(_period(cols["theta0"], cols["omega0"], cols["w0"]), dtype=float).reshape(-1)
        return {"period": per, "codes": np.zeros(per.size, dtype=np.int64), "code": 0, "message": ""}
    control = opts.pop("control", None)
    # a driven sweep's chunk carries the drive as its four per-state columns
    drive = {k: cols[k] for k in _drives.COLUMNS} if _drives.COLUMNS[0] in cols else None
    if kind == "rk4":
        r = kernels.rk4_batch(
            t,
            cols["theta0"],
            cols["omega0"],
            cols["w0"],
            cols["gamma"],
            cols["h"],
            threads=threads,
            control=control,
            drive=drive,
        )
    else:
        r = kernels.cvode_batch(
            t,
            cols["theta0"],
            cols["omega0"],
            cols["w0"],
            cols["gamma"],
            cols["rtol"],
            cols["atol"],
            threads=threads,
            control=control,
            drive=drive,
            **opts,
        )
    keep = (lambda a: a) if want == "trajectory" else (lambda a: np.ascontiguousarray(a[:, -1]))
    return {"theta": keep(r.theta), "omega": keep(r.omega), "codes": r.codes, "code": r.code, "message": r.message}


_RULES = {
    "w0": (lambda a: a > 0, "> 0"),
    "gamma": (lambda a: a >= 0, ">= 0"),
    "h": (lambda a: a > 0, "> 0"),
    "rtol": (lambda a: a > 0, "> 0"),
    "atol": (lambda a: a >= 0, ">= 0"),
}


def _check(flats, shape, want):
    """Refuse non-finite or out-of-domain inputs up front, naming the argument and the state."""
    for name, a in flats.items():
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError(
                for_state(
                    f"{name} = {number(a[bad[0]])} is not finite: every element must be finite", int(bad[0]), shape
                )
            )
    for name, (good, rng) in _RULES.items():
        if name in flats:
            bad = np.flatnonzero(~good(flats[name]))
            if bad.size:
                i = int(bad[0])
                raise ValueError(
                    for_state(f"{name} = {number(flats[name][i])} is out of range: it must be {rng}", i, shape)
                )
    if want == "period" and (flats["gamma"] != 0).any():
        i = int(np.flatnonzero(flats["gamma"] != 0)[0])
        raise ValueError(
            for_state(
                f"gamma = {number(flats['gamma'][i])} is not 0: want='period' needs "
                "gamma = 0 everywhere (the closed-form period is undamped)",
                i,
                shape,
            )
        )


def sweep(
    t: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    gamma: ArrayLike | None = None,
    *,
    g: float | None = None,
    length: float | None = None,
    b: float | None = None,
    mass: float | None = None,
    want: str = "final",
    method: str = "rk4",
    h: ArrayLike = SWEEP_H,
    rtol: ArrayLike = CVODE_RTOL,
    atol: ArrayLike = CVODE_ATOL,
    cvode_method: str = CVODE_METHOD,
    max_steps: int = CVODE_MAX_STEPS,
    chunk_states: int = CHUNK_STATES,
    threads: int | None = THREADS,
    progress: bool | Callable[[int, int | None], object] | None = None,
    client: object | None = None,
    drive: object | None = None,
) -> SweepResult:
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
    w0 : float or array_like, optional
        [1/s], > 0; default: sqrt(g/length), the text's pendulum (sqrt(2))
        when neither is given, as everywhere in the package.
    gamma : float or array_like, optional
        [1/s], >= 0 (0 everywhere for want="period"); default: b/mass when
        both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length) (the
        text's 9.8 and 4.9 for the one not given).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
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
    threads : int or None
        OpenMP threads per chunk: None (the default) chooses from the
        chunk's predicted work locally and takes 1 on Dask workers (whose
        own threads give the parallelism); 0 asks for the OpenMP default.
    progress : bool or callable, optional
        True (tqdm bar; tqdm is optional) or callable(done, total) in states.
    client : dask.distributed.Client, optional
        Run the chunks as Dask tasks on its workers (a worker lost mid-sweep
        has its chunks rerun by Dask; each chunk is placed exactly once).
    drive : Drive or array_like of Drive, optional
        Sweep the driven pendulum (``pendula.Drive``), as ``pendula.rk4`` /
        ``pendula.cvode`` with ``drive=``: one Drive for every state, or an
        array of them that broadcasts with theta0, omega0, w0 and gamma like
        any other axis -- a sweep over a drive parameter is an array of
        drives (``[pendula.Drive("torque", F, 2/3) for F in amplitudes]``).
        ``inputs`` then also holds drive_kind, drive_amplitude,
        drive_frequency and drive_phase per state.  Not with want="period"
        (the closed form is undriven).  The result's ``settled`` and
        ``well`` (an undriven energy rule) raise ValueError when a drive
        has nonzero amplitude: ``pendula.basins`` classifies driven states.

    Returns
    -------
    SweepResult
        Arrays with the batch shape in front and the inputs that made them;
        per-state solver failures are reported in ``codes``, their outputs
        NaN (docs/robustness.md).

    Raises
    ------
    ValueError
        For bad arguments, naming them and the state (``w0[1] = -1.0 ...``).
    TypeError
        For a client that is not a Dask client, or bad types.
    RuntimeError
        When every state failed (``PendulaSolverError`` for a solver
        failure), as for ``rk4`` and ``cvode`` batches.
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
    >>> p = pendula.sweep(None, np.array([0.1, 1.0]), want="period").period
    >>> bool((p == pendula.period(np.array([0.1, 1.0]))).all())
    True

    A theta0 x drive-amplitude grid of the driven damped pendulum:

    >>> ds = np.array([pendula.Drive("torque", f, 2 / 3) for f in (0.5, 1.07, 1.15)])
    >>> r = pendula.sweep([0.0, 30.0], np.array([0.0, 1.0])[:, None], w0=1.0, gamma=0.5, h=0.05, drive=ds[None, :])
    >>> r.theta.shape, r.inputs["drive_amplitude"][0].tolist()
    ((2, 3), [0.5, 1.07, 1.15])
    """
    if not isinstance(want, str) or want not in WANTS:
        raise ValueError(f"want = {want!r} is invalid: it must be one of {', '.join(WANTS)}")
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"method = {method!r} is invalid: it must be 'rk4' or 'cvode'")
    chunk_states = integer_arg(chunk_states, "chunk_states", 1, 2**31 - 1, scalar=True)
    if client is not None and not callable(getattr(client, "submit", None)):
        raise TypeError(f"client must be a dask.distributed Client (or None), got {type(client).__name__}")
    check_threads(threads)
    named = dict(theta0=theta0, omega0=omega0, w0=pendulum_w0(w0, g, length), gamma=pendulum_gamma(gamma, b, mass))
    if drive is not None:
        if want == "period":
            raise ValueError("drive is not supported with want='period': the closed-form period is undriven")
        named.update(_drive_args.columns(drive))  # TypeError naming drive for anything but Drives
    opts = {}
    if want == "period":
        tt = None
    else:
        tt = time_grid(t)
        if not np.isfinite(tt).all() or (np.diff(tt) <= 0).any():
            raise ValueError("t must be finite and strictly increasing (the output times in s)")
        if method == "rk4":
            named["h"] = h
        else:
            named.update(rtol=rtol, atol=atol)
            if not isinstance(cvode_method, str) or cvode_method.lower() not in CVODE_METHODS:
                raise ValueError(f"cvode_method = {cvode_method!r} is invalid: it must be 'adams' or 'bdf'")
            integer_arg(max_steps, "max_steps", 1, 2**63 - 1, scalar=True)
            opts = dict(method=cvode_method, max_steps=max_steps)
    shape, _, flats = broadcast_real(**named)
    _check(flats, shape, want)
    n = int(np.prod(shape, dtype=np.int64)) if shape else 1
    out = None
    if tt is not None:
        # a chunk's trajectories (also for "final": the kernels return them) stay within
        # _memory.CHUNK_BYTES; the whole output of "trajectory" is allocated (or refused) now
        chunk_states = min(chunk_states, max(1, _memory.CHUNK_BYTES // kernels._trajectory_bytes(1, tt.size)))
        if want == "trajectory":
            what = f"the outputs theta and omega of {n} states x {tt.size} times"
            both = _memory.empty((2, n, tt.size), what)
            out = {"theta": both[0], "omega": both[1]}
    starts = list(range(0, n, chunk_states))
    chunks = [{k: v[s : s + chunk_states] for k, v in flats.items()} for s in starts]
    update, close = _longcall._progress_sink(progress, n, "state")
    try:
        if client is None:
            parts = _run_local(method, tt, chunks, opts, want, threads, update, out, starts)
        else:
            parts = _run_dask(
                client, method, tt, chunks, opts, want, 1 if threads is None else threads, update, out, starts
            )
    finally:
        if close is not None:
            close()
    inputs = {k: v.reshape(shape) for k, v in flats.items()}
    return _assemble(parts, shape, tt, want, len(chunks), inputs, out)


def _store(part, out, start):
    """Move a trajectory chunk's series into the sweep's outputs (allocated up
    front), so that no chunk's copy outlives its arrival."""
    if out is not None:
        for k in ("theta", "omega"):
            out[k][start : start + len(part[k])] = part[k]
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
            parts.append(
                _store(
                    _longcall.run(
                        lambda: _chunk(method, tt, cols, dict(opts, control=control), want, threads),
                        control,
                        long=True,
                        progress=sink,
                    ),
                    out,
                    starts[i] if out is not None else 0,
                )
            )
        done += size
        if update is not None:
            update(done)
    return parts


def _run_dask(client, method, tt, chunks, opts, want, threads, update, out=None, starts=()):
    from distributed import wait  # optional dependency: imported only here

    futures = [
        client.submit(
            _chunk, method, tt, cols, dict(opts), want, threads, pure=False, key=_longcall.dask_key("sweep", i)
        )
        for i, cols in enumerate(chunks)
    ]
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
    if not (arrivals == 1).all():  # never expected: Dask resolves each future once
        raise RuntimeError(f"sweep: chunks placed {arrivals.tolist()} times, expected each exactly once")
    return parts


def _wait_some(wait, pending):
    """Wait up to _DASK_POLL_SECONDS for some futures; (finished, still pending)."""
    try:
        res = wait(list(pending), timeout=_DASK_POLL_SECONDS, return_when="FIRST_COMPLETED")
    except TimeoutError:
        return set(), pending
    return set(res.done), set(res.not_done)


def _assemble(parts, shape, tt, want, n_chunks, inputs, out=None):
    codes = np.concatenate([p["codes"] for p in parts]) if parts else np.zeros(0, dtype=np.int64)
    code, message = OK, ""
    failed = np.flatnonzero(codes != OK)
    if failed.size:
        # the first failed chunk's message, indexed for the whole sweep (as the direct batch call says it)
        first = next(p for p in parts if p["code"] != OK)
        code = first["code"]
        message = batch_summary(codes, first["message"], shape)
        raise_if_all_failed(codes, code, message)
    if want == "period":
        per = np.concatenate([p["period"] for p in parts]) if parts else np.zeros(0)
        return SweepResult(
            want, None, None, None, per.reshape(shape), codes.reshape(shape), code, message, n_chunks, inputs
        )
    tail = (tt.size,) if want == "trajectory" else ()
    join = (
        (lambda key: np.concatenate([p[key] for p in parts]).reshape(shape + tail))
        if parts
        else (lambda key: np.zeros(shape + tail))
    )
    if out is not None:  # the trajectories, already in place
        join = lambda key: out[key].reshape(shape + tail)
    return SweepResult(
        want, tt, join("theta"), join("omega"), None, codes.reshape(shape), code, message, n_chunks, inputs
    )


__all__ = ["sweep", "SweepResult", "WELL_NONE"]
