"""The predicted work of a scene's solve decides how the call runs.

Fortran predicts it from the scene alone (scene_solve_work / scene_run_work
of pendula_scene_work, in RK4 steps, a CVODE step counting CVODE_STEP_COST);
pendula/_scene_call.py runs a call predicted above _longcall.SCENE_LONG_STEPS (~2.5 ms)
in a worker thread that Ctrl-C can stop, and a shorter one inline.  The
prediction is checked here against the work the solve itself reports
(result.cost), not against wall time: a damped motion handed over to the
linear closed form once decayed is short however many periods the window
spans; a long undecayed window is long.
"""

import threading

import numpy as np
import pytest
from helpers import HAVE_CVODE

import pendula
from pendula import _longcall
from pendula import scene as scene_mod
from pendula._codes import CVODE_STEP_COST, MODEL_CODES, TAYLOR_STEP_COST, WANT_CODES


def _work(scene, model="auto", fixed=0, setting=0.0, tol=None):
    return scene_mod._scene.scene_work_f2py(
        scene._t_arg(),
        scene.theta0,
        scene.omega0,
        scene.w0,
        scene._w0lo,
        scene.gamma,
        scene.tol if tol is None else tol,
        WANT_CODES[scene.want],
        MODEL_CODES[model],
        fixed,
        setting,
        *scene._drive_args(),
    )


def _reported(result):
    """Work the solve reports, in RK4 steps."""
    return result.cost["steps"] * {"cvode": CVODE_STEP_COST, "taylor": TAYLOR_STEP_COST}.get(result.model, 1)


# Damped scenes of the benchmark grid (scenes 287, 199, 382) that span 50 to 400
# periods but decay within a few: a few dozen RK4 steps, then the linear form.
DECAYED = [
    dict(
        theta0=1.7430472705210027,
        omega0=-2.1978054335978863,
        g=21.476,
        length=7.368,
        gamma=3.4145374878121144,
        t=285.52142322049934,
        tol=3.97e-09,
        want="energy",
    ),
    dict(
        theta0=-1.8253069406363198,
        omega0=2.9822054392899737,
        g=21.086,
        length=1.627,
        gamma=7.200013665590391,
        t=np.linspace(69.0, 137.92603006272975, 5),
        tol=0.000279,
        want="final",
    ),
    dict(
        theta0=20.7833962957327,
        omega0=9.588162967124733,
        g=10.977,
        length=0.154,
        gamma=3.219669994412096,
        t=77.43148004086076,
        tol=0.00103,
        want="theta",
    ),
]


class _Recorder:
    """Stands in for _longcall.run: records `long`, then runs the call."""

    def __init__(self, real):
        self.real, self.longs = real, []

    def __call__(self, call, control, long, *args, **kwargs):
        self.longs.append(long)
        return self.real(call, control, long, *args, **kwargs)


@pytest.mark.parametrize("kw", DECAYED)
def test_decayed_damped_scenes_run_inline_without_a_thread(kw, monkeypatch):
    scene = pendula.Scene(**kw)
    assert scene.w0 * np.max(scene.t) / (2 * np.pi) > 50  # what the old rule called long
    rec = _Recorder(_longcall.run)
    monkeypatch.setattr(_longcall, "run", rec)

    def no_thread(*args, **kwargs):
        raise AssertionError("a short solve started a thread")

    monkeypatch.setattr(threading, "Thread", no_thread)
    res = pendula.solve(scene)
    assert rec.longs == [False]
    assert res.model == "rk4" and "decayed" in res.reason
    # the prediction is within a few times the reported work, far below the threshold
    work = _work(scene)
    assert _reported(res) / 3 <= work <= 10 * _reported(res) + 100
    assert work < _longcall.SCENE_LONG_STEPS / 50


# (scene, model): integrated solves of 1e3 .. 1e6 reported RK4 steps
TRACKED = [
    (dict(theta0=2.5, t=np.linspace(0.0, 300.0, 50), gamma=0.1, tol=1e-8), None),
    (dict(theta0=1.0, t=np.linspace(0.0, 500.0, 20), gamma=1e-3, tol=1e-8), None),
    (dict(theta0=1.0, t=np.linspace(0.0, 200.0, 30), tol=1e-8), "rk4"),
    (dict(theta0=1.0, t=100.0, gamma=0.1, tol=1e-6, want="events"), None),
    (dict(theta0=np.pi, t=np.linspace(0.0, 40.0, 10), gamma=0.5, tol=1e-8), None),
    (dict(theta0=1.0, t=np.linspace(0.0, 200.0, 30), tol=1e-8), "cvode"),
]


@pytest.mark.parametrize("kw, model", TRACKED)
def test_prediction_tracks_the_reported_work(kw, model):
    if (model == "cvode" or kw.get("want") == "events") and not HAVE_CVODE:
        pytest.skip("this build has no CVODE")
    scene = pendula.Scene(**kw)
    res = pendula.solve(scene, model=model)
    done = _reported(res)
    work = _work(scene, model or "auto")
    assert 1e3 < done < 1e6
    # within a factor 10 either way (the outputs and events add their own work)
    assert done / 10 <= work <= 10 * done, (work, done)


def test_long_windows_that_do_not_decay_are_long():
    # the scenes tests/python/test_interrupt.py stops with Ctrl-C
    slow = pendula.Scene(1.0, t=[0.0, 1e6], gamma=1e-5, tol=1e-10)
    assert _work(slow) > 100 * _longcall.SCENE_LONG_STEPS
    assert scene_mod._long_scene(slow, slow._t_arg(), MODEL_CODES["auto"], 0, 0.0)
    fixed = pendula.Scene(1.0, t=[0.0, 1e5], gamma=0.1)
    assert _work(fixed, "rk4", 1, 1e-4) >= 1e9
    assert scene_mod._long_scene(fixed, fixed._t_arg(), MODEL_CODES["rk4"], 1, 1e-4)
    # the same weak damping over a window of ~2 periods (~2e4 RK4 steps): short
    short = pendula.Scene(1.0, t=[0.0, 10.0], gamma=1e-5, tol=1e-10)
    assert not scene_mod._long_scene(short, short._t_arg(), MODEL_CODES["auto"], 0, 0.0)


def test_a_fixed_rk4_run_predicts_its_steps_and_outputs():
    scene = pendula.Scene(1.0, t=np.linspace(0.0, 10.0, 11), gamma=0.1)
    res = pendula.run_model(scene, "rk4", 1e-3)
    assert res.cost["steps"] == 10_000
    assert 10_000 <= _work(scene, "rk4", 1, 1e-3) <= 10_000 + 100 * 11


def test_closed_forms_predict_only_their_outputs():
    t = np.linspace(0.0, 1e4, 1000)
    assert _work(pendula.Scene(2.0, t=t)) <= 10 * t.size  # exact, any window
    assert _work(pendula.Scene(1e-6, t=t, gamma=0.1), "linear") <= 10 * t.size


def test_an_invalid_scene_or_setting_predicts_no_work():
    scene = pendula.Scene(1.0, t=[0.0, 1e6], gamma=1e-5, tol=1e-10)
    assert _work(scene, tol=-1.0) == 0.0  # refused by the solve at once
    assert _work(scene, tol=float("nan")) == 0.0
    assert _work(scene, "rk4", 1, 0.0) == 0.0
    assert _work(scene, "rk4", 1, float("inf")) == 0.0
