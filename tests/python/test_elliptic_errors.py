"""errors="nan": the elliptic functions give NaN per out-of-domain element, as
scipy.special does, instead of raising for the whole call; compared with SciPy
element by element, NaN positions included.  Where the domains differ on
purpose (m > 1 in ellipkinc and ellipj, m < 0 in ellipj, ellipkinc at m = -inf)
the positions are listed and checked too."""

import math

import numpy as np
import pytest

import pendula

sc = pytest.importorskip("scipy.special")

EPS = np.finfo(float).eps
INF, NAN = math.inf, math.nan
# Values: the same function, not a different branch or sheet.  Their accuracy is
# tested against mpmath elsewhere (test_elliptic.py); SciPy itself loses digits
# near m = 1 and at large |u| (4e-10 relative at F(1e3 | 1 - 2**-52), 2e-13 at
# sn(1e3 | 0.9)), so it is no reference at the ulp level.
RTOL = 1e-8

M = np.array([-INF, -1e10, -2.0, 0.0, 0.3, 0.5, 1 - 2**-52, 1.0, 1 + 2**-52, 1.5, 1e300, INF, NAN])
P = np.array([-INF, -1.0, -5e-324, 0.0, 5e-324, 1e-300, 0.25, 0.5, 1.0, 3.0, INF, NAN])


def _same(ours, ref, where=None):
    """Equal NaN positions, equal infinities (with their signs), finite values within RTOL."""
    ours, ref = np.asarray(ours, dtype=float), np.asarray(ref, dtype=float)
    if where is not None:
        ours, ref = ours[where], ref[where]
    np.testing.assert_array_equal(np.isnan(ours), np.isnan(ref))
    np.testing.assert_array_equal(np.isinf(ours), np.isinf(ref))
    np.testing.assert_array_equal(ours[np.isinf(ref)], ref[np.isinf(ref)])
    fin = np.isfinite(ref)
    np.testing.assert_allclose(ours[fin], ref[fin], rtol=RTOL, atol=0)


@pytest.mark.parametrize("name, x", [("ellipk", M), ("ellipe", M), ("ellipkm1", P)])
def test_complete_integrals_nan_where_scipy_gives_nan(name, x):
    _same(getattr(pendula, name)(x, errors="nan"), getattr(sc, name)(x))
    with pytest.raises(ValueError, match="m must be|p = 1 - m must be"):
        getattr(pendula, name)(x)  # the default still refuses the call


def test_ellipem1_nan_where_scipy_ellipe_of_the_complement_is_nan():
    # p chosen so that 1 - p is exact: then scipy's ellipe(1 - p) is the same function
    p = np.array([-INF, -1.0, -0.5, 0.0, 0.25, 0.5, 1.0, 3.0, NAN])
    _same(pendula.ellipem1(p, errors="nan"), sc.ellipe(1 - p))


def _grid(*axes):
    return [a.reshape(-1) for a in np.meshgrid(*axes, indexing="ij")]


PHI = np.array([-INF, -10.0, -1.0, 0.0, 0.5, 1.0, math.pi / 2, 3.0, 1e3, INF, NAN])


def test_ellipkinc_matches_scipy_with_nan_except_where_documented():
    phi, m = _grid(PHI, M)
    ours, ref = pendula.ellipkinc(phi, m, errors="nan"), sc.ellipkinc(phi, m)
    with np.errstate(invalid="ignore"):
        wider = (m > 1) & (m * np.sin(phi) ** 2 <= 1) & np.isfinite(phi)  # defined here, NaN in SciPy
    # m = -inf: F -> 0 for finite phi (SciPy gives 0, here out of domain: NaN); with phi
    # infinite too the limit is indeterminate (SciPy NaN, here +-inf)
    minus_inf = (m == -INF) & ~np.isnan(phi)
    # m = 1 past the pole: fl(pi/2) is below pi/2, so F(fl(pi/2) | 1) = atanh(sin(fl(pi/2)))
    # is finite (here 38.03; SciPy: inf); F is odd, F(-10 | 1) = -inf (SciPy: +inf); phi =
    # +-inf has no F here (NaN), SciPy gives +-inf
    pole = (m == 1) & (np.abs(phi) >= math.pi / 2)
    ordinary = ~wider & ~minus_inf & ~pole
    _same(ours, ref, ordinary)
    assert wider.sum() > 5 and np.isfinite(ours[wider]).all() and np.isnan(ref[wider]).all()
    assert np.isnan(ours[minus_inf & np.isfinite(phi)]).all() and (ref[minus_inf & np.isfinite(phi)] == 0).all()
    assert np.isnan(ours[pole & np.isinf(phi)]).all() and 38 < ours[pole & (phi == math.pi / 2)][0] < 38.1
    beyond = pole & np.isfinite(phi) & (np.abs(phi) > math.pi / 2)
    assert np.array_equal(ours[beyond], np.sign(phi[beyond]) * INF)
    # the extension is the real part of F: F(phi | m) = F(asin(sqrt(m) sin phi) | 1/m)/sqrt(m)
    i = np.flatnonzero(wider & (np.abs(phi) <= math.pi / 2))
    beta = np.arcsin(np.sqrt(m[i]) * np.sin(phi[i]))
    np.testing.assert_allclose(ours[i], sc.ellipkinc(beta, 1 / m[i]) / np.sqrt(m[i]), rtol=RTOL)


