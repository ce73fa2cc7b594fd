"""Plumbing shared by pendula.driven and pendula.chaos (no numerics): the
pendulum's parameters by the package's one convention (w0 or g/length,
gamma or b/mass), the drive's parameters as the arrays the f2py layer takes,
thread and count arguments, and a Fortran batch call run so that Ctrl-C
stops it and progress=True draws a bar (pendula._longcall's watched call),
with the failure contract of docs/robustness.md: argument errors raise
ValueError before any work, a state that fails gets its code and NaN, and
the call raises only when every state failed."""

import re

import numpy as np

from . import _longcall
from ._arrays import as_array, as_real, broadcast_real, check_size, integer_arg
from ._codes import DRIVEN_MAX_STEPS, DRIVEN_MIN_STEPS
from ._defaults import choose_threads
from ._errors import ERR_CANCELLED, OK, _text, batch_summary, for_state, number, raise_for_status, raise_if_all_failed
from .physics import pendulum_gamma, pendulum_w0

STATE_NAMES = ("theta0", "omega0", "w0", "gamma")
"""The per-state arguments of the driven calls (named with their index in messages)."""
_RULES = {
    "theta0": (lambda a: np.isfinite(a), "finite"),
    "omega0": (lambda a: np.isfinite(a), "finite"),
    "w0": (lambda a: np.isfinite(a) & (a > 0), "finite and > 0"),
    "gamma": (lambda a: np.isfinite(a) & (a >= 0), "finite and >= 0"),
}
_FORTRAN_STATE = re.compile(r"^state \d+ of \d+(?: \(\d+ failed, see codes\))?: ")


def pendulum(w0, gamma, g, length, b, mass):
    """(w0, gamma) by the one convention (pendula.physics): w0 or sqrt(g/length)
    (the text's pendulum when none is given), gamma or b/mass (0 when none)."""
    return pendulum_w0(w0, g, length), pendulum_gamma(gamma, b, mass)


def check_states(flats, shape):
    """ValueError before any work for a non-finite state or an out-of-range
    w0 or gamma, naming the argument and the state (``w0[2] = -1.0 ...``)."""
    for name, (rule, text) in _RULES.items():
        a = flats.get(name)
        if a is None or a.size == 0:
            continue
        with np.errstate(invalid="ignore"):
            bad = ~rule(a)
        if bad.any():
            i = int(np.argmax(bad))
            detail = f"{name} = {number(a[i])} is out of range: it must be {text}"
            raise ValueError(detail if not shape or a.size == 1 else for_state(detail, i, shape, STATE_NAMES))


def drive_arg(drive):
    """The drive argument checked: a pendula.Drive."""
    from .driven import Drive

    if not isinstance(drive, Drive):
        raise TypeError(f"drive must be a pendula.Drive, got {type(drive).__name__}")
    return drive


def times_arg(t):
    """Output times as a 1-D float64 copy (the Fortran checks order and finiteness)."""
    arr = as_array(t, "t")
    check_size(arr.size, "t")
    arr = as_real(arr, "t")
    if arr.ndim != 1:
        raise ValueError(f"t must be a 1-D array of times, got shape {arr.shape}")
    return arr


def threads_arg(threads, work):
    """OpenMP threads for ``work`` RK4 lane steps: None chooses from the work
    (pendula._defaults.choose_threads), 0 the OpenMP default, n > 0 n threads."""
    if threads is not None:
        threads = integer_arg(threads, "threads", 0, 4096, scalar=True)
    return choose_threads(threads, work)


def steps_arg(steps):
    """RK4 steps per drive period."""
    return integer_arg(steps, "steps_per_period", DRIVEN_MIN_STEPS, DRIVEN_MAX_STEPS, scalar=True)


def count_arg(x, name, lo, hi=2**31 - 1):
    """An integer count in [lo, hi]."""
    return integer_arg(x, name, lo, hi, scalar=True)


def states(drive, **named):
    """Broadcast the states and parameters and check them (``check_states``);
    returns (shape, scalar, kwargs for the glue, inputs: each broadcast to the shape)."""
    shape, scalar, flats = broadcast_real(**named)
    check_states(flats, shape)
    args = dict(
        theta0=flats["theta0"],
        omega0=flats["omega0"],
        w0=flats["w0"],
        gamma=flats["gamma"],
        kind=drive.code,
        amp=np.array([drive.amplitude]),
        freq=np.array([drive.frequency]),
        phase=np.array([drive.phase]),
    )
    return shape, scalar, args, inputs(drive, shape, flats)


def inputs(drive, shape, flats):
    """A result's inputs: the states and parameters broadcast to the batch
    shape, and the drive's kind, amplitude, frequency and phase."""
    out = {k: np.asarray(v).reshape(shape) for k, v in flats.items()}
    out.update(kind=drive.kind, amplitude=drive.amplitude, frequency=drive.frequency, phase=drive.phase)
    return out


