"""Run a long Fortran call so that Ctrl-C stops it, and optionally watch it.

The Fortran integrators take a ``control`` array (int64, see
src/core/pendula_control.f90): ``control[0] != 0`` asks the call to stop
(it polls the flag about every 0.1 ms and returns PENDULA_ERR_CANCELLED),
``control[1]`` counts the work done.  The f2py wrappers release the GIL
(``!f2py threadsafe``), but a signal handler only runs in the main thread
between bytecodes, so a call made there cannot see Ctrl-C until it returns.
``run`` therefore makes a call predicted to be long in a worker thread and
waits for it with ``join(timeout)``: Ctrl-C interrupts the wait, the flag is
set, the worker returns promptly, and KeyboardInterrupt is raised again.
Short calls run inline, with no thread.
"""

import threading
import uuid

import numpy as np

#: RK4 steps above which a call is "long" (~50 ms at ~25 ns a step).
RK4_LONG_STEPS = 2_000_000
#: CVODE steps (or output points) above which a call is "long" (~0.5 us each).
CVODE_LONG_STEPS = 100_000
#: Predicted RK4 steps above which a scene solve is "long" (~2.5 ms): its
#: prediction is a priori (the first verified pair), and refinements can
#: multiply the work several times; a thread costs ~0.1 ms, a few % of such a call.
SCENE_LONG_STEPS = RK4_LONG_STEPS // 20
# Wait slices of the calling thread: a progress update, or a chance for Ctrl-C.
_POLL_SECONDS = 0.02
_JOIN_SECONDS = 0.05


_local = threading.local()


def dask_key(kind, i):
    """A Dask key for chunk ``i`` of a ``kind`` call, unique to this call: Dask
    hands back a finished result to a submit that reuses a key it still holds,
    so a key built from ``id()`` (reused once the object is freed) could return
    an earlier call's chunk."""
    return f"pendula-{kind}-{i}-{uuid.uuid4().hex}"


def new_control():
    """A fresh control array: [cancel flag, progress]."""
    return np.zeros(2, dtype=np.int64)


def scratch_control():
    """This thread's control array for calls run inline (never cancelled:
    only ``run`` sets a cancel flag, on its own fresh array); saves the
    allocation on short calls."""
    try:
        return _local.control
    except AttributeError:
        _local.control = new_control()
        return _local.control


def _progress_sink(progress, total, unit):
    """A callable(done) from the user's ``progress`` argument, or None."""
    if progress is None or progress is False:
        return None, None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError as exc:
            raise ImportError(
                "progress=True needs the optional package tqdm (pip install tqdm); "
                "or pass progress=callable(done, total) instead"
            ) from exc
        bar = tqdm(total=total, unit=unit, unit_scale=True, leave=False)

        def update(done):
            bar.update(max(done - bar.n, 0))

        return update, bar.close
    if callable(progress):
        return (lambda done: progress(done, total)), None
    raise TypeError(f"progress must be True, False, None or a callable(done, total), got {type(progress).__name__}")


def stop(controls, threads):
    """Raise the cancel flag of every control array and wait for every
    thread (a Ctrl-C meanwhile is absorbed: the caller re-raises the first)."""
    for control in controls:
        control[0] = 1
    for th in threads:
        while th.is_alive():
            try:
                th.join()
            except KeyboardInterrupt:
                pass


def run(call, control, long, progress=None, total=None, unit="step"):
    """Return ``call()``, which runs Fortran work that polls ``control``.

    long: True when the work is predicted to take more than ~50 ms; the call
    then runs in a worker thread so that KeyboardInterrupt (Ctrl-C) sets the
    cancel flag, waits for the worker (it stops within a millisecond or so)
    and is re-raised.  progress: None/False, True (a tqdm bar; tqdm is
    optional) or callable(done, total) called from this thread about every
    20 ms with the counter ``control[1]`` (total: the predicted count, or
    None when unknown), and once at the end.  Results are those of
    ``call()``; an exception raised by it is re-raised here.
    """
    update, close = _progress_sink(progress, total, unit)
    try:
        if not long and update is None:
            return call()
        box = {}

        def worker():
            try:
                box["result"] = call()
            except BaseException as exc:  # re-raised in the caller's thread
                box["error"] = exc

        th = threading.Thread(target=worker, name="pendula-longcall", daemon=True)
        th.start()
        try:
            while th.is_alive():
                th.join(_POLL_SECONDS if update is not None else _JOIN_SECONDS)
                if update is not None:
                    update(int(control[1]))
        except BaseException:
            # Ctrl-C (or an exception from the progress callback): stop the
            # Fortran side (within ~1 ms) and wait for it, so that no worker
            # runs on behind the caller's back; a second Ctrl-C meanwhile is
            # absorbed, the first is re-raised.
            stop([control], [th])
            raise
        if "error" in box:
            raise box["error"]
        if update is not None:
            update(int(control[1]))
        return box["result"]
    finally:
        if close is not None:
            close()
