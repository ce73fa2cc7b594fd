"""Linear damped pendulum theta'' + gamma theta' + w0^2 theta = 0 (text eq. 2.4), in closed form.

One evaluation covers the over-damped (gamma > 2 w0, text §2.1.1), critical
(gamma = 2 w0, §2.1.2) and under-damped (gamma < 2 w0, §2.1.3) motion::

    theta(t) = exp(-gamma t/2) [theta0 C(t) + (omega0 + gamma theta0/2) S(t)]

with C = cosh(beta t), S = sinh(beta t)/beta, beta^2 = gamma^2/4 - w0^2 (cos and
sin of omega_d t below critical), evaluated so that it stays accurate through
gamma = 2 w0, for gamma >> w0, and never overflows (see the Fortran module
``pendula_linear_damped`` for the numerics).
"""
import dataclasses

import numpy as np

from . import _fortran
from ._arrays import as_array, as_real, broadcast_real, real_scalar, restore
from ._errors import raise_for_status

_REGIMES = {1: "underdamped", 2: "critical", 3: "overdamped"}


def _call(t, theta0, omega0, w0, gamma):
    return broadcast_real(t=t, theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)


def linear_damped(t, theta0, omega0, w0, gamma):
    """Angle and angular velocity of the linear damped pendulum.

    Parameters (all broadcast together; scalars in give floats out):
      t       time since the initial state, s, finite and >= 0
      theta0  initial angle theta(0), rad, finite
      omega0  initial angular velocity Omega(0), rad/s, finite
      w0      natural angular frequency sqrt(g/l), 1/s, finite and > 0
      gamma   damping rate b/m, 1/s, finite and >= 0

    Returns ``(theta, omega)``: theta(t) in rad and Omega(t) = theta'(t) in rad/s.
    gamma = 0 gives the small-angle solution theta0 cos(w0 t) + (omega0/w0) sin(w0 t)
    exactly.  Accuracy: error within a few eps of |theta| + |Omega|/max(w0, gamma)
    plus the problem's own condition number (measured worst cases in the README).
    Values below the double range come out as 0, never NaN/Inf.
    Raises ValueError naming the argument for bad input.
    """
    params = dict(theta0=theta0, omega0=omega0, w0=w0, gamma=gamma)
    if all(as_array(v, k).ndim == 0 for k, v in params.items()) and not isinstance(t, (str, bytes)):
        # One trajectory: set up once in Fortran, no broadcast copies of the parameters.
        tt = as_real(t, "t")
        shape, scalar = tt.shape, tt.ndim == 0
        p = {k: float(as_real(v, k)) for k, v in params.items()}
        if tt.size == 0:
            return np.empty(shape), np.empty(shape)
        theta, omega, code, msg = _fortran.linear_damped_one_f2py(
            tt.reshape(-1), p["theta0"], p["omega0"], p["w0"], p["gamma"])
    else:
        shape, scalar, f = _call(t, theta0, omega0, w0, gamma)
        if f["t"].size == 0:
            return np.empty(shape), np.empty(shape)
        theta, omega, code, msg = _fortran.linear_damped_f2py(
            f["t"], f["theta0"], f["omega0"], f["w0"], f["gamma"])
    raise_for_status(code, msg)
    return restore(theta, shape, scalar), restore(omega, shape, scalar)


def linear_damped_envelope(t, theta0, omega0, w0, gamma):
    """Under-damped envelope R exp(-gamma t/2) in rad, |theta(t)| <= envelope.

    R = sqrt(theta0^2 + ((omega0 + gamma theta0/2)/omega_d)^2), so that
    theta(t) = R exp(-gamma t/2) cos(omega_d t - phi) (text §2.1.3, filled in here).
    Arguments as for :func:`linear_damped`; 0 for critical or over-damped motion.
    """
    shape, scalar, f = _call(t, theta0, omega0, w0, gamma)
    if f["t"].size == 0:
        return np.empty(shape)
    env, code, msg = _fortran.linear_damped_envelope_f2py(
        f["t"], f["theta0"], f["omega0"], f["w0"], f["gamma"])
    raise_for_status(code, msg)
    return restore(env, shape, scalar)


@dataclasses.dataclass(frozen=True)
class DampingRegime:
    """Regime of theta'' + gamma theta' + w0^2 theta = 0 and its numbers (rates in 1/s).

    regime          'underdamped' (gamma < 2 w0), 'critical' (gamma == 2 w0 exactly)
                    or 'overdamped' (gamma > 2 w0)
    lambda1,lambda2 eigenvalues of text eq. 2.15 (complex; conjugate pair
                    -gamma/2 -+ i omega_d when under-damped; lambda1 <= lambda2 when real)
    omega_d         damped angular frequency sqrt(w0^2 - gamma^2/4) (0 unless under-damped)
    beta            sqrt(gamma^2/4 - w0^2) (0 unless over-damped)
    decay_slow      -Re(lambda2): rate of the slowest decaying mode
    decay_fast      -Re(lambda1)
    quality_factor  Q = w0/gamma (inf when gamma = 0)
    log_decrement   ln(theta(t)/theta(t + T_d)) = pi gamma/omega_d (inf when not oscillating)
    damped_period   T_d = 2 pi/omega_d in s (inf when not oscillating)
    gamma_critical  2 w0
    damping_ratio   zeta = gamma/(2 w0)
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


def damping_regime(w0, gamma):
    """The regime of the linear damped pendulum and its numbers, as a :class:`DampingRegime`.

    w0 > 0 and gamma >= 0 (1/s, finite scalars); ValueError naming the argument otherwise.
    Critical means gamma == 2*w0 exactly in floating point; how close a value is
    to critical is ``damping_ratio - 1``.
    """
    w0 = real_scalar(w0, "w0")
    gamma = real_scalar(gamma, "gamma")
    (regime, l1, l2, omega_d, beta, slow, fast, q, logdec, td, gcrit, zeta,
     code, msg) = _fortran.damping_regime_f2py(w0, gamma)
    raise_for_status(code, msg)
    return DampingRegime(
        regime=_REGIMES[int(regime)], w0=w0, gamma=gamma,
        lambda1=complex(float(l1[0]), float(l1[1])), lambda2=complex(float(l2[0]), float(l2[1])),
        omega_d=float(omega_d), beta=float(beta), decay_slow=float(slow), decay_fast=float(fast),
        quality_factor=float(q), log_decrement=float(logdec), damped_period=float(td),
        gamma_critical=float(gcrit), damping_ratio=float(zeta))


__all__ = ["linear_damped", "linear_damped_envelope", "damping_regime", "DampingRegime"]
