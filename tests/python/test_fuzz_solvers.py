"""Fuzz leg, the solvers: rk4, sweep, cvode, taylor, Scene, solve, run_model and tradeoff on
adversarial input, each call in a subprocess (what fails a call: see test_fuzz.py)."""

import math

import numpy as np
from fuzz_support import BIG, SETTINGS, Recorder, evaluate, flt, judge, real_args, scalar_src, values, worker  # noqa: F401 (worker: the fixture)
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

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
        return draw(
            st.sampled_from(
                ["[0.0, 1e308]", "[-1e308, 1e308]", "[0.0, 5e-324]", "[1e16, 1e16 + 2]", "[0.0, 1.0, 1.0 + 2**-52]"]
            )
        )
    return draw(
        st.sampled_from(
            [
                "[1.0, 0.0]",
                "[0.0, float('nan')]",
                "[0.0, float('inf')]",
                "np.zeros((2, 2))",
                "np.zeros(0)",
                "[]",
                "[[0.0], [1.0, 2.0]]",
                "'abc'",
                "np.array([0, 1], dtype='uint64')",
                "np.linspace(0.0, 2.0, 9)[::2]",
            ]
        )
    )


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
    chk = (
        _integration_checks(ok, *(float(v[k]) for k in ("theta0", "omega0", "w0")), _span_steps(t, 1, 0, 1)[0])
        if ok
        else None
    )
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma", "h"], chk), "rk4", args)


def test_fuzz_rk4(worker):
    rec = Recorder("rk4")
    _run_rk4(worker, rec)
    rec.verdict()


_DRIVES = [
    "pendula.Drive('torque', 1.15, 2/3)",
    "pendula.Drive('pivot', 0.1, 20.0, 0.5)",
    "[pendula.Drive('torque', 1.15, 2/3), pendula.Drive('pivot', 0.1, 20.0)]",
    "np.array([pendula.Drive('torque', 0.5, 1.0)] * 3, dtype=object)",
    "'torque'",
    "[1.0, 2.0]",
]


@settings(SETTINGS, max_examples=40)
@given(
    t=grid_src(),
    p=real_args(["theta0", "omega0", "w0", "gamma", "h"]),
    fn=st.sampled_from(["rk4", "cvode"]),
    drive=st.sampled_from(_DRIVES),
)
def _run_driven_integrator(worker, rec, t, p, fn, drive):
    v = {k: evaluate(s) for k, s in p.items()}
    if all(x is not None and x.ndim == 0 and np.isfinite(x) for x in v.values()):
        ss = _span_steps(t, float(v["w0"]), float(v["gamma"]), float(v["h"]))
        # a long accepted window is seconds of honest work (bounding it is another test's job)
        assume(ss is None or abs(ss[0]) < 1e3 or float(v["w0"]) <= 0)
    args = [t] + [p[k] for k in ("theta0", "omega0", "w0", "gamma")]
    kwargs = {"drive": drive, "h": p["h"]} if fn == "rk4" else {"drive": drive, "max_steps": "100000"}
    out = worker.call(fn, args, kwargs)
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma", "h", "drive", "max_steps"]), fn, args, kwargs)


def test_fuzz_rk4_and_cvode_with_a_drive(worker):
    rec = Recorder("rk4/cvode drive=")
    _run_driven_integrator(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=30)
