"""Fitting a measured pendulum: g, length, damping and the initial state, with
their uncertainties, from a table of periods or a recorded swing.

``fit_period`` fits the exact period T = 4 K(sin^2(theta0/2)) / w0 (text eq.
1.53) to (amplitude, period) pairs by weighted least squares (the Fortran
``fit_period``: closed form, iterated for amplitude errors).  ``fit_motion``
fits the exact motion to sampled angles (and angular velocities): the
elliptic solution when undamped, the damped pendulum integrated with its
variational equations (Fortran ``sensitivity_solve``) when damped, so the
Jacobian is exact to the integrator's tolerance, never a finite difference.
The least-squares engine is SciPy's ``least_squares`` (the optional extra
``fit``), imported when a fit is asked for.
"""

import math

import numpy as np

from . import _fortran
from ._arrays import as_real, real_scalar
from ._errors import ERR_MAXSTEPS, _text, raise_for_status
from ._fit_result import FitResult

__all__ = ["fit_period", "fit_motion", "FitResult"]

EXTRA = "fit"
LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")


def _scipy():
    try:
        from scipy import optimize, stats  # noqa: F401
    except ImportError:
        raise ImportError(
            "pendula's fits need SciPy (least squares and distributions), an optional "
            f"dependency: pip install 'pendula[{EXTRA}]' (or pip install scipy)"
        ) from None
    return optimize


def _data(x, name, n=None, like="the data"):
    """x as a finite 1-D float array (a scalar repeated n times when n is
    given), or ValueError/TypeError naming it."""
    a = as_real(x, name)
    if a.ndim == 0 and n is not None:
        a = np.full(n, float(a))
    if a.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, not of shape {a.shape}")
    if n is not None and a.size != n:
        raise ValueError(f"{name} has {a.size} values but {like} has {n}: the lengths must match")
    bad = np.nonzero(~np.isfinite(a))[0]
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] = {a[bad[0]]} is not finite: remove or fix that sample")
    return a


#: Scales (sigmas, periods, lengths, g) the fits accept: their squares and
#: reciprocals must stay normal doubles, since least squares square them.
SCALE_RANGE = (1e-150, 1e150)


def _in_scale(a, name, unit, zero=False):
    """Refuse values of a scale outside SCALE_RANGE (0 allowed when zero)."""
    a = np.asarray(a, dtype=float)
    lo, hi = SCALE_RANGE
    bad = ~(((a >= lo) | (zero & (a == 0))) & (a <= hi))
    if np.any(bad):
        i = int(np.argmax(bad.ravel()))
        where = f"{name}[{i}]" if a.ndim else name
        raise ValueError(
            f"{where} = {a.ravel()[i]:.6g} {unit} must lie in [{lo:g}, {hi:g}]" + (" or be 0" if zero else "")
        )


def _positive_scalar(x, name, zero=False, unit=""):
    if x is None:
        return None
    x = real_scalar(x, name)
    if not (math.isfinite(x) and (x > 0 or (zero and x == 0))):
        raise ValueError(f"{name} = {x} must be finite and {'>=' if zero else '>'} 0")
    if unit:
        _in_scale(x, name, unit, zero)
    return x


def _confidence(x):
    x = real_scalar(x, "confidence")
    if not 0.0 < x < 1.0:
        raise ValueError(f"confidence = {x} must lie in (0, 1)")
    return x


def _pendulum(length, g, bob_radius):
    """(length, g, l_eff function) checks: at most one of length and g."""
    length = _positive_scalar(length, "length", unit="m")
    g = _positive_scalar(g, "g", unit="m/s^2")
    if length is not None and g is not None:
        raise ValueError(
            "give length (to estimate g) or g (to estimate the length), not both: "
            "with both, w0 = sqrt(g/l) is known and there is nothing to fit"
        )
    bob_radius = _positive_scalar(bob_radius, "bob_radius", zero=True, unit="m")
    if bob_radius is not None:
        if length is None and g is None:
            raise ValueError("bob_radius corrects g or the length: give length= or g= with it")
        if length is not None and bob_radius >= length:
            raise ValueError(
                f"bob_radius = {bob_radius} m must be smaller than length = {length} m (the pivot-to-centre distance)"
            )
    return length, g, bob_radius or 0.0


