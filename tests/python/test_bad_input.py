"""Bad input, everywhere (issue 9): every public function of ``pendula``.

The table ``API`` below has one entry per public callable in ``pendula.__all__``.
Each entry gives a call that must succeed (finite results) and, per argument,
a *kind* (finite real, > 0, >= 0, increasing times, ...).  From the kinds the
test generates the bad inputs: NaN and +-Inf, wrong signs, strings, None,
complex numbers, object and string arrays, arrays with one NaN element, empty
arrays, 2-D arrays where 1-D times are wanted, non-increasing and repeated
times, incompatible shapes, out-of-range choices and counts.  Each must raise
ValueError or TypeError whose message names the argument (or the name the
Fortran core uses for it) -- never a silent NaN, garbage, a crash.  Array
arguments are passed as numpy arrays and compared with copies afterwards: the
library must never modify its input.

Elliptic special functions follow their own documented rule (NaN in -> NaN
out, finite out-of-domain -> ValueError); their entries say so with
``nan="propagate"``.

A new public function without an entry here, or an entry that declares no
checked argument, FAILS ``test_every_public_callable_has_an_entry``: add it to
the table (that is the point).
"""
from __future__ import annotations

import dataclasses
import inspect
import math
import numbers
import re

import numpy as np
import pytest

import pendula
from helpers import HAVE_CVODE

NAN = float("nan")
INF = float("inf")

# ---- argument kinds ---------------------------------------------------------
REAL = "real"          # any finite real (angles, velocities, a time)
POS = "positive"       # finite and > 0 (g, l, m, w0, h, rtol, tol, ...)
NONNEG = "nonneg"      # finite and >= 0 (gamma, b, atol, ...)
TIMES = "times"        # 1-D, non-empty, finite, strictly increasing
CHOICE = "choice"      # a string from a fixed set
COUNT = "count"        # a positive integer
OTHER = "other"        # checked by ``extra`` cases only


@dataclasses.dataclass
class Arg:
    kind: str
    # Names the message may use for this argument instead of the Python name
    # (the Fortran core writes the text's symbols: l, m, ...).
    aliases: tuple = ()
    # Accepts arrays (broadcast elementwise); scalar-only arguments get a
    # 1-element array as a wrong-shape case instead.
    array: bool = False
    # Extra bad values: (value, exception type) or (value, exception type,
    # {other argument: value}) for a case that needs another argument changed.
    extra: tuple = ()
    # Values of a finite real that are out of domain (ValueError).
    out_of_domain: tuple = ()
    # Extreme valid values to try instead of the kind's default set (a step
    # size of 1e-10 s is valid but would take hours of honest work).
    extremes: tuple = None
    # Other arguments to change for every case of this argument (e.g. drop
    # mass and b when trying bad gamma values on a Scene).
    others: dict = dataclasses.field(default_factory=dict)


@dataclasses.dataclass
class Entry:
    valid: dict
    args: dict
    nan: str = "raise"          # "propagate": NaN in -> NaN out (elliptic rule)
    needs_cvode: bool = False
    # Arguments of the signature deliberately not checked, with the reason.
    unchecked: dict = dataclasses.field(default_factory=dict)


# Public names that are not numerical entry points.
NOT_ENTRY_POINTS = {
    "PendulaSolverError": "exception class",
    "TradeoffTable": "result container built by tradeoff() from checked runs",
    "build_info": "no arguments: build configuration",
    "have_cvode": "no arguments: build configuration",
}

