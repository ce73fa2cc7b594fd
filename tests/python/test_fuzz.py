"""Fuzz leg: every public entry point, adversarial input, each call in a subprocess.

This file: the elementwise and scalar functions, equilibria, the CLI and the
coverage of ``pendula.__all__``; test_fuzz_solvers.py: the integrators and
scenes; fuzz_support.py: the worker, argument sources and judge.

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
import subprocess
import sys

import numpy as np
import pytest
from fuzz_support import (  # noqa: F401 (worker: the fixture)
    BIG,
    HALF_PI,
    SETTINGS,
    Recorder,
    array_src,  # noqa: E402
    evaluate,
    flt,
    judge,
    nonfinite_problem,
    real_args,
    recorded_test,
    scalar_src,
    values,
    worker,
)
from hypothesis import example, given, settings
from hypothesis import strategies as st

import pendula

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
    return np.where(
        m <= 0,
        _abs(phi) < BIG,
        np.where(
            m < 1,
            _abs(phi) / np.sqrt(pc) < BIG,
            np.where(m == 1, _abs(phi) <= HALF_PI, (m * np.sin(phi) ** 2 <= 0.999) & (_abs(phi) < 1e200)),
        ),
    )


def _ellipfm1_bound(phi, p):
    return np.where(
        p >= 1,
        _abs(phi) < BIG,
        np.where(
            p > 0,
            _abs(phi) / np.sqrt(np.abs(p)) < BIG,
            np.where(p == 0, _abs(phi) <= HALF_PI, ((1 - p) * np.sin(phi) ** 2 <= 0.999) & (_abs(phi) < 1e200)),
        ),
    )


def _linear_bounds(t, theta0, omega0, w0, gamma):
    # The energy omega^2/2 + w0^2 theta^2/2 never grows (gamma >= 0): |theta| <= hypot(theta0, omega0/w0).
    ok = (t >= 0) & (w0 > 0) & (gamma >= 0)
    return [ok & (np.hypot(theta0, omega0 / w0) < 1e308), ok & (np.hypot(omega0, w0 * theta0) < 1e308)]


def _envelope_bound(t, theta0, omega0, w0, gamma):
    # R exp(-gamma t/2), R = hypot(theta0, (omega0 + gamma theta0/2)/omega_d), in logs (scaled by 2^-600).
    ok = (t >= 0) & (w0 > 0) & (gamma >= 0)
    r = gamma / (2 * w0)
    wd = w0 * np.sqrt(np.abs((1 - r) * (1 + r)))
    s = 2.0**-600
    big_r = np.hypot(theta0 * s, np.abs(omega0 * s + (gamma / 2) * (theta0 * s)) / wd)
    log_env = np.log(big_r) + 600 * math.log(2) - gamma * t / 2
    return [ok & ((r >= 1) | (log_env < math.log(1.7e308)))]


def _undamped_bounds(t, theta0, omega0, w0):
    # |omega| <= |omega0| + 2 w0 (energy), so |theta(t)| <= |theta0| + |t| (|omega0| + 2 w0).
    wmax = _abs(omega0) + 2 * w0
    return [(w0 > 0) & (_abs(theta0) + _abs(t) * wmax < BIG), (w0 > 0) & (wmax < BIG)]


def _small_angle_bounds(t, theta0, omega0, w0):
    # theta0' cos + (omega0/w0) sin(w0 t) about the nearest 2 pi N: |sin(w0 t)/w0| <= |t|.
    return [
        (w0 > 0) & (_abs(theta0) + 4 + _abs(omega0) * np.minimum(_abs(t), 1 / w0) < BIG),
        (w0 > 0) & (4 * w0 + _abs(omega0) < BIG),
    ]


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
    "elliptic_parameter": (
        ["theta0", "omega0", "w0"],
        lambda theta0, omega0, w0: [_m_energy(theta0, omega0, w0) < 1e300] * 2,
    ),
    "regime": (["theta0", "omega0", "w0"], lambda theta0, omega0, w0: [None]),
    "energy": (["theta", "omega", "w0"], lambda theta, omega, w0: [(_abs(omega) < 1e150) & (_abs(w0) < 1e150)]),
    "linear_damped": (["t", "theta0", "omega0", "w0", "gamma"], _linear_bounds),
    "linear_damped_envelope": (["t", "theta0", "omega0", "w0", "gamma"], _envelope_bound),
}

# Reported reproducers and the values they must give (or a clean refusal).
REPORTED_EXAMPLES = {
    "ellipj": [
        {"u": "0.7", "m": "1e308"},
        {"u": "np.linspace(0.0, 1.0, 64)", "m": "1e308"},
        {"u": "np.linspace(0.0, 1.0, 64)", "m": "'abc'"},
        {"u": "np.arange(64.0)", "m": "True"},
    ],
    "ellipjm1": [{"u": "0.7", "p": "-1e308"}, {"u": "0.7", "p": "1.34e300"}],
    "ellipk": [{"m": "[[0.5], [0.25, 0.5]]"}, {"m": "np.timedelta64(1, 's')"}],
    "ellipf": [{"phi": repr(HALF_PI), "m": "1.0"}],
    "ellipfm1": [{"phi": repr(HALF_PI), "p": "1e-300"}, {"phi": repr(3 * math.pi / 2), "p": "1e-300"}],
    "small_angle": [{"t": "1.5", "theta0": "1.0", "omega0": "0.3", "w0": "5e-324"}],
    "linear_damped_envelope": [
        {"t": "1.5", "theta0": "1.7976931348623157e308", "omega0": "0.5", "w0": "1.4", "gamma": "0.3"}
    ],
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

    return recorded_test(fn, run)


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
    "natural_frequency": (
        ["g", "length"],
        ["w0"],
        lambda g, l: g > 0 and l > 0 and abs(math.log10(g) - math.log10(l)) < 600,
    ),
    "damping_rate": (
        ["b", "mass"],
        ["gamma"],
        lambda b, mass: b >= 0 and mass > 0 and (b == 0 or math.log10(b) - math.log10(mass) < 300),
    ),
    "damping_regime": (
        ["w0", "gamma"],
        ["omega_d", "beta", "decay_slow", "decay_fast", "gamma_critical", "damping_ratio"],
        lambda w0, gamma: 1e-150 < w0 < 1e150 and 0 <= gamma < 1e150,
    ),
    "rk4_max_stable_step": (["w0", "gamma"], ["h"], lambda w0, gamma: 1e-150 < w0 < 1e150 and 0 <= gamma < 1e150),
}


def _scalar_test(fn):
    names, keys, bound = SCALAR[fn]

    @settings(SETTINGS, max_examples=60)
    @given(srcs=real_args(names))
    def run(worker, rec, srcs):
        _scalar_case(worker, rec, fn, srcs, keys, bound)

    return recorded_test(fn, run)


for _fn in SCALAR:
    globals()[f"test_fuzz_{_fn}"] = _scalar_test(_fn)


@st.composite
def int_src(draw):
    """An equilibrium index in some integer (or non-integer) form."""
    n = draw(
        st.one_of(
            st.sampled_from(
                [
                    0,
                    1,
                    -1,
                    2,
                    2**31 - 1,
                    2**31,
                    -(2**31),
                    2**32 + 1,
                    2**62,
                    2**63 - 1,
                    2**63,
                    -(2**63),
                    2**64 - 1,
                    2**64,
                ]
            ),
            st.integers(-100, 100),
        )
    )
    kinds = ["py"]
    for dt, lo, hi in (
        ("int8", -128, 127),
        ("int32", -(2**31), 2**31 - 1),
        ("int64", -(2**63), 2**63 - 1),
        ("uint32", 0, 2**32 - 1),
        ("uint64", 0, 2**64 - 1),
    ):
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
        n = eval(n_src, {"np": np})  # noqa: S307 - our own source
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


# ----------------------------------------------------------------- fits

# A clean swing the fit of a motion can start from; the drawn values replace one sample or the noise.
FIT_T = "np.linspace(0.0, 6.0, 40)"
FIT_THETA = "0.5 * np.cos(3.0 * np.linspace(0.0, 6.0, 40))"


@settings(SETTINGS, max_examples=40)
@given(theta0=array_src((4,)), period=array_src((4,)), sigma=scalar_src(values()))
@example(theta0="np.array([0.1, 1.0, 2.0, 3.14159])", period="np.array([2.0, 2.2, 3.0, 30.0])", sigma="5e-324")
def _run_fit_period(worker, rec, theta0, period, sigma):
    kw = {"sigma_period": sigma}
    rec.add(
        judge(worker.call("fit_period", [theta0, period], kw), ["theta0", "period", "sigma_period"]),
        "fit_period",
        [theta0, period],
        kw,
    )


def test_fuzz_fit_period(worker):
    rec = Recorder("fit_period")
    _run_fit_period(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=30)
@given(v=scalar_src(values()), sigma=scalar_src(values()), where=st.sampled_from(["theta", "t", "sigma"]))
def _run_fit_motion(worker, rec, v, sigma, where):
    t, theta = FIT_T, FIT_THETA
    if where == "theta":
        theta = f"np.r_[{FIT_THETA}[:39], np.ravel({v})[:1]]"
    elif where == "t":
        t = f"np.r_[{FIT_T}[:39], np.ravel({v})[:1]]"
    kw = {"sigma": sigma if where == "sigma" else "1e-2"}
    rec.add(judge(worker.call("fit_motion", [t, theta], kw), ["t", "theta", "sigma"]), "fit_motion", [t, theta], kw)


def test_fuzz_fit_motion(worker):
    rec = Recorder("fit_motion")
    _run_fit_motion(worker, rec)
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
    env = dict(
        os.environ,
        PYTHONPATH=os.pathsep.join(
            [str(pathlib.Path(importlib.util.find_spec("pendula").origin).parents[1]), os.environ.get("PYTHONPATH", "")]
        ),
    )
    line = "python -m pendula " + " ".join(argv)
    try:
        proc = subprocess.run(
            [sys.executable, "-m", "pendula", *argv], capture_output=True, text=True, timeout=60, env=env, cwd=tmp_path
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"HANG (60 s): {line}", pytrace=False)
    assert proc.returncode in (0, 1, 2), f"exit {proc.returncode}: {line}\n{proc.stderr[-400:]}"
    assert "Traceback" not in proc.stderr, f"traceback: {line}\n{proc.stderr[-600:]}"
    if proc.returncode:
        assert proc.stderr.strip(), f"exit {proc.returncode} without a message: {line}"
    assert not (tmp_path / "no").exists(), f"created a folder the user did not ask for: {line}"


# Names in pendula.__all__ that are not called: constants, an exception class, a
# warning class and result containers (their contents are checked through the calls that return them).
NOT_CALLED = {
    "TURNING_POINT",
    "ZERO_CROSSING",
    "WELL_NONE",
    "PendulaSolverError",
    "AngleWarning",
    "IntegrationResult",
    "Events",
    "SceneResult",
    "DampingRegime",
    "TradeoffTable",
    # batch containers: SceneBatch is built by Scene() with array parameters (fuzzed there)
    "BatchIntegrationResult",
    "SceneBatch",
    "SceneBatchResult",
    "SweepResult",
    "TaylorResult",
    "TaylorBatchResult",
    # plot helpers (they return a Figure): their bad input is tested in test_motion_plots.py
    "plot_motion",
    "plot_phase_portrait",
    # the fits' result container (checked through fit_period / fit_motion)
    "FitResult",
    # the driven pendulum's drive and result containers (test_fuzz_driven.py fuzzes its functions)
    "Drive",
    "DrivenResult",
    "Section",
    "LyapunovResult",
    "PeriodicOrbits",
    "Basins",
    "UNSETTLED",
    "FAILED",
}
PLOT_HELPERS = {"plot_motion", "plot_phase_portrait"}
FUZZED = (
    set(ELEMENTWISE)
    | set(SCALAR)
    | {
        "equilibria",
        "rk4",
        "cvode",
        "taylor",
        "Scene",
        "solve",
        "run_model",
        "tradeoff",
        "build_info",
        "have_cvode",
        "sweep",
        "fit_period",
        "fit_motion",
        # test_fuzz_driven.py
        "driven",
        "driven_linear",
        "resonance_curve",
        "poincare",
        "bifurcation",
        "lyapunov",
        "periodic_orbits",
        "find_periodic_orbit",
        "basins",
    }
)


def test_fuzz_covers_every_public_name():
    """A new public name must get a fuzz spec (or be listed as not callable)."""
    missing = sorted(set(pendula.__all__) - FUZZED - NOT_CALLED)
    assert not missing, f"public names with no fuzz spec: {missing}"
    for name in NOT_CALLED - {"TURNING_POINT", "ZERO_CROSSING", "WELL_NONE", "UNSETTLED", "FAILED"} - PLOT_HELPERS:
        assert isinstance(getattr(pendula, name), type), name
