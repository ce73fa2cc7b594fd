"""What the period fit and the motion fit share: argument checks of the data,
the SciPy import, confidence levels and the derived g or length (no fitting)."""

import math

import numpy as np

from ._arrays import as_real, real_scalar

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
