"""Tests of pendula's elliptic integrals and Jacobi functions.

References: tests/data/elliptic_refs.npz, made by tools/gen/gen_elliptic_refs.py
with mpmath at >= 60 digits (340 for the complement forms, so that 1 - mc is
exact) at the EXACT double inputs, with the condition number of each problem.
Errors are reported as relative error / (eps * cond).
"""

import functools
import importlib
import os

import numpy as np
import pytest
import scipy.special as sc

import pendula

# the f2py extension (all the glue is one module, pendula._fortran)
_elliptic = importlib.import_module("pendula._fortran")
_codes = importlib.import_module("pendula._codes")

EPS = np.finfo(float).eps
DATA = np.load(os.path.join(os.path.dirname(__file__), "..", "data", "elliptic_refs.npz"))
TOL_COND = 8.0  # the accuracy target: rel. error <= 8 eps * cond for sn, cn, dn, am
TOL_ULPS = 4.0  # the accuracy target: K, E, F within 4 ulps


def _rel(got, ref):
    got = np.asarray(got, float)
    ref = np.asarray(ref, float)
    return np.abs(got - ref) / np.maximum(np.abs(ref), np.finfo(float).tiny) / EPS


def _jac_table():
    j = DATA["jac"]
    return j[:, 0], j[:, 1], j[:, 2].astype(bool), j[:, 3:7], j[:, 7:11], DATA["jac_region"]


def _into(fn, u, p):
    """Call an f2py *_into_ routine with fresh output arrays; returns (sn, cn, dn, ph)."""
    out = tuple(np.empty(u.size) for _ in range(4))
    fn(u, p, *out)
    return out


def _plan_into(complement):
    """The glue's scalar-parameter Jacobi routine, always with a plan (table of Taylor
    polynomials), for p = 1 - m (complement) or m; called like the other *_into_ routines."""
    which = _codes.GLUE_PARAM_P if complement else _codes.GLUE_PARAM_M
    return functools.partial(_elliptic.ellipj_one_into_f2py, which, _codes.GLUE_JACOBI_PLAN)


_ELLIPJ_INTO = functools.partial(_elliptic.ellipj_into_f2py, _codes.GLUE_PARAM_M)


@pytest.mark.parametrize("region", ["generic", "mneg", "near1", "near1m", "mgt1", "largeu", "m0", "m1"])
@pytest.mark.parametrize("path", ["elementwise", "plan"])
def test_jacobi_against_mpmath(region, path):
    u, p, comp, ref, cond, reg = _jac_table()
    sel = reg == region
    assert sel.sum() >= 8
    worst = 0.0
    for i in np.flatnonzero(sel):
        if path == "elementwise":
            got = (pendula.ellipjm1 if comp[i] else pendula.ellipj)(u[i], p[i])
        else:  # the scalar-parameter (plan) routine, fed a one-element array
            fn = _plan_into(comp[i])
            got = [g[0] for g in _into(fn, np.array([u[i]]), p[i])]
        e = _rel(got, ref[i]) / cond[i]
        worst = max(worst, float(e.max()))
        assert e.max() <= TOL_COND, (u[i], p[i], comp[i], got, ref[i], e)
    print(f"{region}/{path}: worst rel.err/(eps*cond) = {worst:.2f}")


def test_large_u_error_does_not_grow_like_u_eps():
    # u up to 1e6: raw relative error stays at a few hundred eps at most, far below u*eps
    u, p, comp, ref, cond, reg = _jac_table()
    sel = (reg == "largeu") & ~comp
    for i in np.flatnonzero(sel):
        got = pendula.ellipj(u[i], p[i])
        e = _rel(got, ref[i])
        big = np.abs(ref[i]) > 1e-3
        assert (e[big] <= 1e-3 * abs(u[i]) + 64).all(), (u[i], p[i], e)


def test_complete_integrals_against_mpmath():
    for p, comp, kref, eref in DATA["ke"]:
        k = pendula.ellipkm1(p) if comp else pendula.ellipk(p)
        e = pendula.ellipem1(p) if comp else pendula.ellipe(p)
        assert _rel(k, kref) <= TOL_ULPS, (p, comp, k, kref)
        assert _rel(e, eref) <= TOL_ULPS, (p, comp, e, eref)


