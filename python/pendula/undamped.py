"""The undamped pendulum theta'' + w0^2 sin(theta) = 0 in closed form, for any start.

Every initial state (theta0, omega0) is answered exactly, whatever its energy:
libration (swinging, m < 1), separatrix (m = 1, creeping towards the top
forever) and rotation (m > 1, going over the top; theta keeps counting turns).
Here m = sin^2(theta0/2) + (omega0/(2 w0))^2 is the energy over the separatrix
energy.  The text (§1.2-1.3) covers only omega0 = 0 (eq. 1.52) and theta0 = 0
(eq. 1.66) while swinging; both are special cases of ``undamped``.

Units: angles in rad, omega in rad/s, t in s, w0 = sqrt(g/l) in 1/s, energies
per unit m l^2 in 1/s^2.  The pendulum is ``w0=`` or ``g=`` and ``length=``;
given none, the text's (g = 9.8, length = 4.9, w0 = sqrt(2)), as everywhere in
pendula (``pendula.physics``).  Every function broadcasts its array arguments
(numpy rules), accepts any real t (negative, unsorted), returns Python floats
for scalar input and never modifies its input.  Non-finite input or w0 <= 0
raises ValueError naming the argument.

The numerics live in the Fortran modules pendula_undamped, pendula_small_angle
and pendula_equilibria; this module only converts.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from . import _fortran as _undamped
from ._angle_warning import AngleWarning, warn_if_degrees
from ._arrays import as_real, broadcast_real, check_size, integer_arg, restore
from ._codes import GLUE_AMPLITUDE, GLUE_PERIOD, GLUE_SMALL_ANGLE_BOUND, GLUE_SMALL_ANGLE_MOTION
from ._errors import raise_for_status
from .physics import documented, pendulum_w0

REGIMES = {1: "libration", 2: "separatrix", 3: "rotation"}
EQUILIBRIUM_TYPES = {1: "centre", 2: "saddle"}

# Docstring parts of this module (see physics.documented): omega0 and the
# pendulum, "{omega0}"; the state parameters of a function whose theta0 may
# warn, "{swing_state}".
_OMEGA0 = """omega0 : float or array_like, optional
        Initial angular velocity [rad/s], finite.  Default 0.
    {pendulum}"""
_SWING_STATE = """theta0 : float or array_like
        Initial angle [rad], finite; abs(theta0) > 2 pi on a swinging state
        warns (:class:`AngleWarning`).
    {omega0}"""
_documented = documented(swing_state=_SWING_STATE, omega0=_OMEGA0)
#: Largest abs(n) accepted by ``equilibria`` (the Fortran index is a default integer).
N_MAX = 2**31 - 1


@_documented
def undamped(
    t: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> tuple[float | np.ndarray, float | np.ndarray]:
    """Exact motion (theta(t), omega(t)) of the undamped pendulum from any state.

    Solves theta'' + w0^2 sin(theta) = 0 (text eq. 1.3) in closed form for
    every initial state (theta0, omega0), whatever its energy; the text's
    eqs 1.52 (omega0 = 0) and 1.66 (theta0 = 0) are special cases.  With
    m = sin^2(theta0/2) + (omega0/(2 w0))^2 and k = sqrt(m):

    * m < 1 (libration): sin(theta/2) = k sn(w0 t + u0 | m),
      omega = 2 k w0 cn(w0 t + u0 | m);
    * m > 1 (rotation): theta = 2 s am(k w0 t + v0 | 1/m),
      omega = 2 s k w0 dn(...), s = sign(omega0);
    * m = 1 (separatrix): theta = 2 s gd(w0 t + c), omega = 2 s w0 sech(w0 t + c).

    Parameters
    ----------
    t : float or array_like
        Times [s], any real values (negative, unsorted).
    theta0 : float or array_like
        Initial angle [rad], finite.
    {omega0}

    Returns
    -------
    theta, omega : float or ndarray
        Angle [rad] and angular velocity [rad/s] at t, of the broadcast shape
        of all inputs (floats for scalar input).  theta is continuous in t: a
        rotating pendulum's angle grows without bound.

    Raises
    ------
    {raises}

    Notes
    -----
    Accuracy a few eps times the condition number sum abs(x d theta/dx) over x
    in {theta0, omega0, w0, t} (tested to 16 eps times it against mpmath
    over 100 periods).  One state at many times costs one setup.

    Examples
    --------
    >>> import pendula
    >>> theta, omega = pendula.undamped([0.0, 1.0], theta0=1.0)
    >>> theta.round(6), omega.round(6)
    (array([1.      , 0.247234]), array([ 0.      , -1.310406]))
    >>> round(pendula.undamped(2.0, 0.0, omega0=3.0, w0=1.0)[0], 6)   # over the top
    5.076914
    """
    w0 = pendulum_w0(w0, g, length)
    state = [as_real(x, name) for x, name in ((theta0, "theta0"), (omega0, "omega0"), (w0, "w0"))]
    if all(x.ndim == 0 for x in state):
        # one state at many times: only t is copied, the motion is built once
        ta = as_real(t, "t")
        if ta.size == 0:
            return np.empty(ta.shape), np.empty(ta.shape)
        theta, omega, code, msg = _undamped.undamped_one_f2py(ta.reshape(-1), *(float(x) for x in state))
        raise_for_status(code, msg)
        return restore(theta, ta.shape, ta.ndim == 0), restore(omega, ta.shape, ta.ndim == 0)
    shape, scalar, f = _broadcast_states(t=t, theta0=theta0, omega0=omega0, w0=w0)
    n = math.prod(shape)
    if n == 0:
        return np.empty(shape), np.empty(shape)
    theta, omega, code, msg = _undamped.undamped_f2py(n, f["t"], f["theta0"], f["omega0"], f["w0"])
    raise_for_status(code, msg)
    return restore(theta, shape, scalar), restore(omega, shape, scalar)


def _small_angle(which, **named):
    """Broadcast the named inputs, warn for amplitudes that look like degrees,
    call the small-angle glue with selector code which on them (in that order)
    and raise for its status; both results have the inputs' shape."""
    shape, scalar, f = broadcast_real(**named)
    if next(iter(f.values())).size == 0:
        return np.empty(shape), np.empty(shape)
    warn_if_degrees(f["theta0"], f["omega0"], f["w0"])
    a, b, code, msg = _undamped.small_angle_f2py(which, *f.values())
    raise_for_status(code, msg)
    return restore(a, shape, scalar), restore(b, shape, scalar)


