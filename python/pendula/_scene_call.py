"""One scene through Fortran: the predicted work (is the call long?), the
event slots, the f2py call of the solve or the fixed-setting run, its answer
as a ``SceneResult``, and the same for every scene of a ``SceneBatch`` on a
thread pool; ``pendula.scene`` is the public face."""

from __future__ import annotations

import time

import numpy as np

from . import _fortran as _scene
from . import _longcall, _memory
from ._arrays import step_budget
from ._codes import INFO, INFO_SIZE, WANT_CODES
from ._defaults import POOL_STATE_WORK, SERIAL_WORK, STEP_CAP, check_threads
from ._errors import _text, raise_for_status
from ._many import scenes as _scene_batch
from ._scene_types import _MODEL_NAME, Scene, SceneResult
from .integrate import Events


def _scene_args(scene, tt, model_code, fixed, setting):
    # the scene and the model asked, as the f2py glue's scene entries take them first
    return (
        tt,
        scene.theta0,
        scene.omega0,
        scene.w0,
        scene._w0lo,
        scene.gamma,
        scene.tol,
        WANT_CODES[scene.want],
        model_code,
        int(fixed),
        float(setting),
    )


def _scene_work(scene, tt, model_code, fixed, setting):
    # Fortran's prediction of the call's work in RK4 steps from the scene
    # (scene_solve_work / scene_run_work: the model the choice would take, its
    # span, e.g. up to the hand-over of a decaying motion, its steps, the event
    # grid and the outputs).  NaN when it cannot tell.
    return _scene.scene_work_f2py(*_scene_args(scene, tt, model_code, fixed, setting), *scene._drive_args())


def _long_scene(scene, tt, model_code, fixed, setting):
    # Predicted > ~2.5 ms (_longcall.SCENE_LONG_STEPS); NaN: long.
    return not _scene_work(scene, tt, model_code, fixed, setting) <= _longcall.SCENE_LONG_STEPS


def _budget(max_steps):
    return float(step_budget(max_steps))


# Event slots of a first solve: the storage grows with the events found, not
# with the bound on them (a long window's bound can be ~1e9 events, 28 bytes
# each, where the motion has a few thousand): a solve that finds more events
# than slots is run once more with exactly as many (Fortran keeps its own
# list growing geometrically, pendula_scene_events).
_FIRST_EVENT_SLOTS = 65536


def _event_slots(scene, tt):
    # at most Fortran's rigorous bound on the events of the window (scene_event_bound)
    if scene.want != "events":
        return 1
    return int(
        min(_FIRST_EVENT_SLOTS, _scene.scene_event_bound_f2py(scene.w0, float(tt[-1]), scene.theta0, scene.omega0))
    )


def _run(scene, model_code, fixed, setting, max_steps=STEP_CAP, progress=None, control=None):
    # control: a batch thread's control array (the batch layer watches it)
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a pendula.Scene, got {type(scene).__name__}")
    tt = scene._t_arg()
    m = _event_slots(scene, tt)
    budget = _budget(max_steps)
    watched = control is None
    long = watched and _long_scene(scene, tt, model_code, fixed, setting)
    start = time.perf_counter()
    if watched:
        # a short call with no progress to watch runs inline: this thread's scratch array
        control = _longcall.new_control() if long or progress else _longcall.scratch_control()
    while True:
        args = (
            *_scene_args(scene, tt, model_code, fixed, setting),
            m,
            INFO_SIZE,
            budget,
            control,
            *scene._drive_args(),
        )
        # f2py allocates the outputs (3 series of t, energy, m event slots of 28 bytes) before the solve
        out = _memory.guard(
            lambda: _longcall.run(
                lambda: _scene.scene_solve_f2py(*args), control, long, progress if watched else None, unit="step"
            ),
            "the scene's outputs and event slots",
            8 * 4 * tt.size + 28 * m,
        )
        (
            nout,
            tout,
            theta,
            omega,
            energy,
            ev_t,
            ev_kind,
            ev_theta,
            ev_omega,
            n_ev,
            model_out,
            info,
            reason,
            code,
            msg,
        ) = out
        raise_for_status(code, msg)
        if int(n_ev) <= m:
            break
        m = int(n_ev)  # more events than slots: once more with room for every one (same solve, same events)
    wall = time.perf_counter() - start
    return (
        int(nout),
        tout,
        theta,
        omega,
        energy,
        ev_t,
        ev_kind,
        ev_theta,
        ev_omega,
        int(n_ev),
        int(model_out),
        info,
        reason,
        wall,
    )


def _result(scene, raw):
    (nout, tout, theta, omega, energy, ev_t, ev_kind, ev_theta, ev_omega, n_ev, model_out, info, reason, wall) = raw
    num = {name: float(info[i]) for name, i in INFO.items()}
    model = _MODEL_NAME.get(model_out, "unknown")
    cost = {name: int(num[name]) for name in ("closed_form_evals", "rhs_evals", "steps", "runs")}
    cost.update(wall_time=num["wall_time"], python_wall_time=wall)
    kw = {}
    want = scene.want
    if want in ("state", "theta", "energy"):
        # always 1-D arrays, also for a scalar t (shape (1,)): one type per field
        kw.update(
            t=tout[:nout].copy(), theta=theta[:nout].copy(), omega=None if want == "theta" else omega[:nout].copy()
        )
        if want == "energy":
            kw.update(energy=energy[:nout].copy())
            if model == "exact":  # conserved: no time series was evaluated
                kw.update(theta=None, omega=None)
    elif want == "final":
        # shape (1,): the state at t[-1], indexable as r.theta[-1] like a history
        kw.update(t=tout[:1].copy(), theta=theta[:1].copy(), omega=omega[:1].copy())
    elif want == "period":
        kw.update(period=num["period"])
    elif want == "events":
        n = n_ev
        kw.update(
            events=Events(
                t=ev_t[:n].copy(),
                kind=ev_kind[:n].astype(np.int64),
                theta=ev_theta[:n].copy(),
                omega=ev_omega[:n].copy(),
                truncated=False,
            ),
            event_time_error=num["event_time_error"],
        )
    integrated = model in ("rk4", "cvode")
    return SceneResult(
        model=model,
        reason=_text(reason),
        error_estimate=num["error_estimate"],
        tol_met=bool(num["tol_met"]),
        setting=num["setting"] if integrated else None,
        step=num["step"] if model == "rk4" else None,
        rtol=num["rtol"] if model == "cvode" else None,
        cost=cost,
        **kw,
    )


def _batch_run(batch, model_code, fixed, setting, max_steps, progress, threads):
    """solve / run_model of every scene of a SceneBatch on a thread pool."""
    step_budget(max_steps)  # the call's own argument: ValueError/TypeError for the whole call
    check_threads(threads)
    work = batch.scenes.size * POOL_STATE_WORK
    if threads is None and not work > SERIAL_WORK:
        # a small batch: Fortran's prediction of each scene's work, summed until it is enough for threads
        for sc in batch.scenes.reshape(-1):
            work += _scene_work(sc, sc._t_arg(), model_code, fixed, setting)
            if not work <= SERIAL_WORK:
                break

    def one(sc, control):
        return _result(sc, _run(sc, model_code, fixed, setting, max_steps, control=control))

    return _scene_batch.run(batch, one, progress, threads, work)
