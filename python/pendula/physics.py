"""Physical parameters as the text writes them: g, length, mass, b -> w0, gamma.

One convention for the whole package: a function that needs the pendulum takes
it keyword-style as ``w0=`` or as ``g=`` and ``length=``; given none, it is the
text's pendulum, g = 9.8 m/s^2 and length = 4.9 m (w0 = sqrt(2) 1/s), the same
default as ``Scene``.  A damping rate is ``gamma=`` or ``b=`` and ``mass=``
(gamma = b/mass, text eq. 2.2); given none, gamma = 0.  The defaults live in the
Fortran module ``pendula_physics`` and reach Python through ``_codes``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from . import _fortran
from ._arrays import as_real, broadcast_real, real_scalar, restore
from ._codes import G_DEFAULT, GLUE_GAMMA, GLUE_W0, LENGTH_DEFAULT, PARAM_RTOL
from ._errors import raise_for_status


def natural_frequency(g: float = G_DEFAULT, length: float = LENGTH_DEFAULT) -> float:
    """Natural angular frequency w0 = sqrt(g/length) of the pendulum (text eq. 1.4).

    The rate that sets every time scale of the motion: the small-angle
    solution is theta0 cos(w0 t) (eq. 1.7).  Defaults are the text's
    pendulum, g = 9.8 m/s^2 and length = 4.9 m, which give w0 = sqrt(2).

    Parameters
    ----------
    g : float, optional
        Gravitational acceleration [m/s^2], finite and > 0.  Default 9.8.
    length : float, optional
        Pendulum length [m], finite and > 0.  Default 4.9.

    Returns
    -------
    float
        w0 [1/s].

    Raises
    ------
    ValueError
        g or length not finite and > 0, or sqrt(g/length) beyond the largest
        double (the message names g and length).
    TypeError
        g or length not a real scalar (arrays, str, bool, complex).

    Notes
    -----
    Within 1 ulp of sqrt(g/length) for every valid pair, also where g/length
    itself under- or overflows (then computed from the significands and the
    halved exponent).

    Examples
    --------
    >>> import pendula
    >>> round(pendula.natural_frequency(), 12)
    1.414213562373
    >>> pendula.natural_frequency(g=9.8, length=9.8)
    1.0
    """
    w0, code, msg = _fortran.physics_rate_f2py(GLUE_W0, real_scalar(g, "g"), real_scalar(length, "length"))
    raise_for_status(code, msg)
    return float(w0)


def damping_rate(b: float, mass: float) -> float:
    """Damping rate gamma = b/mass of the linear friction force (text eqs 2.2-2.3).

    The friction torque -b l^2 theta' divided by m l^2 gives the term
    gamma theta' of theta'' + gamma theta' + w0^2 sin(theta) = 0 (eq. 2.3).

    Parameters
    ----------
    b : float
        Damping coefficient [kg/s], finite and >= 0.
    mass : float
        Bob mass [kg], finite and > 0.

    Returns
    -------
    float
        gamma [1/s].

    Raises
    ------
    ValueError
        b < 0, mass <= 0, either non-finite, or b/mass beyond the largest double.
    TypeError
        b or mass not a real scalar.

    Notes
    -----
    One correctly rounded division.

    Examples
    --------
    >>> import pendula
    >>> round(pendula.damping_rate(0.05, 0.1), 12)
    0.5
    """
    gamma, code, msg = _fortran.physics_rate_f2py(GLUE_GAMMA, real_scalar(b, "b"), real_scalar(mass, "mass"))
    raise_for_status(code, msg)
    return float(gamma)


_W0_DEFAULT = natural_frequency()

# Docstring parts shared by the functions that take a pendulum, substituted for
# "{pendulum}", "{damping}", "{raises}", "{swing}" and "{checks}" (see ``documented``), so that
# the convention is written once.
DOC_PARTS = {
    "pendulum": """w0 : float or array_like, optional
        Natural angular frequency sqrt(g/length) [1/s], finite and > 0.
    g, length : float, optional
        Gravity [m/s^2] and length [m], finite and > 0, instead of w0 (w0 may
        be given with them only if it agrees).  None of w0, g, length given:
        the text's pendulum, g = 9.8 and length = 4.9 (w0 = sqrt(2)).""",
    "damping": """gamma : float or array_like, optional
        Damping rate b/mass [1/s], finite and >= 0.
    b, mass : float, optional
        Damping coefficient [kg/s] >= 0 and bob mass [kg] > 0, both or
        neither, instead of gamma (gamma = b/mass, text eq. 2.2; gamma may be
        given with them only if it agrees).  None given: gamma = 0.""",
    "raises": """ValueError
        A non-finite input, w0 <= 0, shapes that do not broadcast, or w0
        given with g or length that disagree with it.
    TypeError
        Non-real input (str, bool, complex).""",
    "swing": """AngleWarning
        abs(theta0) > 2 pi while the pendulum swings (degrees given as radians?).""",
}
# The Raises and Warns sections of the functions of a swinging state, "{checks}".
DOC_PARTS["checks"] = f"""Raises
    ------
    {DOC_PARTS["raises"]}

    Warns
    -----
    {DOC_PARTS["swing"]}"""


def documented(f=None, **parts):
    """Decorator: put ``parts`` (one module's own) and then DOC_PARTS into the
    docstring, so a module's part may itself hold "{pendulum}" and the like;
    ``@documented`` or ``@documented(name=text)``."""
    if f is None:
        return lambda g: documented(g, **parts)
    for key, text in [*parts.items(), *DOC_PARTS.items()]:
        f.__doc__ = f.__doc__.replace("{" + key + "}", text)
    return f


