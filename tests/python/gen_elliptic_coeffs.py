"""Maclaurin coefficients of sn, 1 - cn, 1 - dn as polynomials in m (exact rationals).

From the ODEs sn' = cn dn, cn' = -sn dn, dn' = -m sn cn (DLMF 22.13.1-3) by
power-series recursion.  Prints the Fortran parameter arrays used by
src/special/pendula_elliptic.f90 (run: python3 tests/python/gen_elliptic_coeffs.py).
"""
from fractions import Fraction as F

NTERM = 7  # sn up to w^13, 1-cn and 1-dn up to w^14


def _mul(a, b):
    r = [F(0)] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            r[i + j] += x * y
    return r


def _add(a, b):
    n = max(len(a), len(b))
    return [(a[i] if i < len(a) else 0) + (b[i] if i < len(b) else 0) for i in range(n)]


def _cauchy(a, b, n):
    r = [F(0)]
    for i in range(n + 1):
        r = _add(r, _mul(a[i], b[n - i]))
    return r


def series(order=2 * NTERM + 1):
    """Lists s, c, d: coefficient n is a polynomial in m (list, lowest power first)."""
    s = [[F(0)] for _ in range(order + 1)]
    c = [[F(0)] for _ in range(order + 1)]
    d = [[F(0)] for _ in range(order + 1)]
    c[0] = [F(1)]
    d[0] = [F(1)]
    for n in range(order):
        s[n + 1] = [x / (n + 1) for x in _cauchy(c, d, n)]
        c[n + 1] = [-x / (n + 1) for x in _cauchy(s, d, n)]
        d[n + 1] = [F(0)] + [-x / (n + 1) for x in _cauchy(s, c, n)]
    return s, c, d


def fortran_arrays():
    s, c, d = series()
    rows = {"js": [], "jc": [], "jd": []}
    for k in range(NTERM):
        p = s[2 * k + 1] + [F(0)] * NTERM
        rows["js"].append(p[:NTERM])
        p = [-x for x in c[2 * k + 2]] + [F(0)] * NTERM
        rows["jc"].append(p[:NTERM])
        # 1 - dn = m * (...): drop the leading zero power of m
        p = [-x for x in d[2 * k + 2]][1:] + [F(0)] * NTERM
        rows["jd"].append(p[:NTERM])
    out = []
    for name, rr in rows.items():
        vals = []
        for r in rr:
            vals += [f"{float(x):.17e}_wp" for x in r]
        body = ", &\n      ".join(", ".join(vals[i:i + 3]) for i in range(0, len(vals), 3))
        out.append(f"  real(wp), parameter :: {name}(0:{NTERM-1}, 0:{NTERM-1}) = reshape([ &\n      {body}], [{NTERM}, {NTERM}])")
    return "\n".join(out)


if __name__ == "__main__" and len(__import__("sys").argv) == 1:
    print(fortran_arrays())


# ---------------------------------------------------------------- K and E
# Piecewise polynomials (Chebyshev interpolants at 40 digits, written as powers of
# y = m - centre): 17 intervals of width 1/20 on 0 <= m < 0.85, and for
# mc = 1 - m <= 0.15 the logarithmic form (DLMF 19.12.1 structure)
#   K = P(mc) - ln(mc) Q(mc),   E = Pe(mc) - ln(mc) mc Qe1(mc),
# with Q = K(mc)/pi and mc Qe1 = (K(mc) - E(mc))/pi analytic for |mc| < 1, as powers
# of mc itself (so that mc -> 0 gives the exact limits P(0) = ln 4, Pe(0) = 1).
KE_DEG = 12
KE_NINT = 17
KE_WIDTH = 0.05
KE_MC_MAX = 0.15