def test_complete_integrals_at_table_edges():
    # K, E at the edges of the interval table (mc = 1 - m = 2**e (1 + q/16), e = -5..0) and
    # of the logarithmic form (mc < 2**-5), each with its two neighbours, against mpmath at
    # the exact double inputs (m form and complement form); the arrays equal the scalars
    import mpmath as mp

    edges = np.array([2.0**e * (1 + q / 16) for e in range(-5, 1) for q in range(16)])
    p = np.unique(np.concatenate([edges, np.nextafter(edges, 0), np.nextafter(edges, 2)]))
    p = p[p <= 1]
    for comp, x in ((True, p), (False, 1 - p)):
        fk, fe = (pendula.ellipkm1, pendula.ellipem1) if comp else (pendula.ellipk, pendula.ellipe)
        k, e = fk(x), fe(x)
        assert np.array_equal(k, [fk(float(v)) for v in x]) and np.array_equal(e, [fe(float(v)) for v in x])
        for i, v in enumerate(x):
            with mp.workprec(300):
                mm = 1 - mp.mpf(float(v)) if comp else mp.mpf(float(v))
                kref, eref = float(mp.ellipk(mm)), float(mp.ellipe(mm))
            assert _rel(k[i], kref) <= TOL_ULPS, (comp, v, k[i], kref)
            assert _rel(e[i], eref) <= TOL_ULPS, (comp, v, e[i], eref)


def test_complete_integral_arrays_equal_scalars_in_mixed_blocks():
    # blocks (256 elements) mostly in the logarithmic form with a few table points, mostly
    # in the table with a few logarithmic ones, with NaN, out-of-domain and subnormal
    # complements among them: the array forms give the scalar forms' numbers to the bit
    rng = np.random.default_rng(5)
    p = np.concatenate(
        [
            10 ** rng.uniform(-320, -2, 250),
            rng.uniform(0.04, 1, 6),
            [0.0, np.nan, 3.0, 5e-324, 1e-310],
            rng.uniform(0.04, 1, 250),
            10 ** rng.uniform(-15, -2, 6),
            [1.0, 0.03125, np.nextafter(0.03125, 0)],
        ]
    )
    m = np.concatenate([1 - p, [-2.0, 1.0, 1.5, -np.inf]])
    for f, x in ((pendula.ellipkm1, p), (pendula.ellipem1, p), (pendula.ellipk, m), (pendula.ellipe, m)):
        arr = f(x, errors="nan")
        assert np.array_equal(arr, [f(float(v), errors="nan") for v in x], equal_nan=True), f.__name__


def test_incomplete_integral_against_mpmath():
    for phi, p, comp, fref, cond in DATA["f"]:
        f = pendula.ellipfm1(phi, p) if comp else pendula.ellipf(phi, p)
        assert _rel(f, fref) <= TOL_ULPS * cond, (phi, p, comp, f, fref, cond)


def test_special_values():
    assert pendula.ellipk(1.0) == np.inf
    assert pendula.ellipkm1(0.0) == np.inf
    assert pendula.ellipe(1.0) == 1.0
    assert pendula.ellipk(0.0) == pytest.approx(np.pi / 2, rel=EPS)
    assert pendula.ellipe(0.0) == pytest.approx(np.pi / 2, rel=EPS)
    # smallest subnormal complement: K = ln(4/sqrt(mc)) + O(mc)
    mc = 5e-324
    assert pendula.ellipkm1(mc) == pytest.approx(np.log(4) - 0.5 * np.log(mc), rel=2 * EPS)
    assert pendula.ellipem1(mc) == 1.0
    sn, cn, dn, ph = pendula.ellipj(0.3, 0.0)
    assert (sn, cn, dn) == pytest.approx((np.sin(0.3), np.cos(0.3), 1.0), rel=2 * EPS)
    sn, cn, dn, ph = pendula.ellipj(2.0, 1.0)
    assert (sn, cn, dn) == pytest.approx((np.tanh(2.0), 1 / np.cosh(2.0), 1 / np.cosh(2.0)), rel=2 * EPS)
    # m = 1 beyond the cosh overflow (SciPy gives NaN above u = 355.6)
    sn, cn, dn, ph = pendula.ellipj(400.0, 1.0)
    assert sn == 1.0 and 0 < cn < 1e-170 and ph == pytest.approx(np.pi / 2)


def test_identities_all_regions():
    rng = np.random.default_rng(7)
    u = rng.uniform(-50, 50, 4000)
    for m in [-1e10, -3.0, -0.1, 0.0, 0.3, 0.9, 0.999999, 1.0, 1.5, 1e4]:
        sn, cn, dn, ph = pendula.ellipj(u, m)
        assert np.abs(sn**2 + cn**2 - 1).max() <= 6 * EPS
        big = max(1.0, abs(m))
        assert np.abs(dn**2 + m * sn**2 - 1).max() <= 8 * EPS * big
        if m <= 1:
            np.testing.assert_allclose(np.sin(ph), sn, rtol=0, atol=8 * EPS * np.abs(ph).max())
    for p in [1e-3, 1e-10, 1e-100, 1e-300, 5e-324]:
        sn, cn, dn, ph = pendula.ellipjm1(u, p)
        assert np.abs(sn**2 + cn**2 - 1).max() <= 6 * EPS
        assert np.abs(dn**2 - p * sn**2 - cn**2).max() <= 8 * EPS


