"""Fuzz leg: every public entry point, adversarial input, each call in a subprocess.

Walks ``pendula.__all__`` (a public name with no fuzz spec fails the coverage
test) and feeds each function hypothesis-drawn arguments: finite and
non-finite, huge (+-1e308, DBL_MAX), tiny, subnormal, -0.0; Python int/bool,
int64/uint64/float32 scalars, 0-d/1-D/2-D arrays, empty arrays, non-contiguous
views.  Each call runs in a persistent worker process (fuzz_worker.py),
restarted when it dies, and a call FAILS on

* death by a signal (segfault, glibc abort) or a hang (no answer in TIMEOUT s);
* an exception other than ValueError/TypeError/NotImplementedError (f2py's
  internal errors, RuntimeError from bad input); PendulaSolverError passes only
  for an exhausted step budget the caller chose;
* a ValueError/TypeError whose message names none of the arguments;
* a non-finite result where the inputs are finite and the true result is
  provably finite (rigorous a-priori bounds per function, e.g. energy decay for
  the damped pendulum), or a NaN where no input is NaN;
* a changed input (arguments are compared with copies taken before the call);
* a wrong answer where an exact oracle exists (equilibria: theta = n pi, kind by parity).

Every failure is printed as a one-line reproducer; the examples of one entry
point all run (no shrinking), so one test lists all its failures at once.
Budget: a fixed max_examples per entry point, derandomized (same examples in
every run); about a minute in all.  The CLI is exercised on a few fixed cases.
"""
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
from hypothesis import HealthCheck, Phase, assume, example, given, settings
from hypothesis import strategies as st

import pendula

HERE = pathlib.Path(__file__).resolve().parent
TIMEOUT = 20.0          # s per call; a hang, not slowness: the slowest legal call here takes < 2 s
BIG = 1e300             # a-priori bounds below this must give finite results
DBL_MAX = float(np.finfo(np.float64).max)
HALF_PI = math.pi / 2   # the double below pi/2: F(HALF_PI | 1) = atanh(sin(HALF_PI)) ~ 38.03 is finite

SETTINGS = settings(derandomize=True, deadline=None, database=None, print_blob=False,
                    phases=[Phase.explicit, Phase.generate],
                    suppress_health_check=list(HealthCheck))


# ----------------------------------------------------------------- the worker

class Worker:
    """A persistent subprocess running fuzz_worker.py; restarted after a death or hang."""

    def __init__(self):
        self.proc = None
        self.stderr_path = None

    def _start(self):
        spec = importlib.util.find_spec("pendula")
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join([str(pathlib.Path(spec.origin).parents[1]),
                                             env.get("PYTHONPATH", "")])
        env.setdefault("MPLBACKEND", "Agg")
        self.stderr_file = open(os.devnull, "wb")
        self.proc = subprocess.Popen([sys.executable, str(HERE / "fuzz_worker.py")], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=self.stderr_file, env=env)

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
        if head is None:                     # no answer in time: a hang
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

SPECIAL = [0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 0.7, 1e308, -1e308, DBL_MAX, -DBL_MAX, 1.34e300, 5e-324, -5e-324,
           2.2250738585072014e-308, 1e-300, 1e-16, 1e-12, 1 - 2**-53, 1 + 2**-52, math.pi, HALF_PI,
           3 * math.pi / 2, -HALF_PI, 1e16, 2.0**31, 2.0**63, float("nan"), float("inf"), float("-inf")]


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
        return {"int": "{}", "i64": "np.int64({})", "u64": "np.uint64({})",
                "bool": "{!r}"}[form].format(bool(v) if form == "bool" else int(v))
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
        x = eval(src, {"np": np, "pendula": pendula})           # noqa: S307 - our own sources
        try:
            return np.asarray(x, dtype=np.float64)
        except (TypeError, ValueError):
            return None


# ----------------------------------------------------------------- checking results

def reproducer(fn, args, kwargs=None):
    parts = list(args) + [f"{k}={v}" for k, v in (kwargs or {}).items()]
    return f"python -c \"import numpy as np, pendula; print(pendula.{fn}({', '.join(parts)}))\""


ALL_ARG_NAMES = {"m", "p", "phi", "u", "t", "theta0", "omega0", "w0", "gamma", "g", "length", "b", "mass",
                 "tmax", "theta", "omega", "n", "h", "rtol", "atol", "method", "max_steps", "events",
                 "max_events", "tol", "want", "model", "setting", "scene", "models", "repeat",
                 "rk4_steps", "cvode_rtols", "arguments", "argument"}


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
            pytest.fail(f"{self.name}: {len(uniq)} failing call(s) of {self.calls}; first:\n{uniq[0]}",
                        pytrace=False)