@_documented
def small_angle(
    t: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> tuple[float | np.ndarray, float | np.ndarray]:
    """Small-angle (harmonic) model theta0 cos(w0 t) + (omega0/w0) sin(w0 t).

    The solution of the linearised equation theta'' + w0^2 theta = 0 (text
    eqs 1.4, 1.7 and 1.18), about the stable equilibrium 2 pi N nearest theta0
    (the formula above for abs(theta0) < pi).  :func:`small_angle_error` bounds
    its distance from the exact :func:`undamped`.

    Parameters
    ----------
    t : float or array_like
        Times [s], any real values.
    theta0 : float or array_like
        Initial angle [rad], finite; abs(theta0) > 2 pi on a swinging state
        warns (:class:`AngleWarning`: degrees given as radians?).
    {omega0}

    Returns
    -------
    theta, omega : float or ndarray
        Angle [rad] and angular velocity [rad/s] of the model at t, of the
        broadcast shape.

    {checks}

    Notes
    -----
    The model is evaluated to a few ulps; as a model of the pendulum its
    error is what :func:`small_angle_error` bounds (phase drift about
    (theta_max^2/16) w0 t).

    Examples
    --------
    >>> import pendula
    >>> theta, omega = pendula.small_angle([0.0, 1.0], theta0=0.1, w0=1.0)
    >>> theta.round(6), omega.round(6)
    (array([0.1    , 0.05403]), array([ 0.      , -0.084147]))
    """
    return _small_angle(GLUE_SMALL_ANGLE_MOTION, t=t, theta0=theta0, omega0=omega0, w0=pendulum_w0(w0, g, length))


@_documented
def small_angle_error(
    tmax: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> float | np.ndarray:
    """Rigorous bounds on the small-angle model's error over all abs(t) <= abs(tmax).

    How far :func:`small_angle` (text eq. 1.18) is from the exact motion
    (eqs 1.52, 1.66 and their generalisation :func:`undamped`) over a time
    window: from the Fourier series of the exact motion (amplitude error,
    phase drift and harmonics).

    Parameters
    ----------
    tmax : float or array_like
        Half-width of the window [s], any real value (abs(tmax) is used).
    {swing_state}

    Returns
    -------
    dtheta, domega : float or ndarray
        Upper bounds on abs(small_angle - undamped) for theta [rad] and omega
        [rad/s] over the window, of the broadcast shape; +inf for the
        separatrix and rotations (the model cannot go over the top).

    {checks}

    Notes
    -----
    Bounds, not estimates: never below the true error (tested against the
    exact motion); non-decreasing in abs(tmax).  The phase drift grows like
    (m/4) w0 t = (theta_max^2/16) w0 t.

    Examples
    --------
    >>> import pendula
    >>> dtheta, domega = pendula.small_angle_error(10.0, theta0=0.1)
    >>> bool(dtheta < 2e-3), bool(domega < 3e-3)
    (True, True)
    """
    return _small_angle(GLUE_SMALL_ANGLE_BOUND, tmax=tmax, theta0=theta0, omega0=omega0, w0=pendulum_w0(w0, g, length))


def _broadcast_states(**named):
    """``broadcast_real(size1=True, **named)`` without its copies in the common large
    case: every array a contiguous float64 ndarray of one shape, the other inputs Python
    floats (one value for every state).  The f2py kernels take them intent(in) and never
    write to them; anything else goes through broadcast_real."""
    arrays = [v for v in named.values() if type(v) is np.ndarray]
    if not arrays or not all(type(v) is float or type(v) is np.ndarray for v in named.values()):
        return broadcast_real(size1=True, **named)
    shape = arrays[0].shape
    if not all(a.dtype == np.float64 and a.flags.c_contiguous and a.ndim >= 1 and a.shape == shape for a in arrays):
        return broadcast_real(size1=True, **named)
    check_size(arrays[0].size, next(k for k, v in named.items() if v is arrays[0]))
    flats = {k: v.reshape(-1) if type(v) is np.ndarray else np.array([v]) for k, v in named.items()}
    return shape, False, flats


def _state_property(kernel, nout, theta0, omega0, w0, *options, g=None, length=None, amplitude=False):
    """Broadcast the states and run one of the Fortran property kernels (``nout``
    results); ``options`` go between the size and the states.  ``amplitude``:
    theta0 is an amplitude, so warn where it looks like degrees."""
    shape, scalar, f = _broadcast_states(theta0=theta0, omega0=omega0, w0=pendulum_w0(w0, g, length))
    n = math.prod(shape)
    if n == 0:
        return shape, scalar, [np.empty(0)] * nout
    if amplitude:
        warn_if_degrees(f["theta0"], f["omega0"], f["w0"])
    *values, code, msg = kernel(n, *options, f["theta0"], f["omega0"], f["w0"])
    raise_for_status(code, msg)
    return shape, scalar, values


@_documented
def period(
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> float | np.ndarray:
    """Exact period of the undamped pendulum from the state (theta0, omega0).

    Libration: T = 4 K(m)/w0 (text eq. 1.53, here for any start, not only
    omega0 = 0); rotation: the time of one full turn, 2 K(1/m)/(k w0) (the
    period of omega); separatrix: +inf.  m = sin^2(theta0/2) +
    (omega0/(2 w0))^2.

    Parameters
    ----------
    theta0 : float or array_like
        Initial angle [rad], finite; abs(theta0) > 2 pi on a swinging state
        warns (:class:`AngleWarning`: ``period(90)`` is 90 rad, not 90 deg).
    {omega0}

    Returns
    -------
    float or ndarray
        Period [s], of the broadcast shape; +inf on the separatrix.

    {checks}

    Notes
    -----
    Accuracy a few eps times the condition number; 1 - m is formed without
    cancellation, so theta0 = pi - 1e-10 gives the slow hug of the top
    (T ~ 4 ln(8/1e-10)/w0) to full accuracy.

    Examples
    --------
    >>> import pendula
    >>> round(pendula.period(1.0), 6)          # the text's pendulum, w0 = sqrt(2)
    4.737598
    >>> round(pendula.period(1.0, w0=1.0), 6)
    6.699976
    >>> round(pendula.period(1.0, g=9.8, length=1.0), 6)
    2.140229
    """
    shape, scalar, (per,) = _state_property(
        _undamped.period_amplitude_f2py, 1, theta0, omega0, w0, GLUE_PERIOD, g=g, length=length, amplitude=True
    )
    return restore(per, shape, scalar)


@_documented
def amplitude(
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> float | np.ndarray:
    """Amplitude of the swing from the state (theta0, omega0).

    max abs(theta - 2 pi N) over the motion: 2 asin(k) for a libration (the
    text's theta_max of §1.3), pi on the separatrix, +inf for a rotation.

    Parameters
    ----------
    {swing_state}

    Returns
    -------
    float or ndarray
        Amplitude [rad], of the broadcast shape.

    {checks}

    Notes
    -----
    2 asin(k) with k = sqrt(m); accuracy a few eps times the condition
    number (large near the separatrix, where d asin/dk diverges).

    Examples
    --------
    >>> import pendula
    >>> round(pendula.amplitude(0.0, omega0=1.0, w0=1.0), 6)
    1.047198
    >>> pendula.amplitude(0.0, omega0=5.0, w0=1.0)      # rotation
    inf
    """
    shape, scalar, (amp,) = _state_property(
        _undamped.period_amplitude_f2py, 1, theta0, omega0, w0, GLUE_AMPLITUDE, g=g, length=length, amplitude=True
    )
    return restore(amp, shape, scalar)


@_documented
def elliptic_parameter(
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> float | np.ndarray:
    """Elliptic parameter m = E / E_separatrix of a state, and 1 - m.

    m = sin^2(theta0/2) + (omega0/(2 w0))^2 (the text's k^2 of eqs 1.52 and
    1.66, for any start): m < 1 swings, m = 1 is the separatrix, m > 1
    rotates.

    Parameters
    ----------
    theta0 : float or array_like
        Angle [rad], finite (no warning: any angle is a state).
    omega0 : float or array_like, optional
        Angular velocity [rad/s], finite.  Default 0.
    {pendulum}

    Returns
    -------
    m, mc : float or ndarray
        m and its complement 1 - m (dimensionless), of the broadcast shape.

    Raises
    ------
    {raises}

    Notes
    -----
    1 - m is never formed by subtraction: it is (c - abs(q))(c + abs(q)) with
    c = cos(theta0/2) in double-double and q = omega0/(2 w0), so it stays
    relatively accurate near the separatrix, where the period depends on it
    logarithmically.

    Examples
    --------
    >>> import pendula
    >>> m, mc = pendula.elliptic_parameter(1.0)
    >>> round(m, 6), round(mc, 6)
    (0.229849, 0.770151)
    """
    shape, scalar, (m, mc) = _state_property(_undamped.parameter_f2py, 2, theta0, omega0, w0, g=g, length=length)
    return restore(m, shape, scalar), restore(mc, shape, scalar)


@_documented
def regime(
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> str | np.ndarray:
    """Kind of motion from a state: 'libration', 'separatrix' or 'rotation'.

    From m = E / E_separatrix (:func:`elliptic_parameter`): swinging (m < 1,
    text §1.2-1.3), the separatrix (m = 1, creeping towards the top forever)
    or going over the top (m > 1; beyond the text).

    Parameters
    ----------
    theta0 : float or array_like
        Angle [rad], finite.
    omega0 : float or array_like, optional
        Angular velocity [rad/s], finite.  Default 0.
    {pendulum}

    Returns
    -------
    str or ndarray of str
        The regime, of the broadcast shape (a str for scalar input).

    Raises
    ------
    {raises}

    Notes
    -----
    Decided on the sign of 1 - m as computed for :func:`elliptic_parameter`
    (without cancellation), so states a few ulps from the separatrix are
    classified by their own energy.

    Examples
    --------
    >>> import pendula
    >>> pendula.regime(1.0), pendula.regime(0.0, omega0=3.0)
    ('libration', 'rotation')
    """
    shape, scalar, (codes,) = _state_property(_undamped.regime_f2py, 1, theta0, omega0, w0, g=g, length=length)
    if scalar:
        return REGIMES[int(codes[0])]
    names = np.array([""] + [REGIMES[k] for k in sorted(REGIMES)])  # codes are 1, 2, 3
    if len(codes) == 0:
        return np.empty(shape, dtype=names.dtype)
    return names.take(codes).reshape(shape)


@_documented
def energy(
    theta: ArrayLike,
    omega: ArrayLike,
    w0: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
) -> float | np.ndarray:
    """Energy per unit m l^2, omega^2/2 + w0^2 (1 - cos theta).

    K + U of the text's Lagrangian (eq. 1.1) over m l^2.  0 at rest at the
    bottom, 2 w0^2 on the separatrix; constant along
    :func:`undamped`.  theta is any angle of a trajectory (no warning for
    large values: a rotating pendulum's angle counts turns).

    Parameters
    ----------
    theta : float or array_like
        Angle [rad], finite.
    omega : float or array_like
        Angular velocity [rad/s], finite.
    {pendulum}

    Returns
    -------
    float or ndarray
        Energy [1/s^2] (per unit m l^2), of the broadcast shape.

    Raises
    ------
    {raises}

    Notes
    -----
    Computed as omega^2/2 + 2 w0^2 sin^2(theta/2): no cancellation near
    theta = 0, a few ulps.

    Examples
    --------
    >>> import pendula
    >>> round(pendula.energy(3.141592653589793, 0.0), 12)   # 2 w0^2, w0 = sqrt(2)
    4.0
    >>> round(pendula.energy(0.0, 1.0, w0=1.0), 12)
    0.5
    """
    shape, scalar, f = broadcast_real(theta=theta, omega=omega, w0=pendulum_w0(w0, g, length))
    if f["theta"].size == 0:
        return np.empty(shape)
    e, code, msg = _undamped.pendulum_energy_f2py(f["theta"], f["omega"], f["w0"])
    raise_for_status(code, msg)
    return restore(e, shape, scalar)


@_documented
def equilibria(
    n: ArrayLike, w0: ArrayLike | None = None, *, g: ArrayLike | None = None, length: ArrayLike | None = None
) -> float | np.ndarray:
    """Equilibria (n pi, 0) of the pendulum and their linearisation (text §1.1).

    The Jacobian [[0, 1], [-w0^2 cos(n pi), 0]] (eqs 1.9-1.24) has
    eigenvalues +-i w0 for even n (hanging: a centre, stable) and +-w0 for
    odd n (upright: a saddle, unstable).

    Parameters
    ----------
    n : int or array_like of int
        Equilibrium index, abs(n) <= 2**31 - 1 (checked exactly for any integer
        type, uint64 included).
    {pendulum}

    Returns
    -------
    theta : float or ndarray
        n pi [rad], of the broadcast shape of n and w0.
    eigenvalues : ndarray of complex
        The Jacobian's eigenvalues [1/s], shape ``shape + (2,)``.
    kind : str or ndarray of str
        'centre' (even n) or 'saddle' (odd n).

    Raises
    ------
    ValueError
        abs(n) too large, w0 <= 0 or non-finite, shapes that do not broadcast,
        or w0 given with disagreeing g/length.
    TypeError
        n not an integer (bool and floats included), or non-real w0.

    Notes
    -----
    theta = n pi correctly rounded; the eigenvalues are exact up to w0's
    rounding.

    Examples
    --------
    >>> import pendula
    >>> theta, lam, kind = pendula.equilibria(1, w0=1.0)
    >>> round(theta, 6), lam.real.tolist(), kind
    (3.141593, [1.0, -1.0], 'saddle')
    """
    narr = np.asarray(integer_arg(n, "n", -N_MAX, N_MAX))  # checked before any narrowing cast
    w0a = as_real(pendulum_w0(w0, g, length), "w0")
    try:
        shape = np.broadcast_shapes(narr.shape, w0a.shape)
    except ValueError:
        raise ValueError(f"arguments cannot be broadcast together: n{narr.shape}, w0{w0a.shape}") from None
    check_size(int(np.prod(shape, dtype=np.int64)), f"the broadcast of n{narr.shape}, w0{w0a.shape}")
    scalar = narr.ndim == 0 and w0a.ndim == 0
    nf = np.ascontiguousarray(np.broadcast_to(narr, shape), dtype=np.int32).reshape(-1)
    wf = np.ascontiguousarray(np.broadcast_to(w0a, shape), dtype=np.float64).reshape(-1)
    if nf.size == 0:
        return np.empty(shape), np.empty(shape + (2,), dtype=complex), np.empty(shape, dtype="<U6")
    theta, lre, lim, kind, code, msg = _undamped.equilibria_f2py(nf, wf)
    raise_for_status(code, msg)
    lam = np.empty(nf.shape + (2,), dtype=complex)
    lam[:, 0] = lre + 1j * lim
    lam[:, 1] = -lam[:, 0]
    kinds = np.array([EQUILIBRIUM_TYPES[int(k)] for k in kind], dtype=object)
    if scalar:
        return float(theta[0]), lam[0], str(kinds[0])
    return theta.reshape(shape), lam.reshape(shape + (2,)), kinds.reshape(shape).astype(str)


__all__ = [
    "undamped",
    "small_angle",
    "small_angle_error",
    "period",
    "amplitude",
    "elliptic_parameter",
    "regime",
    "energy",
    "equilibria",
    "AngleWarning",
]
