"""The scene's value types: ``Scene`` (parameters, initial state, window,
want, tolerance) and ``SceneResult`` (the answer), and the model and want
names; ``pendula.scene`` is the public face (see its docstring)."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from . import _fortran as _scene
from . import _tables
from ._arrays import SharedTimes, as_real, real_scalar
from ._codes import MODEL_ALIASES, MODEL_CODES, WANT_CODES
from ._defaults import G_DEFAULT, LENGTH_DEFAULT, TOL
from ._errors import raise_for_status
from ._many.ensemble import is_batch as _is_batch
from ._many.scenes import SceneBatch
from .driven import Drive
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
    drive : Drive, optional
        A periodic drive (``pendula.Drive``: a torque F cos(Omega t + phi) or a
        vertically driven pivot), shared by every scene of a batch.  With a
        drive of amplitude != 0 the models are ``"linear"`` (the linearised
        driven damped oscillator in closed form, torque drive only, with the
        linear model's nonlinearity bound) and ``"rk4"`` (the driven RK4
        kernel, N steps per drive period, verified by a run at N/2); want
        ``"period"`` and ``"events"`` are refused.  Amplitude 0: exactly the
        undriven scene.

    Attributes
    ----------
    theta0, omega0, g, length, tol, want, t
        As given (t: a read-only 1-D copy).
    w0, gamma : float
        sqrt(g/length) and the damping rate [1/s] the scene uses.
    mass, b, gamma_given, drive
        As given, or None.

    Raises
    ------
    ValueError
        For inconsistent or out-of-range parameters, naming the argument.
    TypeError
        For non-real input, a want that is not a string or a drive that is
        not a ``pendula.Drive``.

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
    >>> small = pendula.Scene(0.003, t=[0.0, 5.0], gamma=0.3, drive=pendula.Drive("torque", 0.002, 1.2))
    >>> pendula.solve(small).model   # the linearised driven oscillator: no integration
    'linear'
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
        drive=None,
    ):
        # (theta0 defaults to None here only so that pickle and copy, which call
        # __new__ with no arguments, work; __init__ still requires it)
        if cls is Scene and _is_batch(theta0, omega0, g, length, gamma, mass, b, tol):
            make = Scene if drive is None else functools.partial(Scene, drive=drive)  # one drive for the batch
            return SceneBatch(theta0, omega0, t, g, length, gamma, mass, b, tol, want, make=make)
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
        drive: Drive | None = None,
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
        if drive is not None and not isinstance(drive, Drive):
            raise TypeError(f"drive must be a pendula.Drive or None, got {type(drive).__name__}")
        self.drive = drive
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
            *self._drive_args(),
        )
        raise_for_status(code, msg)

    def _drive_args(self):
        # the drive as the f2py glue takes it: has_drive, kind code, amplitude, frequency, phase
        d = self.__dict__.get("drive")
        if d is None:
            return (0, 1, 0.0, 1.0, 0.0)
        return (1, d.code, d.amplitude, d.frequency, d.phase)

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
        drive = "" if self.__dict__.get("drive") is None else f", drive={self.drive!r}"
        return (
            f"Scene(theta0={self.theta0:g}, omega0={self.omega0:g}, w0={self.w0:.6g}, {damping}, "
            f"{window}, tol={self.tol:g}, want={self.want!r}{drive})"
        )


@dataclass(frozen=True, repr=False)
class SceneResult(_tables.Tabular):
    """The answer to a scene: the model used, why, its error estimate, and the wanted quantities.

    Returned by ``solve`` and ``run_model``.

    Parameters
    ----------
    model : str
        The model used: "small_angle", "exact", "linear", "rk4", "cvode" or
        "taylor" (with a drive: "linear" is the linearised driven
        oscillator, "rk4" the driven RK4 kernel; the reason says "driven").
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