# ----------------------------------------------------------------- elementwise functions

def _abs(x):
    return np.abs(x)


def _m_energy(theta0, omega0, w0):
    """m = sin^2(theta0/2) + (omega0/(2 w0))^2 (inf when it overflows)."""
    return np.sin(theta0 / 2) ** 2 + (omega0 / (2 * w0)) ** 2


def _ellipf_bound(phi, m):
    # |F(phi|m)| <= |phi| max(1, 1/sqrt(1 - m)) for m < 1; F(phi|1) = atanh(sin phi) for
    # |phi| < pi/2; for m > 1 inside the domain, away from its edge.
    pc = np.where(m < 1, 1 - m, 1.0)
    return np.where(m <= 0, _abs(phi) < BIG,
           np.where(m < 1, _abs(phi) / np.sqrt(pc) < BIG,
           np.where(m == 1, _abs(phi) <= HALF_PI, (m * np.sin(phi) ** 2 <= 0.999) & (_abs(phi) < 1e200))))


def _ellipfm1_bound(phi, p):
    return np.where(p >= 1, _abs(phi) < BIG,
           np.where(p > 0, _abs(phi) / np.sqrt(np.abs(p)) < BIG,
           np.where(p == 0, _abs(phi) <= HALF_PI, ((1 - p) * np.sin(phi) ** 2 <= 0.999) & (_abs(phi) < 1e200))))


def _linear_bounds(t, theta0, omega0, w0, gamma):
    # The energy omega^2/2 + w0^2 theta^2/2 never grows (gamma >= 0): |theta| <= hypot(theta0, omega0/w0).
    ok = (t >= 0) & (w0 > 0) & (gamma >= 0)
    return [ok & (np.hypot(theta0, omega0 / w0) < 1e308), ok & (np.hypot(omega0, w0 * theta0) < 1e308)]


def _envelope_bound(t, theta0, omega0, w0, gamma):
    # R exp(-gamma t/2), R = hypot(theta0, (omega0 + gamma theta0/2)/omega_d), in logs (scaled by 2^-600).
    ok = (t >= 0) & (w0 > 0) & (gamma >= 0)
    r = gamma / (2 * w0)
    wd = w0 * np.sqrt(np.abs((1 - r) * (1 + r)))
    s = 2.0 ** -600
    big_r = np.hypot(theta0 * s, np.abs(omega0 * s + (gamma / 2) * (theta0 * s)) / wd)
    log_env = np.log(big_r) + 600 * math.log(2) - gamma * t / 2
    return [ok & ((r >= 1) | (log_env < math.log(1.7e308)))]


def _undamped_bounds(t, theta0, omega0, w0):
    # |omega| <= |omega0| + 2 w0 (energy), so |theta(t)| <= |theta0| + |t| (|omega0| + 2 w0).
    wmax = _abs(omega0) + 2 * w0
    return [(w0 > 0) & (_abs(theta0) + _abs(t) * wmax < BIG), (w0 > 0) & (wmax < BIG)]


def _small_angle_bounds(t, theta0, omega0, w0):
    # theta0' cos + (omega0/w0) sin(w0 t) about the nearest 2 pi N: |sin(w0 t)/w0| <= |t|.
    return [(w0 > 0) & (_abs(theta0) + 4 + _abs(omega0) * np.minimum(_abs(t), 1 / w0) < BIG),
            (w0 > 0) & (4 * w0 + _abs(omega0) < BIG)]


def _small_angle_error_bounds(tmax, theta0, omega0, w0):
    ok = (_m_energy(theta0, omega0, w0) < 0.999) & (_abs(tmax) * w0 < 1e250) & (w0 > 1e-150) & (w0 < 1e150)
    return [ok, ok]


def _period_bounds(theta0, omega0, w0):
    m = _m_energy(theta0, omega0, w0)
    return [((m < 0.999) | ((m > 1.001) & (m < 1e300))) & (w0 > 1e-290) & (w0 < 1e290)]


