"""Speed/accuracy trade of every model on a scene: ``tradeoff`` and ``TradeoffTable``.

Each applicable model runs at fixed settings (no choice, no verification) on
the scene's output grid, and so do SciPy's ``solve_ivp`` methods when SciPy
is installed (what a user would otherwise pick); every row's error is
measured against the same reference by the same measure.

RK4 between two output times takes the fewest equal substeps of at most h:
on a grid spaced dt, every h >= dt runs the same steps.  The table shows the
step actually used (``step_used``, the window over the steps taken) and keeps
one row per distinct run.
"""

from __future__ import annotations

import csv as _csv

import numpy as np

from . import _scipy_rows, _tables
from ._arrays import as_real, integer_arg
from ._config import HAVE_CVODE
from ._many.scenes import SceneBatch
from ._scipy_rows import SCIPY_METHODS, _sup_error, _timed  # noqa: F401 (SCIPY_METHODS: named in the docs)
from .integrate import rk4_max_stable_step
from .scene import Scene, _model_code, run_model, solve

SCIPY_RTOLS = (1e-3, 1e-6, 1e-9)
TAYLOR_TOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14)  # tols of the default taylor rows
"""Default rtols of the SciPy rows (atol = rtol * state scale / 100, as CVODE's)."""
_RK4_ROWS = 14  # default RK4 rows: distinct used steps, halving