# ---- the table ----------------------------------------------------------------
API: dict[str, Entry] = {
    # physics (core)
    "natural_frequency": Entry(
        valid=dict(g=9.8, length=4.9),
        args=dict(g=Arg(POS), length=Arg(POS, aliases=("l",)))),
    "damping_rate": Entry(
        valid=dict(b=0.05, mass=0.1),
        args=dict(b=Arg(NONNEG), mass=Arg(POS, aliases=("m",)))),
    "small_angle_period": Entry(
        valid=dict(w0=1.5),
        args=dict(w0=Arg(POS, array=True))),
    "period_series": Entry(
        valid=dict(m=0.3, w0=1.5),
        args=dict(m=Arg(NONNEG, array=True, out_of_domain=(1 + 2**-52, 1.5, 1e10, 1e300),
                        extremes=(0.0, 5e-324, 1e-300, 1 - 2**-53, 1.0)),
                  w0=Arg(POS, array=True))),
    # linear damped (src/damped, linear.py)
    "linear_damped": Entry(
        valid=dict(t=1.5, theta0=0.1, omega0=0.5, w0=1.4, gamma=0.3),
        args=dict(t=Arg(NONNEG, array=True), theta0=Arg(REAL, array=True), omega0=Arg(REAL, array=True),
                  w0=Arg(POS, array=True), gamma=Arg(NONNEG, array=True))),
    "linear_damped_envelope": Entry(
        valid=dict(t=1.5, theta0=0.1, omega0=0.5, w0=1.4, gamma=0.3),
        args=dict(t=Arg(NONNEG, array=True), theta0=Arg(REAL, array=True), omega0=Arg(REAL, array=True),
                  w0=Arg(POS, array=True), gamma=Arg(NONNEG, array=True))),
    "damping_regime": Entry(
        valid=dict(w0=1.4, gamma=0.3),
        args=dict(w0=Arg(POS), gamma=Arg(NONNEG))),
    # elliptic (src/special, elliptic.py): NaN in -> NaN out, out of domain -> ValueError
    "ellipk": Entry(valid=dict(m=0.7), nan="propagate",
                    args=dict(m=Arg(REAL, array=True, out_of_domain=(1.5, 1 + 2**-52, INF)))),
    "ellipe": Entry(valid=dict(m=0.7), nan="propagate",
                    args=dict(m=Arg(REAL, array=True, out_of_domain=(1.5, 1 + 2**-52, INF)))),
    "ellipkm1": Entry(valid=dict(p=0.3), nan="propagate",
                      args=dict(p=Arg(REAL, array=True, out_of_domain=(-0.5, -5e-324, -INF)))),
    "ellipem1": Entry(valid=dict(p=0.3), nan="propagate",
                      args=dict(p=Arg(REAL, array=True, out_of_domain=(-0.5, -5e-324, -INF)))),
    "ellipf": Entry(valid=dict(phi=1.0, m=0.7), nan="propagate",
                    args=dict(phi=Arg(REAL, array=True), m=Arg(REAL, array=True, out_of_domain=(2.0, INF)))),
    "ellipkinc": Entry(valid=dict(phi=1.0, m=0.7), nan="propagate",
                       args=dict(phi=Arg(REAL, array=True), m=Arg(REAL, array=True, out_of_domain=(2.0, INF)))),
    "ellipfm1": Entry(valid=dict(phi=1.0, p=0.3), nan="propagate",
                      args=dict(phi=Arg(REAL, array=True), p=Arg(REAL, array=True, out_of_domain=(-1.0, -INF)))),
    "ellipj": Entry(valid=dict(u=0.8, m=0.7), nan="propagate",
                    args=dict(u=Arg(REAL, array=True), m=Arg(REAL, array=True))),
    "ellipjm1": Entry(valid=dict(u=0.8, p=0.3), nan="propagate",
                      args=dict(u=Arg(REAL, array=True), p=Arg(REAL, array=True))),
    # integrators (src/integrators, integrate.py)
    "rk4": Entry(
        valid=dict(t=[0.0, 0.5, 1.0, 2.0], theta0=0.0, omega0=2.0, w0=1.4, gamma=0.1, h=0.05),
        args=dict(t=Arg(TIMES), theta0=Arg(REAL), omega0=Arg(REAL),
                  w0=Arg(POS), gamma=Arg(NONNEG),
                  # a step outside RK4's stability region is refused, not integrated into garbage
                  h=Arg(POS, extremes=(1e300, 1e154, 1e-300, 5e-324),
                        extra=((50.0, ValueError, dict(t=np.array([0.0, 100.0]))),)),
                  # a budget below the window's steps is refused up front
                  max_steps=Arg(COUNT, extra=((3, ValueError),)),
                  progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))))),
    "rk4_max_stable_step": Entry(
        valid=dict(w0=1.4, gamma=0.1),
        args=dict(w0=Arg(POS), gamma=Arg(NONNEG))),
    "cvode": Entry(
        valid=dict(t=[0.0, 0.5, 1.0, 2.0], theta0=0.0, omega0=2.0, w0=1.4, gamma=0.1, max_steps=200_000),
        needs_cvode=True,
        args=dict(t=Arg(TIMES), theta0=Arg(REAL), omega0=Arg(REAL), w0=Arg(POS), gamma=Arg(NONNEG),
                  rtol=Arg(POS), atol=Arg(NONNEG), method=Arg(CHOICE),
                  max_steps=Arg(COUNT, extra=((3, pendula.PendulaSolverError,
                                               dict(t=np.array([0.0, 100.0]))),)),
                  events=Arg(OTHER, extra=(("yes", TypeError), (None, TypeError), (1.0, TypeError))),
                  # max_events matters only with events=True
                  max_events=Arg(OTHER, extra=(
                      (0, ValueError, dict(events=True)), (-1, ValueError, dict(events=True)),
                      (2.5, TypeError, dict(events=True)), ("7", TypeError, dict(events=True)),
                      (2**40, ValueError, dict(events=True)))),
                  progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))))),
    # undamped (src/undamped, undamped.py): any real t, any real state, w0 > 0
    "undamped": Entry(valid=dict(t=1.3, theta0=1.0, omega0=0.2, w0=1.4), args=dict(
        t=Arg(REAL, array=True), theta0=Arg(REAL, array=True), omega0=Arg(REAL, array=True),
        w0=Arg(POS, array=True))),
    "small_angle": Entry(valid=dict(t=1.3, theta0=0.1, omega0=0.2, w0=1.4), args=dict(
        t=Arg(REAL, array=True), theta0=Arg(REAL, array=True), omega0=Arg(REAL, array=True),
        w0=Arg(POS, array=True))),
    "small_angle_error": Entry(valid=dict(tmax=10.0, theta0=0.1, omega0=0.2, w0=1.4), args=dict(
        tmax=Arg(REAL, array=True), theta0=Arg(REAL, array=True), omega0=Arg(REAL, array=True),
        w0=Arg(POS, array=True))),
    **{name: Entry(valid=dict(theta0=1.0, omega0=0.2, w0=1.4), args=dict(
        theta0=Arg(REAL, array=True), omega0=Arg(REAL, array=True), w0=Arg(POS, array=True)))
       for name in ("period", "amplitude", "elliptic_parameter", "regime")},
    "energy": Entry(valid=dict(theta=1.0, omega=0.2, w0=1.4), args=dict(
        theta=Arg(REAL, array=True), omega=Arg(REAL, array=True), w0=Arg(POS, array=True))),
    "equilibria": Entry(valid=dict(n=3, w0=1.4), args=dict(
        n=Arg(OTHER, extra=((1.5, TypeError), ("1", TypeError), (None, TypeError), (True, TypeError),
                            (np.array([1.0, 2.0]), TypeError), (1 + 1j, TypeError), (2**40, ValueError),
                            (np.array([[1, 2]]), ValueError, dict(w0=np.array([1.0, 2.0, 3.0]))))),
        w0=Arg(POS, array=True))),
    # scenes (src/scene, scene.py)
    "Scene": Entry(
        valid=dict(theta0=0.3, omega0=0.1, t=[0.0, 1.0, 2.0], g=9.8, length=4.9, mass=0.1, b=0.01,
                   tol=1e-6, want="state"),
        args=dict(theta0=Arg(REAL), omega0=Arg(REAL), g=Arg(POS), length=Arg(POS, aliases=("l",)),
                  mass=Arg(POS, aliases=("m",)), b=Arg(NONNEG), tol=Arg(POS), want=Arg(CHOICE),
                  gamma=Arg(NONNEG, others=dict(mass=None, b=None)),
                  t=Arg(TIMES, extra=((np.array([-1.0, 0.0, 1.0]), ValueError), (np.array([]), ValueError))))),
    "solve": Entry(
        valid=dict(scene="SCENE", model=None),
        args=dict(scene=Arg(OTHER, extra=(("scene", TypeError), (None, TypeError), (1.0, TypeError))),
                  model=Arg(CHOICE, extra=(("exact", ValueError, dict(scene="DAMPED")),)),
                  max_steps=Arg(COUNT),
                  progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))))),
    "run_model": Entry(
        valid=dict(scene="SCENE", model="rk4", setting=0.01),
        args=dict(scene=Arg(OTHER, extra=(("scene", TypeError), (None, TypeError))),
                  model=Arg(CHOICE, extra=(("auto", ValueError),)),
                  setting=Arg(POS, aliases=("h",), extremes=(1e300, 1e154, 1e-300, 5e-324)),
                  max_steps=Arg(COUNT, extra=((3, ValueError),)),
                  progress=Arg(OTHER, extra=(("yes", TypeError), (1.0, TypeError))))),
    "tradeoff": Entry(
        valid=dict(scene="SCENE", models=["small_angle", "rk4"], rk4_steps=[0.1, 0.05], cvode_rtols=[1e-6],
                   repeat=1),
        args=dict(scene=Arg(OTHER, extra=(("scene", TypeError), (None, TypeError))),
                  models=Arg(OTHER, extra=((["nope"], ValueError), (["linear"], ValueError), ("rk4", ValueError))),
                  rk4_steps=Arg(OTHER, extra=(([NAN], ValueError), ([-0.1], ValueError), ([0.0], ValueError))),
                  cvode_rtols=Arg(OTHER, extra=(
                      (([NAN], ValueError, dict(models=["cvode"])), ([-1e-6], ValueError, dict(models=["cvode"])))
                      if HAVE_CVODE else ())),
                  repeat=Arg(COUNT),
                  # max_steps bounds the automatic RK4 sweep (rk4_steps=None)
                  max_steps=Arg(COUNT, others=dict(rk4_steps=None))),
        unchecked=dict(csv="output path (file I/O)", plot="output path (file I/O)")),
}


