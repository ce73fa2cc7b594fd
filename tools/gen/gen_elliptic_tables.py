"""Write src/special/pendula_elliptic_tables.f90, the generated coefficients of the
elliptic concern, src/special/pendula_elliptic_ke_tables.inc, the K and E tables (included
by pendula_elliptic_ke and by each compiled variant of its block kernel,
pendula_elliptic_ke_lanes.F90, a leaf that uses no pendula module), and
src/special/pendula_jacobi_series.inc, the generated procedure
series_coeffs (included by pendula_jacobi_kernel, so that
the kernel's hot path inlines it: gfortran does not inline across modules without LTO, and
by each compiled variant of its block kernel, pendula_jacobi_lanes.F90)
(run from anywhere: python3 tools/gen/gen_elliptic_tables.py; needs mpmath).

* Maclaurin coefficients of sn, 1 - cn, 1 - dn as polynomials in m (exact rationals, from
  the ODEs sn' = cn dn, cn' = -sn dn, dn' = -m sn cn, DLMF 22.13.1-3, by power-series
  recursion), written out as the unrolled Horner evaluation `series_coeffs`;
* K and E: piecewise Chebyshev interpolants (tables k_poly, e_poly, ke_log_poly);
* atan on [0, tan(pi/8)] for the amplitude (atan_poly).
``--check`` compares with the file in the tree instead of writing it.
"""

import os
import sys
from fractions import Fraction as F

HERE = os.path.dirname(os.path.abspath(__file__))
TARGET = os.path.join(HERE, "..", "..", "src", "special", "pendula_elliptic_tables.f90")
SERIES_TARGET = os.path.join(HERE, "..", "..", "src", "special", "pendula_jacobi_series.inc")
KE_TARGET = os.path.join(HERE, "..", "..", "src", "special", "pendula_elliptic_ke_tables.inc")

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


def _lit(x):
    return f"{float(x):.17e}_wp"


def _horner(coeffs):
    """Nested Horner text c0 + m * (c1 + m * (...)) of exact coefficients (lowest first);
    a negative last coefficient in parentheses, as Fortran needs after '*'."""
    expr = _lit(coeffs[-1])
    if len(coeffs) > 1 and coeffs[-1] < 0:
        expr = f"({expr})"
    for c in reversed(coeffs[:-1]):
        expr = f"({_lit(c)} + m * {expr})"
    return expr


def _wrap(lhs, expr, width=100):
    """Fortran assignment broken after ' + m * (' where a line would pass `width`."""
    head = f"    {lhs} = "
    parts = expr.split(" + m * ")
    lines, cur = [], head + parts[0]
    for p in parts[1:]:
        piece = " + m * " + p
        if len(cur) + len(piece) > width:
            lines.append(cur + " + &")
            cur = "        m * " + p
        else:
            cur += piece
    lines.append(cur)
    return "\n".join(lines)


def series_fortran():
    """The subroutine series_coeffs(m, cs, cc, cd): coefficients of w^(2k+1) in sn and of
    w^(2k+2) in 1 - cn and 1 - dn at parameter m (degree k in m; 1 - dn has a factor m)."""
    s, c, d = series()
    out = [
        "  !> Maclaurin coefficients of sn, 1 - cn, 1 - dn in w**2 at parameter m: cs(k) of",
        "  !> w**(2k+1) in sn, cc(k) and cd(k) of w**(2k+2) in 1 - cn and 1 - dn (unrolled Horner",
        "  !> in m of exact rational coefficients; terms with zero coefficients are omitted).",
        "  pure subroutine series_coeffs(m, cs, cc, cd)",
        "    real(wp), intent(in) :: m",
        "    real(wp), intent(out) :: cs(0:6), cc(0:6), cd(0:6)",
    ]
    for k in range(NTERM):
        ps = s[2 * k + 1][: k + 1]
        pc = [-x for x in c[2 * k + 2]][: k + 1]
        pd = [-x for x in d[2 * k + 2]][1 : k + 2]
        # degree k in m (1 - dn: m times degree k): the higher entries are exact zeros
        assert not any(s[2 * k + 1][k + 1 :]) and not any(c[2 * k + 2][k + 1 :]) and not any(d[2 * k + 2][k + 2 :])
        out.append(_wrap(f"cs({k})", _horner(ps)))
        out.append(_wrap(f"cc({k})", _horner(pc)))
        out.append(_wrap(f"cd({k})", "m * " + _horner(pd)))
    out.append("  end subroutine series_coeffs")
    return "\n".join(out)


