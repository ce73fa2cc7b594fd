"""Shared machinery of the fuzz legs (test_fuzz.py, test_fuzz_solvers.py): the
persistent worker process that runs each call (fuzz_worker.py), the hypothesis
sources of adversarial arguments, and the judge of a call's outcome (see
test_fuzz.py for what fails a call)."""

import importlib.util
import math
import os
import pathlib
import pickle
import re
import select
import signal
import struct
import subprocess
import sys
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, settings
from hypothesis import strategies as st

import pendula

HERE = pathlib.Path(__file__).resolve().parent
TIMEOUT = 20.0  # s per call; a hang, not slowness: the slowest legal call here takes < 2 s
BIG = 1e300  # a-priori bounds below this must give finite results
DBL_MAX = float(np.finfo(np.float64).max)
HALF_PI = math.pi / 2  # the double below pi/2: F(HALF_PI | 1) = atanh(sin(HALF_PI)) ~ 38.03 is finite

SETTINGS = settings(
    derandomize=True,
    deadline=None,
    database=None,
    print_blob=False,
    phases=[Phase.explicit, Phase.generate],
    suppress_health_check=list(HealthCheck),
)


# ----------------------------------------------------------------- the worker


class Worker:
    """A persistent subprocess running fuzz_worker.py; restarted after a death or hang."""

    def __init__(self):
        self.proc = None
        self.stderr_path = None

    def _start(self):
        spec = importlib.util.find_spec("pendula")
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join([str(pathlib.Path(spec.origin).parents[1]), env.get("PYTHONPATH", "")])
        env.setdefault("MPLBACKEND", "Agg")
        self.stderr_file = open(os.devnull, "wb")
        self.proc = subprocess.Popen(
            [sys.executable, str(HERE / "fuzz_worker.py")],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self.stderr_file,
            env=env,
        )

    def stop(self):
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.kill()
            self.proc.wait()
            self.stderr_file.close()
            self.proc = None

    def _read(self, n, deadline):
        buf = b""
        fd = self.proc.stdout.fileno()
        while len(buf) < n:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([fd], [], [], left)[0]:
                return None
            chunk = os.read(fd, n - len(buf))
            if not chunk:
                return b""
            buf += chunk
        return buf

    def call(self, fn, args=(), kwargs=None):
        """Run pendula.<fn>(*args, **kwargs) (argument SOURCES) in the worker: a dict from the
        worker, or {"kind": "signal"/"exit"/"hang", ...} when it died or did not answer."""
        if self.proc is None or self.proc.poll() is not None:
            self.stop()
            self._start()
        data = pickle.dumps((fn, list(args), dict(kwargs or {})))
        try:
            self.proc.stdin.write(struct.pack("<Q", len(data)) + data)
            self.proc.stdin.flush()
        except BrokenPipeError:
            pass
        deadline = time.monotonic() + TIMEOUT
        head = self._read(8, deadline)
        if head and len(head) == 8:
            body = self._read(struct.unpack("<Q", head)[0], deadline)
            if body:
                return pickle.loads(body)
            head = body
        if head is None:  # no answer in time: a hang
            self.stop()
            return {"kind": "hang"}
        rc = self.proc.wait()
        self.stop()
        if rc < 0:
            return {"kind": "signal", "signal": signal.Signals(-rc).name}
        return {"kind": "exit", "code": rc}


@pytest.fixture(scope="module")
def worker():
    w = Worker()
    yield w
    w.stop()


# ----------------------------------------------------------------- argument sources

SPECIAL = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    2.0,
    0.7,
    1e308,
    -1e308,
    DBL_MAX,
    -DBL_MAX,
    1.34e300,
    5e-324,
    -5e-324,
    2.2250738585072014e-308,
    1e-300,
    1e-16,
    1e-12,
    1 - 2**-53,
    1 + 2**-52,
    math.pi,
    HALF_PI,
    3 * math.pi / 2,
    -HALF_PI,
    1e16,
    2.0**31,
    2.0**63,
    float("nan"),
    float("inf"),
    float("-inf"),
]


