"""Scenes: describe a pendulum and a tolerance; the library picks the cheapest
model whose error fits, says which and why, and backs it with an error estimate.

A ``Scene`` holds the text's parameters (g, length, and either gamma or mass
and b), the initial state (theta0, omega0) at t = 0, the output times ``t``,
what is wanted and a tolerance ``tol``.  ``solve(scene)`` answers it;
``tradeoff(scene)`` measures the speed/accuracy trade of every applicable model.

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
from dataclasses import dataclass, field
import csv as _csv
import time

import numpy as np

from . import _fortran as _scene, _longcall
from ._arrays import as_real, integer_arg, real_scalar
from ._codes import INFO, INFO_SIZE, MODEL_ALIASES, MODEL_CODES, STEP_CAP, WANT_CODES
from ._config import HAVE_CVODE
from ._errors import PendulaSolverError, _text, raise_for_status
from .integrate import Events, _step_budget

MODELS = tuple(name for name in MODEL_CODES if name != "auto")
"""Model names accepted by ``solve(scene, model=...)`` (plus "auto")."""
WANTS = tuple(WANT_CODES)
"""What a scene can ask for (see ``Scene``)."""

_MODEL_NAME = {v: k for k, v in MODEL_CODES.items()}


def _model_code(model, name="model"):
    if model is None:
        return 0
    if not isinstance(model, str):
        raise TypeError(f"{name} must be a string, one of {', '.join(('auto',) + MODELS)}; "
                        f"got {type(model).__name__}")
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

    Raises ValueError (naming the argument) for inconsistent or out-of-range
    parameters, TypeError for non-real input.  The scene keeps its own copy of t.

    Batches: when theta0, omega0, g, length, gamma, mass, b or tol is an
    array (one or more dimensions), they broadcast like NumPy and ``Scene``
    returns a ``SceneBatch`` (one scene per state, t and want shared);
    ``solve``, ``run_model`` and ``tradeoff`` then answer every scene (see
    ``solve``).  A bad value in one state raises ValueError naming the state.
    """

    def __new__(cls, theta0=None, omega0=0.0, t=None, g=9.8, length=4.9, gamma=None, mass=None, b=None,
                tol=1e-6, want="state"):
        # (theta0 defaults to None here only so that pickle and copy, which call
        # __new__ with no arguments, work; __init__ still requires it)
        if cls is Scene and _is_batch(theta0, omega0, g, length, gamma, mass, b, tol):
            return _scene_batch.SceneBatch(theta0, omega0, t, g, length, gamma, mass, b, tol, want)
        return object.__new__(cls)

    def __init__(self, theta0, omega0=0.0, t=None, g=9.8, length=4.9, gamma=None, mass=None, b=None,
                 tol=1e-6, want="state"):
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
            self.g, self.length,
            0.0 if self.gamma_given is None else self.gamma_given,
            1.0 if self.mass is None else self.mass,
            0.0 if self.b is None else self.b,
            int(self.gamma_given is not None), int(self.mass is not None), int(self.b is not None))
        raise_for_status(code, msg)
        self.w0 = float(w0)
        # w0 = fl(sqrt(g/length)); the closed forms take the energy of the data
        # as given (near the separatrix a half-ulp of w0 matters): its residual
        self._w0lo = float(w0lo)
        self.gamma = float(gam)
        if t is None:
            if self.want != "period":
                raise ValueError("t is missing: give the output times (only want='period' needs none)")
            tt = np.zeros(0)
            self._scalar_t = False
        else:
            arr = as_real(t, "t")
            if arr.ndim > 1:
                raise ValueError(f"t must be a scalar or a 1-D array of output times, got shape {arr.shape}")
            self._scalar_t = arr.ndim == 0
            tt = np.ascontiguousarray(arr.reshape(-1))
            if tt.size == 0 and self.want != "period":
                raise ValueError("t has 0 elements: it needs at least 1 output time (>= 0, increasing)")
        tt.setflags(write=False)
        self.t = tt
        code, msg = _scene.scene_check_f2py(self._t_arg(), self.theta0, self.omega0, self.w0, self.gamma,
                                            self.tol, WANT_CODES[self.want], MODEL_CODES["auto"])
        raise_for_status(code, msg)

    def _t_arg(self):
        # f2py needs at least one element; a period scene without t passes a dummy
        # (scene_init ignores t for want = period when it is empty... it is not
        # empty here, so pass 0, which is a valid window for a period scene).
        return self.t if self.t.size else np.zeros(1)

    @property
    def periods(self):
        """Length of the window in small-angle periods, w0 t[-1] / (2 pi)."""
        return float(self.w0 * self.t[-1] / (2 * np.pi)) if self.t.size else 0.0

    def __repr__(self):
        damping = f"gamma={self.gamma:g}"
        if self.mass is not None:
            damping += f" (b={self.b:g}, mass={self.mass:g})"
        n = self.t.size
        window = f"t[{n}] in [{self.t[0]:g}, {self.t[-1]:g}]" if n else "no t"
        return (f"Scene(theta0={self.theta0:g}, omega0={self.omega0:g}, w0={self.w0:.6g}, {damping}, "
                f"{window}, tol={self.tol:g}, want={self.want!r})")


