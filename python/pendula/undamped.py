"""The undamped pendulum theta'' + w0^2 sin(theta) = 0 in closed form, for any start.

Every initial state (theta0, omega0) is answered exactly, whatever its energy:
libration (swinging, m < 1), separatrix (m = 1, creeping towards the top
forever) and rotation (m > 1, going over the top; theta keeps counting turns).
Here m = sin^2(theta0/2) + (omega0/(2 w0))^2 is the energy over the separatrix
energy.  The text (§1.2-1.3) covers only omega0 = 0 (eq. 1.52) and theta0 = 0
(eq. 1.66) while swinging; both are special cases of ``undamped``.

Units: angles in rad, omega in rad/s, t in s, w0 = sqrt(g/l) in 1/s, energies
per unit m l^2 in 1/s^2.  Every function broadcasts its array arguments
(numpy rules), accepts any real t (negative, unsorted), returns Python floats
for scalar input and never modifies its input.  Non-finite input or w0 <= 0
raises ValueError naming the argument.

The numerics live in the Fortran modules pendula_undamped, pendula_small_angle
and pendula_equilibria; this module only converts.
"""
import math

import numpy as np

from . import _fortran as _undamped
from ._arrays import as_array, as_real, broadcast_real, check_size, integer_arg, restore
from ._errors import raise_for_status

REGIMES = {1: "libration", 2: "separatrix", 3: "rotation"}
_PERIOD, _AMPLITUDE = 1, 2     # which property period_amplitude_f2py returns
EQUILIBRIUM_TYPES = {1: "centre", 2: "saddle"}
#: Largest |n| accepted by ``equilibria`` (the Fortran index is a default integer).
N_MAX = 2**31 - 1


def undamped(t, theta0, omega0=0.0, w0=1.0):
    """Exact motion (theta(t), omega(t)) of the undamped pendulum from (theta0, omega0).

    m < 1:  sin(theta/2) = k sn(w0 t + u0 | m), omega = 2 k w0 cn(w0 t + u0 | m);
    m > 1:  theta = 2 s am(k w0 t + v0 | 1/m), omega = 2 s k w0 dn(...), s = sign(omega0);
    m = 1:  theta = 2 s gd(w0 t + c), omega = 2 s w0 sech(w0 t + c),
    with k = sqrt(m) and the phases u0, v0, c fixed by the initial state.
    theta is continuous in t and with theta0 (a rotating pendulum's angle grows
    without bound).  Accuracy: a few eps times the condition number
    sum |x d theta/dx| over x in {theta0, omega0, w0, t} (tested to 16 eps cond
    against mpmath over 100 periods).  One state at many times costs one setup.

    Returns ``(theta, omega)`` in rad and rad/s, of the broadcast shape.
    """
    state = [as_real(x, name) for x, name in ((theta0, "theta0"), (omega0, "omega0"), (w0, "w0"))]
    if all(x.ndim == 0 for x in state):
        # one state at many times: only t is copied, the motion is built once
        ta = as_real(t, "t")
        if ta.size == 0:
            return np.empty(ta.shape), np.empty(ta.shape)
        theta, omega, code, msg = _undamped.undamped_one_f2py(ta.reshape(-1), *(float(x) for x in state))
        raise_for_status(code, msg)
        return restore(theta, ta.shape, ta.ndim == 0), restore(omega, ta.shape, ta.ndim == 0)
    shape, scalar, f = broadcast_real(size1=True, t=t, theta0=theta0, omega0=omega0, w0=w0)
    n = math.prod(shape)
    if n == 0:
        return np.empty(shape), np.empty(shape)
    theta, omega, code, msg = _undamped.undamped_f2py(n, f["t"], f["theta0"], f["omega0"], f["w0"])
    raise_for_status(code, msg)
    return restore(theta, shape, scalar), restore(omega, shape, scalar)


def _two_outputs(kernel, **named):
    """Broadcast the named inputs, call the two-output f2py kernel on them (in
    that order), raise for its status; both results have the inputs' shape."""
    shape, scalar, f = broadcast_real(**named)
    if next(iter(f.values())).size == 0:
        return np.empty(shape), np.empty(shape)
    a, b, code, msg = kernel(*f.values())
    raise_for_status(code, msg)
    return restore(a, shape, scalar), restore(b, shape, scalar)


def small_angle(t, theta0, omega0=0.0, w0=1.0):
    """Small-angle (harmonic) model theta0 cos(w0 t) + (omega0/w0) sin(w0 t) (eq. 1.18).

    Linearised about the stable equilibrium 2 pi N nearest theta0 (identical to
    the formula above for |theta0| < pi).  Use ``small_angle_error`` to know
    how far it is from ``undamped``.  Returns ``(theta, omega)``.
    """
    return _two_outputs(_undamped.small_angle_f2py, t=t, theta0=theta0, omega0=omega0, w0=w0)


