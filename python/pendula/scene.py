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

With a drive (``Scene(..., drive=pendula.Drive(...))``, amplitude != 0)
the models are ``"linear"`` -- the linearised driven damped oscillator in
closed form (torque drive), with the undriven linear model's nonlinearity
bound over the motion's amplitude -- and ``"rk4"`` -- the driven RK4 kernel,
whole steps per drive period, checked by a run at half the steps; want
"period" and "events" are refused (``pendula_scene_driven``).

The model and want names, the codes and the limits come from the Fortran
core (``pendula._codes``, generated at build time); so do all the rules on a
scene: this module passes its arguments through.

Units: angles rad, Omega rad/s, t s, g m/s^2, length m, mass kg, b kg/s,
gamma and w0 1/s, energies per unit m l^2 in 1/s^2.
"""

from __future__ import annotations

from typing import Callable

from . import _fortran as _scene  # noqa: F401 (the f2py module: tests patch and call it here)
from ._arrays import real_scalar
from ._codes import MODEL_CODES
from ._config import HAVE_CVODE  # noqa: F401 (read by benchmarks/bench_scenes.py)
from ._defaults import STEP_CAP, THREADS, check_threads
from ._many.scenes import SceneBatch, SceneBatchResult
from ._scene_call import _batch_run, _long_scene, _result, _run  # noqa: F401 (_long_scene: tests)
from ._scene_types import MODELS, WANTS, Scene, SceneResult, _model_code  # noqa: F401


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


__all__ = ["Scene", "SceneResult", "solve", "run_model", "SceneBatch", "SceneBatchResult"]


def __getattr__(name):
    # tradeoff and TradeoffTable live a layer above this module (pendula._tradeoff
    # builds on Scene and solve); pendula.scene.tradeoff keeps working, looked up
    # on first use instead of imported here, so imports run one way.
    if name in ("tradeoff", "TradeoffTable"):
        from . import _tradeoff

        return getattr(_tradeoff, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