class TradeoffTable:
    """Rows of a speed/accuracy study, one per run (built by ``tradeoff``).

    Parameters
    ----------
    scene : Scene
        The scene measured (want "state").
    rows : list of dict
        One dict per run with the keys of ``COLUMNS``.
    reference : str
        How the reference was made.
    reference_result : SceneResult, optional
        The reference itself.

    Attributes
    ----------
    rows : list of dict
        model (a pendula model, or ``"scipy <method>"``); setting (the
        requested ``"h=..."``, ``"rtol=..."`` or ``"closed form"``);
        step_used [s] (RK4: the window over the steps taken, the step
        actually used on a uniform grid; None for the others); steps (RK4
        steps, or None); sup_error [rad] (sup over the output grid of
        max(abs(d theta), abs(d Omega)/w0) against the reference);
        wall_time [s] (best of the repeats, the whole Python call);
        rhs_evals; closed_form_evals; error_estimate [rad] (what the model
        claimed, 0 when unverified).
    scene, reference, reference_result
        As given.

    Notes
    -----
    ``str(table)`` is the whole table, aligned; ``repr`` a few lines.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> scene = pendula.Scene(0.5, t=np.linspace(0, 2, 5))
    >>> table = pendula.tradeoff(scene, models=["exact", "rk4"], rk4_steps=[0.1, 0.05], repeat=1,
    ...                          scipy=False)
    >>> table.column("model")
    ['exact', 'rk4', 'rk4']
    >>> print(table)  # doctest: +ELLIPSIS
    model ...
    """

    COLUMNS = (
        "model",
        "setting",
        "sup_error",
        "wall_time",
        "rhs_evals",
        "closed_form_evals",
        "error_estimate",
        "step_used",
        "steps",
    )

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
        """One column as a list.

        Parameters
        ----------
        name : str
            One of ``COLUMNS``.

        Returns
        -------
        list
            The column's values, one per row.

        Raises
        ------
        KeyError
            For a name not in ``COLUMNS``.

        Examples
        --------
        >>> import pendula
        >>> table = pendula.tradeoff(pendula.Scene(0.5, t=[0.0, 1.0]), models=["exact"], repeat=1)
        >>> table.column("setting")
        ['closed form']
        """
        return [r[name] for r in self.rows]

    def _best(self):
        best = {}
        for r in self.rows:
            if r["model"] not in best or r["sup_error"] < best[r["model"]]["sup_error"]:
                best[r["model"]] = r
        return ", ".join(f"{m} {r['sup_error']:.2g} rad in {r['wall_time']:.2g} s" for m, r in best.items())

    def __repr__(self):
        return _tables.block(
            "TradeoffTable",
            [
                f"{len(self.rows)} rows, models: {_tables.counts([r['model'] for r in self.rows])}",
                f"scene: {self.scene!r}",
                f"reference: {self.reference}",
                f"smallest sup_error per model: {self._best() or 'none'}",
                "print(table) shows the rows; table.to_pandas() gives a DataFrame",
            ],
        )

    def __str__(self):
        head = (
            "model",
            "setting",
            "step_used_s",
            "sup_error_rad",
            "wall_time_s",
            "rhs_evals",
            "closed_form_evals",
            "error_estimate",
        )
        body = [
            (
                r["model"],
                r["setting"],
                "-" if r["step_used"] is None else f"{r['step_used']:.4g}",
                f"{r['sup_error']:.3g}",
                f"{r['wall_time']:.3g}",
                str(r["rhs_evals"]),
                str(r["closed_form_evals"]),
                f"{r['error_estimate']:.3g}",
            )
            for r in self.rows
        ]
        widths = [max(len(x) for x in col) for col in zip(head, *body)]
        lines = ["  ".join(x.ljust(w) for x, w in zip(line, widths)).rstrip() for line in [head] + body]
        return "\n".join(lines + [f"reference: {self.reference}"])

    def to_pandas(self):
        """The table as a pandas DataFrame, one row per run.

        Returns
        -------
        pandas.DataFrame
            The columns of ``COLUMNS``; ``attrs["reference"]`` says how the
            reference was made.

        Raises
        ------
        ImportError
            When pandas is not installed.

        Examples
        --------
        >>> import pendula
        >>> table = pendula.tradeoff(pendula.Scene(0.5, t=[0.0, 1.0]), models=["exact"], repeat=1)
        >>> table.to_pandas()[["model", "setting"]].values.tolist()
        [['exact', 'closed form']]
        """
        pd = _tables.optional("pandas")
        out = pd.DataFrame([{k: r[k] for k in self.COLUMNS} for r in self.rows], columns=list(self.COLUMNS))
        out.attrs["reference"] = self.reference
        return out

    def to_csv(self, path):
        """Write the table as CSV, one row per run.

        Parameters
        ----------
        path : str or path-like
            The file to write (overwritten).

        Returns
        -------
        str or path-like
            ``path``.

        Raises
        ------
        OSError
            When the file cannot be written.

        Examples
        --------
        >>> import os, tempfile, pendula
        >>> table = pendula.tradeoff(pendula.Scene(0.5, t=[0.0, 1.0]), models=["exact"], repeat=1)
        >>> path = table.to_csv(os.path.join(tempfile.mkdtemp(), "t.csv"))
        >>> open(path).readline().strip()
        'model,setting,sup_error,wall_time,rhs_evals,closed_form_evals,error_estimate,step_used,steps'
        """
        with open(path, "w", newline="") as fh:
            w = _csv.DictWriter(fh, fieldnames=self.COLUMNS, extrasaction="ignore")
            w.writeheader()
            for r in self.rows:
                w.writerow(r)
        return path

    def plot(self, path, title=None, ax=None):
        """Work-precision plot: sup error against wall time, log-log, one line per model.

        Parameters
        ----------
        path : str or path-like or None
            PNG to write (None with ``ax``: draw only).
        title : str, optional
            Plot title (default "Work-precision").
        ax : matplotlib Axes, optional
            Draw into these axes.

        Returns
        -------
        str or None
            The path written, or None.

        Raises
        ------
        ImportError
            When matplotlib is not installed.

        Notes
        -----
        Drawn by ``pendula.figures.work_precision_plot``; the scene's tol is a
        horizontal line.

        Examples
        --------
        >>> import os, tempfile, pendula
        >>> table = pendula.tradeoff(pendula.Scene(0.5, t=[0.0, 1.0]), models=["exact"], repeat=1)
        >>> os.path.basename(table.plot(os.path.join(tempfile.mkdtemp(), "wp.png")))
        'wp.png'
        """
        from .figures import tradeoff_rows, work_precision_plot

        return work_precision_plot(
            tradeoff_rows(self), path, title=title or "Work-precision", tol=self.scene.tol, ax=ax
        )


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