def _disagree(given, name, derived, what):
    """ValueError where ``given`` (its finite elements: a non-finite one is
    refused later by its own check) differs from ``derived`` by more than
    PARAM_RTOL relative -- Scene's test for gamma against b/mass."""
    a = as_real(given, name)
    bad = np.isfinite(a) & (np.abs(a - derived) > PARAM_RTOL * np.maximum(np.abs(a), derived))
    if bad.any():
        x = float(a.reshape(-1)[int(np.flatnonzero(bad)[0])])
        raise ValueError(
            f"{name} = {x!r} and {what} = {derived!r} disagree: give {name}, "
            f"or {'g and length' if name == 'w0' else 'mass and b'}, not both"
        )


def pendulum_w0(w0=None, g=None, length=None):
    """w0 from the package's one convention (see the module docstring): ``w0``
    as given (scalar or array, checked by the caller's kernel), else
    sqrt(g/length) with the text's value for the one not given.  w0 together
    with g or length is accepted only when they agree within PARAM_RTOL
    relative, as Scene accepts gamma together with b and mass."""
    if g is None and length is None:
        return _W0_DEFAULT if w0 is None else w0
    derived = natural_frequency(G_DEFAULT if g is None else g, LENGTH_DEFAULT if length is None else length)
    if w0 is None:
        return derived
    _disagree(w0, "w0", derived, "sqrt(g/length)")
    return w0


def pendulum_gamma(gamma=None, b=None, mass=None):
    """gamma from the one convention: ``gamma`` as given, else b/mass (both
    needed), else 0; gamma together with b and mass is accepted when they agree
    within PARAM_RTOL relative -- Scene's rule (pendula_scene_setup)."""
    if b is None and mass is None:
        return 0.0 if gamma is None else gamma
    if b is None or mass is None:
        given, missing = ("mass", "b") if b is None else ("b", "mass")
        raise ValueError(
            f"{given} is given without {missing}: give both mass and b (gamma = b/mass, eq. 2.1), or gamma alone"
        )
    derived = damping_rate(b, mass)
    if gamma is None:
        return derived
    _disagree(gamma, "gamma", derived, "b/mass")
    return gamma


@documented
def small_angle_period(
    w0: ArrayLike | None = None, *, g: ArrayLike | None = None, length: ArrayLike | None = None
) -> float | np.ndarray:
    """Small-angle period T0 = 2 pi / w0 = 2 pi sqrt(length/g) (text eq. 1.8).

    The period of the harmonic model theta0 cos(w0 t), the limit of the
    exact period ``pendula.period`` as the amplitude goes to 0.

    Parameters
    ----------
    {pendulum}

    Returns
    -------
    float or ndarray
        T0 [s], of w0's shape (a float for scalar input).

    Raises
    ------
    ValueError
        w0 non-finite or below 3.5e-308 (T0 would overflow); g or length not
        finite and > 0; w0 given with g or length that disagree with it.
    TypeError
        Non-real input (str, bool, complex, None inside an array).

    Notes
    -----
    Correctly rounded up to the final division: within 1 ulp.

    Examples
    --------
    >>> import pendula
    >>> round(pendula.small_angle_period(), 6)          # the text's pendulum
    4.442883
    >>> round(pendula.small_angle_period(1.0), 6)
    6.283185
    >>> pendula.small_angle_period([1.0, 2.0]).round(6)
    array([6.283185, 3.141593])
    """
    shape, scalar, f = broadcast_real(w0=pendulum_w0(w0, g, length))
    t0, code, msg = _fortran.small_angle_period_f2py(f["w0"])
    raise_for_status(code, msg)
    return restore(t0, shape, scalar)


@documented
def period_series(
    m: ArrayLike, w0: ArrayLike | None = None, *, g: ArrayLike | None = None, length: ArrayLike | None = None
) -> float | np.ndarray:
    """The textbook's amplitude correction to the period, T0 (1 + m/4 + 9 m^2/64).

    T0 = 2 pi / w0 is the small-angle period (text eq. 1.8) and m = k^2 the
    parameter of a libration (m = sin^2(theta0/2) released from rest, eq.
    1.53's K(k^2)): the first three terms of the exact T = T0 2 K(m)/pi
    (DLMF 19.5.1).  A model, not the period: ``pendula.period`` is exact.

    Parameters
    ----------
    m : float or array_like
        Elliptic parameter, in [0, 1].
    {pendulum}

    Returns
    -------
    float or ndarray
        The series' period [s], of the broadcast shape of m and w0.

    Raises
    ------
    ValueError
        m outside [0, 1], w0 out of range, shapes that do not broadcast, or
        w0 given with disagreeing g/length.
    TypeError
        Non-real input.

    Notes
    -----
    Relative error against the exact period 25 m^3/256 + O(m^4); unbounded
    as m -> 1, where the exact period diverges and the series stays finite.

    Examples
    --------
    >>> import pendula
    >>> round(pendula.period_series(0.0, w0=1.0), 6)
    6.283185
    >>> round(pendula.period_series(0.5), 4)          # the text's pendulum
    5.1544
    """
    shape, scalar, f = broadcast_real(m=m, w0=pendulum_w0(w0, g, length))
    if f["m"].size == 0:
        return np.empty(shape)
    t, code, msg = _fortran.period_series_f2py(f["m"], f["w0"])
    raise_for_status(code, msg)
    return restore(t, shape, scalar)


__all__ = ["natural_frequency", "damping_rate", "small_angle_period", "period_series"]
