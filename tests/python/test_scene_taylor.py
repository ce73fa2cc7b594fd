"""The Taylor series as a model of the scenes: solve meets tolerances down to ~1e-14 of the
motion's size where RK4 and CVODE stop at their rounding floors (true errors against the
high-precision Taylor reference of benchmarks/scene_reference.py, itself checked against
mpmath.odefun and the elliptic solution in test_scene_bench.py, and the exact elliptic
solution for gamma = 0), says honestly where it cannot, and run_model runs it."""

import pathlib

import mpmath as mp
import numpy as np
import pytest
from helpers import load_file

import pendula
from pendula._codes import EVENT_TURNING

ref = load_file(pathlib.Path(__file__).resolve().parents[2] / "benchmarks" / "scene_reference.py")


def _true_error(r, s):
    """sup over the outputs of max(|d theta|, |d Omega|/w0) against the reference."""
    if s.gamma == 0:
        th, om, _ = ref.undamped(list(s.t), s.theta0, s.omega0, mp.mpf(s.w0))
    else:
        th, om = ref.Taylor(mp.mpf(s.w0), s.gamma).solve(list(s.t), s.theta0, s.omega0)
    return max(max(abs(float(a - x)), abs(float(b - y)) / s.w0) for a, b, x, y in zip(th, om, r.theta, r.omega))


def _size(theta0, omega0, w0):
    return abs((theta0 + np.pi) % (2 * np.pi) - np.pi) + abs(omega0) / w0


# the scene (2.5 rad, gamma = 0.1, 30 s) and two more damped ones
SCENES = [
    dict(theta0=2.5, omega0=0.0, gamma=0.1, t=np.linspace(0, 30, 31)),
    dict(theta0=1.0, omega0=0.5, gamma=0.3, t=np.linspace(0, 20, 11)),
    dict(theta0=0.2, omega0=-1.0, gamma=0.05, t=np.linspace(0, 25, 6)),
]


@pytest.mark.parametrize("kw", SCENES)
@pytest.mark.parametrize("rel", [1e-12, 1e-14])
def test_tight_tolerances_are_met_by_the_taylor_model(kw, rel):
    s0 = pendula.Scene(**kw)
    tol = rel * _size(s0.theta0, s0.omega0, s0.w0)
    s = pendula.Scene(**kw, tol=tol)
    r = pendula.solve(s)
    assert r.model == "taylor" and r.tol_met, r.reason
    assert _true_error(r, s) <= r.error_estimate <= tol


def test_below_the_floor_it_says_so_with_the_floor_reached():
    s = pendula.Scene(theta0=2.5, t=np.linspace(0, 30, 31), gamma=0.1, tol=1e-16)
    r = pendula.solve(s)
    assert r.model == "taylor" and not r.tol_met
    assert r.reason.startswith("tol NOT met") and "floor reached" in r.reason
    # the estimate is the floor, and it is honest
    assert 1e-16 < r.error_estimate < 1e-13
    assert _true_error(r, s) <= r.error_estimate


def test_a_long_window_at_tol_1e8_takes_the_taylor_model():
    s = pendula.Scene(theta0=2.5, t=np.linspace(0, 1000, 1001), gamma=0.001, tol=1e-8)
    r = pendula.solve(s)
    assert r.model == "taylor" and r.tol_met and r.error_estimate <= 1e-8, r.reason
    # a few thousand Taylor steps (RK4 needs millions for the same tol)
    assert r.cost["steps"] < 2e4
    tight = pendula.solve(pendula.Scene(theta0=2.5, t=s.t, gamma=0.001, tol=1e-10))
    assert tight.model == "taylor" and tight.error_estimate < 1e-10
    d = max(np.max(np.abs(r.theta - tight.theta)), np.max(np.abs(r.omega - tight.omega)) / s.w0)
    assert d <= r.error_estimate + tight.error_estimate


def test_run_model_taylor_against_the_elliptic_solution():
    s = pendula.Scene(theta0=3.0, omega0=0.1, t=np.linspace(0, 12, 7), tol=1e-12)
    r = pendula.run_model(s, "taylor")
    assert r.model == "taylor" and "Taylor" in r.reason and r.cost["runs"] == 1
    assert r.tol_met and _true_error(r, s) <= r.error_estimate <= 1e-12
    # the setting is ignored: the scene's tol decides
    r2 = pendula.run_model(s, "taylor", 0.5)
    assert np.array_equal(r.theta, r2.theta)


def test_forced_taylor_and_cheap_scenes_keep_their_models():
    s = pendula.Scene(theta0=0.4, t=np.linspace(0, 10, 21), gamma=0.2, tol=1e-9)
    r = pendula.solve(s, model="taylor")
    assert r.model == "taylor" and r.tol_met and "forced" in r.reason
    # closed forms stay where they fit
    assert pendula.solve(pendula.Scene(theta0=1e-3, t=np.linspace(0, 10, 11), gamma=0.3, tol=1e-8)).model == "linear"
    assert pendula.solve(pendula.Scene(theta0=2.0, t=np.linspace(0, 10, 11), tol=1e-12)).model == "exact"


def test_events_by_the_taylor_model():
    s = pendula.Scene(theta0=2.5, t=[30.0], gamma=0.1, tol=1e-12, want="events")
    r = pendula.solve(s)
    assert r.model == "taylor" and r.tol_met, r.reason
    ev = r.events if hasattr(r, "events") else None
    times = np.asarray(ev.t if ev is not None else r.event_t)
    kinds = np.asarray(ev.kind if ev is not None else r.event_kind)
    assert times.size > 5 and np.all(np.diff(times) > 0) and times[-1] <= 30.0
    th, om = ref.Taylor(mp.mpf(s.w0), s.gamma).solve(list(times), s.theta0, s.omega0)
    for k, x, y in zip(kinds, th, om):
        if k == EVENT_TURNING:
            assert abs(float(y)) / s.w0 < 1e-10
        else:
            assert abs(float(mp.sin(x / 2))) < 1e-10


def test_bad_input():
    s = pendula.Scene(theta0=1.0, t=[0.0, 1.0], gamma=0.1)
    with pytest.raises(ValueError):
        pendula.run_model(s, "taylr")
    with pytest.raises(ValueError):
        pendula.run_model(pendula.Scene(theta0=1.0, want="period"), "taylor")
    with pytest.raises(ValueError):
        pendula.solve(pendula.Scene(theta0=1.0, t=[0.0, 1.0], gamma=0.1, tol=-1e-12), model="taylor")
    with pytest.raises(TypeError):
        pendula.run_model(s, 6)
