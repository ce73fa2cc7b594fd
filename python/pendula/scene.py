"""Scenes: describe a pendulum and a tolerance; the library picks the cheapest
model whose error fits, says which and why, and backs it with an error estimate.

A ``Scene`` holds the text's parameters (g, length, and either gamma or mass
and b), the initial state (theta0, omega0) at t = 0, the output times ``t``,
what is wanted and a tolerance ``tol``.  ``solve(scene)`` answers it;
``tradeoff(scene)`` (``pendula.tradeoff``) measures the speed/accuracy trade of
every applicable model.

The tolerance is ABSOLUTE, on theta in rad, over the whole window, with Omega
scaled by w0: the error measure is sup_t max(|d theta|, |d Omega|/w0).

Models, cheapest first (the choice and the solve are in Fortran,
``pendula_scene``):

- ``"small_angle"`` (gamma = 0): theta0 cos(w0 t) + (omega0/w0) sin(w0 t),
  chosen when its rigorous bound over the window (phase drift ~ (m/4) w0 t) is
  <= tol;
- ``"linear"`` (gamma > 0): the linear damped closed form, chosen when the
  estimated error of dropping sin(theta) - theta (amplitude^2 frequency shift
  accumulated over the decaying window, and a Green's-function bound) is <= tol;
- ``"exact"`` (gamma = 0): the elliptic closed form (error a few eps times the
  condition number);
- ``"rk4"``: step h from tol and the window length (global error ~ C h^4 T),
  verified a posteriori by a second run at 2h (Richardson), refined until the
  estimate meets tol;
- ``"cvode"``: rtol from tol and the number of periods (a local tolerance is not
  a global error), verified by a run ten times tighter; used instead of RK4
  when RK4 would need more than ``pendula._codes.RK4_STEP_LIMIT`` steps (long
  runs), when its rounding would eat tol, or on stiff runs, and SUNDIALS was
  built.

The model and want names, the codes and the limits come from the Fortran
core (``pendula._codes``, generated at build time); so do all the rules on a
scene: this module passes its arguments through.

Units: angles rad, Omega rad/s, t s, g m/s^2, length m, mass kg, b kg/s,
gamma and w0 1/s, energies per unit m l^2 in 1/s^2.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from . import _fortran as _scene
from . import _longcall, _memory, _tables
from ._arrays import SharedTimes, as_real, real_scalar, step_budget
from ._codes import INFO, INFO_SIZE, MODEL_ALIASES, MODEL_CODES, WANT_CODES
from ._config import HAVE_CVODE  # noqa: F401 (read by benchmarks/bench_scenes.py)
from ._defaults import G_DEFAULT, LENGTH_DEFAULT, POOL_STATE_WORK, SERIAL_WORK, STEP_CAP, THREADS, TOL, check_threads
from ._errors import _text, raise_for_status
from ._many import scenes as _scene_batch
from ._many.ensemble import is_batch as _is_batch
from ._many.scenes import SceneBatch, SceneBatchResult
from .integrate import Events

MODELS = tuple(name for name in MODEL_CODES if name != "auto")
"""Model names accepted by ``solve(scene, model=...)`` (plus "auto")."""
WANTS = tuple(WANT_CODES)
"""What a scene can ask for (see ``Scene``)."""

_MODEL_NAME = {v: k for k, v in MODEL_CODES.items()}


def _model_code(model, name="model"):
    if model is None:
        return 0
    if not isinstance(model, str):
        raise TypeError(f"{name} must be a string, one of {', '.join(('auto',) + MODELS)}; got {type(model).__name__}")
    key = model.strip().lower()
    key = MODEL_ALIASES.get(key, key)
    if key not in MODEL_CODES:
        raise ValueError(f"{name} = {model!r} is unknown: it must be one of {', '.join(('auto',) + MODELS)}")
    return MODEL_CODES[key]


class Scene:
    """A pendulum scene: parameters, initial state, window, wanted quantity, tolerance.

    Parameters
    ----------
    theta0, omega0 : float
        Initial angle [rad] and angular velocity [rad/s] at t = 0 (any finite values).
    t : float or 1-D array
        Output times [s], finite, >= 0, strictly increasing (the window is
        [0, t[-1]]).  May be omitted only for ``want="period"``.
    g, length : float
        Gravity [m/s^2] and pendulum length [m] (> 0); w0 = sqrt(g/length).
        Defaults: the text's g = 9.8, length = 4.9 (w0 = sqrt(2)).
    gamma : float, optional
        Damping rate [1/s] >= 0 (theta'' + gamma theta' + w0^2 sin theta = 0).
    mass, b : float, optional
        Bob mass [kg] > 0 and damping constant [kg/s] >= 0: gamma = b/mass
        (text eq. 2.1).  Give both or neither; giving gamma as well is allowed
        only when it equals b/mass.  No damping given: gamma = 0.
    tol : float
        Absolute tolerance [rad] > 0 on theta over the whole window (Omega/w0 too).
    want : str
        ``"state"``: theta and omega at t; ``"theta"``: theta only;
        ``"final"``: the state at t[-1] only (no history kept);
        ``"energy"``: energy per unit m l^2 [1/s^2], Omega^2/2 + w0^2 (1 - cos theta), at t;
        ``"period"``: the period (libration) or time per revolution (rotation) [s],
        gamma = 0 only (K computed once, no time series);
        ``"events"``: turning points (Omega = 0) and zero crossings (passes through the bottom,
        theta = 0 mod 2 pi) in (0, t[-1]].

    Attributes
    ----------
    theta0, omega0, g, length, tol, want, t
        As given (t: a read-only 1-D copy).
    w0, gamma : float
        sqrt(g/length) and the damping rate [1/s] the scene uses.
    mass, b, gamma_given
        As given, or None.

    Raises
    ------
    ValueError
        For inconsistent or out-of-range parameters, naming the argument.
    TypeError
        For non-real input or a want that is not a string.

    Notes
    -----
    Batches: when theta0, omega0, g, length, gamma, mass, b or tol is an
    array (one or more dimensions), they broadcast like NumPy and ``Scene``
    returns a ``SceneBatch`` (one scene per state, t and want shared);
    ``solve``, ``run_model`` and ``tradeoff`` then answer every scene (see
    ``solve``).  A bad value in one state raises ValueError naming the state.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> scene = pendula.Scene(theta0=0.0, omega0=2.0, t=np.linspace(0, 30, 601), mass=0.1, b=0.01)
    >>> scene  # doctest: +ELLIPSIS
    Scene(theta0=0, omega0=2, w0=1.41421, gamma=0.1 (b=0.01, mass=0.1), t[601] in [0, 30], ...)
    >>> round(scene.periods, 3)
    6.752
    """

    def __new__(
        cls,
        theta0=None,
        omega0=0.0,
        t=None,
        g=G_DEFAULT,
        length=LENGTH_DEFAULT,
        gamma=None,
        mass=None,
        b=None,
        tol=TOL,
        want="state",
    ):
        # (theta0 defaults to None here only so that pickle and copy, which call
        # __new__ with no arguments, work; __init__ still requires it)
        if cls is Scene and _is_batch(theta0, omega0, g, length, gamma, mass, b, tol):
            return SceneBatch(theta0, omega0, t, g, length, gamma, mass, b, tol, want, make=Scene)
        return object.__new__(cls)

    def __init__(
        self,
        theta0: ArrayLike,
        omega0: ArrayLike = 0.0,
        t: ArrayLike | None = None,
        g: ArrayLike = G_DEFAULT,
        length: ArrayLike = LENGTH_DEFAULT,
        gamma: ArrayLike | None = None,
        mass: ArrayLike | None = None,
        b: ArrayLike | None = None,
        tol: ArrayLike = TOL,
        want: str = "state",
    ) -> None:
        self.theta0 = real_scalar(theta0, "theta0")
        self.omega0 = real_scalar(omega0, "omega0")
        self.g = real_scalar(g, "g")
        self.length = real_scalar(length, "length")
        self.gamma_given = None if gamma is None else real_scalar(gamma, "gamma")
        self.mass = None if mass is None else real_scalar(mass, "mass")
        self.b = None if b is None else real_scalar(b, "b")
        self.tol = real_scalar(tol, "tol")
        if not isinstance(want, str):
            raise TypeError(f"want must be a string, one of {', '.join(WANTS)}; got {type(want).__name__}")
        if want.strip().lower() not in WANT_CODES:
            raise ValueError(f"want = {want!r} is unknown: it must be one of {', '.join(WANTS)}")
        self.want = want.strip().lower()
        w0, gam, w0lo, code, msg = _scene.scene_physics_f2py(
            self.g,
            self.length,
            0.0 if self.gamma_given is None else self.gamma_given,
            1.0 if self.mass is None else self.mass,
            0.0 if self.b is None else self.b,
            int(self.gamma_given is not None),
            int(self.mass is not None),
            int(self.b is not None),
        )
        raise_for_status(code, msg)
        self.w0 = float(w0)
        # w0 = fl(sqrt(g/length)); the closed forms take the energy of the data
        # as given (near the separatrix a half-ulp of w0 matters): its residual
        self._w0lo = float(w0lo)
        self.gamma = float(gam)
        if isinstance(t, SharedTimes):
            tt = t.array  # a batch's checked, read-only grid: shared, not copied
        elif t is None:
            if self.want != "period":
                raise ValueError("t is missing: give the output times (only want='period' needs none)")
            tt = np.zeros(0)
            tt.setflags(write=False)
        else:
            arr = as_real(t, "t")
            if arr.ndim > 1:
                raise ValueError(f"t must be a scalar or a 1-D array of output times, got shape {arr.shape}")
            tt = np.ascontiguousarray(arr.reshape(-1))
            if tt.size == 0 and self.want != "period":
                raise ValueError("t has 0 elements: it needs at least 1 output time (>= 0, increasing)")
            tt.setflags(write=False)
        self.t = tt
        code, msg = _scene.scene_check_f2py(
            self._t_arg(),
            self.theta0,
            self.omega0,
            self.w0,
            self.gamma,
            self.tol,
            WANT_CODES[self.want],
            MODEL_CODES["auto"],
        )
        raise_for_status(code, msg)

    def _t_arg(self):
        # f2py needs at least one element; a period scene without t passes a dummy
        # (scene_init ignores t for want = period when it is empty... it is not
        # empty here, so pass 0, which is a valid window for a period scene).
        return self.t if self.t.size else np.zeros(1)

    @property
    def periods(self):
        """Length of the window in small-angle periods, w0 t[-1] / (2 pi).

        Returns
        -------
        float
            The number of periods (0 for a scene without t).

        Examples
        --------
        >>> import pendula
        >>> pendula.Scene(0.1, t=[0.0, 10.0], g=9.8, length=9.8).periods == 10 / (2 * 3.141592653589793)
        True
        """
        return float(self.w0 * self.t[-1] / (2 * np.pi)) if self.t.size else 0.0

    def __repr__(self):
        damping = f"gamma={self.gamma:g}"
        if self.mass is not None:
            damping += f" (b={self.b:g}, mass={self.mass:g})"
        n = self.t.size
        window = f"t[{n}] in [{self.t[0]:g}, {self.t[-1]:g}]" if n else "no t"
        return (
            f"Scene(theta0={self.theta0:g}, omega0={self.omega0:g}, w0={self.w0:.6g}, {damping}, "
            f"{window}, tol={self.tol:g}, want={self.want!r})"
        )


@dataclass(frozen=True, repr=False)
class SceneResult(_tables.Tabular):
    """The answer to a scene: the model used, why, its error estimate, and the wanted quantities.

    Returned by ``solve`` and ``run_model``.

    Parameters
    ----------
    model : str
        The model used: "small_angle", "exact", "linear", "rk4" or "cvode".
    reason : str
        Why it was chosen.
    error_estimate : float
        Estimated sup over the window of max(abs(d theta) [rad],
        abs(d Omega)/w0); for want "events" the larger of that and
        event_time_error [s].
    tol_met : bool
        error_estimate <= the scene's tol.
    setting : float or None
        RK4 step h [s] or CVODE rtol of the returned run (None for closed
        forms; kept for compatibility: ``step`` and ``rtol`` say which).
    cost : dict
        closed_form_evals, rhs_evals, steps, runs (integrator runs,
        verification included), wall_time [s] (inside Fortran),
        python_wall_time [s] (the whole call).
    step : float or None
        The RK4 step h [s] (model "rk4").
    rtol : float or None
        The CVODE rtol (model "cvode").
    t : numpy.ndarray or None
        Output times [s]: shape (n_t,) for want "state", "theta" and
        "energy" (also for a scalar t: shape (1,)), (1,) -- t[-1] -- for
        "final"; None for "period" and "events".
    theta, omega : numpy.ndarray or None
        Angle [rad] and angular velocity [rad/s] at t, with t's shape
        (``r.theta[-1]`` is the final angle for every want that has one);
        omega None for want "theta"; both None for "energy" answered by the
        exact model (conserved: no series evaluated).
    energy : numpy.ndarray or None
        Energy per unit m l^2 [1/s^2] at t (want "energy").
    period : float or None
        Period or time per revolution [s] (want "period").
    events : Events or None
        Turning points and zero crossings (want "events").
    event_time_error : float or None
        Estimated error of the event times [s] (want "events").

    Notes
    -----
    The field types do not depend on the data: series are always 1-D
    arrays.  ``repr`` is a few lines; ``to_pandas`` / ``to_xarray`` convert
    the series (pandas / xarray are optional dependencies).

    Examples
    --------
    >>> import pendula
    >>> r = pendula.solve(pendula.Scene(1.0, t=[0.0, 2.0], want="final"))
    >>> r.model, r.tol_met, r.theta.shape
    ('exact', True, (1,))
    >>> round(float(r.theta[-1]), 6)
    -0.886993
    """

    model: str
    reason: str
    error_estimate: float
    tol_met: bool
    setting: object
    cost: dict
    step: object = None
    rtol: object = None
    t: object = None
    theta: object = None
    omega: object = None
    energy: object = None
    period: object = None
    events: Events = field(default=None)
    event_time_error: object = None

    def _series(self):
        return {"theta": self.theta, "omega": self.omega, "energy": self.energy}

    def _table(self):
        attrs = {"model": self.model, "error_estimate": self.error_estimate, "tol_met": int(self.tol_met)}
        if self.period is not None:  # want "period": one row, the period [s]
            return dict(t=None, fields={"period": np.array(self.period)}, attrs=attrs)
        if self.t is None:
            raise ValueError("this result has no time series to convert (want='events'): use result.events.to_pandas()")
        return dict(t=self.t, fields=self._series(), attrs=attrs)

    def __repr__(self):
        setting = (
            f", step h={self.step:.4g} s"
            if self.step is not None
            else f", rtol={self.rtol:.3g}"
            if self.rtol is not None
            else ""
        )
        c = self.cost
        quantities = _tables.series(self.t, self._series()) if self.t is not None else ""
        if self.period is not None:
            quantities = f"period={self.period:.17g} s"
        if self.events is not None:
            quantities = f"events: {self.events.summary()}, time error ~{self.event_time_error:.2g} s"
        return _tables.block(
            "SceneResult",
            [
                f"model={self.model!r}{setting}, error_estimate={self.error_estimate:.3g} rad, tol_met={self.tol_met}",
                f"reason: {_tables.clip(self.reason)}",
                quantities,
                f"cost: runs={c.get('runs')}, steps={c.get('steps')}, rhs_evals={c.get('rhs_evals')}, "
                f"closed_form_evals={c.get('closed_form_evals')}, wall_time={c.get('python_wall_time', 0.0):.3g} s",
            ],
        )


def _long_scene(scene, tt, model_code, fixed, setting):
    # Predicted > ~2.5 ms (_longcall.SCENE_LONG_STEPS): Fortran predicts the work of
    # the call in RK4 steps from the scene (scene_solve_work / scene_run_work:
    # the model the choice would take, its span, e.g. up to the hand-over of a
    # decaying motion, its steps, the event grid and the outputs).  NaN: long.
    work = _scene.scene_work_f2py(
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
    return not work <= _longcall.SCENE_LONG_STEPS


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
            m,
            INFO_SIZE,
            budget,
            control,
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


def solve(
    scene: Scene | SceneBatch,
    model: str | None = None,
    max_steps: int = STEP_CAP,
    progress: bool | Callable[[int, int | None], object] | None = None,
    threads: int | None = THREADS,
) -> SceneResult | SceneBatchResult:
    """Answer ``scene`` with the cheapest model whose error estimate is <= scene.tol.

    Parameters
    ----------
    scene : Scene or SceneBatch
        The scene(s) to answer.
    model : str, optional
        None or "auto" to let the library choose, or one of ``MODELS`` to
        force it (its setting is still chosen from tol and verified).
    max_steps : int
        Work budget in RK4 steps (a CVODE step counts as
        ``pendula._codes.CVODE_STEP_COST``; the default ``STEP_CAP`` is about
        a minute of CPU): a solve predicted to need more is refused before it
        starts, with a message naming what to change (window, tol, or a
        larger max_steps).
    progress : bool or callable, optional
        True for a tqdm bar (needs tqdm) or a callable(done, total) called
        about every 20 ms with the integrator's work so far (RK4 steps /
        CVODE right-hand-side evaluations; total None); for a batch, scenes.
    threads : int or None
        Threads of a batch: None (the default) chooses from the predicted
        work (one thread for a small batch), 0 asks for OMP_NUM_THREADS or
        every core; unused for one scene.

    Returns
    -------
    SceneResult or SceneBatchResult
        model, reason, error_estimate, tol_met, cost and the wanted
        quantities; a ``SceneBatchResult`` for a ``SceneBatch``.

    Raises
    ------
    ValueError
        For an unknown model name or a model that does not apply
        (small_angle/exact with gamma > 0), or a solve over max_steps.
    TypeError
        For a scene that is not a Scene or SceneBatch, or a non-integer
        max_steps or threads, or a progress that is not callable.
    NotImplementedError
        For "cvode" in a build without SUNDIALS.
    PendulaSolverError
        When an integrator fails.
    KeyboardInterrupt
        Ctrl-C during a long solve (within a millisecond or so).

    Notes
    -----
    When no model can meet tol (e.g. tol below the rounding floor of the
    exact solution over a long window), the most accurate one is used and
    ``tol_met`` is False with the reason saying so.

    A ``SceneBatch`` gives a ``SceneBatchResult``: every scene solved as
    alone (bit for bit) on ``threads`` threads, per-scene codes and
    messages for the scenes whose solve failed (the others keep their
    answers), stacked quantities with the batch shape in front; the call
    raises only when every scene failed.  Ctrl-C stops every thread.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> r = pendula.solve(pendula.Scene(0.0, 2.0, t=np.linspace(0, 30, 601), gamma=0.1, tol=1e-6))
    >>> r.model, r.tol_met, r.error_estimate <= 1e-6
    ('taylor', True, True)
    >>> b = pendula.solve(pendula.Scene([0.1, 3.0], t=[0.0, 1.0]))
    >>> list(b.model), b.theta.shape
    (['exact', 'exact'], (2, 2))
    """
    code = _model_code(model)
    if isinstance(scene, SceneBatch):
        return _batch_run(scene, code, False, 0.0, max_steps, progress, threads)
    check_threads(threads)
    return _result(scene, _run(scene, code, False, 0.0, max_steps, progress))


def run_model(
    scene: Scene | SceneBatch,
    model: str,
    setting: float | None = None,
    max_steps: int = STEP_CAP,
    progress: bool | Callable[[int, int | None], object] | None = None,
    threads: int | None = THREADS,
) -> SceneResult | SceneBatchResult:
    """Run one model on ``scene`` at a fixed setting, with no choice and no verification.

    For work-precision studies (``tradeoff``).

    Parameters
    ----------
    scene : Scene or SceneBatch
        The scene(s).
    model : str
        One of ``MODELS`` (not "auto").
    setting : float, optional
        RK4 step h [s] > 0 or CVODE rtol > 0 (atol = rtol * state scale /
        100); required for "rk4" and "cvode", ignored for the closed forms.
    max_steps, progress, threads
        As for ``solve`` (an RK4 run of more than max_steps steps is refused
        up front).

    Returns
    -------
    SceneResult or SceneBatchResult
        The run's answer; its error_estimate is what the model claims
        without verification (0 for an unverified integration).

    Raises
    ------
    ValueError
        For "auto", an unknown or inapplicable model, a missing or bad
        setting, an unstable RK4 step, a run over max_steps.
    TypeError
        For a scene that is not a Scene or SceneBatch, a model that is not a
        str, a non-integer max_steps or threads, or a progress that is not
        callable.
    NotImplementedError
        For "cvode" in a build without SUNDIALS.
    PendulaSolverError
        When an integrator fails.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> r = pendula.run_model(pendula.Scene(0.0, 2.0, t=np.linspace(0, 30, 601), gamma=0.1), "rk4", 0.05)
    >>> r.model, r.step, r.cost["steps"]
    ('rk4', 0.05, 600)
    """
    code = _model_code(model)
    if code == MODEL_CODES["auto"]:
        raise ValueError("model = 'auto' is not a model: use solve(scene) to let the library choose")
    if code in (MODEL_CODES["rk4"], MODEL_CODES["cvode"]):
        if setting is None:
            raise ValueError(f"setting is missing: model {model!r} needs a step h (rk4) or an rtol (cvode)")
        setting = real_scalar(setting, "setting")
    else:
        setting = 0.0
    if isinstance(scene, SceneBatch):
        return _batch_run(scene, code, True, setting, max_steps, progress, threads)
    check_threads(threads)
    return _result(scene, _run(scene, code, True, setting, max_steps, progress))


def _batch_run(batch, model_code, fixed, setting, max_steps, progress, threads):
    """solve / run_model of every scene of a SceneBatch on a thread pool."""
    step_budget(max_steps)  # the call's own argument: ValueError/TypeError for the whole call
    check_threads(threads)
    work = batch.scenes.size * POOL_STATE_WORK
    if threads is None and not work > SERIAL_WORK:
        # a small batch: Fortran's prediction of each scene's work, summed until it is enough for threads
        for sc in batch.scenes.reshape(-1):
            work += _scene.scene_work_f2py(
                sc._t_arg(),
                sc.theta0,
                sc.omega0,
                sc.w0,
                sc._w0lo,
                sc.gamma,
                sc.tol,
                WANT_CODES[sc.want],
                model_code,
                int(fixed),
                float(setting),
            )
            if not work <= SERIAL_WORK:
                break

    def one(sc, control):
        return _result(sc, _run(sc, model_code, fixed, setting, max_steps, control=control))

    return _scene_batch.run(batch, one, progress, threads, work)


__all__ = ["Scene", "SceneResult", "solve", "run_model", "SceneBatch", "SceneBatchResult"]


def __getattr__(name):
    # tradeoff and TradeoffTable live a layer above this module (pendula._tradeoff
    # builds on Scene and solve); pendula.scene.tradeoff keeps working, looked up
    # on first use instead of imported here, so imports run one way.
    if name in ("tradeoff", "TradeoffTable"):
        from . import _tradeoff

        return getattr(_tradeoff, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