def test_period_4k_and_amplitude():
    for m, p in [(0.3, None), (0.9, None), (None, 1e-12), (-5.0, None)]:
        if p is None:
            k = pendula.ellipk(m) if m >= 0 else pendula.ellipk(m / (m - 1)) / np.sqrt(1 - m)
            f = lambda x: pendula.ellipj(x, m)  # noqa: E731
        else:
            k = pendula.ellipkm1(p)
            f = lambda x: pendula.ellipjm1(x, p)  # noqa: E731
        u = np.linspace(-k, 3 * k, 97)
        a, b = f(u), f(u + 4 * k)
        for x, y in zip(a[:3], b[:3]):
            np.testing.assert_allclose(y, x, rtol=0, atol=64 * EPS * (1 + 4 * k))
        # am advances by 2 pi over a period
        np.testing.assert_allclose(b[3] - a[3], 2 * np.pi, rtol=0, atol=64 * EPS * (1 + 4 * k))


def test_amplitude_inverts_ellipf():
    # F(am(u|m) | m) = u, the definition of am; and d(am)/du = dn by central differences
    rng = np.random.default_rng(3)
    for m in [0.2, 0.7, 0.99, -2.0]:
        u = rng.uniform(-3, 3, 200)
        _, _, dn, ph = pendula.ellipj(u, m)
        np.testing.assert_allclose(pendula.ellipf(ph, m), u, rtol=16 * EPS, atol=16 * EPS)
        h = 1e-4
        d = (pendula.ellipj(u + h, m)[3] - pendula.ellipj(u - h, m)[3]) / (2 * h)
        np.testing.assert_allclose(d, dn, rtol=0, atol=1e-7 * max(1, abs(m)))


def test_agrees_with_scipy_where_scipy_is_right():
    rng = np.random.default_rng(11)
    u = rng.uniform(-20, 20, 20000)
    m = rng.uniform(0, 0.99, 20000)
    ours = pendula.ellipj(u, m)
    theirs = sc.ellipj(u, m)
    for a, b in zip(ours, theirs):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    np.testing.assert_allclose(pendula.ellipk(m), sc.ellipk(m), rtol=4 * EPS)
    np.testing.assert_allclose(pendula.ellipe(m), sc.ellipe(m), rtol=4 * EPS)
    p = 10.0 ** rng.uniform(-300, 0, 2000)
    np.testing.assert_allclose(pendula.ellipkm1(p), sc.ellipkm1(p), rtol=4 * EPS)
    phi = rng.uniform(-10, 10, 20000)
    np.testing.assert_allclose(pendula.ellipf(phi, m), sc.ellipkinc(phi, m), rtol=8 * EPS, atol=1e-15)
    # the scalar-m fast path gives the same numbers as SciPy too
    ours = pendula.ellipj(u, 0.8)
    theirs = sc.ellipj(u, 0.8)
    for a, b in zip(ours, theirs):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def test_scipy_failures_fixed():
    # a known SciPy defect: garbage for 1 - m <= 1e-10 and u >= 1.5 K
    p = 1e-12
    k = pendula.ellipkm1(p)
    sn, cn, dn, ph = pendula.ellipjm1(1.7 * k, p)
    assert abs(cn) <= 1 and abs(sn) <= 1 and 0 < dn <= 1
    assert sn**2 + cn**2 == pytest.approx(1, abs=4 * EPS)
    # m > 1 and m < 0 are defined (SciPy: NaN)
    assert np.isfinite(pendula.ellipj(0.3, 4.0)).all()
    assert np.isfinite(pendula.ellipj(0.3, -4.0)).all()
    assert np.isfinite(pendula.ellipf(0.4, 4.0))