# ---- helpers --------------------------------------------------------------------


def _public_callables():
    out = {}
    for name in pendula.__all__:
        obj = getattr(pendula, name)
        # Result records (dataclasses) carry no checks of their own.
        if inspect.isclass(obj) and dataclasses.is_dataclass(obj):
            continue
        if callable(obj) and name not in NOT_ENTRY_POINTS:
            out[name] = obj
    return out


def _walk_numbers(result):
    """Every float/complex found in a result (arrays, tuples, dicts, objects)."""
    if result is None or isinstance(result, (str, bytes, bool)):
        return
    if isinstance(result, numbers.Number):
        yield result
    elif isinstance(result, np.ndarray):
        if result.dtype.kind in "fc":
            yield from result.ravel().tolist()
        elif result.dtype == object:
            for x in result.ravel():
                yield from _walk_numbers(x)
    elif isinstance(result, dict):
        for v in result.values():
            yield from _walk_numbers(v)
    elif isinstance(result, (list, tuple)):
        for v in result:
            yield from _walk_numbers(v)
    elif dataclasses.is_dataclass(result):
        for f in dataclasses.fields(result):
            yield from _walk_numbers(getattr(result, f.name))
    elif hasattr(result, "__dict__"):
        for k, v in vars(result).items():
            if not k.startswith("_"):
                yield from _walk_numbers(v)