def tradeoff(
    scene: Scene | SceneBatch,
    models=None,
    rk4_steps=None,
    cvode_rtols=None,
    repeat: int = 3,
    csv=None,
    plot=None,
    max_steps: int = 2000000,
    scipy=None,
    scipy_rtols=None,
) -> TradeoffTable | np.ndarray:
    """Measure the speed/accuracy trade of every applicable model on ``scene``.

    Parameters
    ----------
    scene : Scene or SceneBatch
        The scene (its t, parameters and initial state; want is ignored:
        the state (theta, Omega) at t is measured).
    models : list of str, optional
        Subset of ``MODELS`` to run (default: every one that applies --
        small_angle and exact when gamma = 0, linear otherwise, rk4,
        cvode when built, and taylor at the tols ``TAYLOR_TOLS``; for a
        driven scene linear (torque drive) and rk4, the driven models).
    rk4_steps : list of float, optional
        RK4 steps h [s] > 0 (default: halving from 0.9 of the stability
        limit, up to 14 distinct used steps while a run stays under
        ``max_steps`` steps).
    cvode_rtols : list of float, optional
        CVODE rtols > 0 (default 1e-3 ... 1e-12).
    repeat : int
        Runs per row (>= 1); the wall time is the best of them.
    csv, plot : str or path-like, optional
        Also write the CSV / a log-log work-precision PNG there.
    max_steps : int
        RK4 step budget of the default steps (>= 1).
    scipy : bool or list of str, optional
        Add ``scipy.integrate.solve_ivp`` rows: True for ``SCIPY_METHODS``
        (RK45, DOP853, Radau, LSODA), a list for those methods, False for
        none; None (default): True when SciPy is installed and ``models``
        is not given.
    scipy_rtols : list of float, optional
        rtols of the SciPy rows (default ``SCIPY_RTOLS``).

    Returns
    -------
    TradeoffTable or numpy.ndarray
        The table; for a ``SceneBatch``, an object array of tables with the
        batch shape (the scenes run one after another, so that their wall
        times do not compete for cores).

    Raises
    ------
    ValueError
        For a model that does not apply, bad settings or counts, csv/plot
        with a batch.
    TypeError
        When scene is not a Scene, or scipy is not None, a bool or a list
        of method names.
    ImportError
        For ``scipy=True`` (or a list) without SciPy installed.

    Notes
    -----
    Each model runs at a FIXED setting with no verification.  The error
    of every row is the sup over the output grid of max(abs(d theta),
    abs(d Omega)/w0) [rad] against one reference: the exact elliptic
    solution when gamma = 0 (undriven), otherwise ``solve`` at tol = 1e-12 with RK4
    (the driven RK4 kernel for a driven scene; or the automatic choice, or the Taylor series at tol = 1e-15, when
    that estimates better; its estimate is in ``table.reference``).  Taylor
    rows run the Taylor series at each tol (its setting).  RK4 between output times takes
    the fewest equal substeps of at most h, so every h above the output
    spacing runs the same steps: ``step_used`` shows the step taken and
    rows that repeat another's run are dropped.  SciPy rows use atol =
    rtol * S / 100 (S: the state scale max(abs(theta0), abs(omega0)/w0),
    Omega's scaled by w0) and the analytic Jacobian for the implicit
    methods; an explicit method is skipped when stability alone would
    need more than ``max_steps`` steps (stiff scenes), and a method's
    tighter rtols are skipped once a run takes over a second.

    Examples
    --------
    >>> import numpy as np, pendula
    >>> scene = pendula.Scene(0.5, t=np.linspace(0, 2, 21))
    >>> table = pendula.tradeoff(scene, models=["rk4"], rk4_steps=[0.4, 0.2, 0.1, 0.05], repeat=1)
    >>> table.column("step_used")   # h = 0.4 and 0.2 both run 0.1 s steps
    [0.1, 0.05]
    """
    if isinstance(scene, SceneBatch):
        if csv is not None or plot is not None:
            raise ValueError("csv and plot take one scene: call tradeoff per scene of the batch to write them")
        # the scenes one after another: their wall times must not compete for cores
        out = np.empty(scene.scenes.size, dtype=object)
        for i, sc in enumerate(scene.scenes.reshape(-1)):
            out[i] = tradeoff(
                sc,
                models=models,
                rk4_steps=rk4_steps,
                cvode_rtols=cvode_rtols,
                repeat=repeat,
                max_steps=max_steps,
                scipy=scipy,
                scipy_rtols=scipy_rtols,
            )
        return out.reshape(scene.shape)
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
    methods = _scipy_rows.methods(scipy, models is None)
    scipy_rtols = _positive_list(scipy_rtols, "scipy_rtols") or list(SCIPY_RTOLS)
    st = Scene(
        theta0=scene.theta0,
        omega0=scene.omega0,
        t=scene.t,
        g=scene.g,
        length=scene.length,
        gamma=scene.gamma,
        tol=scene.tol,
        want="state",
        drive=scene.drive,
    )
    models = _models(st, models)
    ref, reference = _reference(st)
    rows = []
    seen = set()

    def add(name, setting, fn):
        res, wall = _timed(fn, 1)  # one run says whether it repeats another row's
        integrated = name in ("rk4", "cvode", "taylor")
        steps = res.cost["steps"] if integrated else None
        used = float(st.t[-1]) / steps if name == "rk4" and steps else None
        key = (name, used if name == "rk4" else setting)
        if key in seen:
            return False
        seen.add(key)
        if repeat > 1:
            res, wall2 = _timed(fn, repeat - 1)
            wall = min(wall, wall2)
        rows.append(
            {
                "model": name,
                "setting": setting,
                "sup_error": _sup_error(res.theta, res.omega, ref.theta, ref.omega, st.w0),
                "wall_time": wall,
                "rhs_evals": res.cost["rhs_evals"],
                "closed_form_evals": res.cost["closed_form_evals"],
                "error_estimate": res.error_estimate,
                "step_used": used,
                "steps": steps,
            }
        )
        return True

    tend = float(st.t[-1])
    for name in models:
        if name in ("small_angle", "exact", "linear"):
            add(name, "closed form", lambda name=name: run_model(st, name))
        elif name == "rk4" and rk4_steps is not None:
            for h in rk4_steps:
                add("rk4", f"h={h:.3g}", lambda h=h: run_model(st, "rk4", h))
        elif name == "rk4":
            h, kept = 0.9 * rk4_max_stable_step(st.w0, st.gamma), 0
            while tend / h <= max_steps and kept < _RK4_ROWS:
                kept += add("rk4", f"h={h:.3g}", lambda h=h: run_model(st, "rk4", h))
                h /= 2
        elif name == "cvode":
            rtols = cvode_rtols if cvode_rtols is not None else [10.0**-k for k in range(3, 13)]
            for r in rtols:
                try:
                    add("cvode", f"rtol={r:.0e}", lambda r=r: run_model(st, "cvode", r))
                except RuntimeError:
                    pass  # budget exhausted at this setting: no point to plot
        elif name == "taylor":
            for tl in TAYLOR_TOLS:
                sc = Scene(
                    theta0=st.theta0,
                    omega0=st.omega0,
                    t=st.t,
                    g=st.g,
                    length=st.length,
                    gamma=st.gamma,
                    tol=tl,
                    want="state",
                )
                add("taylor", f"tol={tl:.0e}", lambda sc=sc: run_model(sc, "taylor"))
    for m in methods:
        rows += _scipy_rows.rows(st, m, scipy_rtols, ref, repeat, max_steps)
    table = TradeoffTable(st, rows, reference, ref)
    if csv is not None:
        table.to_csv(csv)
    if plot is not None:
        table.plot(plot)
    return table


