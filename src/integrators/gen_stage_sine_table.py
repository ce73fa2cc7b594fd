#!/usr/bin/env python3
"""Generate the constants of pendula_rk4_kernel.f90 (run: python3 gen_stage_sine_table.py).

Prints, as Fortran, the table sin(2 pi j / 256), j = 0..255 (correctly
rounded by mpmath at 60 digits), the three-part Cody-Waite split of the node
spacing 2 pi / 256 (24 + 24 + 53 bits, so that k*P1 and k*P2 are exact for
|k| < 2**29), and the near-minimax polynomials (Chebyshev interpolation,
mpmath.chebyfit, 4 coefficients each) on |r| <= 0.125 for
    P(z) = (sin r - r) / (r z),   Q(z) = (1 - cos r) / z,   z = r**2.
"""
import mpmath as mp

mp.mp.dps = 60
N = 256
RMAX = mp.mpf("0.125")
NCOEF = 4


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

    def pz(z):
        if z == 0:
            return mp.mpf(-1) / 6
        r = mp.sqrt(z)
        return (mp.sin(r) - r) / (r * z)

    def qz(z):
        if z == 0:
            return mp.mpf(1) / 2
        r = mp.sqrt(z)
        return (1 - mp.cos(r)) / z

    for name, fn, w in (("ps", pz, RMAX ** 3), ("qc", qz, RMAX ** 2)):
        poly, err = mp.chebyfit(fn, [0, RMAX ** 2], NCOEF, error=True)
        coefs = list(reversed(poly))
        print(f"  ! {name}: max error of the fit times |r|**{3 if name == 'ps' else 2}: "
              f"{mp.nstr(err * w, 3)}")
        print(f"  real(wp), parameter :: " + ", ".join(f"{name}{i} = {f(cf)}" for i, cf in enumerate(coefs[:2]))
              + ", &")
        print(f"      " + ", ".join(f"{name}{i + 2} = {f(cf)}" for i, cf in enumerate(coefs[2:])))
    vals = [mp.sin(c * j) for j in range(N)]
    print(f"  real(wp), parameter :: node_sin(0:{N - 1}) = [ &")
    rows = [", ".join(f(v) for v in vals[i:i + 3]) for i in range(0, N, 3)]
    print("      " + ", &\n      ".join(rows) + " ]")


if __name__ == "__main__":
    main()
