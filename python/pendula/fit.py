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
from ._errors import raise_for_status
from ._fit_common import (
    _confidence,
    _data,
    _derived,
    _in_scale,
    _pendulum,
    _scipy,
)
from ._fit_motion import SENSITIVITY_INTEGRATORS, fit_motion  # noqa: F401 (the integrators slot: pendula.fit.SENSITIVITY_INTEGRATORS)
from ._fit_result import FitResult

__all__ = ["fit_period", "fit_motion", "FitResult"]


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
