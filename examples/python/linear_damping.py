#!/usr/bin/env python3
"""Linear damped pendulum (text §2.1, eqs 2.4-2.47) in each regime, and through critical damping.

Mirrors examples/fortran/example_linear_damping.f90.  w0 = sqrt(2) 1/s and
gamma = 0.5, 2, 3, 5 x w0 (under-, critically and over-damped; the text's figs
10, 11, 13 use 3, 5, 2 and its §2.1.3 on the under-damped case is empty): the
regime numbers, then theta [rad] and Omega [rad/s] at a few times (s) for
theta0 = 0.1 rad, Omega0 = 0, 0.5, -0.5 rad/s.  Writes linear_damping.csv into --out.
"""

import _example_support
import numpy as np

import pendula

RATIOS = [0.5, 2.0, 3.0, 5.0]
OMEGA0S = [0.0, 0.5, -0.5]
TIMES = np.array([0.0, 0.5, 1.0, 2.0, 5.0])
COLUMNS = [
    "gamma_over_w0",
    "gamma_per_s",
    "regime",
    "theta0_rad",
    "omega0_rad_per_s",
    "t_s",
    "theta_rad",
    "omega_rad_per_s",
]


def main(argv=None):
    args = _example_support.parse_args(__doc__, "linear_damping.csv", argv)

    w0 = pendula.natural_frequency(9.8, 4.9)
    theta0 = 0.1
    rows = []
    for r in RATIOS:
        gamma = r * w0
        info = pendula.damping_regime(w0, gamma)
        print(f"\ngamma = {r:g} w0 = {gamma:.6f} 1/s: {info.regime}")
        print(f"  eigenvalues [1/s]: {info.lambda1:.6g}, {info.lambda2:.6g}")
        print(
            f"  Q = {info.quality_factor:.6g}, omega_d = {info.omega_d:.6g} 1/s, "
            f"log decrement = {info.log_decrement:.6g}, decay slow/fast = "
            f"{info.decay_slow:.6g}/{info.decay_fast:.6g} 1/s"
        )
        print(f"{'Omega0 [rad/s]':>16} {'t [s]':>8} {'theta [rad]':>16} {'Omega [rad/s]':>16}")
        for om0 in OMEGA0S:
            theta, omega = pendula.linear_damped(TIMES, theta0, om0, w0, gamma)
            for t, th, om in zip(TIMES, theta, omega):
                print(f"{om0:16.3f} {t:8.3f} {th:16.6e} {om:16.6e}")
                rows.append([r, gamma, info.regime, theta0, om0, t, th, om])

    print("\nThrough critical damping (theta0 = 0.1 rad, Omega0 = 0.5 rad/s, t = 2 s):")
    for eps in [-1e-4, -1e-8, -1e-12, 0.0, 1e-12, 1e-8, 1e-4]:
        gamma = 2 * w0 * (1 + eps)
        th, _ = pendula.linear_damped(2.0, theta0, 0.5, w0, gamma)
        print(f"  gamma/(2 w0) - 1 = {eps:9.1e}  {pendula.damping_regime(w0, gamma).regime:>12}  theta = {th:.15e} rad")

    _example_support.write_csv(args.out, "linear_damping.csv", COLUMNS, rows)


if __name__ == "__main__":
    main()