@dataclass(frozen=True)
class SceneResult:
    """The answer to a scene.

    model: the model used ("small_angle", "exact", "linear", "rk4", "cvode");
    reason: why it was chosen; error_estimate: estimated sup over the window of
    max(|d theta| [rad], |d Omega|/w0), for want "events" the larger of that
    and event_time_error [s]; tol_met: error_estimate <= tol;
    setting: RK4 step h [s] or CVODE rtol of the returned run (None for closed
    forms; kept for compatibility, ``step`` and ``rtol`` say which); step: the
    RK4 step h [s] (model "rk4", else None); rtol: the CVODE rtol (model
    "cvode", else None); cost: dict with closed_form_evals, rhs_evals, steps, runs
    (integrator runs, verification included), wall_time (s, inside Fortran)
    and python_wall_time (s, the whole call).

    Quantities (None when not asked for): t, theta, omega (want "state",
    "theta" -- omega None --, "final" -- scalars at t[-1] --, "energy");
    energy [1/s^2] (want "energy"); period [s] (want "period"); events
    (``pendula.Events``, want "events") and event_time_error [s].
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


def _long_scene(scene, tt, model_code, setting):
    # Predicted > ~50 ms: an integrated window of more than a few dozen
    # periods, a fixed RK4 run of more than _longcall.RK4_LONG_STEPS steps, or many outputs.
    # Closed forms (gamma = 0, or the linear model) are fast per point.
    span = float(tt[-1]) if tt.size else 0.0
    if tt.size > 100_000:
        return True
    if model_code == MODEL_CODES["rk4"] and setting > 0:
        return span / setting > _longcall.RK4_LONG_STEPS
    closed_undamped = (MODEL_CODES[name] for name in ("auto", "small_angle", "exact"))
    if scene.gamma == 0 and model_code in closed_undamped:
        return False
    return scene.w0 * span / (2 * np.pi) > 50


def _budget(max_steps):
    return float(min(_step_budget(max_steps), 2**62))


_MAX_EVENT_SLOTS = 2**30


def _event_slots(scene, tt):
    # Fortran's rigorous bound on the events of the window (scene_event_bound),
    # so that one solve always has room for them all.
    if scene.want != "events":
        return 1
    return int(min(_MAX_EVENT_SLOTS, _scene.scene_event_bound_f2py(scene.w0, float(tt[-1]), scene.theta0,
                                                                    scene.omega0)))


def _run(scene, model_code, fixed, setting, max_steps=STEP_CAP, progress=None, control=None):
    # control: a batch thread's control array (the batch layer watches it)
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a pendula.Scene, got {type(scene).__name__}")
    tt = scene._t_arg()
    m = _event_slots(scene, tt)
    budget = _budget(max_steps)
    watched = control is None
    long = watched and _long_scene(scene, tt, model_code, float(setting))
    start = time.perf_counter()
    control = _longcall.new_control() if watched else control
    args = (tt, scene.theta0, scene.omega0, scene.w0, scene._w0lo, scene.gamma, scene.tol, WANT_CODES[scene.want],
            model_code, int(fixed), float(setting), m, INFO_SIZE, budget, control)
    out = _longcall.run(lambda: _scene.scene_solve_f2py(*args), control, long, progress if watched else None,
                        unit="step")
    (nout, tout, theta, omega, energy, ev_t, ev_kind, ev_theta, ev_omega, n_ev, model_out, info,
     reason, code, msg) = out
    raise_for_status(code, msg)
    if int(n_ev) > m:
        raise PendulaSolverError(f"the window holds {int(n_ev)} events, more than the {m} this "
                                 "Python layer keeps: shorten the window")
    wall = time.perf_counter() - start
    return (int(nout), tout, theta, omega, energy, ev_t, ev_kind, ev_theta, ev_omega, int(n_ev),
            int(model_out), info, reason, wall)


def _result(scene, raw):
    (nout, tout, theta, omega, energy, ev_t, ev_kind, ev_theta, ev_omega, n_ev, model_out, info, reason,
     wall) = raw
    num = {name: float(info[i]) for name, i in INFO.items()}
    model = _MODEL_NAME.get(model_out, "unknown")
    cost = {name: int(num[name]) for name in ("closed_form_evals", "rhs_evals", "steps", "runs")}
    cost.update(wall_time=num["wall_time"], python_wall_time=wall)
    kw = {}
    want = scene.want
    if want in ("state", "theta", "energy"):
        t = tout[:nout].copy()
        th = theta[:nout].copy()
        om = omega[:nout].copy()
        if scene._scalar_t:
            t, th, om = float(t[0]), float(th[0]), float(om[0])
        kw.update(t=t, theta=th, omega=None if want == "theta" else om)
        if want == "energy":
            e = energy[:nout].copy()
            kw.update(energy=float(e[0]) if scene._scalar_t else e)
            if model == "exact":   # conserved: no time series was evaluated
                kw.update(theta=None, omega=None)
    elif want == "final":
        kw.update(t=float(tout[0]), theta=float(theta[0]), omega=float(omega[0]))
    elif want == "period":
        kw.update(period=num["period"])
    elif want == "events":
        n = n_ev
        kw.update(events=Events(t=ev_t[:n].copy(), kind=ev_kind[:n].astype(np.int64),
                                theta=ev_theta[:n].copy(), omega=ev_omega[:n].copy(), truncated=False),
                  event_time_error=num["event_time_error"])
    integrated = model in ("rk4", "cvode")
    return SceneResult(model=model, reason=_text(reason), error_estimate=num["error_estimate"],
                       tol_met=bool(num["tol_met"]), setting=num["setting"] if integrated else None,
                       step=num["step"] if model == "rk4" else None,
                       rtol=num["rtol"] if model == "cvode" else None, cost=cost, **kw)


def solve(scene, model=None, max_steps=STEP_CAP, progress=None, threads=0):
    """Answer ``scene`` with the cheapest model whose error estimate is <= scene.tol.

    model: None or "auto" to let the library choose, or one of ``MODELS`` to
    force it (its setting is still chosen from tol and verified).  Returns a
    ``SceneResult`` (model, reason, error_estimate, tol_met, cost, and the
    wanted quantities).  When no model can meet tol (e.g. tol below the
    rounding floor of the exact solution over a long window), the most accurate
    one is used and ``tol_met`` is False with the reason saying so.

    max_steps: work budget in RK4 steps (a CVODE step counts as
    ``pendula._codes.CVODE_STEP_COST``; the default ``STEP_CAP`` is about a
    minute of CPU): a solve predicted to need more is
    refused before it starts, with a message naming what to change (window,
    tol, or a larger max_steps).  Long solves stop on Ctrl-C
    (KeyboardInterrupt within a millisecond or so).  progress: True for a
    tqdm bar (needs tqdm) or a callable(done, total) called about every 20 ms
    with the integrator's work so far (RK4 steps / CVODE right-hand-side
    evaluations; total None).

    Raises ValueError for an unknown model name or a model that does not apply
    (small_angle/exact with gamma > 0), NotImplementedError for "cvode" in a
    build without SUNDIALS, ``PendulaSolverError`` when an integrator fails.

    A ``SceneBatch`` (``Scene`` with array parameters) gives a
    ``SceneBatchResult``: every scene solved as alone (bit for bit) on
    ``threads`` threads (0: OMP_NUM_THREADS or every core), per-scene codes
    and messages for the scenes whose solve failed (the others keep their
    answers), stacked quantities with the batch shape in front; the call
    raises only when every scene failed.  progress counts scenes; Ctrl-C
    stops every thread.
    """
    code = _model_code(model)
    if isinstance(scene, _scene_batch.SceneBatch):
        return _scene_batch.run(scene, code, False, 0.0, max_steps, progress, threads)
    _check_threads(threads)
    return _result(scene, _run(scene, code, False, 0.0, max_steps, progress))


def run_model(scene, model, setting=None, max_steps=STEP_CAP, progress=None, threads=0):
    """Run one model on ``scene`` at a fixed setting, with no choice and no verification.

    setting: RK4 step h [s] or CVODE rtol (atol = rtol * state scale / 100);
    ignored for the closed forms.  For work-precision studies (``tradeoff``).
    max_steps, progress, Ctrl-C, threads and batches: as for ``solve`` (an RK4 run of more than
    max_steps steps is refused up front).
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
    if isinstance(scene, _scene_batch.SceneBatch):
        return _scene_batch.run(scene, code, True, setting, max_steps, progress, threads)
    _check_threads(threads)
    return _result(scene, _run(scene, code, True, setting, max_steps, progress))