def test_extreme_arguments_stay_bounded():
    # |u| far beyond the precision of the period, huge |m|, infinities: no crash, bounded output
    u = np.array([1e15, -1e200, 1e308, 3.0, 0.5])
    for m in [0.5, 1e300, -1e300, 1 - 1e-16, 1e-300]:
        for res in (pendula.ellipj(u, m), pendula.ellipj(np.tile(u, 100), m)):
            sn, cn, dn, ph = res
            assert (np.abs(sn) <= 1).all() and (np.abs(cn) <= 1 + 4 * EPS).all()
    # the plan (table) path and the elementwise path at astronomically large u
    big = np.array([1e15, 1e17, 3e19, 1e25, 7e27, 1e30, 1e100, 1.7e308, -1e25])
    for m in [0.0, 0.5, 1 - 1e-12, -1e10, 2.0]:
        for res in (_into(_plan_into(False), big, m), _into(_ELLIPJ_INTO, big, np.full_like(big, m))):
            assert all((np.abs(x) <= 1 + 4 * EPS).all() for x in res[:2])
    for p in [5e-324, 1e-5]:
        res = _into(_plan_into(True), big, p)
        assert all((np.abs(x) <= 1 + 4 * EPS).all() for x in res[:2])
    # no limit at infinity: ValueError naming the argument (the Fortran core gives NaN)
    with pytest.raises(ValueError, match="u = inf"):
        pendula.ellipj(np.inf, 0.5)
    with pytest.raises(ValueError, match="u = -inf"):
        pendula.ellipj(np.array([1.0, -np.inf] * 40), 0.5)
    with pytest.raises(ValueError, match="m = -inf"):
        pendula.ellipj(1.0, -np.inf)
    with pytest.raises(ValueError, match="p = inf"):
        pendula.ellipjm1(np.ones(100), np.inf)
    assert pendula.ellipk(-np.inf) == 0.0
    # empty in, empty out
    assert pendula.ellipk(np.array([])).shape == (0,)
    assert pendula.ellipf(np.zeros((0, 3)), 0.5).shape == (0, 3)
    assert [a.shape for a in pendula.ellipj(np.array([]), 0.5)] == [(0,)] * 4


def test_nan_and_domain():
    assert np.isnan(pendula.ellipk(np.nan))
    assert np.isnan(pendula.ellipe(np.nan))
    assert np.isnan(pendula.ellipf(np.nan, 0.5)) and np.isnan(pendula.ellipf(0.5, np.nan))
    assert all(np.isnan(pendula.ellipj(np.nan, 0.5)))
    assert all(np.isnan(pendula.ellipj(0.5, np.nan)))
    assert all(np.isnan(pendula.ellipj(np.array([np.nan, np.nan]), 0.5)[0]))
    with pytest.raises(ValueError, match="m must be <= 1"):
        pendula.ellipk(1.5)
    with pytest.raises(ValueError, match="m must be <= 1"):
        pendula.ellipe([0.1, 2.0])
    with pytest.raises(ValueError, match=r"p = 1 - m must be >= 0"):
        pendula.ellipkm1(-1e-3)
    with pytest.raises(ValueError, match=r"m\*sin\(phi\)\*\*2 <= 1"):
        pendula.ellipf(1.2, 2.0)
    with pytest.raises(ValueError, match=r"m\*sin\(phi\)\*\*2 <= 1"):
        pendula.ellipkinc(np.array([0.1, 1.2]), 2.0)
    with pytest.raises(TypeError):
        pendula.ellipk("a")


def test_shapes_scalars_broadcasting_and_no_input_change():
    assert isinstance(pendula.ellipk(0.5), float)
    assert isinstance(pendula.ellipj(0.5, 0.5)[0], float)
    u = np.linspace(0, 1, 6).reshape(2, 3)
    m = np.array([0.1, 0.5, 0.9])
    u0, m0 = u.copy(), m.copy()
    sn, cn, dn, ph = pendula.ellipj(u, m)
    assert sn.shape == (2, 3)
    np.testing.assert_array_equal(u, u0)
    np.testing.assert_array_equal(m, m0)
    for a, b in zip((sn, cn, dn, ph), sc.ellipj(u, m)):
        np.testing.assert_allclose(a, b, rtol=4 * EPS, atol=4 * EPS)
    assert pendula.ellipf(np.zeros((4, 1)), np.zeros(5)).shape == (4, 5)
    with pytest.raises(ValueError):
        pendula.ellipj(np.zeros(3), np.zeros(4))


# ---- extreme inputs: |m| up to huge(), phi at the doubles nearest odd multiples of pi/2,
# F near m = 1 and phi = pi/2 (references: mpmath at the exact double inputs)