def _all_nan(result):
    vals = list(_walk_numbers(result))
    return bool(vals) and all(isinstance(v, numbers.Number) and v != v for v in vals)


def _snapshot(kwargs):
    # zero-stride views of 2**31 elements are read-only and never copied
    return {k: np.array(v, copy=True) for k, v in kwargs.items()
            if isinstance(v, np.ndarray) and v.size < 10**6}


def _assert_unmodified(kwargs, snap):
    for k, before in snap.items():
        after = kwargs[k]
        assert after.shape == before.shape and after.dtype == before.dtype, \
            f"argument {k} changed shape/dtype in the call"
        if before.dtype.kind in "fc":
            assert np.array_equal(after, before, equal_nan=True), f"argument {k} was modified in place"
        else:
            assert all(a is b or a == b for a, b in zip(after.ravel(), before.ravel())), \
                f"argument {k} was modified in place"


def _as_array_arg(value):
    if isinstance(value, np.ndarray):
        return value
    return np.array([value, value], dtype=float)


# ---- case generation ----------------------------------------------------------------
@dataclasses.dataclass
class Case:
    func: str
    arg: str
    label: str
    value: object
    expect: object          # exception type, or "nan" (NaN out), or "error-or-empty"
    others: dict = dataclasses.field(default_factory=dict)   # overrides of other args

    @property
    def id(self):
        return f"{self.func}-{self.arg}-{self.label}"


class _Obj:
    pass


def _defaults(fname):
    sig = inspect.signature(getattr(pendula, fname))
    return {p.name: p.default for p in sig.parameters.values() if p.default is not p.empty}