ELEMENTWISE = {
    # name: (argument names, mask function -> one mask (or None: unchecked) per output)
    "ellipk": (["m"], lambda m: [m < 1]),
    "ellipkm1": (["p"], lambda p: [p > 0]),
    "ellipe": (["m"], lambda m: [m <= 1]),
    "ellipem1": (["p"], lambda p: [p >= 0]),
    "ellipf": (["phi", "m"], lambda phi, m: [_ellipf_bound(phi, m)]),
    "ellipkinc": (["phi", "m"], lambda phi, m: [_ellipf_bound(phi, m)]),
    "ellipfm1": (["phi", "p"], lambda phi, p: [_ellipfm1_bound(phi, p)]),
    # sn, cn, dn are finite for every finite (u, m); |am'| = |dn| <= sqrt(max(1, 1 - m)).
    "ellipj": (["u", "m"], lambda u, m: [True, True, True, _abs(u) * np.sqrt(np.maximum(1, 1 - m)) < BIG]),
    "ellipjm1": (["u", "p"], lambda u, p: [True, True, True, _abs(u) * np.sqrt(np.maximum(1, p)) < BIG]),
    "small_angle_period": (["w0"], lambda w0: [w0 > 1e-300]),
    "period_series": (["m", "w0"], lambda m, w0: [w0 > 1e-300]),
    "undamped": (["t", "theta0", "omega0", "w0"], _undamped_bounds),
    "small_angle": (["t", "theta0", "omega0", "w0"], _small_angle_bounds),
    "small_angle_error": (["tmax", "theta0", "omega0", "w0"], _small_angle_error_bounds),
    "period": (["theta0", "omega0", "w0"], _period_bounds),
    "amplitude": (["theta0", "omega0", "w0"], lambda theta0, omega0, w0: [_m_energy(theta0, omega0, w0) < 0.999]),
    "elliptic_parameter": (["theta0", "omega0", "w0"],
                           lambda theta0, omega0, w0: [_m_energy(theta0, omega0, w0) < 1e300] * 2),
    "regime": (["theta0", "omega0", "w0"], lambda theta0, omega0, w0: [None]),
    "energy": (["theta", "omega", "w0"], lambda theta, omega, w0: [(_abs(omega) < 1e150) & (_abs(w0) < 1e150)]),
    "linear_damped": (["t", "theta0", "omega0", "w0", "gamma"], _linear_bounds),
    "linear_damped_envelope": (["t", "theta0", "omega0", "w0", "gamma"], _envelope_bound),
}

# Reported reproducers and the values they must give (or a clean refusal).
REPORTED_EXAMPLES = {
    "ellipj": [{"u": "0.7", "m": "1e308"}, {"u": "np.linspace(0.0, 1.0, 64)", "m": "1e308"},
               {"u": "np.linspace(0.0, 1.0, 64)", "m": "'abc'"}, {"u": "np.arange(64.0)", "m": "True"}],
    "ellipjm1": [{"u": "0.7", "p": "-1e308"}, {"u": "0.7", "p": "1.34e300"}],
    "ellipk": [{"m": "[[0.5], [0.25, 0.5]]"}, {"m": "np.timedelta64(1, 's')"}],
    "ellipf": [{"phi": repr(HALF_PI), "m": "1.0"}],
    "ellipfm1": [{"phi": repr(HALF_PI), "p": "1e-300"}, {"phi": repr(3 * math.pi / 2), "p": "1e-300"}],
    "small_angle": [{"t": "1.5", "theta0": "1.0", "omega0": "0.3", "w0": "5e-324"}],
    "linear_damped_envelope": [{"t": "1.5", "theta0": "1.7976931348623157e308", "omega0": "0.5",
                                "w0": "1.4", "gamma": "0.3"}],
}


def check_elementwise(worker, rec, fn, srcs):
    names, masks_of = ELEMENTWISE[fn]
    args = [srcs[n] for n in names]
    out = worker.call(fn, args)

    def checks(result):
        vals = [evaluate(srcs[n]) for n in names]
        if any(v is None for v in vals):
            return f"accepted an argument that is not real: {result!r:.80}"
        try:
            b = np.broadcast_arrays(*vals)
        except ValueError:
            return "accepted arguments that cannot be broadcast together"
        finite_in = np.all([np.isfinite(x) for x in b], axis=0)
        nan_in = np.any([np.isnan(x) for x in b], axis=0)
        with np.errstate(all="ignore"):
            masks = masks_of(**dict(zip(names, b)))
        res = result if isinstance(result, list) else [result]
        for i, (r, m) in enumerate(zip(res, masks)):
            if m is None or isinstance(r, (str, list)):
                continue
            p = nonfinite_problem(f"output {i}", r, np.asarray(m) & finite_in, nan_in)
            if p:
                return p
        return None

    rec.add(judge(out, names, checks), fn, args)