def _mp_jacobi(u, m):
    """sn, cn, dn at exact double u, m by the modulus transformations (DLMF 22.6.11/12),
    which keep mpmath's own series in their easy range; 400 digits so that 1 - m is exact."""
    import mpmath as mp

    with mp.workdps(400):
        u, m = mp.mpf(u), mp.mpf(m)
        if m > 1:
            k = mp.sqrt(m)
            s, c, d = (mp.ellipfun(f, k * u, m=1 / m) for f in ("sn", "cn", "dn"))
            return float(s / k), float(d), float(c)
        k1 = mp.sqrt(1 - m)
        s, c, d = (mp.ellipfun(f, u * k1, m=-m / (1 - m)) for f in ("sn", "cn", "dn"))
        return float(s / d / k1), float(c / d), float(1 / d)


@pytest.mark.parametrize("m", [1e308, -1e308, 1.7976931348623157e308, -1.7976931348623157e308, 1.4e300, -1.4e300])
def test_ellipj_huge_parameter(m):
    # once a segfault (double-double overflow in the plan set-up, then a table index from NaN)
    for u in (1e-160, 1e-155):
        ref = _mp_jacobi(u, m)
        for got in (pendula.ellipj(u, m)[:3], pendula.ellipjm1(u, -m if abs(m) > 1e300 else 1 - m)[:3]):
            assert np.all(_rel(got, ref) <= TOL_COND), (u, m, got, ref)
    # |u| sqrt|m| ~ 1e154: the phase is below the resolution of u (cond ~ |u| sqrt|m|);
    # the values must be finite and consistent, on every path (scalar, array, plan)
    u = np.linspace(-1e3, 1e3, 2001)
    for sn, cn, dn, ph in (
        pendula.ellipj(0.7, m),
        pendula.ellipj(u, m),
        pendula.ellipj(u, np.full_like(u, m)),
        pendula.ellipjm1(u, m),
    ):
        assert np.all(np.isfinite(sn) & np.isfinite(cn) & np.isfinite(dn) & np.isfinite(ph))
    sn, cn, dn, _ = pendula.ellipj(u, m)
    assert np.all(np.abs(sn * sn + cn * cn - 1) <= 8 * EPS)


@pytest.mark.parametrize(
    "phi,p,ref",
    [
        (np.pi / 2, 1e-300, 38.025003373828868),
        (np.pi / 2, 1e-40, 38.025003367161134),
        (np.pi / 2, 0.0, 38.025003373828868),
        (3 * np.pi / 2, 1e-300, 730.47450770561424),
        (-3 * np.pi / 2, 1e-300, -730.47450770561424),
        (-np.pi / 2, 1e-300, -38.025003373828868),
    ],
)
def test_ellipf_at_double_nearest_odd_multiple_of_half_pi(phi, p, ref):
    # the multiple of pi was taken from the rounded quotient anint(phi/pi): fl(pi/2) was
    # reduced to -pi/2 - 6e-17 and F came out as F + 2K (656.49 instead of 38.03)
    got = pendula.ellipfm1(phi, p)
    assert _rel(got, ref) <= TOL_ULPS, (phi, p, got, ref)
    if p == 0.0:
        assert _rel(pendula.ellipf(phi, 1.0), ref) <= TOL_ULPS


def test_ellipf_near_one_and_half_pi_matches_mpmath():
    # 1 - m in [1e-12, 1e-3], phi within 1e-2 of pi/2: F at the exact double inputs to
    # <= 8 eps (once 3,460 eps: 1 - m sin^2 phi cancelled; now cos^2 + mc sin^2)
    import mpmath as mp

    rng = np.random.default_rng(8)
    n = 300
    m = 1 - 10.0 ** rng.uniform(-12, -3, n)
    phi = np.pi / 2 + 10.0 ** rng.uniform(-10, -2, n) * rng.choice([-1.0, 1.0], n)
    with mp.workdps(50):
        ref = np.array([float(mp.ellipf(mp.mpf(a), mp.mpf(b))) for a, b in zip(phi, m)])
    e = _rel(pendula.ellipf(phi, m), ref)
    ec = _rel(pendula.ellipfm1(phi, 1 - m), ref)  # 1 - m is exact for these m
    print(f"F near m = 1, phi = pi/2: worst {e.max():.2f} eps (m form), {ec.max():.2f} eps (p form)")
    assert e.max() <= 8 and ec.max() <= 8


def test_ellipf_huge_phi():
    # n = phi/pi beyond 2**53: reduced in steps; F = phi 2K/pi to rounding, +-Inf beyond huge
    k = pendula.ellipk(0.5)
    for phi in (1e17, 1e100, 1e300, 8.98e307):
        assert abs(pendula.ellipf(phi, 0.5) / (phi * k / (np.pi / 2)) - 1) <= 4 * EPS
    assert pendula.ellipf(1.7976931348623157e308, 0.5) == np.inf
    assert pendula.ellipf(-1.7976931348623157e308, 0.5) == -np.inf
