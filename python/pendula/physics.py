"""Physical parameters as the text writes them: g, l, mass, b -> w0, gamma."""
import numpy as np

from . import _fortran
from ._arrays import broadcast_real, real_scalar, restore
from ._errors import raise_for_status


def natural_frequency(g=9.8, length=4.9):
    """Natural angular frequency w0 = sqrt(g/l) in 1/s (text eq. 1.7).

    g in m/s^2 and length in m, both finite and > 0 (ValueError otherwise).
    The text's values g = 9.8, l = 4.9 give w0 = sqrt(2).  Within 1 ulp for
    every such pair, also where g/length under- or overflows (then
    sqrt(g)/sqrt(length)); ValueError naming g and length when w0 itself would
    exceed the largest double.
    """
    w0, code, msg = _fortran.natural_frequency_f2py(real_scalar(g, "g"), real_scalar(length, "length"))
    raise_for_status(code, msg)
    return float(w0)


def damping_rate(b, mass):
    """Damping rate gamma = b/m in 1/s (text eq. 2.1); b >= 0 kg/s, mass > 0 kg."""
    gamma, code, msg = _fortran.damping_rate_f2py(real_scalar(b, "b"), real_scalar(mass, "mass"))
    raise_for_status(code, msg)
    return float(gamma)


def small_angle_period(w0):
    """Small-angle period T0 = 2 pi / w0 in s (text eq. 1.8); w0 > 0 in 1/s, array or scalar."""
    shape, scalar, f = broadcast_real(w0=w0)
    t0, code, msg = _fortran.small_angle_period_f2py(f["w0"])
    raise_for_status(code, msg)
    return restore(t0, shape, scalar)


def period_series(m, w0):
    """The textbook's amplitude correction to the period, T0 (1 + m/4 + 9 m²/64) in s.

    T0 = 2 pi / w0 (text eq. 1.8) and m = k² the parameter of a libration
    (m = sin²(theta0/2) released from rest), in [0, 1]; w0 > 0 in 1/s; arrays
    broadcast.  The first three terms of the exact T = T0 2K(m)/pi (DLMF
    19.5.1), so a model, not the period: relative error 25 m³/256 + O(m⁴)
    (``pendula.period`` gives the exact one).  ValueError naming m or w0
    outside their ranges.
    """
    shape, scalar, f = broadcast_real(m=m, w0=w0)
    if f["m"].size == 0:
        return np.empty(shape)
    t, code, msg = _fortran.period_series_f2py(f["m"], f["w0"])
    raise_for_status(code, msg)
    return restore(t, shape, scalar)


__all__ = ["natural_frequency", "damping_rate", "small_angle_period", "period_series"]