def flt(v):
    """Source text of a float (exact round trip, nan/inf included)."""
    v = float(v)
    if math.isnan(v):
        return "float('nan')"
    if math.isinf(v):
        return "float('inf')" if v > 0 else "-float('inf')"
    return repr(v)


def values(moderate=False):
    """A float: the special values, any double, or a moderate one."""
    parts = [st.sampled_from(SPECIAL), st.floats(-10.0, 10.0)]
    if not moderate:
        parts.append(st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True))
    return st.one_of(*parts)


@st.composite
def scalar_src(draw, vals=None):
    """Source of one real scalar in some Python/NumPy form."""
    v = draw(vals if vals is not None else values())
    forms = ["float", "float", "f64", "f32", "0d"]
    if math.isfinite(v) and abs(v) < 2.0**64:
        forms += ["int", "i64"] if abs(v) < 2.0**63 else ["int"]
        if v >= 0:
            forms.append("u64")
        if v in (0.0, 1.0):
            forms.append("bool")
    form = draw(st.sampled_from(forms))
    if form in ("int", "i64", "u64", "bool"):
        return {"int": "{}", "i64": "np.int64({})", "u64": "np.uint64({})", "bool": "{!r}"}[form].format(
            bool(v) if form == "bool" else int(v)
        )
    return {"float": "{}", "f64": "np.float64({})", "f32": "np.float32({})", "0d": "np.array({})"}[form].format(flt(v))


DTYPES = ["float64", "float64", "float32", "int64", "uint64", "int8", "bool"]


@st.composite
def array_src(draw, shape, vals=None):
    """Source of an array of ``shape`` in some dtype and layout (C, strided view, transposed)."""
    n = int(np.prod(shape))
    vs = draw(st.lists(vals if vals is not None else values(), min_size=n, max_size=n))
    dtype = draw(st.sampled_from(DTYPES))
    body = "[" + ", ".join(flt(v) for v in vs) + "]"
    if dtype in ("int64", "uint64", "int8", "bool"):
        lim = {"int64": 2.0**62, "uint64": 2.0**63, "int8": 127, "bool": 2}[dtype]
        ok = [v if math.isfinite(v) and abs(v) < lim else 0.0 for v in vs]
        ok = [abs(v) if dtype in ("uint64", "bool") else v for v in ok]
        body = "[" + ", ".join(repr(int(v)) for v in ok) + "]"
    if n == 0:
        return f"np.zeros({shape!r}, dtype='{dtype}')"
    layout = draw(st.sampled_from(["c", "strided", "t"])) if len(shape) >= 1 else "c"
    if layout == "strided" and len(shape) == 1:
        return f"np.repeat(np.array({body}, dtype='{dtype}'), 2)[::2]"
    if layout == "t" and len(shape) == 2:
        return f"np.array({body}, dtype='{dtype}').reshape({shape[1]}, {shape[0]}).T"
    return f"np.array({body}, dtype='{dtype}').reshape({shape!r})"


SHAPES = [(), (), (1,), (3,), (2, 3), (0,), (3, 0)]


@st.composite
def real_args(draw, names, vals=None):
    """Sources for real arguments ``names`` sharing one broadcast shape (each a scalar or an array)."""
    shape = draw(st.sampled_from(SHAPES))
    out = {}
    for name in names:
        v = (vals or {}).get(name)
        if shape == () or draw(st.booleans()):
            out[name] = draw(scalar_src(v))
        else:
            out[name] = draw(array_src(shape, v))
    return out


def evaluate(src):
    """What the library sees: the source evaluated and converted to float64 (None if it cannot be)."""
    with np.errstate(all="ignore"):
        x = eval(src, {"np": np, "pendula": pendula})  # noqa: S307 - our own sources
        try:
            return np.asarray(x, dtype=np.float64)
        except (TypeError, ValueError):
            return None