def small_angle_error(tmax, theta0, omega0=0.0, w0=1.0):
    """Rigorous bounds on the small-angle model's error over all |t| <= |tmax|.

    Returns ``(dtheta, domega)``: upper bounds on |small_angle - undamped| for
    theta (rad) and omega (rad/s).  From the Fourier series of the exact motion
    (amplitude error + phase drift + harmonics); the phase drift grows like
    (m/4) w0 t = (theta_max^2/16) w0 t.  +inf for the separatrix and rotation
    (the model cannot go over the top).  Non-decreasing in |tmax|.
    """
    return _two_outputs(_undamped.small_angle_bound_f2py, tmax=tmax, theta0=theta0, omega0=omega0, w0=w0)


def _state_property(kernel, nout, theta0, omega0, w0, *options):
    """Broadcast the states and run one of the Fortran property kernels (``nout`` results);
    ``options`` go between the size and the states."""
    shape, scalar, f = broadcast_real(size1=True, theta0=theta0, omega0=omega0, w0=w0)
    n = math.prod(shape)
    if n == 0:
        return shape, scalar, [np.empty(0)] * nout
    *values, code, msg = kernel(n, *options, f["theta0"], f["omega0"], f["w0"])
    raise_for_status(code, msg)
    return shape, scalar, values


def period(theta0, omega0=0.0, w0=1.0):
    """Period in s of the motion from (theta0, omega0).

    Libration: T = 4 K(m)/w0 (eq. 1.53, for any start, not only omega0 = 0);
    rotation: the time of one full turn 2 K(1/m)/(k w0) (the period of omega);
    separatrix: +inf.  theta0 = pi - 1e-10 gives the slow hug of the top
    (T ~ 4 ln(8/1e-10)/w0).  Accuracy a few eps times its condition number.
    """
    shape, scalar, (per,) = _state_property(_undamped.period_amplitude_f2py, 1, theta0, omega0, w0, _PERIOD)
    return restore(per, shape, scalar)


def amplitude(theta0, omega0=0.0, w0=1.0):
    """Amplitude in rad: max |theta - 2 pi N| = 2 asin(k) for libration, pi on the separatrix, +inf for rotation."""
    shape, scalar, (amp,) = _state_property(_undamped.period_amplitude_f2py, 1, theta0, omega0, w0, _AMPLITUDE)
    return restore(amp, shape, scalar)


def elliptic_parameter(theta0, omega0=0.0, w0=1.0):
    """``(m, 1 - m)``: m = sin^2(theta0/2) + (omega0/(2 w0))^2 = E/E_separatrix and its
    complement, the latter computed without cancellation (accurate near the separatrix)."""
    shape, scalar, (m, mc) = _state_property(_undamped.parameter_f2py, 2, theta0, omega0, w0)
    return restore(m, shape, scalar), restore(mc, shape, scalar)


def regime(theta0, omega0=0.0, w0=1.0):
    """'libration' (m < 1), 'separatrix' (m = 1) or 'rotation' (m > 1); a str, or an array of str."""
    shape, scalar, (codes,) = _state_property(_undamped.regime_f2py, 1, theta0, omega0, w0)
    if scalar:
        return REGIMES[int(codes[0])]
    names = np.array([""] + [REGIMES[k] for k in sorted(REGIMES)])   # codes are 1, 2, 3
    if len(codes) == 0:
        return np.empty(shape, dtype=names.dtype)
    return names.take(codes).reshape(shape)


def energy(theta, omega, w0=1.0):
    """Energy per unit m l^2 in 1/s^2: omega^2/2 + w0^2 (1 - cos theta) (eq. 1.2).

    0 at rest at the bottom, 2 w0^2 on the separatrix; constant along ``undamped``.
    Computed as omega^2/2 + 2 w0^2 sin^2(theta/2) (no cancellation near theta = 0).
    """
    shape, scalar, f = broadcast_real(theta=theta, omega=omega, w0=w0)
    if f["theta"].size == 0:
        return np.empty(shape)
    e, code, msg = _undamped.pendulum_energy_f2py(f["theta"], f["omega"], f["w0"])
    raise_for_status(code, msg)
    return restore(e, shape, scalar)


def equilibria(n, w0=1.0):
    """Equilibria (n pi, 0) and their linearisation (text §1.1, eqs 1.9-1.24).

    ``n``: integer or integer array (the equilibrium index), |n| <= 2**31 - 1
    (ValueError otherwise, checked exactly for any integer type, uint64
    included; bool and floats raise TypeError).  Returns
    ``(theta, eigenvalues, kind)``: theta = n pi in rad; eigenvalues of the
    Jacobian [[0, 1], [-w0^2 cos(n pi), 0]] in 1/s, a complex array of shape
    ``shape + (2,)`` (+-i w0 for even n, +-w0 for odd n); kind 'centre' (even n,
    hanging, stable) or 'saddle' (odd n, upright, unstable).
    """
    narr = np.asarray(integer_arg(n, "n", -N_MAX, N_MAX))   # checked before any narrowing cast
    w0a = as_real(w0, "w0")
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


__all__ = ["undamped", "small_angle", "small_angle_error", "period", "amplitude", "elliptic_parameter",
           "regime", "energy", "equilibria"]