def _cheb_monomial(f, a, b, n, mp):
    c = (a + b) / 2
    h = (b - a) / 2
    xs = [mp.cos(mp.pi * (k + mp.mpf(1) / 2) / (n + 1)) for k in range(n + 1)]
    fs = [f(c + h * x) for x in xs]
    V = mp.matrix(n + 1, n + 1)
    for i, x in enumerate(xs):
        for j in range(n + 1):
            V[i, j] = x ** j
    co = mp.lu_solve(V, mp.matrix(fs))
    return [co[j] / h ** j for j in range(n + 1)]


def _shift_to_zero(co, c, mp):
    """Coefficients of sum co[j] (x - c)^j as powers of x (exact binomial expansion)."""
    out = [mp.mpf(0)] * len(co)
    for j, a in enumerate(co):
        for i in range(j + 1):
            out[i] += a * mp.binomial(j, i) * (-c) ** (j - i)
    return out


def ke_tables():
    import mpmath as mp
    mp.mp.dps = 40
    kt, et = [], []
    for i in range(KE_NINT):
        a, b = mp.mpf(i) * KE_WIDTH, mp.mpf(i + 1) * KE_WIDTH
        kt.append(_cheb_monomial(mp.ellipk, a, b, KE_DEG, mp))
        et.append(_cheb_monomial(mp.ellipe, a, b, KE_DEG, mp))
    P = lambda x: mp.ellipk(1 - x) + mp.log(x) * mp.ellipk(x) / mp.pi  # noqa: E731
    Q = lambda x: mp.ellipk(x) / mp.pi  # noqa: E731
    Pe = lambda x: mp.ellipe(1 - x) + mp.log(x) * (mp.ellipk(x) - mp.ellipe(x)) / mp.pi  # noqa: E731
    Qe1 = lambda x: (mp.ellipk(x) - mp.ellipe(x)) / (mp.pi * x)  # noqa: E731
    lo, hi = mp.mpf(0), mp.mpf(KE_MC_MAX)
    near = [_shift_to_zero(_cheb_monomial(f, lo, hi, KE_DEG, mp), (lo + hi) / 2, mp)
            for f in (P, Q, Pe, Qe1)]
    return kt, et, near


def ke_fortran():
    kt, et, near = ke_tables()
    n = KE_DEG + 1

    def arr(name, rows):
        vals = [f"{float(x):.17e}_wp" for r in rows for x in r]
        body = ", &\n      ".join(", ".join(vals[i:i + 3]) for i in range(0, len(vals), 3))
        return (f"  real(wp), parameter :: {name}(0:{n-1}, 0:{len(rows)-1}) = reshape([ &\n"
                f"      {body}], [{n}, {len(rows)}])")
    return "\n".join([arr("kpoly", kt), arr("epoly", et), arr("kepoly1", near)])


if __name__ == "__main__" and "--ke" in __import__("sys").argv:
    print(ke_fortran())


# ---------------------------------------------------------------- amplitude
# atan(w) = w + w t P(t), t = w^2 <= tan(pi/8)^2 (after atan(x) = pi/4 + atan((x-1)/(x+1))),
# P of degree 10 (Chebyshev interpolant at 40 digits, powers of t): <= 1.2 ulps measured.
def atan_poly(deg=10):
    import mpmath as mp
    mp.mp.dps = 40
    T = (mp.sqrt(2) - 1) ** 2

    def g(t):
        if t == 0:
            return mp.mpf(-1) / 3
        w = mp.sqrt(t)
        return (mp.atan(w) - w) / (w * t)
    return _shift_to_zero(_cheb_monomial(g, mp.mpf(0), T, deg, mp), T / 2, mp)


if __name__ == "__main__" and "--atan" in __import__("sys").argv:
    vals = [f"{float(x):.17e}_wp" for x in atan_poly()]
    body = ", &\n      ".join(", ".join(vals[i:i + 3]) for i in range(0, len(vals), 3))
    print(f"  real(wp), parameter :: atpoly(0:{len(vals)-1}) = [ &\n      {body}]")
