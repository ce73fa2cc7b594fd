"""Speed/accuracy trade of every model on a scene: ``tradeoff`` and ``TradeoffTable``.

Each applicable model runs at fixed settings (no choice, no verification) on
the scene's output grid; its error is measured against one reference, the
same for every row.
"""
import csv as _csv
import time

import numpy as np

from . import _scene_batch
from ._arrays import as_real, integer_arg
from ._config import HAVE_CVODE
from .scene import Scene, _model_code, run_model, solve


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
