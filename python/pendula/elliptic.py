"""Elliptic integrals and Jacobi elliptic functions for every real parameter.

Names, the parameter convention (m = k**2) and the return order follow
``scipy.special`` so code can switch by changing an import:

* ``ellipk(m)``, ``ellipkm1(p)`` (= K(1 - p)), ``ellipe(m)``, ``ellipem1(p)``
  (= E(1 - p)): complete integrals, m <= 1 (p >= 0).
* ``ellipf(phi, m)`` (alias ``ellipkinc``), ``ellipfm1(phi, p)`` (= F(phi | 1 - p)):
  incomplete integral of the first kind, any real phi (rad), m sin^2(phi) <= 1.
* ``ellipj(u, m) -> (sn, cn, dn, ph)``, ``ellipjm1(u, p)`` (= ellipj(u, 1 - p)):
  Jacobi functions and amplitude for all real u and m.

The ``*m1`` complement forms take p = 1 - m directly: near m = 1 (the
pendulum's separatrix) forming 1 - m in floating point loses every digit,
while p can be as small as the smallest subnormal double.

Beyond SciPy: m < 0 and m > 1 are supported (SciPy returns NaN); for m > 1 the
amplitude is ph = atan2(sn, cn), which stays in [-pi/2, pi/2] since cn > 0.
NaN input gives NaN output; out-of-domain input raises ValueError (also u or m
infinite in ellipj, where sn, cn, dn have no limit).  Empty arrays give empty arrays.
"""
import numpy as np

from . import _fortran as _elliptic
from ._arrays import as_array, broadcast_real, check_size, real_scalar, restore

__all__ = ["ellipk", "ellipkm1", "ellipe", "ellipem1", "ellipf", "ellipkinc",
           "ellipfm1", "ellipj", "ellipjm1"]


def _prepare(**named):
    """(shape, scalar, flat float64 arrays): like _arrays.broadcast_real, but a single
    float64 contiguous array (the common large case) is passed on without a copy;
    the f2py routines take it intent(in) and never write to it."""
    vals = list(named.values())
    if all(isinstance(v, np.ndarray) and v.dtype == np.float64 and v.flags.c_contiguous
           and v.ndim >= 1 and v.shape == vals[0].shape for v in vals):
        check_size(vals[0].size, next(iter(named)))
        return vals[0].shape, False, {k: v.reshape(-1) for k, v in named.items()}
    return broadcast_real(**named)


def _empty(shape, n_out):
    out = tuple(np.empty(shape) for _ in range(n_out))
    return out if n_out > 1 else out[0]


def _first_bad(bad, **arrays):
    i = int(np.flatnonzero(bad)[0])
    return ", ".join(f"{k} = {float(v[i])!r}" for k, v in arrays.items())


def _check_nan_domain(out, message, **inputs):
    """NaN from non-NaN input means the Fortran core met a domain error."""
    if not np.isnan(np.sum(out)):   # one fast pass: no NaN at all (Inf alone sums to Inf)
        return
    bad = np.isnan(out)
    if bad.any():
        for v in inputs.values():
            bad &= ~np.isnan(v)
        if bad.any():
            raise ValueError(f"{message} (got {_first_bad(bad, **inputs)})")


def _one_output(kernel, message, **named):
    """Broadcast the named inputs, call the one-output f2py kernel on them (in
    that order) and raise ValueError (message) where it returns NaN for
    non-NaN input (a domain error); the result has the inputs' shape."""
    shape, scalar, f = _prepare(**named)
    if next(iter(f.values())).size == 0:
        return _empty(shape, 1)
    out = kernel(*f.values())
    _check_nan_domain(out, message, **f)
    return restore(out, shape, scalar)


def ellipk(m):
    """Complete elliptic integral of the first kind K(m), m = k**2 <= 1.

    K(1) = inf.  ValueError for m > 1.  Accuracy: a few ulps (AGM).
    """
    return _one_output(_elliptic.ellipk_f2py, "ellipk: m must be <= 1", m=m)


def ellipkm1(p):
    """K(1 - p) for p >= 0, accurate for tiny p (down to the smallest subnormal).

    Same name and meaning as scipy.special.ellipkm1.  ValueError for p < 0.
    """
    return _one_output(_elliptic.ellipkm1_f2py, "ellipkm1: p = 1 - m must be >= 0", p=p)


def ellipe(m):
    """Complete elliptic integral of the second kind E(m), m <= 1 (E(1) = 1).

    ValueError for m > 1.  Accuracy: a few ulps.
    """
    return _one_output(_elliptic.ellipe_f2py, "ellipe: m must be <= 1", m=m)