def _derived(names, values, cov, length, g, r):
    """Append g (given length) or length (given g) to the parameters, with the
    covariance by the delta method.  Finite bob of radius r: l_eff = l + 2 r^2/(5 l)."""
    i = names.index("w0")
    w0 = values[i]
    grad = np.zeros(len(names))
    if length is not None:
        leff = length + 0.4 * r * r / length
        extra, name = w0 * w0 * leff, "g"
        grad[i] = 2.0 * w0 * leff
    elif g is not None:
        leff = g / (w0 * w0)
        disc = leff * leff - 1.6 * r * r
        if disc < 0:
            raise ValueError(f"no pendulum of bob radius {r} m has w0 = {w0:.6g} 1/s with g = {g} m/s^2")
        extra, name = 0.5 * (leff + math.sqrt(disc)), "length"
        # d l / d w0 = (d l / d leff)(d leff / d w0), l = (leff + sqrt(leff^2 - 8 r^2/5)) / 2
        grad[i] = 0.5 * (1.0 + leff / math.sqrt(disc)) * (-2.0 * leff / w0) if disc > 0 else math.inf
    else:
        return list(names), np.asarray(values), np.asarray(cov)
    jac = np.vstack([np.eye(len(names)), grad])
    return list(names) + [name], np.append(values, extra), jac @ cov @ jac.T


# ------------------------------------------------------------------ periods


