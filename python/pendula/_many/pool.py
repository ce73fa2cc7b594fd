"""Run one scalar pendula call per state of a batch on a pool of threads.

For the batch paths that have no Fortran batch kernel (scenes, CVODE with
events): every scalar call releases the GIL inside Fortran (f2py
``threadsafe``), so ``threads`` Python threads keep ``threads`` cores busy
while the per-state work is much longer than its Python overhead.  States are
handed out one at a time (dynamic schedule: one slow state does not hold up a
thread's share).  Each thread owns a ``control`` array (pendula_control);
Ctrl-C in the calling thread raises every cancel flag, waits for the threads
(each stops within a millisecond or so) and re-raises KeyboardInterrupt.
"""

import threading

import numpy as np

from .. import _longcall
from .._defaults import choose_threads, default_threads
from .._errors import ERR_SOLVER, for_state


def map_states(fn, n, threads=None, progress=None, work=float("nan"), shape=None, names=None):
    """Call ``fn(i, control)`` for i in range(n) on a thread pool.

    Returns ``(values, codes, messages)``: values[i] is fn's result (None when
    it raised), codes an int64 array (0, or the raised exception's
    ``pendula_code``, ERR_SOLVER when it has none), messages the exceptions'
    texts ('' for a success).  A ValueError without a ``pendula_code`` is an
    argument error found by the Python layer: it is re-raised as a ValueError
    naming the state (``shape``: the batch shape, for the index).  An
    exception that is neither a ValueError, a RuntimeError nor
    NotImplementedError (a bug, a TypeError) is re-raised.
    progress: as ``pendula.rk4`` (done = finished states, total = n).
    threads: as the batch kernels, None chosen from the predicted ``work``
    (RK4-step units; NaN: unknown, threads).
    """
    nthreads = choose_threads(threads, work) or default_threads()
    nthreads = max(1, min(nthreads, n))
    values, messages = [None] * n, [""] * n
    codes = np.zeros(n, dtype=np.int64)
    update, close = _longcall._progress_sink(progress, n, "state")
    lock = threading.Lock()
    state = {"next": 0, "done": 0, "error": None}
    controls = [_longcall.new_control() for _ in range(nthreads)]

    def worker(control):
        while True:
            with lock:
                i = state["next"]
                if i >= n or control[0] or state["error"] is not None:
                    return
                state["next"] = i + 1
            try:
                values[i] = fn(i, control)
            except ValueError as exc:
                if hasattr(exc, "pendula_code"):
                    codes[i] = exc.pendula_code
                    messages[i] = str(exc)
                else:  # an argument error: the whole call is refused
                    with lock:
                        if state["error"] is None:
                            state["error"] = ValueError(for_state(exc, i, (n,) if shape is None else shape, names))
                    return
            except (RuntimeError, NotImplementedError) as exc:
                codes[i] = getattr(exc, "pendula_code", ERR_SOLVER)
                messages[i] = str(exc)
            except BaseException as exc:  # a bug or a cancel: stop every thread, re-raise below
                with lock:
                    if state["error"] is None:
                        state["error"] = exc
                return
            with lock:
                state["done"] += 1

    pool = [threading.Thread(target=worker, args=(c,), name="pendula-batch", daemon=True) for c in controls]
    try:
        for th in pool:
            th.start()
        try:
            for th in pool:
                while th.is_alive():
                    th.join(_longcall._POLL_SECONDS)
                    if update is not None:
                        update(state["done"])
        except BaseException:
            _longcall.stop(controls, pool)
            raise
        if state["error"] is not None:
            raise state["error"]
        if update is not None:
            update(state["done"])
    finally:
        if close is not None:
            close()
    return values, codes, messages