def ellipem1(p):
    """E(1 - p) for p >= 0, accurate for tiny p.  ValueError for p < 0."""
    return _one_output(_elliptic.ellipem1_f2py, "ellipem1: p = 1 - m must be >= 0", p=p)


def ellipf(phi, m):
    """Incomplete elliptic integral of the first kind F(phi | m).

    phi in rad, any real value (F(phi + n pi) = F(phi) + 2 n K(m)); any real m
    with m sin^2(phi) <= 1, including m > 1 (there the quasi-period uses
    Re K(m) = K(1/m)/sqrt(m)).  ValueError where m sin^2(phi) > 1.
    Same as scipy.special.ellipkinc (alias ``ellipkinc``) where SciPy is defined.
    """
    return _one_output(_elliptic.ellipf_f2py, "ellipf: need m*sin(phi)**2 <= 1", phi=phi, m=m)


ellipkinc = ellipf


def ellipfm1(phi, p):
    """F(phi | 1 - p) with the complementary parameter p = 1 - m (accurate near m = 1).

    ValueError where (1 - p) sin^2(phi) > 1.
    """
    return _one_output(_elliptic.ellipfm1_f2py, "ellipfm1: need (1 - p)*sin(phi)**2 <= 1", phi=phi, p=p)


def _check_finite_jacobi(sn, u, m, name):
    """sn, cn, dn have no limit as u -> +-Inf (nor as m -> +-Inf): ValueError there."""
    if not np.isnan(np.sum(sn)):
        return
    bad = np.isnan(sn) & ~np.isnan(u) & ~np.isnan(m)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        arg, val = ("u", u[i]) if np.isinf(u[i]) else (name, m[i])
        raise ValueError(f"ellipj: {arg} = {float(val)!r} is out of range: it must be finite "
                         f"(sn, cn, dn have no limit there)")


def _outputs(n):
    """sn, cn, dn, ph as the rows of one uninitialised (4, n) block, which the f2py
    *_into_ routines fill in place: f2py would zero each array it allocates itself
    (a wasted pass over 4 n doubles), and one large block is cheaper to obtain from
    the allocator than four (measured: ~65 vs ~69-72 ns/point for ellipj on 1e6
    random points).  Each output is a contiguous view of that block."""
    out = np.empty((4, n))
    return out[0], out[1], out[2], out[3]


def _jacobi(u, m, name, vec, one_m):
    # ragged or non-numeric input fails here, by name, before its shape is asked
    u = u if isinstance(u, np.ndarray) else as_array(u, "u")
    m = m if isinstance(m, np.ndarray) else as_array(m, name)
    if np.ndim(m) == 0 and np.ndim(u) != 0:
        # one parameter, many u: the library decides whether a plan pays off
        mval = real_scalar(m, name)
        shape, _, f = _prepare(u=u)
        if f["u"].size == 0:
            return _empty(shape, 4)
        res = _outputs(f["u"].size)
        one_m(f["u"], mval, *res)
        _check_finite_jacobi(res[0], f["u"], np.broadcast_to(mval, f["u"].shape), name)
        return tuple(r.reshape(shape) for r in res)
    shape, scalar, f = _prepare(u=u, **{name: m})
    if f["u"].size == 0:
        return _empty(shape, 4)
    res = _outputs(f["u"].size)
    vec(f["u"], f[name], *res)
    _check_finite_jacobi(res[0], f["u"], f[name], name)
    return tuple(restore(r, shape, scalar) for r in res)


def ellipj(u, m):
    """Jacobi elliptic functions ``(sn, cn, dn, ph) = ellipj(u, m)``, like scipy.special.

    All real u and m (m = k**2; m < 0 and m > 1 through the modulus
    transformations).  ph is the amplitude am(u|m) in rad.  Accuracy: a few eps
    times the condition number, also for |u| large (u is reduced modulo the
    period with K in double-double) and for m within 1e-300 of 1 via ``ellipjm1``.
    """
    return _jacobi(u, m, "m", _elliptic.ellipj_into_f2py, _elliptic.ellipj_one_m_into_f2py)


def ellipjm1(u, p):
    """``ellipj(u, 1 - p)`` with the complementary parameter p = 1 - m (any real p).

    Use it near the separatrix (m -> 1), where 1 - m cannot be formed in floating
    point: p down to the smallest subnormal double keeps full accuracy.
    """
    return _jacobi(u, p, "p", _elliptic.ellipjm1_into_f2py, _elliptic.ellipjm1_one_m_into_f2py)
