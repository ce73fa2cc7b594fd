#!/usr/bin/env python3
"""Generate the power-of-five table of pendula_format_digits.f90
(run: python3 tools/gen/gen_pow5_table.py).

Prints, as Fortran, 5**(22 q) for q = Q_MIN..Q_MAX as a double-double times a
power of two: 5**(22 q) = (hi + lo) * 2**ex with 1 <= hi < 2, hi the correctly
rounded double and lo the correctly rounded rest, so |hi + lo - 5**(22 q) / 2**ex|
<= 2**-106 (relative).  Exact rational arithmetic (Python integers and
fractions); repr() of a double reads back to the same double, so the literals
are exact.
"""

from fractions import Fraction

STEP, Q_MIN, Q_MAX = 22, -14, 15


def entry(q):
    v = Fraction(5) ** (STEP * q)
    ex = v.numerator.bit_length() - v.denominator.bit_length()
    if Fraction(2) ** ex > v:
        ex -= 1
    w = v / Fraction(2) ** ex  # 1 <= w < 2
    assert 1 <= w < 2
    hi = float(w)  # Fraction -> float rounds to nearest
    lo = float(w - Fraction(hi))
    err = abs(Fraction(hi) + Fraction(lo) - w) / w
    assert err <= Fraction(1, 2**106), (q, float(err))
    return hi, lo, ex


def lit(v):
    return repr(float(v)) + "_wp"


def main():
    rows = [entry(q) for q in range(Q_MIN, Q_MAX + 1)]
    print(f"  integer, parameter :: POW5_STEP = {STEP}, POW5_QMIN = {Q_MIN}, POW5_QMAX = {Q_MAX}")
    print("  ! 5**(POW5_STEP*q) = (POW5_HI(q) + POW5_LO(q)) * 2**POW5_EX(q), 1 <= POW5_HI < 2")
    print("  real(wp), parameter :: POW5_HI(POW5_QMIN:POW5_QMAX) = [ &")
    print(
        "      "
        + ", &\n      ".join(", ".join(lit(r[0]) for r in rows[i : i + 3]) for i in range(0, len(rows), 3))
        + " ]"
    )
    print("  real(wp), parameter :: POW5_LO(POW5_QMIN:POW5_QMAX) = [ &")
    print(
        "      "
        + ", &\n      ".join(", ".join(lit(r[1]) for r in rows[i : i + 3]) for i in range(0, len(rows), 3))
        + " ]"
    )
    print("  integer, parameter :: POW5_EX(POW5_QMIN:POW5_QMAX) = [ &")
    print(
        "      "
        + ", &\n      ".join(", ".join(str(r[2]) for r in rows[i : i + 10]) for i in range(0, len(rows), 10))
        + " ]"
    )


if __name__ == "__main__":
    main()
