"""Worker process of the fuzz leg (test_fuzz.py): runs pendula calls fed over a pipe.

Protocol: the parent writes length-prefixed pickles ``(fn, [arg sources],
{kw: source})``; each source is a Python expression (numpy as ``np``, the
package as ``pendula``) that builds the argument, so the parent's one-line
reproducer is exactly what ran here.  The worker answers with a length-prefixed
pickle ``dict(kind=..., ...)``:

* ``ok``: ``result`` is the call's value made plain (tuples -> lists,
  dataclasses -> dicts, numbers -> float64/complex arrays, str kept), and
  ``modified`` names any argument array the call changed;
* ``exc``: ``type``, ``module``, ``message`` and ``allowed`` (a ValueError,
  TypeError or NotImplementedError -- the exceptions bad input may raise).

A crash kills only this process; the parent sees EOF and the exit signal.
The protocol uses a private copy of fd 1, and fd 1 itself is pointed at
stderr, so anything the library might print cannot corrupt the pipe.
"""

import copy
import dataclasses
import os
import pickle
import struct
import sys
import warnings

import numpy as np


def _plain(x):
    if isinstance(x, (str, bytes)) or x is None or isinstance(x, bool):
        return x
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return {f.name: _plain(getattr(x, f.name)) for f in dataclasses.fields(x)}
    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (tuple, list)):
        return [_plain(v) for v in x]
    if isinstance(x, np.ndarray) and x.dtype.kind in "US":
        return x.tolist()
    if hasattr(x, "rows") and hasattr(x, "reference"):  # TradeoffTable
        return {"rows": _plain(list(x.rows)), "reference": x.reference}
    try:
        arr = np.asarray(x)
    except Exception:  # noqa: BLE001 - report what it is instead
        return repr(type(x))
    if arr.dtype.kind in "biuf":
        return arr.astype(np.float64)
    if arr.dtype.kind == "c":
        return arr.astype(np.complex128)
    return repr(type(x))


def _same(a, b):
    if isinstance(a, np.ndarray):
        return (
            isinstance(b, np.ndarray)
            and a.dtype == b.dtype
            and a.shape == b.shape
            and np.array_equal(a, b, equal_nan=a.dtype.kind in "fc")
        )
    if isinstance(a, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if hasattr(a, "__dict__") and not isinstance(a, type):  # e.g. a Scene: compare its state
        return type(a) is type(b) and _same(vars(a), vars(b))
    try:
        return bool(a == b) or (a != a and b != b)
    except Exception:  # noqa: BLE001
        return True


def _run(pendula, fn, arg_src, kw_src):
    ns = {"np": np, "pendula": pendula}
    try:
        args = [eval(s, ns) for s in arg_src]  # noqa: S307 - test-generated code
        kwargs = {k: eval(s, ns) for k, s in kw_src.items()}  # noqa: S307
        before = [copy.deepcopy(a) for a in args], {k: copy.deepcopy(v) for k, v in kwargs.items()}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = getattr(pendula, fn)(*args, **kwargs)
        modified = [f"argument {i + 1}" for i, (a, b) in enumerate(zip(before[0], args)) if not _same(a, b)]
        modified += [k for k, v in kwargs.items() if not _same(before[1][k], v)]
        return {"kind": "ok", "result": _plain(out), "modified": modified}
    except Exception as exc:  # noqa: BLE001 - classified by the parent
        return {
            "kind": "exc",
            "type": type(exc).__name__,
            "module": type(exc).__module__,
            "message": str(exc)[:400],
            "allowed": isinstance(exc, (ValueError, TypeError, NotImplementedError)),
            "solver": type(exc).__name__ == "PendulaSolverError",
        }


def main():
    proto_out = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    proto_in = sys.stdin.buffer
    import pendula

    while True:
        head = proto_in.read(8)
        if len(head) < 8:
            return
        (n,) = struct.unpack("<Q", head)
        fn, arg_src, kw_src = pickle.loads(proto_in.read(n))
        data = pickle.dumps(_run(pendula, fn, arg_src, kw_src))
        proto_out.write(struct.pack("<Q", len(data)) + data)
        proto_out.flush()


if __name__ == "__main__":
    main()
