"""Fuzz leg, the driven pendulum: driven, driven_linear, resonance_curve and the chaos
tools on adversarial states and parameters, each call in a subprocess (what fails a
call: see test_fuzz.py).  Small counts keep every legal call short."""

from fuzz_support import SETTINGS, Recorder, judge, real_args, worker  # noqa: F401 (worker: the fixture)
from hypothesis import given, settings
from hypothesis import strategies as st

_DRIVE = "pendula.Drive('torque', 1.15, 2/3)"
_CALLS = {
    "driven": (["[0.0, 1.0, 20.0]"], {"steps_per_period": "16"}),
    "poincare": ([], {"transient": "2", "points": "2", "steps_per_period": "16"}),
    "lyapunov": ([], {"transient": "1", "periods": "16", "steps_per_period": "16"}),
    "periodic_orbits": ([], {"transient": "2", "nmax": "2", "steps_per_period": "16"}),
    "find_periodic_orbit": ([], {"period": "1", "steps_per_period": "16"}),
    "basins": ([], {"transient": "2", "nmax": "2", "steps_per_period": "16"}),
}


def _fuzz(fn):
    pre, kw = _CALLS[fn]

    @settings(SETTINGS, max_examples=25)
    @given(p=real_args(["theta0", "omega0", "w0", "gamma"]))
    def run(worker, rec, p):
        args = pre + [p["theta0"], p["omega0"]]
        kwargs = {"drive": _DRIVE, "w0": p["w0"], "gamma": p["gamma"], **kw}
        out = worker.call(fn, args, kwargs)
        rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma", "steps_per_period", "drive"]), fn, args, kwargs)

    def test(worker):
        rec = Recorder(fn)
        run(worker, rec)
        rec.verdict()

    return test


for _fn in _CALLS:
    globals()[f"test_fuzz_{_fn}"] = _fuzz(_fn)


@settings(SETTINGS, max_examples=40)
@given(p=real_args(["frequency", "w0", "gamma"]))
def _run_resonance(worker, rec, p):
    out = worker.call("resonance_curve", [p["frequency"]], {"w0": p["w0"], "gamma": p["gamma"]})
    rec.add(judge(out, ["frequency", "w0", "gamma"]), "resonance_curve", [p["frequency"]])


def test_fuzz_resonance_curve(worker):
    rec = Recorder("resonance_curve")
    _run_resonance(worker, rec)
    rec.verdict()


@settings(SETTINGS, max_examples=25)
@given(
    p=real_args(["theta0", "omega0", "w0", "gamma"]),
    t=st.sampled_from(["[0.0, 1.0]", "[0.0, 1e308]", "[-1.0]", "[float('nan')]", "[]"]),
)
def _run_linear(worker, rec, p, t):
    out = worker.call(
        "driven_linear",
        [t, p["theta0"], p["omega0"]],
        {"drive": "pendula.Drive('torque', 0.01, 1.3)", "w0": p["w0"], "gamma": p["gamma"]},
    )
    rec.add(judge(out, ["t", "theta0", "omega0", "w0", "gamma", "drive"]), "driven_linear", [t])


def test_fuzz_driven_linear(worker):
    rec = Recorder("driven_linear")
    _run_linear(worker, rec)
    rec.verdict()