def fit_period(
    theta0, period, *, sigma_period=None, sigma_theta0=None, length=None, g=None, bob_radius=None, confidence=0.95
):
    r"""Fit w0, g or the length to periods measured at several amplitudes.

    The model is the exact period of the swing, T = 4 K(m)/w0 with
    m = sin^2(theta0/2) (text eq. 1.53), valid for every amplitude
    abs(theta0) < pi; it is linear in 1/w0, so the weighted least squares are
    closed form when the amplitudes are exact.  Amplitude uncertainties are
    propagated through dT/dtheta0 (effective variance, Orear, Am. J. Phys. 50
    (1982) 912: s_i^2 = sigma_T,i^2 + (dT/dtheta0 sigma_theta0,i)^2, iterated to
    convergence).  The fit runs in the Fortran core (``fit_period`` of
    ``use pendula``).

    Parameters
    ----------
    theta0 : array_like
        Amplitudes [rad] (the turning angle of each swing), abs(theta0) < pi.
    period : array_like
        Measured periods [s], > 0, one per amplitude.
    sigma_period : float or array_like, optional, keyword-only
        Standard uncertainty of each period [s], > 0.  Without it the
        uncertainty is estimated from the scatter (all points weighted
        alike): standard errors are scaled by sqrt(chi2/dof), intervals use
        Student's t, and there is no goodness-of-fit p-value.
    sigma_theta0 : float or array_like, optional, keyword-only
        Standard uncertainty of each amplitude [rad], >= 0.
    length : float, optional, keyword-only
        Pendulum length [m] (pivot to the bob's centre): also estimate
        g = w0^2 l_eff.
    g : float, optional, keyword-only
        Gravitational acceleration [m/s^2]: also estimate the length.
    bob_radius : float, optional, keyword-only
        Radius r [m] of a solid spherical bob on a light string (with
        ``length`` or ``g``): the physical pendulum has I = m (l^2 + 2 r^2/5)
        about the pivot, so w0^2 = m g l / I = g / l_eff with
        l_eff = l + 2 r^2 / (5 l) (Nelson & Olsson, "The pendulum -- rich
        physics from a simple system", Am. J. Phys. 54 (1986) 112).  The
        equation of motion keeps the form theta'' = -w0^2 sin(theta), so the
        exact period still applies.
    confidence : float, optional, keyword-only
        Level of the confidence intervals, in (0, 1); default 0.95.

    Returns
    -------
    FitResult
        ``estimates``/``stderr``/``intervals`` of ``w0`` and of ``g`` or
        ``length``; ``chi2``, ``reduced_chi2``, ``pvalue``; ``residuals``
        (measured minus model periods, s); ``small_angle``: what the
        small-angle formula T = 2 pi/w0 gives -- ``w0`` overall (weighted
        fit) and ``w0_per_point`` = 2 pi/T_i, and ``g``/``g_per_point`` (or
        ``length``/``length_per_point``) -- the bias of ignoring the
        amplitude.

    Raises
    ------
    ValueError
        Too few points (1 with ``sigma_period``, else 2), lengths that differ,
        non-finite data, abs(theta0) >= pi (a rotation has no swing period),
        periods or sigmas out of range, both ``length`` and ``g``.
    TypeError
        Data or options that are not real numbers.
    ImportError
        When SciPy (the optional extra ``fit``) is not installed.

    Notes
    -----
    Periods, uncertainties, ``length``, ``g`` and ``bob_radius`` must lie in
    ``SCALE_RANGE`` = [1e-150, 1e150] (in their units): the least squares
    square them.

    Examples
    --------
    A 0.75 m pendulum timed at 10 to 150 degrees (g = 9.81 m/s^2):

    >>> import numpy as np, pendula
    >>> th = np.radians([10.0, 30.0, 60.0, 90.0, 120.0, 150.0])
    >>> T = pendula.period(th, g=9.81, length=0.75)
    >>> r = pendula.fit_period(th, T, sigma_period=1e-3, length=0.75)
    >>> round(r.estimates["g"], 6), round(r.stderr["g"], 4)
    (9.81, 0.0036)
    >>> round(float(r.small_angle["g_per_point"][-1]), 2)   # the small-angle formula at 150 deg
    3.16
    """
    _scipy()
    theta0 = _data(theta0, "theta0")
    n = theta0.size
    period = _data(period, "period", n, "theta0")
    known = sigma_period is not None
    sp = _data(1.0 if sigma_period is None else sigma_period, "sigma_period", n, "theta0")
    st = _data(0.0 if sigma_theta0 is None else sigma_theta0, "sigma_theta0", n, "theta0")
    _in_scale(period, "period", "s")
    if known:
        _in_scale(sp, "sigma_period", "s")
    if sigma_theta0 is not None:
        _in_scale(st, "sigma_theta0", "rad", zero=True)
    need = 1 if known else 2
    if n < need:
        raise ValueError(
            f"{n} period(s) cannot determine w0 "
            + ("" if known else "and its uncertainty ")
            + f"(need at least {need}"
            + ("" if known else ", or give sigma_period")
            + ")"
        )
    conf = _confidence(confidence)
    length, g, r = _pendulum(length, g, bob_radius)
    if not known and sigma_theta0 is not None:
        raise ValueError(
            "sigma_theta0 needs sigma_period: amplitude errors are propagated into "
            "period errors, which must then be known too"
        )
    w0, se, chi2, _, w0_sa, code, msg = _fortran.fit_period_f2py(theta0, period, sp, st)
    raise_for_status(code, msg)
    f, dfdth = _fortran.period_factor_f2py(theta0)
    dof = n - 1
    var = se * se
    if not known:
        var *= chi2 / dof if dof > 0 else math.nan
    names, values, cov = _derived(["w0"], np.array([w0]), np.array([[var]]), length, g, r)
    model = lambda x: _fortran.period_factor_f2py(np.atleast_1d(x))[0] / w0  # noqa: E731
    resid = period - f / w0
    sa = {"w0": float(w0_sa), "w0_per_point": 2.0 * np.pi / period}
    if length is not None:
        leff = length + 0.4 * r * r / length
        sa["g"] = w0_sa**2 * leff
        sa["g_per_point"] = sa["w0_per_point"] ** 2 * leff
    elif g is not None:
        for key, w in (("length", w0_sa), ("length_per_point", sa["w0_per_point"])):
            leff = g / np.square(w)
            sa[key] = 0.5 * (leff + np.sqrt(np.maximum(leff * leff - 1.6 * r * r, 0.0)))
    s_eff = np.sqrt(sp**2 + (dfdth / w0 * st) ** 2)
    chi2_out = float(np.sum((resid / s_eff) ** 2))
    return FitResult(
        kind="period",
        names=names,
        values=values,
        covariance=cov,
        sigma_known=known,
        dof=dof,
        chi2=chi2_out,
        confidence=conf,
        residuals=resid,
        model=model,
        data={
            "theta0": theta0,
            "period": period,
            "sigma_period": sp if known else None,
            "sigma_theta0": None if sigma_theta0 is None else st,
            "sigma_effective": s_eff if known else None,
        },
        small_angle=sa,
        info={"engine": "pendula Fortran fit_period (weighted least squares)", "bob_radius": r},
    )