def _driven(st):
    return st.drive is not None and st.drive.amplitude != 0


def _models(st, models):
    if _driven(st):  # the linearised driven oscillator (torque drive) and the driven RK4 kernel
        applicable = ["linear", "rk4"] if st.drive.kind == "torque" else ["rk4"]
    else:
        applicable = ["linear", "rk4"] if st.gamma > 0 else ["small_angle", "exact", "rk4"]
        if HAVE_CVODE:
            applicable.append("cvode")
        applicable.append("taylor")
    if models is None:
        return applicable
    for mname in models:
        _model_code(mname, "models")
    bad = [mname for mname in models if mname not in applicable]
    if bad:
        raise ValueError(f"models {bad} do not apply to this scene (applicable: {applicable})")
    return models


def _reference(st):
    """(reference SceneResult, how it was made) for the state scene st."""
    if _driven(st):  # the driven RK4 kernel at tol = 1e-12, Richardson-checked
        ref = solve(
            Scene(st.theta0, st.omega0, t=st.t, g=st.g, length=st.length, gamma=st.gamma, tol=1e-12, drive=st.drive),
            model="rk4",
        )
        return ref, f"the driven RK4 kernel at tol = 1e-12, its a posteriori estimate {ref.error_estimate:.2g} rad"
    if st.gamma == 0:
        ref = run_model(st, "exact")
        return ref, f"exact elliptic solution (rounding estimate {ref.error_estimate:.2g} rad)"
    ref_scene = Scene(
        theta0=st.theta0, omega0=st.omega0, t=st.t, g=st.g, length=st.length, gamma=st.gamma, tol=1e-12, want="state"
    )
    # RK4 first (fixed steps, verified at 2h; its many cheap steps are fine for a
    # reference), the automatic choice when RK4 cannot meet 1e-12 (stiff, long)
    ref = solve(ref_scene, model="rk4")
    if not ref.tol_met:
        alt = solve(ref_scene)
        if alt.error_estimate < ref.error_estimate:
            ref = alt
    # the Taylor series at its floor, when it estimates better (the taylor rows reach below 1e-12)
    alt = run_model(
        Scene(
            theta0=st.theta0,
            omega0=st.omega0,
            t=st.t,
            g=st.g,
            length=st.length,
            gamma=st.gamma,
            tol=1e-15,
            want="state",
        ),
        "taylor",
    )
    if alt.error_estimate < ref.error_estimate:
        return alt, f"the Taylor series at tol = 1e-15, its error estimate {alt.error_estimate:.2g} rad"
    return ref, (
        f"converged integration: solve(tol=1e-12) -> {ref.model} at setting {ref.setting:.3g}, "
        f"its a posteriori estimate {ref.error_estimate:.2g} rad"
    )


__all__ = ["tradeoff", "TradeoffTable"]
