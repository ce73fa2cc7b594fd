"""SciPy ``solve_ivp`` rows of ``tradeoff``: the trade measured against what
a user would otherwise pick, on the same reference and error measure.

SciPy is optional: imported only when rows are asked for.
"""

import importlib.util
import math
import time

import numpy as np

from ._tables import optional
from .integrate import rk4_max_stable_step

SCIPY_METHODS = ("RK45", "DOP853", "Radau", "LSODA")
"""SciPy ``solve_ivp`` methods ``tradeoff`` adds as rows (``scipy=True``)."""


def _sup_error(theta, omega, ref_theta, ref_omega, w0):
    """The tradeoff error measure: sup over t of max(abs(d theta), abs(d Omega)/w0)."""
    return float(max(np.max(np.abs(theta - ref_theta)), np.max(np.abs(omega - ref_omega)) / w0))


def _timed(fn, repeat):
    """(fn's result, the best wall time [s] of ``repeat`` runs)."""
    best = np.inf
    out = None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return out, best


_IMPLICIT = ("Radau", "BDF", "LSODA")
# a method's tighter rtols are skipped once one run takes longer than this [s]
_SLOW_RUN = 1.0


def methods(scipy, default_all):
    """The solve_ivp methods asked for by tradeoff's ``scipy`` argument."""
    if scipy is None:
        return list(SCIPY_METHODS) if default_all and importlib.util.find_spec("scipy") is not None else []
    if scipy is True:
        optional("scipy")
        return list(SCIPY_METHODS)
    if scipy is False:
        return []
    if isinstance(scipy, str):
        raise ValueError(f"scipy = {scipy!r} must be a list of solve_ivp method names, e.g. [{scipy!r}]")
    if not isinstance(scipy, (list, tuple)) or not all(isinstance(m, str) for m in scipy):
        raise TypeError(
            f"scipy must be True, False, None or a list of solve_ivp method names "
            f"(e.g. {list(SCIPY_METHODS[:2])}), got {scipy!r}"
        )
    bad = [m for m in scipy if m not in SCIPY_METHODS + ("BDF",)]
    if bad:
        raise ValueError(f"scipy methods {bad} are unknown: use some of {list(SCIPY_METHODS) + ['BDF']}")
    optional("scipy")
    return list(scipy)


def rhs_and_jacobian(w0, gamma):
    """solve_ivp's fun(t, y) and jac(t, y) for theta'' = -gamma theta' - w0^2 sin(theta),
    y = (theta [rad], omega [rad/s]); w0, gamma [1/s]."""

    def rhs(_, y):
        return [y[1], -gamma * y[1] - w0 * w0 * math.sin(y[0])]

    def jac(_, y):
        return [[0.0, 1.0], [-w0 * w0 * math.cos(y[0]), -gamma]]

    return rhs, jac


def rows(st, method, rtols, ref, repeat, max_steps):
    """TradeoffTable rows of solve_ivp(method) on the state scene st at each rtol."""
    tend = float(st.t[-1])
    # an explicit method needs at least the steps stability allows (RK4's limit as the measure)
    if tend <= 0 or (method not in _IMPLICIT and tend / rk4_max_stable_step(st.w0, st.gamma) > max_steps):
        return []
    solve_ivp = optional("scipy").integrate.solve_ivp
    w0 = st.w0
    scale = max(abs(st.theta0), abs(st.omega0) / w0) or 1.0
    rhs, jac = rhs_and_jacobian(w0, st.gamma)
    out = []
    for r in rtols:
        kw = {"jac": jac} if method in _IMPLICIT else {}

        def run(r=r, kw=kw):
            return solve_ivp(
                rhs,
                (0.0, tend),
                [st.theta0, st.omega0],
                method=method,
                t_eval=st.t,
                rtol=r,
                atol=[r * scale / 100, r * w0 * scale / 100],
                **kw,
            )

        sol, wall = _timed(run, repeat)
        if sol.status != 0:
            break  # tighter rtols fail too
        out.append(
            {
                "model": f"scipy {method}",
                "setting": f"rtol={r:.0e}",
                "sup_error": _sup_error(sol.y[0], sol.y[1], ref.theta, ref.omega, w0),
                "wall_time": wall,
                "rhs_evals": int(sol.nfev),
                "closed_form_evals": 0,
                "error_estimate": 0.0,
                "step_used": None,
                "steps": None,
            }
        )
        if wall > _SLOW_RUN:
            break
    return out