def test_ellipfm1_matches_ellipkinc_of_the_complement():
    phi, p = _grid(PHI, np.array([-1.0, -0.5, 0.0, 0.25, 0.5, 1.0, 3.0, NAN]))
    _same(pendula.ellipfm1(phi, p, errors="nan"), pendula.ellipkinc(phi, 1 - p, errors="nan"))


U = np.array([-INF, -1e3, -2.5, 0.0, 0.5, 1.0, 7.0, 1e3, INF, NAN])


@pytest.mark.parametrize("func", ["ellipj", "ellipjm1"])
def test_ellipj_matches_scipy_with_nan_except_where_documented(func):
    m_axis = np.array([-INF, -3.0, 0.0, 0.3, 0.9, 1.0, 2.0, INF, NAN])
    u, m = _grid(U, m_axis)
    if func == "ellipj":
        ours = pendula.ellipj(u, m, errors="nan")
    else:  # only where 1 - (1 - m) == m, so that both see the same parameter
        ours = pendula.ellipjm1(u, 1 - m, errors="nan")
    ref = sc.ellipj(u, m)
    wider = ((m < 0) | (m > 1)) & np.isfinite(m) & np.isfinite(u)  # defined here, NaN in SciPy
    # m = 1: sn = tanh(u) etc. have limits as |u| -> inf; SciPy gives NaN for |u| > 355.6
    wider |= (m == 1) & (np.abs(u) > 355.6)
    for o, r in zip(ours, ref):
        _same(o, r, ~wider)
        assert np.isfinite(o[wider]).all() and np.isnan(r[wider]).all()
    assert np.array_equal(ours[0][(m == 1) & (np.abs(u) > 355.6)], np.sign(u[(m == 1) & (np.abs(u) > 355.6)]))
    # with one m and many u (the plan path) the same elements are NaN
    for mval in (0.5, 2.0, INF):
        one = getattr(pendula, func)(U, mval if func == "ellipj" else 1 - mval, errors="nan")
        ref_nan = np.isnan(U) | np.isinf(U) | np.isinf(mval)
        np.testing.assert_array_equal(np.isnan(one[0]), ref_nan)


def test_in_domain_results_are_the_same_either_way():
    m = np.linspace(-5.0, 1.0, 101)
    assert np.array_equal(pendula.ellipk(m), pendula.ellipk(m, errors="nan"))
    phi = np.linspace(-4.0, 4.0, 33)
    assert np.array_equal(pendula.ellipf(phi, 0.7), pendula.ellipf(phi, 0.7, errors="nan"))
    for a, b in zip(pendula.ellipj(phi, 3.0), pendula.ellipj(phi, 3.0, errors="nan")):
        assert np.array_equal(a, b)
    assert pendula.ellipe(0.5, errors="nan") == pendula.ellipe(0.5)
    assert math.isnan(pendula.ellipe(2.0, errors="nan"))


@pytest.mark.parametrize(
    "name, args",
    [
        ("ellipk", (0.5,)),
        ("ellipkm1", (0.5,)),
        ("ellipe", (0.5,)),
        ("ellipem1", (0.5,)),
        ("ellipf", (1.0, 0.5)),
        ("ellipkinc", (1.0, 0.5)),
        ("ellipfm1", (1.0, 0.5)),
        ("ellipj", (1.0, 0.5)),
        ("ellipjm1", (1.0, 0.5)),
    ],
)
def test_errors_is_checked_by_name(name, args):
    f = getattr(pendula, name)
    for bad in ("ignore", "NaN", "coerce", ""):
        with pytest.raises(ValueError, match=r"errors = .* is not one of 'raise' .* or 'nan'"):
            f(*args, errors=bad)
    for bad in (None, 1, True, b"nan"):
        with pytest.raises(TypeError, match="errors must be the str"):
            f(*args, errors=bad)
    with pytest.raises(TypeError):
        f(*args, "nan")  # keyword-only, as the other options of pendula


def test_the_documented_differences_from_scipy_hold():
    """Each difference docs/guide/elliptic.md lists, checked."""
    x32 = np.array([0.25, 0.5], dtype=np.float32)
    assert sc.ellipk(x32).dtype == np.float32 and pendula.ellipk(x32).dtype == np.float64
    assert type(pendula.ellipk(0.5)) is float and type(pendula.ellipk(np.array(0.5))) is float
    assert type(sc.ellipk(0.5)) is np.float64
    assert math.isinf(sc.ellipk(True))
    with pytest.raises(TypeError, match="bool"):
        pendula.ellipk(True)
    with pytest.raises(TypeError):
        pendula.ellipk(x32, out=np.empty(2))
    masked = np.ma.masked_array([0.25, 0.5], mask=[False, True])
    assert isinstance(sc.ellipk(masked), np.ma.MaskedArray)
    assert type(pendula.ellipk(masked)) is np.ndarray