def _elementwise_test(fn):
    names = ELEMENTWISE[fn][0]
    n_examples = 60 if fn in ("undamped", "small_angle_error", "period") else 80

    @settings(SETTINGS, max_examples=n_examples)
    @given(srcs=real_args(names))
    def run(worker, rec, srcs):
        check_elementwise(worker, rec, fn, srcs)

    for ex in REPORTED_EXAMPLES.get(fn, []):
        run = example(srcs=ex)(run)

    def test(worker):
        rec = Recorder(fn)
        run(worker, rec)
        rec.verdict()
    test.__name__ = f"test_fuzz_{fn}"
    return test


for _fn in ELEMENTWISE:
    globals()[f"test_fuzz_{_fn}"] = _elementwise_test(_fn)


# ----------------------------------------------------------------- scalar-parameter functions

def _dict_finite(keys, ok):
    def checks(result):
        if not ok:
            return None
        for k in keys:
            v = result[k] if isinstance(result, dict) else result
            if not np.all(np.isfinite(np.asarray(v))):
                return f"{k} = {v!r} is not finite, but the true value is"
        return None
    return checks


def _scalar_case(worker, rec, fn, srcs, finite_keys, bound):
    names = list(srcs)
    vals = [evaluate(s) for s in srcs.values()]
    ok = all(v is not None and v.ndim == 0 and np.isfinite(v) for v in vals)
    with np.errstate(all="ignore"):
        ok = ok and bool(bound(*[float(v) for v in vals]))
    out = worker.call(fn, list(srcs.values()))
    rec.add(judge(out, names, _dict_finite(finite_keys, ok)), fn, list(srcs.values()))


SCALAR = {
    # name: (argument names, result keys that must be finite, a-priori condition for that)
    "natural_frequency": (["g", "length"], ["w0"],
                          lambda g, l: g > 0 and l > 0 and abs(math.log10(g) - math.log10(l)) < 600),
    "damping_rate": (["b", "mass"], ["gamma"],
                     lambda b, mass: b >= 0 and mass > 0 and (b == 0 or math.log10(b) - math.log10(mass) < 300)),
    "damping_regime": (["w0", "gamma"], ["omega_d", "beta", "decay_slow", "decay_fast", "gamma_critical",
                                         "damping_ratio"],
                       lambda w0, gamma: 1e-150 < w0 < 1e150 and 0 <= gamma < 1e150),
    "rk4_max_stable_step": (["w0", "gamma"], ["h"], lambda w0, gamma: 1e-150 < w0 < 1e150 and 0 <= gamma < 1e150),
}


def _scalar_test(fn):
    names, keys, bound = SCALAR[fn]

    @settings(SETTINGS, max_examples=60)
    @given(srcs=real_args(names))
    def run(worker, rec, srcs):
        _scalar_case(worker, rec, fn, srcs, keys, bound)

    def test(worker):
        rec = Recorder(fn)
        run(worker, rec)
        rec.verdict()
    test.__name__ = f"test_fuzz_{fn}"
    return test


for _fn in SCALAR:
    globals()[f"test_fuzz_{_fn}"] = _scalar_test(_fn)


@st.composite
def int_src(draw):
    """An equilibrium index in some integer (or non-integer) form."""
    n = draw(st.one_of(st.sampled_from([0, 1, -1, 2, 2**31 - 1, 2**31, -2**31, 2**32 + 1, 2**62, 2**63 - 1,
                                        2**63, -2**63, 2**64 - 1, 2**64]), st.integers(-100, 100)))
    kinds = ["py"]
    for dt, lo, hi in (("int8", -128, 127), ("int32", -2**31, 2**31 - 1), ("int64", -2**63, 2**63 - 1),
                       ("uint32", 0, 2**32 - 1), ("uint64", 0, 2**64 - 1)):
        if lo <= n <= hi:
            kinds += [dt, dt + "[]"]
    form = draw(st.sampled_from(kinds + ["float", "bool"]))
    if form == "py":
        return repr(n)
    if form == "float":
        return flt(float(n))
    if form == "bool":
        return repr(n % 2 == 1)
    if form.endswith("[]"):
        return f"np.array([{n}, 3], dtype='{form[:-2]}')"
    return f"np.{form}({n})"


