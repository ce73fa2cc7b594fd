"""``fit_motion``: the exact motion fitted to a sampled swing (public through
pendula.fit)."""

import math

import numpy as np

from . import _fortran
from ._arrays import real_scalar
from ._errors import ERR_MAXSTEPS, _text, raise_for_status
from ._fit_common import (
    LOSSES,
    _confidence,
    _data,
    _derived,
    _in_scale,
    _pendulum,
    _positive_scalar,
    _scipy,
)
from ._fit_result import FitResult


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

    # The least squares see the rates (omega0, w0, gamma, omega_offset) in units of the
    # starting w0: SciPy moves a start within 1e-10 of a bound of 0 to 1e-10 (its
    # strictly feasible start), which in 1/s would put a slow pendulum's w0 and gamma
    # (a record in other units than seconds) far off, and stall the fit there.
    unit = np.array([x0[i_w0] if k in ("omega0", "w0", "gamma", "omega_offset") else 1.0 for k in names])

    def run(x, m, **tols):
        sol = optimize.least_squares(
            lambda y: evaluate(y * unit, m)[0],
            x / unit,
            jac=lambda y: evaluate(y * unit, m)[1] * unit,
            bounds=(lower, np.full(npar, np.inf)),
            method="trf",
            x_scale="jac",
            loss=loss,
            f_scale=f_scale,
            max_nfev=max_nfev,
            **tols,
        )
        sol.x = sol.x * unit
        return sol

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
