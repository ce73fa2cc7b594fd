#!/usr/bin/env python3
"""Generate the constants of pendula_rk4_tables.inc (included by pendula_rk4_kernel.f90 and
the batch kernel variants) (run: python3 tools/gen/gen_stage_sine_table.py).

Prints, as Fortran, the table sin(2 pi j / 256), j = 0..255 (correctly
rounded by mpmath at 60 digits) and the three-part Cody-Waite split of the
node spacing 2 pi / 256 (24 + 24 + 53 bits, so that k*P1 and k*P2 are exact
for |k| < 2**29).  The kernel derives cos x_k and the Taylor coefficients of
sin(x_k + r) from this table by constant expressions.
"""

import mpmath as mp

mp.mp.dps = 60
N = 256


def round_bits(x, bits):
    e = mp.floor(mp.log(abs(x), 2))
    scale = mp.mpf(2) ** (bits - 1 - e)
    return mp.nint(x * scale) / scale


def f(x):
    return repr(float(x)) + "_wp"


def main():
    c = 2 * mp.pi / N
    p1 = round_bits(c, 24)
    p2 = round_bits(c - p1, 24)
    p3 = mp.mpf(float(c - p1 - p2))
    print(f"  real(wp), parameter :: node_p1 = {f(p1)}, node_p2 = {f(p2)}, &")
    print(f"      node_p3 = {f(p3)}, nodes_per_radian = {f(N / (2 * mp.pi))}")
    print(f"  ! residual of the split: {float(c - p1 - p2 - p3):.2e}")

    vals = [mp.sin(c * j) for j in range(N)]
    print(f"  real(wp), parameter :: node_sin(0:{N - 1}) = [ &")
    rows = [", ".join(f(v) for v in vals[i : i + 3]) for i in range(0, N, 3)]
    print("      " + ", &\n      ".join(rows) + " ]")


if __name__ == "__main__":
    main()