def _equilibria_checks(n_src):
    def checks(result):
        n = eval(n_src, {"np": np})                          # noqa: S307 - our own source
        theta, lam, kind = result
        ns = [int(x) for x in np.asarray(n, dtype=object).reshape(-1)]
        kinds = kind if isinstance(kind, list) else [kind]
        for i, k in enumerate(ns):
            th = float(np.asarray(theta).reshape(-1)[i])
            want = "centre" if k % 2 == 0 else "saddle"
            if kinds[i] != want or abs(th - k * math.pi) > 1e-15 * abs(k * math.pi):
                return f"equilibria(n = {k}) gave theta = {th!r}, kind {kinds[i]!r} (true {k * math.pi!r}, {want!r})"
        return None
    return checks


@settings(SETTINGS, max_examples=60)
@given(n=int_src(), w0=scalar_src(values(moderate=True)))
@example(n="2**63", w0="1.0")
@example(n="2**64 - 1", w0="1.0")
@example(n="np.array([2**64 - 1], dtype='uint64')", w0="1.0")
def _run_equilibria(worker, rec, n, w0):
    out = worker.call("equilibria", [n, w0])
    rec.add(judge(out, ["n", "w0"], _equilibria_checks(n)), "equilibria", [n, w0])


def test_fuzz_equilibria(worker):
    rec = Recorder("equilibria")
    _run_equilibria(worker, rec)
    rec.verdict()


def test_fuzz_no_argument_functions(worker):
    rec = Recorder("no-argument functions")
    for fn in ("build_info", "have_cvode"):
        rec.add(judge(worker.call(fn), []), fn, [])
    rec.verdict()


# ----------------------------------------------------------------- integrators

@st.composite
def grid_src(draw):
    """Source of an output grid t: increasing (short or extreme), or bad (unsorted, NaN, 2-D, empty)."""
    kind = draw(st.sampled_from(["lin", "lin", "lin", "extreme", "bad"]))
    if kind == "lin":
        t0 = draw(st.sampled_from([0.0, -1.0, 5e-324, 1e3]))
        span = draw(st.sampled_from([1.0, 10.0, 1e-300, 5e-324, 0.1]))
        n = draw(st.sampled_from([1, 2, 5]))
        return f"np.linspace({flt(t0)}, {flt(t0 + span)}, {n})"
    if kind == "extreme":
        return draw(st.sampled_from(["[0.0, 1e308]", "[-1e308, 1e308]", "[0.0, 5e-324]", "[1e16, 1e16 + 2]",
                                     "[0.0, 1.0, 1.0 + 2**-52]"]))
    return draw(st.sampled_from(["[1.0, 0.0]", "[0.0, float('nan')]", "[0.0, float('inf')]", "np.zeros((2, 2))",
                                 "np.zeros(0)", "[]", "[[0.0], [1.0, 2.0]]", "'abc'", "np.array([0, 1], dtype='uint64')",
                                 "np.linspace(0.0, 2.0, 9)[::2]"]))


def _span_steps(t_src, w0, gamma, h):
    """(span, rough step count) of an integration; None when the inputs are not a valid grid."""
    t = evaluate(t_src)
    if t is None or t.ndim != 1 or t.size < 1 or not np.all(np.isfinite(t)):
        return None
    with np.errstate(all="ignore"):
        span = float(t[-1] - t[0])
        return span, (span / h if h > 0 else np.inf)


def _integration_checks(ok, theta0, omega0, w0, span):
    def checks(result):
        if not ok:
            return None
        wmax = abs(omega0) + 2 * w0
        if not (abs(theta0) + span * wmax < BIG and wmax < BIG):
            return None
        for key in ("theta", "omega"):
            if not np.all(np.isfinite(result[key])):
                return f"{key} has non-finite values {result[key]!r:.80} though the motion is bounded"
        return None
    return checks


@settings(SETTINGS, max_examples=60)
@given(t=grid_src(), p=real_args(["theta0", "omega0", "w0", "gamma", "h"]))
def _run_rk4(worker, rec, t, p):
    v = {k: evaluate(s) for k, s in p.items()}
    scal = all(x is not None and x.ndim == 0 for x in v.values())
    ok = scal and all(np.isfinite(x) for x in v.values())
    if ok:
        ss = _span_steps(t, float(v["w0"]), float(v["gamma"]), float(v["h"]))
        # 1e6 .. 2e9 steps is accepted work that takes seconds (bounding it is another test's job)
        assume(ss is None or ss[1] < 2e5 or ss[1] > 3e9 or float(v["w0"]) <= 0 or float(v["gamma"]) < 0)
        ok = ss is not None
    args = [t] + [p[k] for k in ("theta0", "omega0", "w0", "gamma", "h")]
    out = worker.call("rk4", args)
    chk = _integration_checks(ok, *(float(v[k]) for k in ("theta0", "omega0", "w0")),
                              _span_steps(t, 1, 0, 1)[0]) if ok else None
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma", "h"], chk), "rk4", args)


