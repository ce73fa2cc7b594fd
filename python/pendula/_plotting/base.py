"""Plumbing shared by the figure modules: the text's parameters, library calls
that say clearly when a part of the library is missing from this build, result
unpacking and saving.  See :mod:`pendula.figures`.
"""

from pathlib import Path

import numpy as np

import pendula as _pd

from ..plots import DPI

G = 9.8  # m/s^2, the text's g
LENGTH = 4.9  # m, the text's l
MASS = 0.100  # kg, the text's m in §2.2


class FigureUnavailable(RuntimeError):
    """A figure needs a part of the library that this build does not have."""


# --------------------------------------------------------------------------
# small plumbing: library calls with clear "missing" errors, result unpacking
# --------------------------------------------------------------------------


def _need(name):
    fn = getattr(_pd, name, None)
    if fn is None:
        raise FigureUnavailable(f"pendula.{name} is not available in this build")
    return fn


def _w0():
    return _pd.natural_frequency(G, LENGTH)


def _pair(res):
    """(theta, omega) from a tuple or from a result object with .theta/.omega."""
    if hasattr(res, "theta"):
        return np.asarray(res.theta, dtype=float), np.asarray(res.omega, dtype=float)
    return np.asarray(res[0], dtype=float), np.asarray(res[1], dtype=float)


def _exact(t, theta0, omega0, w0):
    return _pair(_need("undamped")(t, theta0, omega0, w0))


def _small(t, theta0, omega0, w0):
    return _pair(_need("small_angle")(t, theta0, omega0, w0))


def _linear(t, theta0, omega0, w0, gamma):
    return _pair(_need("linear_damped")(t, theta0, omega0, w0, gamma))


def _reference(t, theta0, omega0, w0, gamma):
    """A converged solution of the nonlinear damped equation (eq. 2.3) and its label."""
    if getattr(_pd, "cvode", None) is not None and _pd.build_info()["cvode"]:
        res = _pd.cvode(t, theta0, omega0, w0, gamma, rtol=1e-11, atol=1e-13, method="bdf")
        return _pair(res) + ("pendula.cvode (BDF, rtol 1e-11)",)
    res = _need("rk4")(t, theta0, omega0, w0, gamma, 1e-3)
    return _pair(res) + ("pendula.rk4 (h = 0.001 s)",)


def _text_listing(t_end, h, theta0, omega0, w0, gamma):
    """The text's printed RK4 listing (§2.2, with its line-67 typo): t, theta, omega."""
    textbook = getattr(_pd, "textbook", None)
    if textbook is None:
        try:
            from .. import textbook  # noqa: F811 (not re-exported by every build)
        except ImportError:
            raise FigureUnavailable(
                "pendula.textbook (the text's printed RK4 listing) is not available in this build"
            ) from None
    res = textbook.text_listing_rk4(t_end, h, theta0, omega0, w0, gamma, typo=True)
    if hasattr(res, "theta"):
        return (np.asarray(res.t, dtype=float), np.asarray(res.theta, dtype=float), np.asarray(res.omega, dtype=float))
    return tuple(np.asarray(r, dtype=float) for r in res[:3])


def _save(fig, out_dir, name):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.savefig(path, dpi=DPI)
    return path


def _npts(quick, full=2000):
    return 300 if quick else full


def _pi_label(x):
    return f"{x:.2f}π"


_TEXT_H = 0.05  # s, the text's §2.2 RK4 step
_TEXT_TEND = 30.0  # s, the end of the text's §2.2 window