@given(
    t=grid_src(),
    p=real_args(["theta0", "omega0", "w0", "gamma", "h"]),
    want=st.sampled_from(["'final'", "'trajectory'", "'period'", "'bogus'"]),
    chunk=st.sampled_from(["1", "7", "4096", "0", "-3", "2**70", "True"]),
)
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
@given(
    t=grid_src(),
    p=real_args(["theta0", "omega0", "w0", "gamma", "rtol", "atol"]),
    method=st.sampled_from(["'adams'", "'bdf'", "'BDF'", "'rk'", "3"]),
    max_steps=st.sampled_from(["1", "1000", "20000", "0", "-5", "2**70", "1.5", "True"]),
    events=st.sampled_from(["False", "True", "1"]),
    max_events=st.sampled_from(["100", "1", "0", "10**8"]),
)
@example(
    t="np.linspace(0.0, 10.0, 3)",
    p={"theta0": "0.0", "omega0": "2.0", "w0": "np.sqrt(2)", "gamma": "0.1", "rtol": "1e-8", "atol": "0.0"},
    method="'adams'",
    max_steps="20000",
    events="False",
    max_events="100",
)
@example(
    t="[0.0, 1e-300]",
    p={"theta0": "0.0", "omega0": "2.0", "w0": "np.sqrt(2)", "gamma": "0.1", "rtol": "1e-8", "atol": "1e-10"},
    method="'adams'",
    max_steps="20000",
    events="False",
    max_events="100",
)
def _run_cvode(worker, rec, t, p, method, max_steps, events, max_events):
    v = {k: evaluate(s) for k, s in p.items()}
    ok = all(x is not None and x.ndim == 0 and np.isfinite(x) for x in v.values())
    ss = _span_steps(t, 1, 0, 1)
    if ok and ss is not None:
        # keep the run short: a few hundred periods at most
        assume(not (float(v["w0"]) > 0 and (ss[0] * (float(v["w0"]) + float(v["gamma"])) > 1e3)))
    ok = ok and ss is not None and float(v["rtol"]) >= 1e-14
    args = [t] + [p[k] for k in ("theta0", "omega0", "w0", "gamma")]
    kw = {
        "rtol": p["rtol"],
        "atol": p["atol"],
        "method": method,
        "max_steps": max_steps,
        "events": events,
        "max_events": max_events,
    }
    out = worker.call("cvode", args, kw)
    chk = _integration_checks(ok, *(float(v[k]) for k in ("theta0", "omega0", "w0")), ss[0]) if ok else None
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma"] + list(kw), chk), "cvode", args, kw)


@settings(SETTINGS, max_examples=40)
@given(
    t=grid_src(),
    p=real_args(["theta0", "omega0", "w0", "gamma", "tol"]),
    max_steps=st.sampled_from(["1", "1000", "200000", "0", "-5", "2**70", "1.5", "True"]),
    events=st.sampled_from(["False", "True", "1"]),
    max_events=st.sampled_from(["100", "1", "0", "10**8"]),
)
@example(
    t="np.linspace(0.0, 10.0, 3)",
    p={"theta0": "2.5", "omega0": "0.0", "w0": "np.sqrt(2)", "gamma": "0.1", "tol": "1e-12"},
    max_steps="200000",
    events="True",
    max_events="100",
)
def _run_taylor(worker, rec, t, p, max_steps, events, max_events):
    v = {k: evaluate(s) for k, s in p.items()}
    ok = all(x is not None and x.ndim == 0 and np.isfinite(x) for x in v.values())
    ss = _span_steps(t, 1, 0, 1)
    if ok and ss is not None:
        # keep the run short: a few hundred periods at most
        assume(not (float(v["w0"]) > 0 and (abs(ss[0]) * (float(v["w0"]) + float(v["gamma"])) > 1e3)))
    ok = ok and ss is not None
    args = [t] + [p[k] for k in ("theta0", "omega0", "w0", "gamma")]
    kw = {"tol": p["tol"], "max_steps": max_steps, "events": events, "max_events": max_events}
    out = worker.call("taylor", args, kw)
    chk = _integration_checks(ok, *(float(v[k]) for k in ("theta0", "omega0", "w0")), abs(ss[0])) if ok else None
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma"] + list(kw), chk), "taylor", args, kw)


def test_fuzz_taylor(worker):
    rec = Recorder("taylor")
    _run_taylor(worker, rec)
    rec.verdict()


def test_fuzz_cvode(worker):
    rec = Recorder("cvode")
    _run_cvode(worker, rec)
    rec.verdict()


# ----------------------------------------------------------------- scenes