def test_fuzz_rk4(worker):
    rec = Recorder("rk4")
    _run_rk4(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=30)
@given(t=grid_src(), p=real_args(["theta0", "omega0", "w0", "gamma", "h"]),
       want=st.sampled_from(["'final'", "'trajectory'", "'period'", "'bogus'"]),
       chunk=st.sampled_from(["1", "7", "4096", "0", "-3", "2**70", "True"]))
def _run_sweep(worker, rec, t, p, want, chunk):
    v = {k: evaluate(s) for k, s in p.items()}
    scal = all(x is not None and x.ndim == 0 for x in v.values())
    ok = scal and all(np.isfinite(x) for x in v.values()) and want in ("'final'", "'trajectory'")
    if ok:
        ss = _span_steps(t, float(v["w0"]), float(v["gamma"]), float(v["h"]))
        assume(ss is None or ss[1] < 2e5 or ss[1] > 3e9 or float(v["w0"]) <= 0 or float(v["gamma"]) < 0)
        ok = ss is not None
    args = [t] + [p[k] for k in ("theta0", "omega0", "w0", "gamma")]
    out = worker.call("sweep", args, {"h": p["h"], "want": want, "chunk_states": chunk})
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma", "h", "want", "chunk_states"]), "sweep", args)


def test_fuzz_sweep(worker):
    rec = Recorder("sweep")
    _run_sweep(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=60)
@given(t=grid_src(), p=real_args(["theta0", "omega0", "w0", "gamma", "rtol", "atol"]),
       method=st.sampled_from(["'adams'", "'bdf'", "'BDF'", "'rk'", "3"]),
       max_steps=st.sampled_from(["1", "1000", "20000", "0", "-5", "2**70", "1.5", "True"]),
       events=st.sampled_from(["False", "True", "1"]),
       max_events=st.sampled_from(["100", "1", "0", "10**8"]))
@example(t="np.linspace(0.0, 10.0, 3)", p={"theta0": "0.0", "omega0": "2.0", "w0": "np.sqrt(2)", "gamma": "0.1",
                                           "rtol": "1e-8", "atol": "0.0"},
         method="'adams'", max_steps="20000", events="False", max_events="100")
@example(t="[0.0, 1e-300]", p={"theta0": "0.0", "omega0": "2.0", "w0": "np.sqrt(2)", "gamma": "0.1",
                               "rtol": "1e-8", "atol": "1e-10"},
         method="'adams'", max_steps="20000", events="False", max_events="100")
def _run_cvode(worker, rec, t, p, method, max_steps, events, max_events):
    v = {k: evaluate(s) for k, s in p.items()}
    ok = all(x is not None and x.ndim == 0 and np.isfinite(x) for x in v.values())
    ss = _span_steps(t, 1, 0, 1)
    if ok and ss is not None:
        # keep the run short: a few hundred periods at most
        assume(not (float(v["w0"]) > 0 and (ss[0] * (float(v["w0"]) + float(v["gamma"])) > 1e3)))
    ok = ok and ss is not None and float(v["rtol"]) >= 1e-14
    args = [t] + [p[k] for k in ("theta0", "omega0", "w0", "gamma")]
    kw = {"rtol": p["rtol"], "atol": p["atol"], "method": method, "max_steps": max_steps, "events": events,
          "max_events": max_events}
    out = worker.call("cvode", args, kw)
    chk = _integration_checks(ok, *(float(v[k]) for k in ("theta0", "omega0", "w0")), ss[0]) if ok else None
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma"] + list(kw), chk), "cvode", args, kw)


def test_fuzz_cvode(worker):
    rec = Recorder("cvode")
    _run_cvode(worker, rec)
    rec.verdict()


# ----------------------------------------------------------------- scenes

SCENE_ARGS = ["theta0", "omega0", "t", "g", "length", "gamma", "mass", "b", "tol", "want"]