# ------------------------------------------------------------------ motion


def _rk4_sensitivity(t, t_ref, theta0, omega0, w0, gamma, tol):
    """theta, omega (n,) and their Jacobians (n, 4) in (theta0, omega0, w0,
    gamma): the Fortran RK4 integration of the variational equations.  A
    record too long for the step budget at tol is bad data for a fit
    (ValueError naming t and tol), not a solver failure."""
    th, om, jt, jo, _, code, msg = _fortran.sensitivity_f2py(t, t_ref, theta0, omega0, w0, gamma, tol)
    if code == ERR_MAXSTEPS:
        raise ValueError(f"the record is too long to fit at this tol: {_text(msg)}; or check the times t (in s?)")
    raise_for_status(code, msg)
    return th, om, jt, jo


#: Integrators of the damped pendulum with its variational equations, by name:
#: ``f(t, t_ref, theta0, omega0, w0, gamma, tol) -> (theta, omega, jac_theta,
#: jac_omega)`` with Jacobians of shape (len(t), 4) over (theta0, omega0, w0,
#: gamma).  ``fit_motion(integrator=...)`` picks one; another integrator (a
#: Taylor method) plugs in by adding an entry.
SENSITIVITY_INTEGRATORS = {"rk4": _rk4_sensitivity}


def _motion_data(t, theta, omega, sigma, sigma_omega):
    t = _data(t, "t")
    n = t.size
    if n == 0:
        raise ValueError("t is empty: a fit needs samples")
    theta = _data(theta, "theta", n, "t")
    omega = None if omega is None else _data(omega, "omega", n, "t")
    sig = None if sigma is None else _data(sigma, "sigma", n, "t")
    sig_om = None
    if omega is not None:
        if (sigma is None) != (sigma_omega is None):
            raise ValueError(
                "give sigma and sigma_omega together (or neither): angles and angular "
                "velocities need their own uncertainties"
            )
        sig_om = None if sigma_omega is None else _data(sigma_omega, "sigma_omega", n, "t")
    if omega is None and sigma_omega is not None:
        raise ValueError("sigma_omega was given without omega: give the angular velocities too")
    for name, s, unit in (("sigma", sig, "rad"), ("sigma_omega", sig_om, "rad/s")):
        if s is not None:
            _in_scale(s, name, unit)
    if n and np.ptp(t) == 0:
        raise ValueError(f"all {n} samples are at one time t = {t[0]}: a swing needs samples spread in time")
    step = np.diff(t)
    if np.any(step <= 0):
        i = int(np.nonzero(step <= 0)[0][0]) + 1
        raise ValueError(
            f"t must be strictly increasing (sort the samples by time, one per time): "
            f"t[{i}] = {t[i]} does not exceed t[{i - 1}] = {t[i - 1]}"
        )
    return t, theta, omega, sig, sig_om