# ---------------------------------------------------------------- K and E
# Piecewise polynomials (Chebyshev interpolants at 40 digits, written as powers of
# t = m - centre) on intervals cut by the bits of mc = 1 - m: each binade [2**e, 2**(e+1))
# of mc, e = -5..-1, in KE_SPLIT pieces of equal width, so that every interval's
# distance to the singularity at m = 1 is at least 2 KE_SPLIT half-widths and ONE degree
# serves them all (index = the exponent and top mantissa bits of mc, no search); one more
# interval [1, 1 + 1/KE_SPLIT) of mc holds m = 0.  For mc < 2**-5 the logarithmic form
# (DLMF 19.12.1 structure)
#   K = P(mc) - ln(mc) Q(mc),   E = Pe(mc) - ln(mc) mc Qe1(mc),
# with Q = K(mc)/pi and mc Qe1 = (K(mc) - E(mc))/pi analytic for |mc| < 1, as powers
# of mc itself (so that mc -> 0 gives the exact limits P(0) = ln 4, Pe(0) = 1).
KE_DEG = 8  # degree of the interval polynomials
KE_SPLIT = 16  # pieces per binade of mc (the top 4 mantissa bits)
KE_EMIN = -5  # the lowest binade of the table: mc >= 2**KE_EMIN, below it the log form
KE_NINT = -KE_EMIN * KE_SPLIT + 1
KE_LOG_DEG = 7  # degree of P, Q, Pe, Qe1 on [0, 2**KE_EMIN]
KE_BLOCK = 256  # elements per block of the array forms (the block's scratch stays in L1)


def _cheb_monomial(f, a, b, n, mp):
    c = (a + b) / 2
    h = (b - a) / 2
    xs = [mp.cos(mp.pi * (k + mp.mpf(1) / 2) / (n + 1)) for k in range(n + 1)]
    fs = [f(c + h * x) for x in xs]
    V = mp.matrix(n + 1, n + 1)
    for i, x in enumerate(xs):
        for j in range(n + 1):
            V[i, j] = x**j
    co = mp.lu_solve(V, mp.matrix(fs))
    return [co[j] / h**j for j in range(n + 1)]


def _shift_to_zero(co, c, mp):
    """Coefficients of sum co[j] (x - c)^j as powers of x (exact binomial expansion)."""
    out = [mp.mpf(0)] * len(co)
    for j, a in enumerate(co):
        for i in range(j + 1):
            out[i] += a * mp.binomial(j, i) * (-c) ** (j - i)
    return out


def ke_intervals(mp):
    """(m_lo, m_hi) of table interval i = 0..KE_NINT-1: mc in 2**e [1 + q/S, 1 + (q+1)/S)
    with e = KE_EMIN + i // S, q = i % S (the index the Fortran reads from mc's bits)."""
    out = []
    for i in range(KE_NINT):
        e, q = KE_EMIN + i // KE_SPLIT, i % KE_SPLIT
        lo = mp.mpf(2) ** e * (1 + mp.mpf(q) / KE_SPLIT)
        hi = mp.mpf(2) ** e * (1 + mp.mpf(q + 1) / KE_SPLIT)
        out.append((1 - hi, 1 - lo))
    return out


def ke_tables():
    import mpmath as mp

    mp.mp.dps = 40
    kt, et = [], []
    for a, b in ke_intervals(mp):
        kt.append(_cheb_monomial(mp.ellipk, a, b, KE_DEG, mp))
        et.append(_cheb_monomial(mp.ellipe, a, b, KE_DEG, mp))
    P = lambda x: mp.ellipk(1 - x) + mp.log(x) * mp.ellipk(x) / mp.pi  # noqa: E731
    Q = lambda x: mp.ellipk(x) / mp.pi  # noqa: E731
    Pe = lambda x: mp.ellipe(1 - x) + mp.log(x) * (mp.ellipk(x) - mp.ellipe(x)) / mp.pi  # noqa: E731
    Qe1 = lambda x: (mp.ellipk(x) - mp.ellipe(x)) / (mp.pi * x)  # noqa: E731
    lo, hi = mp.mpf(0), mp.mpf(2) ** KE_EMIN
    near = [_shift_to_zero(_cheb_monomial(f, lo, hi, KE_LOG_DEG, mp), (lo + hi) / 2, mp) for f in (P, Q, Pe, Qe1)]
    return kt, et, near


def _array(name, rows):
    n = len(rows[0])
    vals = [_lit(x) for r in rows for x in r]
    body = ", &\n      ".join(", ".join(vals[i : i + 3]) for i in range(0, len(vals), 3))
    return (
        f"  real(wp), parameter :: {name}(0:{n - 1}, 0:{len(rows) - 1}) = reshape([ &\n"
        f"      {body}], [{n}, {len(rows)}])"
    )


