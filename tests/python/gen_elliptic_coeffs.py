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


if __name__ == "__main__":
    print(fortran_arrays())
