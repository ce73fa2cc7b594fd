"""Linear damped pendulum theta'' + gamma theta' + w0^2 theta = 0 (text eq. 2.4), in closed form.

One evaluation covers the over-damped (gamma > 2 w0, text §2.1.1), critical
(gamma = 2 w0, §2.1.2) and under-damped (gamma < 2 w0, §2.1.3) motion::

    theta(t) = exp(-gamma t/2) [theta0 C(t) + (omega0 + gamma theta0/2) S(t)]

with C = cosh(beta t), S = sinh(beta t)/beta, beta^2 = gamma^2/4 - w0^2 (cos and
sin of omega_d t below critical), evaluated so that it stays accurate through
gamma = 2 w0, for gamma >> w0, and never overflows (see the Fortran module
``pendula_linear_damped`` for the numerics).  The pendulum is ``w0=`` or ``g=`` and
``length=`` (default the text's, w0 = sqrt(2)), the damping ``gamma=`` or ``b=`` and
``mass=`` (default none), as everywhere in pendula (``pendula.physics``).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike

from . import _fortran
from ._arrays import as_array, as_real, broadcast_real, real_scalar, restore
from ._errors import raise_for_status
from .physics import documented, pendulum_gamma, pendulum_w0

_REGIMES = {1: "underdamped", 2: "critical", 3: "overdamped"}


_START = """t : float or array_like
        Time since the initial state [s], finite and >= 0.
    theta0 : float or array_like
        Initial angle [rad], finite.
    omega0 : float or array_like, optional
        Initial angular velocity [rad/s], finite.  Default 0.
    {pendulum}
    {damping}"""


def _params(w0, gamma, g, length, b, mass):
    return pendulum_w0(w0, g, length), pendulum_gamma(gamma, b, mass)


@documented(start=_START)
def linear_damped(
    t: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    gamma: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
    b: ArrayLike | None = None,
    mass: ArrayLike | None = None,
) -> tuple[float | np.ndarray, float | np.ndarray]:
    """Angle and angular velocity of the linear damped pendulum.

    The solution of theta'' + gamma theta' + w0^2 theta = 0 (text eq. 2.4)
    from (theta0, omega0) at t = 0, in all three regimes: over-damped
    (gamma > 2 w0, eqs 2.19-2.29), critical (gamma = 2 w0, eqs 2.30-2.47)
    and under-damped (gamma < 2 w0, §2.1.3, empty in the text and filled in
    here).

    Parameters
    ----------
    {start}

    Returns
    -------
    theta, omega : float or ndarray
        theta(t) [rad] and omega(t) = theta'(t) [rad/s], of the broadcast
        shape of all inputs (floats for scalar input).

    Raises
    ------
    ValueError
        t < 0, a non-finite input, w0 <= 0, gamma < 0, shapes that do not
        broadcast, mass without b (or b without mass), or redundant
        parameters that disagree.
    TypeError
        Non-real input.

    Notes
    -----
    Evaluated as exp(-gamma t/2) [theta0 C(t) + (omega0 + gamma theta0/2) S(t)]
    with C = cosh(beta t), S = sinh(beta t)/beta, beta^2 = gamma^2/4 - w0^2
    (cos and sin below critical), continuous through gamma = 2 w0.  Error
    within a few eps of abs(theta) + abs(omega)/max(w0, gamma) plus the problem's
    own condition number; values below the double range come out as 0,
    never NaN or Inf.  gamma = 0 gives the small-angle solution exactly.

    Examples
    --------
    >>> import pendula
    >>> theta, omega = pendula.linear_damped([0.0, 1.0], theta0=0.1, w0=1.0, gamma=0.5)
    >>> theta.round(6), omega.round(6)
    (array([0.1     , 0.060705]), array([ 0.      , -0.066269]))
    >>> round(pendula.linear_damped(1.0, 0.1, b=0.05, mass=0.1)[0], 6)   # gamma = 0.5
    0.02762
    """
    w0, gamma = _params(w0, gamma, g, length, b, mass)
    params = dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    if all(as_array(v, k).ndim == 0 for k, v in params.items()) and not isinstance(t, (str, bytes)):
        # One trajectory: set up once in Fortran, no broadcast copies of the parameters.
        tt = as_real(t, "t")
        shape, scalar = tt.shape, tt.ndim == 0
        p = {k: float(as_real(v, k)) for k, v in params.items()}
        if tt.size == 0:
            return np.empty(shape), np.empty(shape)
        theta, omega, code, msg = _fortran.linear_damped_one_f2py(
            tt.reshape(-1), p["theta0"], p["omega0"], p["w0"], p["gamma"]
        )
    else:
        shape, scalar, f = broadcast_real(t=t, **params)
        if f["t"].size == 0:
            return np.empty(shape), np.empty(shape)
        theta, omega, code, msg = _fortran.linear_damped_f2py(f["t"], f["theta0"], f["omega0"], f["w0"], f["gamma"])
    raise_for_status(code, msg)
    return restore(theta, shape, scalar), restore(omega, shape, scalar)


@documented(start=_START)
def linear_damped_envelope(
    t: ArrayLike,
    theta0: ArrayLike,
    omega0: ArrayLike = 0.0,
    w0: ArrayLike | None = None,
    gamma: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
    b: ArrayLike | None = None,
    mass: ArrayLike | None = None,
) -> float | np.ndarray:
    """Under-damped envelope R exp(-gamma t/2), with abs(theta(t)) <= envelope.

    R = sqrt(theta0^2 + ((omega0 + gamma theta0/2)/omega_d)^2), so that
    theta(t) = R exp(-gamma t/2) cos(omega_d t - phi) (text §2.1.3, filled in
    here); omega_d = sqrt(w0^2 - gamma^2/4).

    Parameters
    ----------
    {start}

    Returns
    -------
    float or ndarray
        The envelope [rad], of the broadcast shape; 0 for critical or
        over-damped motion (no oscillation to envelope).

    Raises
    ------
    ValueError
        As for :func:`linear_damped`.
    TypeError
        Non-real input.

    Notes
    -----
    R and the exponential are each evaluated to a few ulps; the bound
    abs(theta(t)) <= envelope holds with equality where cos(omega_d t - phi) = +-1.

    Examples
    --------
    >>> import pendula
    >>> round(pendula.linear_damped_envelope(0.0, 0.1, w0=1.0, gamma=0.5), 6)
    0.1...
    """
    w0, gamma = _params(w0, gamma, g, length, b, mass)
    shape, scalar, f = broadcast_real(t=t, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    if f["t"].size == 0:
        return np.empty(shape)
    env, code, msg = _fortran.linear_damped_envelope_f2py(f["t"], f["theta0"], f["omega0"], f["w0"], f["gamma"])
    raise_for_status(code, msg)
    return restore(env, shape, scalar)


@dataclasses.dataclass(frozen=True)
class DampingRegime:
    """Regime of theta'' + gamma theta' + w0^2 theta = 0 and its numbers.

    Returned by :func:`damping_regime`; the eigenvalues are those of the
    text's eq. 2.15, lambda = -gamma/2 +- sqrt(gamma^2/4 - w0^2).

    Attributes
    ----------
    regime : str
        'underdamped' (gamma < 2 w0), 'critical' (gamma == 2 w0 exactly) or
        'overdamped' (gamma > 2 w0).
    w0, gamma : float
        The rates it was computed for [1/s].
    lambda1, lambda2 : complex
        Eigenvalues [1/s]: the conjugate pair -gamma/2 -+ i omega_d when
        under-damped; real with lambda1 <= lambda2 otherwise.
    omega_d : float
        Damped angular frequency sqrt(w0^2 - gamma^2/4) [1/s] (0 unless under-damped).
    beta : float
        sqrt(gamma^2/4 - w0^2) [1/s] (0 unless over-damped).
    decay_slow, decay_fast : float
        -Re(lambda2) and -Re(lambda1) [1/s]: decay rates of the slow and fast modes.
    quality_factor : float
        Q = w0/gamma (inf when gamma = 0).
    log_decrement : float
        ln(theta(t)/theta(t + T_d)) = pi gamma/omega_d (inf when not oscillating).
    damped_period : float
        T_d = 2 pi/omega_d [s] (inf when not oscillating).
    gamma_critical : float
        2 w0 [1/s].
    damping_ratio : float
        zeta = gamma/(2 w0).

    Examples
    --------
    >>> import pendula
    >>> r = pendula.damping_regime(w0=1.0, gamma=0.5)
    >>> r.regime, round(r.omega_d, 6), r.quality_factor
    ('underdamped', 0.968246, 2.0)
    """

    regime: str
    w0: float
    gamma: float
    lambda1: complex
    lambda2: complex
    omega_d: float
    beta: float
    decay_slow: float
    decay_fast: float
    quality_factor: float
    log_decrement: float
    damped_period: float
    gamma_critical: float
    damping_ratio: float


@documented
def damping_regime(
    w0: ArrayLike | None = None,
    gamma: ArrayLike | None = None,
    *,
    g: ArrayLike | None = None,
    length: ArrayLike | None = None,
    b: ArrayLike | None = None,
    mass: ArrayLike | None = None,
) -> DampingRegime:
    """The regime of the linear damped pendulum and its numbers.

    Classifies theta'' + gamma theta' + w0^2 theta = 0 (text eq. 2.4) by its
    eigenvalues (eq. 2.15): over-damped (§2.1.1), critical (§2.1.2) or
    under-damped (§2.1.3), with the rates, periods and quality factor.

    Parameters
    ----------
    {pendulum}
    {damping}

    Returns
    -------
    DampingRegime
        The regime and its numbers (rates in 1/s, periods in s).

    Raises
    ------
    ValueError
        w0 <= 0, gamma < 0, a non-finite value, mass without b (or b without
        mass), or redundant parameters that disagree.
    TypeError
        w0 or gamma not a real scalar (arrays are refused here).

    Notes
    -----
    Critical means gamma == 2*w0 exactly in floating point; how close a value
    is to critical is ``damping_ratio - 1``.  omega_d and beta are formed as
    sqrt((w0 - gamma/2)(w0 + gamma/2)), without cancellation near critical.

    Examples
    --------
    >>> import pendula
    >>> pendula.damping_regime(gamma=3 * 2**0.5).regime      # the text's fig. 10: gamma = 3 w0
    'overdamped'
    >>> pendula.damping_regime(w0=1.0, gamma=2.0).regime
    'critical'
    >>> pendula.damping_regime(b=0.05, mass=0.1).regime      # §2.2's b and m
    'underdamped'
    """
    w0, gamma = _params(w0, gamma, g, length, b, mass)
    w0 = real_scalar(w0, "w0")
    gamma = real_scalar(gamma, "gamma")
    (regime, l1, l2, omega_d, beta, slow, fast, q, logdec, td, gcrit, zeta, code, msg) = _fortran.damping_regime_f2py(
        w0, gamma
    )
    raise_for_status(code, msg)
    return DampingRegime(
        regime=_REGIMES[int(regime)],
        w0=w0,
        gamma=gamma,
        lambda1=complex(float(l1[0]), float(l1[1])),
        lambda2=complex(float(l2[0]), float(l2[1])),
        omega_d=float(omega_d),
        beta=float(beta),
        decay_slow=float(slow),
        decay_fast=float(fast),
        quality_factor=float(q),
        log_decrement=float(logdec),
        damped_period=float(td),
        gamma_critical=float(gcrit),
        damping_ratio=float(zeta),
    )


__all__ = ["linear_damped", "linear_damped_envelope", "damping_regime", "DampingRegime"]
