"""The text's own section 2.2 RK4 listing, reproduced in pure Python for comparison.

The listing (lines 64-87 of both listings in section 2.2) integrates
theta'' + (b/m) theta' + (g/l) sin(theta) = 0 with a hand-written RK4 whose
line 67 is printed as

    m2 = m1 * h * k1 / 2.0        # printed
    m2 = m1 + h * k1 / 2.0        # meant (classic RK4)

With the typo the scheme is not consistent with the ODE (the second stage
uses a velocity of order h instead of Omega), so the text's figures 14 and 15
come from a wrong integration: for b = 0.01 kg/s the printed listing ends
1.56 rad away from the true solution at t = 30 s.

``text_listing_rk4`` runs the loop exactly as printed (``while t < t_end``
with t accumulated by repeated ``t = t + h``, Python floats, one ``np.sin``
per stage), so it can be overlaid on the figures and timed as "the text's
pure-Python RK4 loop".  With ``typo=False`` it is the correct classic RK4 --
the same scheme as ``pendula.rk4`` -- and agrees with it to rounding.
This module is a reference for comparisons, not an integrator to use.
"""

import numpy as np

from ._arrays import real_scalar


def text_listing_rk4(t_end, h, theta0, omega0, w0, gamma, typo=True):
    """Run the text's section 2.2 RK4 listing; return (t, theta, omega) arrays.

    t_end [s] (the listing's tf = 30), h [s] (0.05), theta0 [rad] (0),
    omega0 [rad/s] (2), w0 = sqrt(g/l) [1/s], gamma = b/m [1/s].  The first
    sample is t = 0; steps continue while t < t_end, so the last sample can
    lie up to h beyond t_end, as in the text.  typo=True reproduces line 67
    as printed (m2 = m1 * h * k1 / 2.0), typo=False the intended
    m2 = m1 + h * k1 / 2.0.  ValueError for h <= 0 or non-finite arguments.
    """
    t_end = real_scalar(t_end, "t_end")
    h = real_scalar(h, "h")
    y = real_scalar(theta0, "theta0")
    u = real_scalar(omega0, "omega0")
    w0 = real_scalar(w0, "w0")
    gamma = real_scalar(gamma, "gamma")
    for name, v in (("t_end", t_end), ("h", h), ("theta0", y), ("omega0", u), ("w0", w0), ("gamma", gamma)):
        if not np.isfinite(v):
            raise ValueError(f"{name} = {v} is invalid: it must be a finite real number")
    if not h > 0:
        raise ValueError(f"h = {h} is out of range: it must be finite and > 0")
    if not w0 > 0:
        raise ValueError(f"w0 = {w0} is out of range: it must be finite and > 0")
    if gamma < 0:
        raise ValueError(f"gamma = {gamma} is out of range: it must be finite and >= 0")
    if t_end / h > 1e8:
        raise ValueError(f"t_end / h = {t_end / h:g} steps is too many for a pure-Python loop (limit 1e8)")
    w0sq = w0 * w0

    def f(y, u):
        # line 31-32 of the listing: u' = - b * u / m - g * sin(y) / l
        return -gamma * u - w0sq * np.sin(y)

    t = 0.0
    tx, theta, omega = [t], [y], [u]
    while t < t_end:
        m1 = u
        k1 = f(y, u)
        m2 = m1 * h * k1 / 2.0 if typo else m1 + h * k1 / 2.0  # line 67
        y_2 = y + h * m1 / 2.0
        u_2 = m2
        k2 = f(y_2, u_2)
        m3 = m1 + h * k2 / 2.0
        y_3 = y + h * m2 / 2.0
        u_3 = m3
        k3 = f(y_3, u_3)
        m4 = m1 + h * k3
        y_4 = y + h * m3
        u_4 = m4
        k4 = f(y_4, u_4)
        t = t + h
        y = y + h * (m1 + (2.0 * m2) + (2.0 * m3) + m4) / 6.0
        u = u + h * (k1 + (2.0 * k2) + (2.0 * k3) + k4) / 6.0
        tx.append(t)
        theta.append(y)
        omega.append(u)
    return np.array(tx), np.array(theta, dtype=float), np.array(omega, dtype=float)


__all__ = ["text_listing_rk4"]