def _check_threads(threads):
    if threads != 0 or type(threads) is not int:
        _threads(threads)   # checked, unused: one scene runs on one thread


class TradeoffTable:
    """Rows of a speed/accuracy study (see ``tradeoff``).

    rows: list of dicts with model, setting, sup_error [rad] (sup over the
    output grid of max(|d theta|, |d Omega|/w0) against the reference),
    wall_time [s] (best of the repeats, the whole Python call),
    rhs_evals, closed_form_evals, error_estimate (what the model claimed, 0
    when unverified).  reference: how the reference was made;
    reference_result: the reference itself (a ``SceneResult``).
    """

    COLUMNS = ("model", "setting", "sup_error", "wall_time", "rhs_evals", "closed_form_evals",
               "error_estimate")

    def __init__(self, scene, rows, reference, reference_result=None):
        self.scene = scene
        self.rows = rows
        self.reference = reference
        self.reference_result = reference_result

    def __iter__(self):
        return iter(self.rows)

    def __len__(self):
        return len(self.rows)

    def __getitem__(self, i):
        return self.rows[i]

    def column(self, name):
        """One column as a list."""
        return [r[name] for r in self.rows]

    def to_csv(self, path):
        """Write the table as CSV (one row per run); returns the path."""
        with open(path, "w", newline="") as fh:
            w = _csv.DictWriter(fh, fieldnames=self.COLUMNS, extrasaction="ignore")
            w.writeheader()
            for r in self.rows:
                w.writerow(r)
        return path

    def plot(self, path, title=None, ax=None):
        """Work-precision plot: sup error against wall time, log-log, one line per model
        (``pendula.figures.work_precision_plot``).  ax: draw into these axes (path
        may then be None); returns the path written, or None."""
        from .figures import tradeoff_rows, work_precision_plot
        return work_precision_plot(tradeoff_rows(self), path, title=title or "Work-precision",
                                   tol=self.scene.tol, ax=ax)