SCENE_ARGS = ["theta0", "omega0", "t", "g", "length", "gamma", "mass", "b", "tol", "want", "drive"]
# drives of a scene: a small torque (the linear closed form), a chaotic one, a fast pivot, none at all
SCENE_DRIVES = [
    "pendula.Drive('torque', 0.002, 1.2)",
    "pendula.Drive('torque', 1.15, 0.667, 0.3)",
    "pendula.Drive('pivot', 0.1, 30.0)",
    "pendula.Drive('torque', 0.0, 1.0)",
]


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
    kw["want"] = draw(
        st.sampled_from(["'state'", "'theta'", "'final'", "'energy'", "'period'", "'events'", "'nonsense'", "None"])
    )
    if draw(st.integers(0, 3)) == 0:
        kw["drive"] = draw(st.sampled_from(SCENE_DRIVES))
    v = {k: evaluate(s) for k, s in kw.items() if k not in ("want", "t", "drive")}
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
            cheap = (
                tend * (w0 + abs(gamma)) < 300
                and 0 < w0 < 1e100
                and abs(gamma) < 1e3 * w0 + 1
                and tol >= 1e-10
                and abs(float(v["omega0"])) < 1e3 * w0 + 1
            )
            cheap = cheap or not (g > 0 and length > 0 and math.isfinite(tend))  # refused up front
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
@example(
    sc=("pendula.Scene(theta0=1.0, t=1.0, length=5e-324)", {"theta0": "1.0", "t": "1.0", "length": "5e-324"}, True)
)
def _run_scene(worker, rec, sc):
    src, kw, cheap = sc
    out = worker.call("Scene", [], kw)
    rec.add(judge(out, SCENE_ARGS), "Scene", [], kw)


def test_fuzz_scene(worker):
    rec = Recorder("Scene")
    _run_scene(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=40)
@given(
    sc=scene_src(),
    model=st.sampled_from(
        ["None", "'auto'", "'small_angle'", "'exact'", "'linear'", "'rk4'", "'cvode'", "'bogus'", "3"]
    ),
)
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
@given(
    sc=scene_src(),
    model=st.sampled_from(["'small_angle'", "'exact'", "'linear'", "'rk4'", "'cvode'", "'auto'"]),
    setting=st.one_of(st.just("None"), scalar_src()),
)
def _run_model(worker, rec, sc, model, setting):
    src, kw, cheap = sc
    assume(cheap)
    sv = evaluate(setting) if setting != "None" else None
    if model == "'rk4'" and sv is not None and sv.ndim == 0 and 0 < sv < 1e-4:
        assume(False)  # accepted tiny steps are long work, not a defect
    if model == "'cvode'" and sv is not None and sv.ndim == 0 and 0 < sv < 1e-12:
        assume(False)
    out = worker.call("run_model", [src, model, setting])
    rec.add(judge(out, SCENE_ARGS + ["scene", "model", "setting"], _scene_checks), "run_model", [src, model, setting])


def test_fuzz_run_model(worker):
    rec = Recorder("run_model")
    _run_model(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=8)
@given(
    sc=scene_src(),
    models=st.sampled_from(["None", "['rk4']", "['exact', 'rk4']", "'rk4'", "['bogus']"]),
    rk4_steps=st.sampled_from(["None", "[0.1, 0.05]", "[0.0]", "[float('nan')]", "[]"]),
    repeat=st.sampled_from(["1", "0", "True"]),
)
def _run_tradeoff(worker, rec, sc, models, rk4_steps, repeat):
    src, kw, cheap = sc
    assume(cheap)
    kwargs = {"models": models, "rk4_steps": rk4_steps, "cvode_rtols": "[1e-4]", "repeat": repeat, "max_steps": "20000"}
    out = worker.call("tradeoff", [src], kwargs)
    rec.add(
        judge(out, SCENE_ARGS + ["scene", "models", "rk4_steps", "repeat", "cvode_rtols"]), "tradeoff", [src], kwargs
    )


def test_fuzz_tradeoff(worker):
    rec = Recorder("tradeoff")
    _run_tradeoff(worker, rec)
    rec.verdict()