def _cases_for(fname, entry):
    cases = []
    defaults = _defaults(fname) if hasattr(pendula, fname) else {}
    for aname, spec in entry.args.items():
        v = entry.valid[aname] if aname in entry.valid else defaults.get(aname)
        add = lambda label, value, expect, others=None: cases.append(  # noqa: E731
            Case(fname, aname, label, value, expect, {**spec.others, **(others or {})}))
        if v is None:
            v = 1.0   # an optional real left at None in the valid call
        if spec.kind in (REAL, POS, NONNEG, TIMES):
            # non-finite values
            if spec.kind == TIMES:
                base = np.asarray(v, dtype=float)
                for label, bad in (("nan", NAN), ("inf", INF), ("-inf", -INF)):
                    t = base.copy()
                    t[-1] = bad
                    add(label, t, ValueError)
            else:
                nan_expect = "nan" if entry.nan == "propagate" else ValueError
                add("nan", NAN, nan_expect)
                # Elliptic rule: +-Inf is either out of domain (ValueError) or
                # has a defined value; never NaN.
                if INF not in spec.out_of_domain:
                    add("inf", INF, ValueError if entry.nan == "raise" else "error-or-defined")
                if -INF not in spec.out_of_domain:
                    add("-inf", -INF, ValueError if entry.nan == "raise" else "error-or-defined")
                if spec.array:
                    add("array-with-nan", np.array([v, NAN]), "nan-element" if entry.nan == "propagate"
                        else ValueError)
                    add("array-with-inf", np.array([v, INF]), ValueError if entry.nan == "raise"
                        else "error-or-defined")
                    add("empty-array", np.array([], dtype=float), "error-or-empty")
                    add("object-array", np.array([v, _Obj()], dtype=object), TypeError)
                    add("string-array", np.array(["1.0", "2.0"]), TypeError)
                    add("complex-array", np.array([v + 1j, v]), TypeError)
                else:
                    add("1-element-array", np.array([v]), (ValueError, TypeError))
                    add("2-element-array", np.array([v, v]), (ValueError, TypeError))
            # wrong signs
            if spec.kind == POS:
                add("zero", 0.0, ValueError)
                add("negative", -abs(v) if v else -1.0, ValueError)
                add("-0.0", -0.0, ValueError)
            elif spec.kind == NONNEG:
                add("negative", -1.0, ValueError)
                add("tiny-negative", -5e-324, ValueError)
            for i, bad in enumerate(spec.out_of_domain):
                add(f"out-of-domain-{i}", bad, ValueError)
            # wrong types
            add("string", "1.0", TypeError)
            if defaults.get(aname, "") is not None:   # None is valid for optional arguments
                add("None", None, TypeError)
            add("complex", complex(float(np.ravel(v)[0]), 1.0), TypeError)
            add("object", _Obj(), TypeError)
            add("list-of-strings", ["a", "b"], TypeError)
            # one validation path: the same answer on every route (scalar, array, plan)
            x = float(np.ravel(v)[0])
            add("ragged", [[x], [x, x]], ValueError)
            add("timedelta64", np.timedelta64(1, "s"), TypeError)
            add("datetime64", np.datetime64("2020-01-01"), TypeError)
            add("bool", True, TypeError)
            add("numpy-bool", np.bool_(False), TypeError)
            if spec.array or spec.kind == TIMES:
                add("bool-array", np.array([True, False] * 40), TypeError)
                add("timedelta-array", np.array([1, 2], dtype="m8[s]"), TypeError)
                # f2py passes sizes as 4-byte integers: a clear refusal, not a wrapped size
                # (a zero-stride view: no 2**31 elements are ever allocated)
                add("2**31-elements", np.broadcast_to(np.float64(x), (2**31 + 8,)), ValueError)
            if spec.kind == TIMES:
                base = np.asarray(v, dtype=float)
                add("empty", np.array([], dtype=float), ValueError)
                rep = base.copy()
                rep[-1] = rep[-2]
                add("repeated", rep, ValueError)
                add("decreasing", base[::-1].copy(), ValueError)
                add("2-D", np.stack([base, base + 1]), ValueError)
        elif spec.kind == CHOICE:
            add("unknown", "no-such-choice", ValueError)
            if defaults.get(aname, "") is not None:
                add("None", None, (TypeError, ValueError))
            add("number", 1.0, (TypeError, ValueError))
        elif spec.kind == COUNT:
            add("zero", 0, ValueError)
            add("negative", -3, ValueError)
            add("float", 2.5, (TypeError, ValueError))
            add("string", "10", TypeError)
            if defaults.get(aname, "") is not None:
                add("None", None, TypeError)
        for i, ex in enumerate(spec.extra):
            add(f"extra-{i}", ex[0], ex[1], ex[2] if len(ex) > 2 else None)
    # incompatible shapes between two array arguments
    arr = [a for a, s in entry.args.items() if s.array and s.kind in (REAL, POS, NONNEG)]
    if len(arr) >= 2:
        a, b = arr[:2]
        cases.append(Case(fname, a, f"shape-mismatch-with-{b}",
                          np.full(2, entry.valid[a], dtype=float), ValueError,
                          {b: np.full(3, entry.valid[b], dtype=float)}))
    return cases


ALL_CASES = [c for f, e in API.items() for c in _cases_for(f, e)]