def _sup_error(theta, omega, ref_theta, ref_omega, w0):
    return float(max(np.max(np.abs(theta - ref_theta)), np.max(np.abs(omega - ref_omega)) / w0))


def _timed(fn, repeat):
    best = np.inf
    out = None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return out, best


def _count(x, name):
    return integer_arg(x, name, 1, 2**63 - 1, scalar=True)


def _positive_list(xs, name):
    if xs is None:
        return None
    arr = as_real(xs, name)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D list of settings, got shape {arr.shape}")
    bad = [float(v) for v in arr if not (np.isfinite(v) and v > 0)]
    if bad:
        raise ValueError(f"{name} contains {bad[0]}: every setting must be finite and > 0")
    return [float(v) for v in arr]


def tradeoff(scene, models=None, rk4_steps=None, cvode_rtols=None, repeat=3, csv=None, plot=None,
             max_steps=2_000_000):
    """Measure the speed/accuracy trade of every applicable model on ``scene``.

    Runs the closed forms that apply (small_angle and exact when gamma = 0,
    linear otherwise), RK4 over a range of steps h (halving from just inside
    the stability limit while the run stays under ``max_steps`` steps) and
    CVODE over rtol = 1e-3 ... 1e-12 (when built), each at a FIXED setting with
    no verification, on the state (theta, Omega) at scene.t.  The error is the
    sup over the output grid of max(|d theta|, |d Omega|/w0) against a
    reference: the exact elliptic solution when gamma = 0, otherwise
    ``solve`` at tol = 1e-12 with RK4 (or the automatic choice when that
    estimates better; verified a posteriori, its estimate is reported in
    ``table.reference``).  Wall time is the best of ``repeat``
    calls.  models: subset of ``MODELS`` to run; rk4_steps / cvode_rtols:
    explicit settings.  csv / plot: paths to also write the CSV and a log-log
    work-precision PNG.  Returns a ``TradeoffTable``; for a ``SceneBatch``,
    an object array of them with the batch shape (the scenes run one after
    another, so that their wall times do not compete for cores; csv/plot
    are refused for a batch).
    """
    if isinstance(scene, _scene_batch.SceneBatch):
        if csv is not None or plot is not None:
            raise ValueError("csv and plot take one scene: call tradeoff per scene of the batch to write them")
        return _scene_batch.tradeoff(scene, models=models, rk4_steps=rk4_steps, cvode_rtols=cvode_rtols,
                                     repeat=repeat, max_steps=max_steps)
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a pendula.Scene, got {type(scene).__name__}")
    if scene.t.size < 1:
        raise ValueError("tradeoff needs output times: the scene has no t")
    repeat = _count(repeat, "repeat")
    max_steps = _count(max_steps, "max_steps")
    if isinstance(models, str):
        raise ValueError(f"models = {models!r} must be a list of model names, e.g. [{models!r}]")
    rk4_steps = _positive_list(rk4_steps, "rk4_steps")
    cvode_rtols = _positive_list(cvode_rtols, "cvode_rtols")
    st = Scene(theta0=scene.theta0, omega0=scene.omega0, t=scene.t, g=scene.g, length=scene.length,
               gamma=scene.gamma, tol=scene.tol, want="state")
    damped = st.gamma > 0
    applicable = ["linear", "rk4"] if damped else ["small_angle", "exact", "rk4"]
    if HAVE_CVODE:
        applicable.append("cvode")
    if models is None:
        models = applicable
    else:
        for mname in models:
            _model_code(mname, "models")
        bad = [mname for mname in models if mname not in applicable]
        if bad:
            raise ValueError(f"models {bad} do not apply to this scene (applicable: {applicable})")
    if damped:
        ref_scene = Scene(theta0=st.theta0, omega0=st.omega0, t=st.t, g=st.g, length=st.length,
                          gamma=st.gamma, tol=1e-12, want="state")
        # RK4 first (fixed steps, verified at 2h; its many cheap steps are fine for a
        # reference), the automatic choice when RK4 cannot meet 1e-12 (stiff, long)
        ref = solve(ref_scene, model="rk4")
        if not ref.tol_met:
            alt = solve(ref_scene)
            if alt.error_estimate < ref.error_estimate:
                ref = alt
        reference = (f"converged integration: solve(tol=1e-12) -> {ref.model} at setting {ref.setting:.3g}, "
                     f"its a posteriori estimate {ref.error_estimate:.2g} rad")
    else:
        ref = run_model(st, "exact")
        reference = f"exact elliptic solution (rounding estimate {ref.error_estimate:.2g} rad)"
    rows = []

    def add(name, setting, fn):
        res, wall = _timed(fn, repeat)
        rows.append({"model": name, "setting": setting,
                     "sup_error": _sup_error(res.theta, res.omega, ref.theta, ref.omega, st.w0),
                     "wall_time": wall, "rhs_evals": res.cost["rhs_evals"],
                     "closed_form_evals": res.cost["closed_form_evals"],
                     "error_estimate": res.error_estimate})

    tend = float(st.t[-1])
    for name in models:
        if name in ("small_angle", "exact", "linear"):
            add(name, "closed form", lambda name=name: run_model(st, name))
        elif name == "rk4":
            from .integrate import rk4_max_stable_step
            steps = rk4_steps
            if steps is None:
                h = 0.9 * rk4_max_stable_step(st.w0, st.gamma)
                steps = []
                while tend / h <= max_steps and len(steps) < 14:
                    steps.append(h)
                    h /= 2
            for h in steps:
                add("rk4", f"h={h:.3g}", lambda h=h: run_model(st, "rk4", h))
        elif name == "cvode":
            rtols = cvode_rtols if cvode_rtols is not None else [10.0**-k for k in range(3, 13)]
            for r in rtols:
                try:
                    add("cvode", f"rtol={r:.0e}", lambda r=r: run_model(st, "cvode", r))
                except RuntimeError:
                    pass   # budget exhausted at this setting: no point to plot
    table = TradeoffTable(st, rows, reference, ref)
    if csv is not None:
        table.to_csv(csv)
    if plot is not None:
        table.plot(plot)
    return table


# Last: the batch layer builds on this module's Scene, _run and _result.
from . import _scene_batch  # noqa: E402
from ._batch import _threads  # noqa: E402
from ._ensemble import is_batch as _is_batch  # noqa: E402
from ._scene_batch import SceneBatch, SceneBatchResult  # noqa: E402

__all__ = ["Scene", "SceneResult", "solve", "run_model", "tradeoff", "TradeoffTable", "SceneBatch",
           "SceneBatchResult"]