@st.composite
def scene_src(draw):
    """(source of a pendula.Scene(...) call, its keyword sources, cheap): cheap when solving it
    takes well under a second (short window in periods, moderate tol), so it may be solved."""
    kw = {"theta0": draw(scalar_src()), "omega0": draw(scalar_src())}
    kw["t"] = draw(st.one_of(grid_src(), st.sampled_from(["None", "2.0", "np.linspace(0.0, 3.0, 4)"])))
    for name in ("g", "length", "gamma", "tol"):
        if draw(st.booleans()):
            kw[name] = draw(scalar_src())
    if draw(st.integers(0, 4)) == 0:
        kw["mass"], kw["b"] = draw(scalar_src()), draw(scalar_src())
    kw["want"] = draw(st.sampled_from(["'state'", "'theta'", "'final'", "'energy'", "'period'", "'events'",
                                       "'nonsense'", "None"]))
    v = {k: evaluate(s) for k, s in kw.items() if k not in ("want", "t")}
    t = evaluate(kw["t"]) if kw["t"] != "None" else np.zeros(1)
    cheap = False
    with np.errstate(all="ignore"):
        if all(x is not None and x.ndim == 0 for x in v.values()) and t is not None and t.size:
            g = float(v.get("g", 9.8))
            length = float(v.get("length", 4.9))
            gamma = float(v["b"] / v["mass"]) if "mass" in v else float(v.get("gamma", 0.0))
            w0 = math.sqrt(g / length) if g > 0 and length > 0 else 0.0
            tend = float(np.max(np.abs(t))) if np.all(np.isfinite(t)) else np.inf
            tol = float(v.get("tol", 1e-6))
            cheap = (tend * (w0 + abs(gamma)) < 300 and 0 < w0 < 1e100 and abs(gamma) < 1e3 * w0 + 1
                     and tol >= 1e-10 and abs(float(v["omega0"])) < 1e3 * w0 + 1)
            cheap = cheap or not (g > 0 and length > 0 and math.isfinite(tend))   # refused up front
    src = "pendula.Scene(" + ", ".join(f"{k}={s}" for k, s in kw.items()) + ")"
    return src, kw, bool(cheap)


def _scene_checks(result):
    # Every quantity the answer holds must be finite: the cheap scenes are bounded motions.
    for key in ("theta", "omega", "energy", "error_estimate"):
        val = result.get(key)
        if val is not None and not np.all(np.isfinite(np.asarray(val, dtype=float))):
            return f"SceneResult.{key} = {val!r:.80} is not finite"
    return None


@settings(SETTINGS, max_examples=60)
@given(sc=scene_src())
@example(sc=("pendula.Scene(theta0=1.0, t=1.0, g=5e-324)", {"theta0": "1.0", "t": "1.0", "g": "5e-324"}, True))
@example(sc=("pendula.Scene(theta0=1.0, t=1.0, length=5e-324)", {"theta0": "1.0", "t": "1.0", "length": "5e-324"},
             True))
def _run_scene(worker, rec, sc):
    src, kw, cheap = sc
    out = worker.call("Scene", [], kw)
    rec.add(judge(out, SCENE_ARGS), "Scene", [], kw)


def test_fuzz_scene(worker):
    rec = Recorder("Scene")
    _run_scene(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=40)
@given(sc=scene_src(), model=st.sampled_from(["None", "'auto'", "'small_angle'", "'exact'", "'linear'", "'rk4'",
                                               "'cvode'", "'bogus'", "3"]))
def _run_solve(worker, rec, sc, model):
    src, kw, cheap = sc
    assume(cheap)
    out = worker.call("solve", [src], {"model": model})
    rec.add(judge(out, SCENE_ARGS + ["scene", "model"], _scene_checks), "solve", [src], {"model": model})


def test_fuzz_solve(worker):
    rec = Recorder("solve")
    _run_solve(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=30)
@given(sc=scene_src(), model=st.sampled_from(["'small_angle'", "'exact'", "'linear'", "'rk4'", "'cvode'", "'auto'"]),
       setting=st.one_of(st.just("None"), scalar_src()))
def _run_model(worker, rec, sc, model, setting):
    src, kw, cheap = sc
    assume(cheap)
    sv = evaluate(setting) if setting != "None" else None
    if model == "'rk4'" and sv is not None and sv.ndim == 0 and 0 < sv < 1e-4:
        assume(False)   # accepted tiny steps are long work, not a defect
    if model == "'cvode'" and sv is not None and sv.ndim == 0 and 0 < sv < 1e-12:
        assume(False)
    out = worker.call("run_model", [src, model, setting])
    rec.add(judge(out, SCENE_ARGS + ["scene", "model", "setting"], _scene_checks), "run_model",
            [src, model, setting])


def test_fuzz_run_model(worker):
    rec = Recorder("run_model")
    _run_model(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=8)
