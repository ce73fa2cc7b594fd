#!/usr/bin/env python3
"""Exact undamped motion for each regime: libration, near-separatrix, separatrix, rotation.

Mirrors examples/fortran/example_exact_motion.f90 (text §1.2-1.3, eqs 1.52 and 1.66
generalised to any initial state).  For each state it prints theta [rad], Omega
[rad/s] and the relative energy drift at a few times (s), then checks the text's
own expression (1.52), theta = 2 asin(k sn(K - w0 t | k^2)), against the library.
Writes exact_motion.csv into --out.
"""

import _example_support
import numpy as np

import pendula

STATES = [
    ("libration, text fig 7: theta0 = 0.9 pi, Omega0 = 0", 0.9 * np.pi, 0.0),
    ("libration, text fig 9: theta0 = 0, v0 = 1.9 w0 l", 0.0, 1.9),  # Omega0 in units of w0
    ("near the top: theta0 = pi - 1e-10, Omega0 = 0", np.pi - 1e-10, 0.0),
    ("separatrix: theta0 = 0, Omega0 = 2 w0", 0.0, 2.0),
    ("rotation: theta0 = 0, Omega0 = 2.5 w0 (theta unwrapped)", 0.0, 2.5),
]
COLUMNS = ["state", "theta0_rad", "omega0_rad_per_s", "t_s", "theta_rad", "omega_rad_per_s", "relative_energy_drift"]


def energy(theta, omega, w0):
    """Energy per unit m l^2 in 1/s^2: Omega^2/2 + 2 w0^2 sin^2(theta/2) (eq. 1.54)."""
    return 0.5 * omega**2 + 2 * (w0 * np.sin(theta / 2)) ** 2


def main(argv=None):
    args = _example_support.parse_args(__doc__, "exact_motion.csv", argv)

    w0 = pendula.natural_frequency(9.8, 4.9)
    print(f"Undamped pendulum, w0 = {w0:.12f} 1/s (g = 9.8 m/s^2, l = 4.9 m)")
    rows = []
    for title, theta0, om in STATES:
        omega0 = om * w0
        period = pendula.period(theta0, omega0, w0)
        span = period if np.isfinite(period) else 8 / w0  # separatrix: infinite period
        t = span * np.array([0, 0.125, 0.25, 0.5, 0.75, 1.0, 10.0])
        theta, omega = pendula.undamped(t, theta0, omega0, w0)
        e0 = energy(theta0, omega0, w0)
        print(f"\n{title}\n  period or time per turn = {period:.16e} s")
        print(f"{'t [s]':>14} {'theta [rad]':>24} {'Omega [rad/s]':>24} {'energy drift':>13}")
        for ti, th, omg in zip(t, theta, omega):
            drift = (energy(th, omg, w0) - e0) / e0
            print(f"{ti:14.6f} {th:24.15e} {omg:24.15e} {drift:13.2e}")
            rows.append([title, theta0, omega0, ti, th, omg, drift])

    # The text's eq. 1.52 for theta0 = 0.9 pi agrees with the general solution.
    theta0 = 0.9 * np.pi
    k = np.sin(theta0 / 2)
    t = np.linspace(0.0, 10.0, 101)
    sn, _, _, _ = pendula.ellipj(pendula.ellipk(k * k) - w0 * t, k * k)
    theta_text = 2 * np.arcsin(k * sn)
    theta_lib, _ = pendula.undamped(t, theta0, 0.0, w0)
    worst = np.max(np.abs(theta_text - theta_lib))
    print(f"\ntext eq. 1.52 vs pendula.undamped, theta0 = 0.9 pi, t in [0, 10] s: max |diff| = {worst:.3e} rad")
    if worst > 1e-12:
        raise SystemExit("error: eq. 1.52 and the general solution disagree")

    _example_support.write_csv(args.out, "exact_motion.csv", COLUMNS, rows)


if __name__ == "__main__":
    main()