_PLACEHOLDERS = {
    "SCENE": lambda: pendula.Scene(theta0=0.3, omega0=0.1, t=np.linspace(0.0, 2.0, 5), tol=1e-6),
    "DAMPED": lambda: pendula.Scene(theta0=0.3, omega0=0.1, t=np.linspace(0.0, 2.0, 5), gamma=0.1, tol=1e-6),
}


def _materialise(v):
    """Lists of numbers in the table become float arrays (to check they stay unmodified)."""
    if isinstance(v, (list, tuple)) and all(isinstance(x, numbers.Real) for x in v):
        return np.array(v, dtype=float)
    return v


def _call(fname, kwargs):
    for k, v in list(kwargs.items()):
        if isinstance(v, str) and v in _PLACEHOLDERS:
            kwargs[k] = _PLACEHOLDERS[v]()
    return getattr(pendula, fname)(**kwargs)


def _skip_if_unavailable(entry):
    if entry.needs_cvode and not HAVE_CVODE:
        pytest.skip("CVODE not built")


# ---- the tests -------------------------------------------------------------------------
def test_every_public_callable_has_an_entry():
    public = _public_callables()
    missing = sorted(set(public) - set(API))
    assert not missing, ("public functions without a bad-input entry in "
                         f"tests/python/test_bad_input.py: {missing}")
    stale = sorted(set(API) - set(public))
    assert not stale, f"table entries that are not public callables: {stale}"
    for name, entry in API.items():
        assert entry.args, f"{name}: an entry must declare at least one checked argument"
        sig = inspect.signature(public[name])
        params = {p.name for p in sig.parameters.values()
                  if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)}
        unknown = set(entry.args) - params
        assert not unknown, f"{name}: table names arguments it does not have: {unknown}"
        # Every real-valued or array parameter must be checked (or excused).
        for p in sig.parameters.values():
            if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                continue
            if p.name in entry.args or p.name in entry.unchecked:
                continue
            d = p.default
            assert d is None or isinstance(d, (bool, str)), (
                f"{name}({p.name}=...) has no entry in the bad-input table "
                "(add it to args, or to unchecked with a reason)")


@pytest.mark.parametrize("fname", sorted(API))
def test_valid_call_gives_finite_results_and_keeps_inputs(fname):
    entry = API[fname]
    _skip_if_unavailable(entry)
    kwargs = {k: _materialise(v) for k, v in entry.valid.items()}
    snap = _snapshot(kwargs)
    result = _call(fname, kwargs)
    _assert_unmodified(kwargs, snap)
    vals = list(_walk_numbers(result))
    is_text = isinstance(result, str) or (isinstance(result, np.ndarray) and result.dtype.kind in "UO")
    assert vals or is_text, f"{fname}: the valid call returned no numbers"
    assert all(np.isfinite(v) for v in vals), f"{fname}: the valid call returned non-finite values"
    # Array variants of array arguments: broadcasting keeps them untouched too.
    for aname, spec in entry.args.items():
        if spec.array:
            kw = dict(kwargs)
            kw[aname] = _as_array_arg(entry.valid[aname])
            snap = _snapshot(kw)
            res = _call(fname, kw)
            _assert_unmodified(kw, snap)
            assert all(np.isfinite(v) for v in _walk_numbers(res))


def _names_argument(msg, aname, spec):
    low = msg.lower()
    names = (aname,) + tuple(spec.aliases)
    for n in names:
        if re.search(r"(?<![A-Za-z0-9_])" + re.escape(n.lower()) + r"(?![A-Za-z0-9_])", low):
            return True
    return False