@given(sc=scene_src(), models=st.sampled_from(["None", "['rk4']", "['exact', 'rk4']", "'rk4'", "['bogus']"]),
       rk4_steps=st.sampled_from(["None", "[0.1, 0.05]", "[0.0]", "[float('nan')]", "[]"]),
       repeat=st.sampled_from(["1", "0", "True"]))
def _run_tradeoff(worker, rec, sc, models, rk4_steps, repeat):
    src, kw, cheap = sc
    assume(cheap)
    kwargs = {"models": models, "rk4_steps": rk4_steps, "cvode_rtols": "[1e-4]", "repeat": repeat,
              "max_steps": "20000"}
    out = worker.call("tradeoff", [src], kwargs)
    rec.add(judge(out, SCENE_ARGS + ["scene", "models", "rk4_steps", "repeat", "cvode_rtols"]), "tradeoff",
            [src], kwargs)


def test_fuzz_tradeoff(worker):
    rec = Recorder("tradeoff")
    _run_tradeoff(worker, rec)
    rec.verdict()


# ----------------------------------------------------------------- CLI and coverage

CLI_CASES = [
    ["solve", "--theta0", "1e308", "--t-end", "1", "--n", "3"],
    ["solve", "--theta0", "nan", "--t-end", "1"],
    ["solve", "--theta0", "1", "--t-end", "1", "--g", "5e-324", "--n", "3"],
    ["solve", "--theta0", "1", "--omega0", "-1.7976931348623157e308", "--t-end", "1", "--n", "3"],
    ["solve", "--theta0", "0.5", "--t-end", "5e-324", "--n", "2", "--want", "final"],
    ["period", "--theta0", "3.141592653589793", "1e308", "-1e308", "5e-324"],
    ["tradeoff", "--theta0", "0.5", "--t-end", "2", "--n", "3", "--models", "rk4", "--repeat", "2"],
    ["solve", "--theta0", "0.5", "--t-end", "1", "--csv", "{tmp}/no/such/dir/x.csv"],
]


@pytest.mark.parametrize("argv", CLI_CASES, ids=lambda a: " ".join(a)[:60])
def test_fuzz_cli(argv, tmp_path):
    """`python -m pendula` exits 0 (answer), 1 (solver failure) or 2 (bad value, with a
    message) -- never a traceback or a signal -- and creates no folder it was not asked for."""
    argv = [a.format(tmp=tmp_path) for a in argv]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(pathlib.Path(importlib.util.find_spec("pendula").origin).parents[1]), os.environ.get("PYTHONPATH", "")]))
    line = "python -m pendula " + " ".join(argv)
    try:
        proc = subprocess.run([sys.executable, "-m", "pendula", *argv], capture_output=True, text=True,
                              timeout=60, env=env, cwd=tmp_path)
    except subprocess.TimeoutExpired:
        pytest.fail(f"HANG (60 s): {line}", pytrace=False)
    assert proc.returncode in (0, 1, 2), f"exit {proc.returncode}: {line}\n{proc.stderr[-400:]}"
    assert "Traceback" not in proc.stderr, f"traceback: {line}\n{proc.stderr[-600:]}"
    if proc.returncode:
        assert proc.stderr.strip(), f"exit {proc.returncode} without a message: {line}"
    assert not (tmp_path / "no").exists(), f"created a folder the user did not ask for: {line}"


# Names in pendula.__all__ that are not called: constants, an exception class and
# result containers (their contents are checked through the calls that return them).
NOT_CALLED = {"TURNING_POINT", "ZERO_CROSSING", "PendulaSolverError", "IntegrationResult", "Events",
              "SceneResult", "DampingRegime", "TradeoffTable",
              # batch containers: SceneBatch is built by Scene() with array parameters (fuzzed there)
              "BatchIntegrationResult", "SceneBatch", "SceneBatchResult", "SweepResult"}
FUZZED = (set(ELEMENTWISE) | set(SCALAR) | {"equilibria", "rk4", "cvode", "Scene", "solve", "run_model",
                                            "tradeoff", "build_info", "have_cvode", "sweep"})


def test_fuzz_covers_every_public_name():
    """A new public name must get a fuzz spec (or be listed as not callable)."""
    missing = sorted(set(pendula.__all__) - FUZZED - NOT_CALLED)
    assert not missing, f"public names with no fuzz spec: {missing}"
    for name in NOT_CALLED - {"TURNING_POINT", "ZERO_CROSSING"}:
        assert isinstance(getattr(pendula, name), type), name