class Outcome:
    """Per-state codes of a batch call and its message ('' when every state succeeded)."""

    def __init__(self, codes, code=OK, message=""):
        self.codes, self.code, self.message = codes, code, message

    @property
    def failed(self):
        """Flat mask of the failed states."""
        return self.codes.reshape(-1) != OK


def watched(fn, work, n, progress, shape=(), **kwargs):
    """Call the glue ``fn(**kwargs, control=...)`` in a watched thread when
    ``work`` (RK4 lane steps) is large or a progress bar is wanted; then
    ``settle`` its status.  Returns (outputs without codes and status, Outcome)."""
    control = _longcall.new_control()
    out = _longcall.run(
        lambda: fn(control=control, **kwargs),
        control,
        long=work > _longcall.RK4_LONG_STEPS,
        progress=progress,
        total=n,
        unit="state",
    )
    return settle(list(out), shape)


def settle(out, shape):
    """The failure contract on a glue's outputs ``[..., codes, first_failed,
    code, msg]``: a whole-call error (no state named), Ctrl-C and a failed
    scalar call raise; a batch raises only when every state failed
    (``raise_if_all_failed``), else its Outcome carries the codes and the
    summary message.  Returns (outputs without codes and status, Outcome)."""
    codes, first, code, msg = np.asarray(out[-4]).astype(np.int64), int(out[-3]), int(out[-2]), out[-1]
    if code == OK:
        return out[:-4], Outcome(codes.reshape(shape))
    if code == ERR_CANCELLED or first == 0 or not shape:
        raise_for_status(code, _FORTRAN_STATE.sub("", _text(msg), count=1))
    message = batch_summary(codes, _text(msg), shape, STATE_NAMES)
    raise_if_all_failed(codes, code, message)
    return out[:-4], Outcome(codes.reshape(shape), code, message)


def check_client(client):
    """None, or an object with ``submit`` (a dask.distributed Client)."""
    if client is not None and not callable(getattr(client, "submit", None)):
        raise TypeError(f"client must be a dask.distributed Client (or None), got {type(client).__name__}")
    return client


def run_chunk(name, kwargs):
    """One chunk on a Dask worker: the glue ``pendula._fortran.<name>`` on one thread."""
    from . import _fortran

    return list(getattr(_fortran, name)(control=_longcall.new_control(), **kwargs))


def dask_chunks(client, name, chunks, progress, total):
    """Run the glue ``name`` on each chunk's kwargs on Dask (``run_chunk``) and
    join the outputs in the glue's format: arrays whose last axis is the
    chunk's states concatenated along it, codes and the first failure
    indexed for the whole batch, the first failed chunk's status.  A
    progress bar counts the states of the chunks done; Ctrl-C (or any
    error) cancels the futures still pending."""
    from distributed import as_completed  # optional dependency: imported only here

    sizes = [len(c["theta0"]) for c in chunks]
    futures = [
        client.submit(run_chunk, name, c, pure=False, key=_longcall.dask_key(name, i)) for i, c in enumerate(chunks)
    ]
    index = {f.key: i for i, f in enumerate(futures)}
    parts = [None] * len(chunks)
    update, close = _longcall._progress_sink(progress, total, "state")
    done = 0
    try:
        for f in as_completed(futures):
            i = index[f.key]
            parts[i] = f.result()
            done += sizes[i]
            if update is not None:
                update(done)
    except BaseException:
        client.cancel(futures)
        raise
    finally:
        if close is not None:
            close()
    return join_chunks(parts, sizes)


def join_chunks(parts, sizes):
    """The chunks' glue outputs joined as one call's (see ``dask_chunks``)."""
    out = []
    for k in range(len(parts[0]) - 3):
        items = [p[k] for p in parts]
        if all(isinstance(a, np.ndarray) and a.ndim and a.shape[-1] == m for a, m in zip(items, sizes)):
            out.append(np.concatenate(items, axis=-1))
        else:
            out.append(items[0])
    first, code, msg, start = 0, OK, "", 0
    for p, m in zip(parts, sizes):
        if int(p[-2]) != OK and code == OK:
            code, msg = int(p[-2]), p[-1]
            first = start + int(p[-3]) if int(p[-3]) else 0
        start += m
    return out + [first, code, msg]


def nan_failed(outcome, *arrays):
    """NaN in every real output of a failed state (arrays shaped ``shape + ...``), in place."""
    bad = outcome.codes != OK
    if bad.any():
        for a in arrays:
            if a is not None:
                a[bad] = np.nan


class Call:
    """The checked arguments every driven/chaos call shares (built by ``prepare``):
    the drive, steps per period, counts, threads, Dask client and chunk size,
    and the broadcast states (shape, glue kwargs ``args``, result ``inputs``)."""

    def __init__(self, drive, steps, counts, threads, client, chunk_states, shape, args, inputs):
        self.drive, self.steps, self.counts, self.threads = drive, steps, counts, threads
        self.client, self.chunk_states = client, chunk_states
        self.shape, self.args, self.inputs = shape, args, inputs
        self.n = args["theta0"].size