@pytest.mark.parametrize("case", ALL_CASES, ids=[c.id for c in ALL_CASES])
def test_bad_input(case):
    entry = API[case.func]
    _skip_if_unavailable(entry)
    spec = entry.args[case.arg]
    kwargs = {k: _materialise(v) for k, v in entry.valid.items()}
    kwargs.update(case.others)
    kwargs[case.arg] = case.value
    snap = _snapshot(kwargs)
    expect = case.expect
    if expect == "nan":
        result = _call(case.func, kwargs)
        assert _all_nan(result), f"{case.id}: NaN in must give NaN out, got {result!r}"
    elif expect == "nan-element":
        result = _call(case.func, kwargs)
        arr = np.asarray(result, dtype=float)
        assert np.isnan(arr[..., 1]).all() and np.isfinite(arr[..., 0]).all(), \
            f"{case.id}: NaN element must give NaN only there, got {result!r}"
    elif expect == "error-or-empty":
        try:
            result = _call(case.func, kwargs)
        except ValueError as exc:
            assert _names_argument(str(exc), case.arg, spec), \
                f"{case.id}: message does not name {case.arg!r}: {exc}"
        else:
            vals = list(_walk_numbers(result))
            assert not vals or all(np.isfinite(v) for v in vals)
            arrs = [np.asarray(r) for r in (result if isinstance(result, tuple) else (result,))]
            assert any(a.size == 0 for a in arrs), \
                f"{case.id}: empty input must give an empty result or ValueError, got {result!r}"
    elif expect == "error-or-defined":
        try:
            result = _call(case.func, kwargs)
        except ValueError as exc:
            assert _names_argument(str(exc), case.arg, spec), \
                f"{case.id}: message does not name {case.arg!r}: {exc}"
        else:
            vals = list(_walk_numbers(result))
            assert vals and not any(v != v for v in vals), \
                f"{case.id}: must raise ValueError or give a defined (non-NaN) value, got {result!r}"
    else:
        exc_types = expect
        with pytest.raises(exc_types) as info:
            result = _call(case.func, kwargs)
            pytest.fail(f"{case.id}: no exception, returned {result!r}")  # pragma: no cover
        msg = str(info.value)
        if case.arg in case.others or case.label.startswith("shape-mismatch"):
            assert _names_argument(msg, case.arg, spec) or "shape" in msg.lower() or "broadcast" in msg.lower()
        else:
            assert _names_argument(msg, case.arg, spec), \
                f"{case.id}: message does not name {case.arg!r}: {msg!r}"
    _assert_unmodified(kwargs, snap)


# ---- extreme but valid values -------------------------------------------------------------------
EXTREMES = {
    REAL: (1e300, -1e300, 1e-300, -5e-324, 1e20),
    POS: (1e-300, 5e-324, 1e300, 1e154, 1e-10, 1e10),
    NONNEG: (0.0, 5e-324, 1e300, 1e10),
}
EXTREME_CASES = [(f, a, x) for f, e in API.items() for a, spec in e.args.items()
                 for x in (spec.extremes if spec.extremes is not None else EXTREMES.get(spec.kind, ()))
                 if x not in spec.out_of_domain]
# A number printed without its exponent letter ("1.00000+300", Fortran's Ew.d
# for 3-digit exponents) is garbage in a message.
_MANGLED = re.compile(r"\d[+-]\d{3}(?![\d.])")


@pytest.mark.parametrize("fname, arg, value", EXTREME_CASES,
                         ids=[f"{f}-{a}-{x!r}" for f, a, x in EXTREME_CASES])
def test_extreme_valid_values(fname, arg, value):
    """Huge, tiny and subnormal values inside the domain: a result without NaN,
    or a clear error (ValueError naming the argument, or PendulaSolverError
    when an integrator cannot do it) -- never a silent NaN."""
    entry = API[fname]
    _skip_if_unavailable(entry)
    kwargs = {k: _materialise(v) for k, v in entry.valid.items()}
    kwargs.update(entry.args[arg].others)
    kwargs[arg] = value
    try:
        result = _call(fname, kwargs)
    except ValueError as exc:
        msg = str(exc)
        assert not _MANGLED.search(msg), f"{fname}({arg}={value!r}): mangled number in message: {msg}"
        # Scene(g=5e-324) said "w0 = 0 is out of range": a refusal names what was given
        assert _names_argument(msg, arg, entry.args[arg]), f"{fname}({arg}={value!r}): {msg}"
    except pendula.PendulaSolverError as exc:
        msg = str(exc)
        assert not _MANGLED.search(msg), f"{fname}({arg}={value!r}): mangled number in message: {msg}"
    else:
        vals = list(_walk_numbers(result))
        nan = [v for v in vals if v != v]
        assert not nan, f"{fname}({arg}={value!r}): silent NaN in the result {result!r}"


def test_case_count_report():
    """Not a check of the library: records how much this file tries."""
    n_entry = len(API)
    n_cases = len(ALL_CASES)
    print(f"\nbad-input table: {n_entry} entry points, {n_cases} bad inputs, "
          f"{len(EXTREME_CASES)} extreme valid values")
    assert n_cases >= 10 * n_entry