# ----------------------------------------------------------------- checking results


def reproducer(fn, args, kwargs=None):
    parts = list(args) + [f"{k}={v}" for k, v in (kwargs or {}).items()]
    return f"python -c \"import numpy as np, pendula; print(pendula.{fn}({', '.join(parts)}))\""


ALL_ARG_NAMES = {
    "m",
    "p",
    "phi",
    "u",
    "t",
    "theta0",
    "omega0",
    "w0",
    "gamma",
    "g",
    "length",
    "b",
    "mass",
    "tmax",
    "theta",
    "omega",
    "n",
    "h",
    "rtol",
    "atol",
    "method",
    "max_steps",
    "events",
    "max_events",
    "tol",
    "want",
    "model",
    "setting",
    "scene",
    "models",
    "repeat",
    "rk4_steps",
    "cvode_rtols",
    "arguments",
    "argument",
}


def judge(out, names, checks=None):
    """A problem description for the worker's answer, or None when it is acceptable.
    ``checks(result)`` returns a problem with a successful result, or None."""
    kind = out["kind"]
    if kind == "hang":
        return f"HANG (no answer in {TIMEOUT:g} s)"
    if kind == "signal":
        return f"killed by {out['signal']}"
    if kind == "exit":
        return f"worker exited with status {out['code']}"
    if kind == "exc":
        if out["solver"] and "step budget" in out["message"]:
            return None
        if not out["allowed"]:
            return f"{out['module']}.{out['type']}: {out['message'][:160]}"
        if out["type"] != "NotImplementedError":
            words = set(re.findall(r"[A-Za-z_][A-Za-z_0-9]*", out["message"]))
            if not words & (set(names) | {"arguments", "argument"}):
                return f"{out['type']} names no argument ({sorted(names)}): {out['message'][:160]}"
        return None
    if out["modified"]:
        return f"input modified: {out['modified']}"
    return checks(out["result"]) if checks else None


def nonfinite_problem(label, value, expect_finite, nan_ok):
    """Problem text when ``value`` (an output array) is NaN where no input was NaN, or
    non-finite where ``expect_finite`` (broadcastable mask) holds."""
    v = np.asarray(value)
    if v.dtype.kind not in "fc":
        return None
    exp = np.broadcast_to(expect_finite, v.shape) if np.ndim(expect_finite) <= v.ndim else expect_finite
    nok = np.broadcast_to(nan_ok, v.shape) if np.ndim(nan_ok) <= v.ndim else nan_ok
    bad = (np.isnan(v) & ~nok) | (~np.isfinite(v) & exp)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        return f"{label} = {v.reshape(-1)[i]!r} at element {i}, but the true value is finite"
    return None


class Recorder:
    """Collects failures of one entry point; asserts at the end with one reproducer per line."""

    def __init__(self, name):
        self.name = name
        self.lines = []
        self.calls = 0

    def add(self, problem, fn, args, kwargs=None):
        self.calls += 1
        if problem:
            self.lines.append(f"{problem}\n    {reproducer(fn, args, kwargs)}")

    def verdict(self):
        if self.lines:
            uniq = list(dict.fromkeys(self.lines))
            print(f"\n{self.name}: {len(uniq)} failing call(s) of {self.calls}:\n" + "\n".join(uniq[:40]))
            pytest.fail(f"{self.name}: {len(uniq)} failing call(s) of {self.calls}; first:\n{uniq[0]}", pytrace=False)


def recorded_test(label, run):
    """The test function test_fuzz_<label>: runs the hypothesis-driven
    run(worker, rec) and fails once, listing every reproducer it recorded."""

    def test(worker):
        rec = Recorder(label)
        run(worker, rec)
        rec.verdict()

    test.__name__ = f"test_fuzz_{label}"
    return test