def ke_fortran():
    kt, et, near = ke_tables()
    s, lo = KE_SPLIT, 2.0**KE_EMIN
    return "\n".join(
        [
            f"  !> K and E: polynomials in t = m - c_i of degree {KE_DEG} on the intervals i = 0..{KE_NINT - 1} of",
            f"  !> mc = 1 - m in 2**e [1 + q/{s}, 1 + (q+1)/{s}), e = {KE_EMIN} + i/{s}, q = mod(i, {s}) (c_i: the",
            f"  !> interval's centre in m; k_poly, e_poly), and for mc < {lo:g} the logarithmic form",
            "  !> K = P(mc) - ln(mc) Q(mc), E = Pe(mc) - ln(mc) mc Qe1(mc) in powers of mc (columns P, Q,",
            f"  !> Pe, Qe1 of ke_log_poly, degree {KE_LOG_DEG}).  Chebyshev interpolants at 40 digits;",
            "  !> truncation < 0.02 ulp.",
            _array("k_poly", kt),
            _array("e_poly", et),
            _array("ke_log_poly", near),
            "",
            "  integer, parameter :: ke_emin = " + str(KE_EMIN) + "   ! the table holds mc >= 2**ke_emin",
            f"  integer, parameter :: ke_top = ubound(k_poly, 2)   ! its last interval (mc in [1, 1 + 1/{s}))",
            "  real(wp), parameter :: mc_log = 2.0_wp**ke_emin   ! below: the logarithmic forms",
            "  !> Elements per block of the array forms: the most the block kernel takes (its scratch",
            "  !> stays in L1).",
            f"  integer, parameter :: nb = {KE_BLOCK}",
        ]
    )


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


def atan_fortran():
    vals = [_lit(x) for x in atan_poly()]
    decl = "  real(wp), parameter :: "
    # continuation lines under the name, as fprettify (tools/lint.sh) aligns them
    cont = ", &\n" + " " * len(decl)
    body = cont.join(", ".join(vals[i : i + 3]) for i in range(0, len(vals), 3))
    return "\n".join(
        [
            "  !> atan(w) = w + w t P(t), t = w**2 <= tan(pi/8)**2: P of degree 10 (Chebyshev",
            "  !> interpolant at 40 digits); atan on [-1, 1] within 1.2 ulps.",
            f"{decl}atan_poly(0:{len(vals) - 1}) = [ &\n{' ' * len(decl)}{body}]",
        ]
    )


def module_text():
    return "\n".join(
        [
            "!> GENERATED by tools/gen/gen_elliptic_tables.py -- do not edit; rerun the generator.",
            "!> Coefficient tables of the elliptic concern: the atan polynomial of the amplitude",
            "!> (the K and E interpolants are in pendula_elliptic_ke_tables.inc, the Maclaurin",
            "!> coefficients of sn, cn, dn in m in pendula_jacobi_series.inc).",
            "module pendula_elliptic_tables",
            "  use pendula_kinds, only: wp",
            "  implicit none",
            "  private",
            "  public :: atan_poly",
            "",
            atan_fortran(),
            "",
            "end module pendula_elliptic_tables",
            "",
        ]
    )


def ke_text():
    return "\n".join(
        [
            "! GENERATED by tools/gen/gen_elliptic_tables.py -- do not edit; rerun the generator.",
            "! Included in the specification part of pendula_elliptic_ke and of each compiled",
            "! variant of its block kernel (pendula_elliptic_ke_lanes.F90): one text, so every",
            "! variant computes exactly what the scalar K and E compute.  Needs wp in scope.",
            ke_fortran(),
            "",
        ]
    )


def series_text():
    return "\n".join(
        [
            "! GENERATED by tools/gen/gen_elliptic_tables.py -- do not edit; rerun the generator.",
            "! Included in the contains section of pendula_jacobi_kernel and of each compiled",
            "! variant of its block kernel (pendula_jacobi_lanes.F90).",
            series_fortran(),
            "",
        ]
    )


def main(argv):
    status = 0
    for target, text in ((TARGET, module_text()), (KE_TARGET, ke_text()), (SERIES_TARGET, series_text())):
        target = os.path.normpath(target)
        if "--check" in argv:
            with open(target) as f:
                same = f.read() == text
            print(f"{target}: {'identical' if same else 'DIFFERS'}")
            status |= 0 if same else 1
            continue
        with open(target, "w") as f:
            f.write(text)
        print(f"wrote {target}")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