# ---- the Fortran API (`use pendula`): every non-elemental procedure reports a status -----------------------------
# House rule: non-elemental Fortran procedures take a type(status_t) argument
# (message naming the argument and its range).  Elemental procedures cannot
# carry one and follow their documented value rule (NaN in -> NaN out, or a
# documented limit), which the concern tests check.  Exemptions, with reasons:
FORTRAN_NO_STATUS = {
    # total functions of integer codes / no arguments
    "cancel_requested": "total: reads the cancel flag of a control array",
    "add_progress": "total: adds to the progress counter of a control array",
    "rk4_batch_openmp": "no arguments (build constant)",
    "code_name": "total function of a status code",
    "regime_name": "total function of a regime code",
    "equilibrium_type_name": "total function of a type code",
    "undamped_regime_name": "total function of a regime code",
    "scene_model_code": "total function of a name", "scene_model_name": "total function of a code",
    "scene_want_code": "total function of a name", "scene_want_name": "total function of a code",
    "cvode_available": "no arguments",
    # the elliptic functions' own rule (NaN in -> NaN out, out of domain -> NaN; Python raises)
    "ellipj_plan": "elliptic rule", "ellipj_planm1": "elliptic rule",
    # whether a Jacobi plan pays off: a total decision on (m, n) for any m and n
    "ellipj_plan_pays": "total decision", "ellipjm1_plan_pays": "total decision",
    # documented unchecked kernels with a checked entry point (reported to their concerns)
    "linear_eigenvalues": "helper of rk4_max_stable_step on checked inputs",
}


def _fortran_public_procedures():
    """(file, name, info) for every procedure that `use pendula` exports: the
    union of the public lists of the modules the umbrella uses (facades such as
    pendula_integrators re-export their modules' names)."""
    from test_threads import _logical_lines
    files = sorted(p for p in (ROOT / "src").rglob("*") if p.suffix in (".f90", ".F90"))
    parsed = {f: _logical_lines(f.read_text()) for f in files}
    module_file, public_of = {}, {}
    for f, lines in parsed.items():
        mod = None
        for _, st in lines:
            m = re.match(r"module\s+(?!procedure)(\w+)\s*$", st, re.I)
            if m:
                mod = m.group(1).lower()
                module_file.setdefault(mod, set()).add(f)   # pendula_cvode has a stub twin
                public_of.setdefault(mod, set())
            m = re.match(r"public\s*::\s*(.*)", st, re.I)
            if m and mod:
                public_of[mod] |= {x.strip().lower() for x in m.group(1).split(",")}
    umbrella = [re.match(r"use\s+(\w+)", st, re.I).group(1).lower()
                for _, st in parsed[ROOT / "src" / "pendula.f90"] if re.match(r"use\s+\w+", st, re.I)]
    exported = set().union(*(public_of.get(m, set()) for m in umbrella))
    out = []
    for f, lines in parsed.items():
        cur = None
        procs = {}
        for _, st in lines:
            low = st.lower()
            m = re.match(r"((?:(?:pure|elemental|impure|recursive|module)\s+)*)"
                         r"(?:(?:real|integer|logical|character|type|class|complex)\b[^:]*?\s+)?"
                         r"(subroutine|function)\s+(\w+)\s*\(", low)
            if m and not low.startswith("end"):
                cur = m.group(3)
                procs[cur] = {"elemental": "elemental" in m.group(1), "status": False}
                continue
            if cur and re.match(r"(type|class)\s*\(\s*status_t\s*\)", low):
                procs[cur]["status"] = True
            if re.match(r"end\s*(subroutine|function)\b", low):
                cur = None
        mods_here = {m for m, fs in module_file.items() if f in fs}
        for name in sorted(exported & set(procs)):
            if any(name in public_of[m] for m in mods_here):
                out.append((f.relative_to(ROOT), name, procs[name]))
    return out


ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]


@pytest.mark.skipif(not (ROOT / "src").is_dir(), reason="needs the source tree")
def test_fortran_public_procedures_report_a_status():
    procs = _fortran_public_procedures()
    assert len(procs) > 20, "the scan of src/ found too few public procedures"
    bad = [f"{path}: {name}" for path, name, p in procs
           if not p["elemental"] and not p["status"] and name not in FORTRAN_NO_STATUS
           and not str(path).endswith("pendula_status.f90")]
    assert not bad, ("public non-elemental Fortran procedures without a type(status_t) argument "
                     "(add one, or an exemption with its reason to FORTRAN_NO_STATUS):\n" + "\n".join(bad))
    uniq = {name: p for _, name, p in procs}   # the CVODE stub twin defines the same names
    print(f"\nFortran API (use pendula): {len(uniq)} procedures, "
          f"{sum(1 for p in uniq.values() if p['status'])} with a status, "
          f"{sum(1 for p in uniq.values() if p['elemental'])} elemental")