def prepare(given, checks=(), **counts):
    """Check a call's shared arguments, taken by name from ``given`` (the
    call's ``locals()`` on entry: drive, theta0, omega0, w0, gamma, g,
    length, b, mass, steps_per_period, threads and, when it has them,
    client and chunk_states), in the order the calls always did: drive,
    steps, each count ``name=(value, lo[, hi])``, the ``checks`` (callables
    run next), threads, client, chunk_states, then the pendulum and the
    states.  Returns a ``Call``."""
    from ._defaults import check_threads

    drive = drive_arg(given["drive"])
    steps = steps_arg(given["steps_per_period"])
    counts = {name: count_arg(spec[0], name, *spec[1:]) for name, spec in counts.items()}
    for check in checks:
        check()
    threads = given["threads"]
    check_threads(threads)
    client = check_client(given.get("client"))
    chunk_states = count_arg(given.get("chunk_states", 1), "chunk_states", 1)
    w0, gamma = pendulum(*(given[k] for k in ("w0", "gamma", "g", "length", "b", "mass")))
    shape, _, args, inputs = states(drive, theta0=given["theta0"], omega0=given["omega0"], w0=w0, gamma=gamma)
    return Call(drive, steps, counts, threads, client, chunk_states, shape, args, inputs)


def chunk_args(args, start, size, n, **extra):
    """The glue's kwargs for states [start, start + size): per-state arrays sliced, the others as they are."""
    out = {
        k: (v[start : start + size] if isinstance(v, np.ndarray) and v.size == n and n > 1 else v)
        for k, v in args.items()
    }
    out.update(extra)
    return out


def run(glue, call, work, progress, opts, shape=None, chunk_opts=None, per_chunk=None):
    """Run the glue ``pendula._fortran.<glue>`` on the call's states with the
    options ``opts``: locally (a watched call, threads from the work) or, with
    a client, on Dask in chunks of ``call.chunk_states`` states on one thread
    each (``chunk_opts``, if given, replaces ``opts`` there, and
    ``per_chunk(chunk)`` adds options of its own to each), joined so that
    the answer is bit for bit the local one.  Returns (outputs without codes
    and status, Outcome)."""
    from . import _fortran

    n, shape = call.n, call.shape if shape is None else shape
    if call.client is None:
        fn = getattr(_fortran, glue)
        return watched(fn, work, n, progress, shape, threads=threads_arg(call.threads, work), **opts, **call.args)
    extra = opts if chunk_opts is None else chunk_opts
    chunks = [
        chunk_args(call.args, s0, call.chunk_states, n, threads=1, **extra) for s0 in range(0, n, call.chunk_states)
    ]
    for chunk in chunks if per_chunk is not None else ():
        chunk.update(per_chunk(chunk))
    return settle(dask_chunks(client=call.client, name=glue, chunks=chunks, progress=progress, total=n), shape)


def per_state(a, shape):
    """A glue output of shape (k, n) as ``shape + (k,)`` (C order)."""
    return np.ascontiguousarray(np.asarray(a).T).reshape(shape + (np.shape(a)[0],))


def fill_doc(fn):
    """Decorator: put the shared parameter text ``DOC_PARTS[name]`` where the
    docstring has a line ``{name}`` (so that one text documents every call)."""
    for name, text in DOC_PARTS.items():
        fn.__doc__ = fn.__doc__.replace("    {" + name + "}\n", text)
    return fn


DOC_PARTS = {
    "pendulum": """\
    w0 : float or array_like, optional
        Small-angle angular frequency [1/s], > 0; default sqrt(g/length),
        the text's pendulum (sqrt(2)) when g and length are not given either.
    gamma : float or array_like, optional
        Damping rate [1/s], >= 0; default b/mass when both are given, else 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], > 0: w0 = sqrt(g/length).
    b, mass : float, optional
        Damping constant [kg/s] and bob mass [kg]: gamma = b/mass (give both).
""",
    "threads": """\
    threads : int or None, optional
        OpenMP threads: None (default) chooses from the work, 0 the OpenMP
        default, n > 0 n threads.
""",
    "progress": """\
    progress : bool or callable, optional
        True for a tqdm bar, or ``callable(done, total)`` (states).
""",
    "dask": """\
    client : dask.distributed.Client, optional
        Run on Dask in chunks of ``chunk_states`` states (one thread each);
        the answer is bit for bit the local one.
    chunk_states : int, optional
        States per Dask chunk (default ``pendula._defaults.CHUNK_STATES``).
""",
}
"""Parameter text shared by the driven/chaos docstrings (``fill_doc``)."""