def fit_motion(
    t,
    theta,
    *,
    omega=None,
    sigma=None,
    sigma_omega=None,
    damping="linear",
    fit_offsets=False,
    length=None,
    g=None,
    t_ref=None,
    p0=None,
    loss="linear",
    f_scale=1.0,
    tol=None,
    integrator="rk4",
    confidence=0.95,
    max_nfev=None,
):
    r"""Fit w0 (or g, or the length), the damping and the initial state to a recorded swing.

    Least squares on the exact model: theta(t) of the undamped pendulum in
    closed form (elliptic functions, any amplitude) when ``damping=None``;
    the nonlinear pendulum with linear viscous damping,
    theta'' + gamma theta' + w0^2 sin(theta) = 0 (text eq. 2.2), integrated
    together with its variational equations when ``damping="linear"``.  The
    Jacobian comes from the variational equations (derivatives of the
    solution with respect to theta0, Omega0, w0, gamma), not from finite
    differences.  Starting values come from the data (zero crossings or the
    spectrum for the period, the period-amplitude relation for w0, the
    logarithmic decrement for gamma).  The engine is SciPy's
    ``least_squares`` (trust-region reflective, gamma >= 0 and w0 > 0).

    Parameters
    ----------
    t : array_like
        Sample times [s], strictly increasing, any spacing.
    theta : array_like
        Measured angles [rad], same length; a swing (abs(theta) < pi about the
        centre).
    omega : array_like, optional, keyword-only
        Measured angular velocities [rad/s] at the same times.
    sigma, sigma_omega : float or array_like, optional, keyword-only
        Standard uncertainties [rad], [rad/s] per sample, in [1e-150, 1e150]
        (``SCALE_RANGE``).  Without them
        the noise is estimated from the residuals (errors scaled by
        sqrt(chi2/dof), Student's t intervals, no p-value).
    damping : {"linear", None}, optional, keyword-only
        Model: linear viscous damping (fit gamma [1/s]) or none.
    fit_offsets : bool, optional, keyword-only
        Also fit a constant angle offset of the sensor (``theta_offset``,
        rad: measured = true + offset) and, with ``omega``, of the rate
        sensor (``omega_offset``).
    length, g : float, optional, keyword-only
        Give the length [m] to estimate g = w0^2 l, or g [m/s^2] to estimate
        the length.
    t_ref : float, optional, keyword-only
        Time [s] at which theta0 and Omega0 are the state (default: the
        first sample; must not be later).  A time offset of the clock is
        thereby absorbed: the fit finds the state at t_ref, whatever the
        clock's zero.
    p0 : dict, optional, keyword-only
        Starting values to use instead of the automatic ones, by name
        (``theta0``, ``omega0``, ``w0``, ``gamma``, ``theta_offset``, ``omega_offset``).
    loss : str, optional, keyword-only
        SciPy's robust loss for outliers: "linear" (least squares, the
        default), "soft_l1", "huber", "cauchy", "arctan".  With a robust
        loss the covariance is the least-squares one at the robust estimate.
    f_scale : float, optional, keyword-only
        The residual (in units of sigma) where a robust loss begins to treat
        points as outliers (default 1).
    tol : float, optional, keyword-only
        Integration error target [rad] of the damped model, in [1e-15, 1]
        (default 1e-3 of the smallest sigma, within [1e-11, 1e-7]; 1e-9
        without sigma).
    integrator : str, optional, keyword-only
        Key of ``pendula.fit.SENSITIVITY_INTEGRATORS`` (``"rk4"``: the
        Fortran RK4 of the variational equations; a higher-order integrator
        plugs in by adding an entry).
    confidence : float, optional, keyword-only
        Level of the intervals, in (0, 1); default 0.95.
    max_nfev : int, optional, keyword-only
        Most model evaluations (SciPy's default when None).

    Returns
    -------
    FitResult
        Parameters ``theta0`` [rad], ``omega0`` [rad/s] (the state at
        ``t_ref``), ``w0`` [1/s], ``gamma`` [1/s] (damped), the offsets
        (when fitted) and ``g`` or ``length`` (when asked for); residuals in
        rad (``residuals_omega`` in rad/s); ``info`` holds the engine's
        report (``nfev``, ``message``, ``t_ref``).

    Raises
    ------
    ValueError
        Too few samples for the parameters, mismatched lengths, non-finite
        data, all samples at one time, times not increasing, abs(theta) >= pi about
        the centre (the data show a rotation, not a swing), no swing to find
        a period in (give ``p0``), a bad option.
    TypeError
        Data or options of the wrong type (strings, booleans, a p0 that is
        not a dict).
    RuntimeError
        When the least squares do not converge.
    ImportError
        When SciPy (the optional extra ``fit``) is not installed.

    Examples
    --------
    A swing of 120 degrees, lightly damped, sampled 20 times a second:

    >>> import numpy as np, pendula
    >>> t = np.arange(0.0, 10.0, 0.05)
    >>> r0 = pendula.rk4(t, np.radians(120.0), 0.0, 3.6, 0.05, h=1e-3)
    >>> rng = np.random.default_rng(1)
    >>> theta = r0.theta + rng.normal(0.0, 1e-3, t.size)
    >>> r = pendula.fit_motion(t, theta, sigma=1e-3, length=0.75)
    >>> abs(r["w0"] - 3.6) < 3 * r.stderr["w0"], abs(r["gamma"] - 0.05) < 3 * r.stderr["gamma"]
    (True, True)
    >>> r.names
    ('theta0', 'omega0', 'w0', 'gamma', 'g')
    """
    optimize = _scipy()
    if damping not in ("linear", None):
        raise ValueError(f"damping must be 'linear' or None, not {damping!r}")
    if integrator not in SENSITIVITY_INTEGRATORS:
        raise ValueError(f"integrator must be one of {sorted(SENSITIVITY_INTEGRATORS)}, not {integrator!r}")
    conf = _confidence(confidence)
    length, g, _ = _pendulum(length, g, None)
    if loss not in LOSSES:
        raise ValueError(f"loss must be one of {', '.join(LOSSES)}, not {loss!r}")
    if f_scale is None:
        raise TypeError("f_scale must be a real number > 0 (in units of sigma), not None")
    f_scale = _positive_scalar(f_scale, "f_scale", unit="(in sigmas)")
    if not isinstance(fit_offsets, (bool, np.bool_)):
        raise TypeError(f"fit_offsets must be True or False, not {type(fit_offsets).__name__}")
    if max_nfev is not None:
        if isinstance(max_nfev, (bool, np.bool_)) or not isinstance(max_nfev, (int, np.integer)):
            raise TypeError(f"max_nfev must be a positive integer or None, not {type(max_nfev).__name__}")
        if max_nfev < 1:
            raise ValueError(f"max_nfev = {max_nfev} must be >= 1")
    if p0 is not None and not isinstance(p0, dict):
        raise TypeError(f"p0 must be a dict of starting values by name, not {type(p0).__name__}")
    t, theta, omega, sig, sig_om = _motion_data(t, theta, omega, sigma, sigma_omega)
    n = t.size
    damped = damping == "linear"
    names = ["theta0", "omega0", "w0"] + (["gamma"] if damped else [])
    if fit_offsets:
        names += ["theta_offset"] + (["omega_offset"] if omega is not None else [])
    npar = len(names)
    nres = n * (1 if omega is None else 2)
    known = sig is not None
    if nres < npar + (0 if known else 1):
        raise ValueError(
            f"{n} sample(s) cannot determine the {npar} parameters {', '.join(names)}"
            + ("" if known else " and the noise")
            + f": need at least {npar + (0 if known else 1)}"
            + (" values" if omega is not None else " samples")
        )
    t_ref = float(t[0]) if t_ref is None else real_scalar(t_ref, "t_ref")
    if not math.isfinite(t_ref) or t_ref > t[0]:
        raise ValueError(f"t_ref = {t_ref} must be finite and not later than the first sample t = {t[0]}")
    p0 = {k: real_scalar(v, f"p0[{k!r}]") for k, v in (p0 or {}).items()}
    unknown = set(p0) - set(names)
    if unknown:
        raise ValueError(f"p0 names {sorted(unknown)} are not parameters of this fit ({', '.join(names)})")
    # The centre of the swing: the sensor offset's start (0 when not fitted).
    offset = float(p0.get("theta_offset", 0.5 * (theta.max() + theta.min()) if fit_offsets else 0.0))
    reach = np.abs(theta - offset)
    if reach.max() >= math.pi:
        i = int(np.argmax(reach))
        raise ValueError(
            f"theta[{i}] = {theta[i]:.6g} rad is {reach[i]:.6g} rad from the centre (>= pi): "
            "the data show a rotation (over the top), and fit_motion fits a swing; "
            "unwrapped angles of a rotating pendulum cannot be fitted"
        )
    if not {"theta0", "omega0", "w0"} <= set(p0) or (damped and "gamma" not in p0):
        from ._fit_start import start_values

        s = start_values(t, theta, omega, t_ref, offset, None if sig is None else float(np.median(sig)))
        start = dict(zip(["theta0", "omega0", "w0", "gamma"], s))
    else:
        start = {}
    if omega is not None and start:
        fast = np.abs(omega).max()
        if fast > 3.0 * start["w0"]:  # a swing is slower than 2 w0 at the bottom (the separatrix)
            raise ValueError(
                f"omega reaches {fast:.6g} rad/s, beyond the separatrix speed 2 w0 ~ "
                f"{2 * start['w0']:.4g} rad/s of a swing: the data show a rotation "
                "(or omega is not in rad/s)"
            )
    start.update(theta_offset=offset, omega_offset=0.0)
    start.update(p0)
    x0 = np.array([start[k] for k in names], dtype=float)
    i_w0 = names.index("w0")
    lower = np.full(npar, -np.inf)
    lower[i_w0] = 0.0
    if damped:
        lower[names.index("gamma")] = 0.0
        x0[names.index("gamma")] = max(x0[names.index("gamma")], 1e-6 * x0[i_w0])
    if not x0[i_w0] > 0:
        raise ValueError(f"the starting w0 = {x0[i_w0]} must be > 0")
    if tol is None:
        tol = float(np.clip(1e-3 * np.min(sig), 1e-11, 1e-7)) if known else 1e-9
    tol = _positive_scalar(tol, "tol")
    if not 1e-15 <= tol <= 1.0:
        raise ValueError(
            f"tol = {tol:.6g} rad must lie in [1e-15, 1] (below 1e-15 double precision "
            "cannot follow; above 1 rad there is no fit)"
        )
    solve = SENSITIVITY_INTEGRATORS[integrator]
    w_th = 1.0 / sig if known else np.ones(n)
    w_om = None if omega is None else (1.0 / sig_om if known else np.ones(n))
    cols = [0, 1, 2] + ([3] if damped else [])

    def unpack(x):
        p = dict(zip(names, x))
        return (
            p["theta0"],
            p["omega0"],
            p["w0"],
            p.get("gamma", 0.0),
            p.get("theta_offset", 0.0),
            p.get("omega_offset", 0.0),
        )

    cache = {}

    def evaluate(x, m=n):
        """Weighted residuals and Jacobian over the first m samples."""
        key = (x.tobytes(), m)
        if key not in cache:
            cache.clear()
            th0, om0, w0, gam, dth, dom = unpack(x)
            tt = t[:m]
            th, om, jt, jo = solve(tt, t_ref, th0, om0, max(w0, 1e-300), gam, tol)
            if not damped:
                # the exact elliptic solution for the values; the variational
                # equations (integrated at gamma = 0) for the Jacobian
                from .undamped import undamped

                th, om = undamped(tt - t_ref, th0, om0, w0)
            res = [(th + dth - theta[:m]) * w_th[:m]]
            jac = [jt[:, cols] * w_th[:m, None]]
            if omega is not None:
                res.append((om + dom - omega[:m]) * w_om[:m])
                jac.append(jo[:, cols] * w_om[:m, None])
            jac = np.vstack(jac)
            if fit_offsets:
                extra = np.zeros((jac.shape[0], npar - len(cols)))
                extra[:m, 0] = w_th[:m]
                if omega is not None:
                    extra[m:, 1] = w_om[:m]
                jac = np.hstack([jac, extra])
            cache[key] = (np.concatenate(res), jac)
        return cache[key]

    def run(x, m, **tols):
        return optimize.least_squares(
            lambda x: evaluate(x, m)[0],
            x,
            jac=lambda x: evaluate(x, m)[1],
            bounds=(lower, np.full(npar, np.inf)),
            method="trf",
            x_scale="jac",
            loss=loss,
            f_scale=f_scale,
            max_nfev=max_nfev,
            **tols,
        )

    # Continuation over the record: a w0 off by a fraction of a percent puts
    # a long record's later swings out of phase, a local minimum the solver
    # cannot leave; fitting 3, 6, 12, ... starting periods first (each stage
    # starting from the last) keeps the phase error small at every stage.
    nfev, x_start = 0, x0.copy()
    period = 2.0 * math.pi / x0[i_w0]
    span = 3.0 * period
    while t[-1] - t_ref > 1.5 * span:
        m = int(np.searchsorted(t, t_ref + span, side="right"))
        if m * (1 if omega is None else 2) >= 3 * npar:
            stage = run(np.clip(x0, lower + 1e-12 * np.abs(x0), None), m)
            nfev += stage.nfev
            if stage.status > 0:
                x0 = stage.x
        span *= 2.0
    x0 = np.clip(x0, lower + 1e-12 * np.abs(x0) + 1e-300, None)
    sol = run(x0, n, xtol=1e-12, ftol=1e-12, gtol=1e-10)
    nfev += sol.nfev
    if sol.status <= 0:
        raise RuntimeError(f"the least squares did not converge: {sol.message}")
    x = sol.x
    r, jac = evaluate(x)
    chi2 = float(np.sum(r * r))
    dof = nres - npar
    # Covariance (J^T J)^-1 through the SVD of J with unit columns: the
    # conditioning of the fit, not of the parameters' units, decides singularity.
    norms = np.linalg.norm(jac, axis=0)
    if not np.all(np.isfinite(jac)) or np.any(norms == 0):
        bad = names[int(np.argmin(np.where(np.isfinite(norms), norms, 0.0)))]
        raise ValueError(f"the data cannot determine {bad}: the model does not depend on it here")
    _, s, vt = np.linalg.svd(jac / norms, full_matrices=False)
    if s[-1] <= s[0] * 1e-12:
        bad = names[int(np.argmax(np.abs(vt[-1])))]
        raise ValueError(
            f"the data cannot determine {bad}: the Jacobian is singular (too short a record, "
            "or parameters that trade off exactly)"
        )
    cov = (vt.T / s**2) @ vt / np.outer(norms, norms)
    if not known:
        cov *= chi2 / dof
    th0, om0, w0, gam, dth, dom = unpack(x)
    resid = -r[:n] / w_th
    resid_om = None if omega is None else -r[n:] / w_om
    out_names, values, cov = _derived(names, x, cov, length, g, 0.0)

    def model(tt):
        tt = np.atleast_1d(tt)
        if not damped:
            from .undamped import undamped

            return undamped(tt - t_ref, th0, om0, w0)[0] + dth
        out = np.full(tt.shape, np.nan)  # the damped model runs forward from t_ref only
        keep = np.nonzero(tt >= t_ref)[0]
        keep = keep[np.argsort(tt[keep], kind="stable")]
        if keep.size:
            out[keep] = solve(tt[keep], t_ref, th0, om0, w0, gam, tol)[0]
        return out + dth

    return FitResult(
        kind="motion",
        names=out_names,
        values=values,
        covariance=cov,
        sigma_known=known,
        dof=dof,
        chi2=chi2,
        confidence=conf,
        residuals=resid,
        residuals_omega=resid_om,
        model=model,
        data={"t": t, "theta": theta, "omega": omega, "sigma": sig},
        info={
            "engine": "scipy.optimize.least_squares (trf)",
            "nfev": nfev,
            "njev": sol.njev,
            "message": sol.message,
            "loss": loss,
            "integrator": integrator if damped else "elliptic (values), " + integrator + " variational (Jacobian)",
            "t_ref": t_ref,
            "start": dict(zip(names, x_start.tolist())),
            "tol": tol,
        },
    )
