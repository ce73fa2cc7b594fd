#!/usr/bin/env python3
"""Period of the pendulum: exact vs small-angle vs the usual approximations (text §1.2, fig 4).

Mirrors examples/fortran/example_period_table.f90.  For amplitudes theta0 from
1 to 179.999 degrees released from rest (g = 9.8 m/s^2, l = 4.9 m) it prints the
exact period T = 4 K(k^2)/w0 (eq. 1.53, k = sin(theta0/2)) and the relative error
of the small-angle period T0 = 2 pi/w0 (eq. 1.8), the series T0 (1 + k^2/4 + 9k^4/64),
Kidd-Fogg T0/sqrt(cos(theta0/2)) and Lima-Arun -T0 ln(c)/(1 - c), c = cos(theta0/2);
then periods of states the text cannot handle (Omega0 != 0, rotation).
Writes period_table.csv into --out.
"""

import _example_support
import numpy as np

import pendula

DEGREES = [1, 5, 10, 20, 30, 45, 60, 90, 120, 150, 170, 179, 179.9, 179.999]
COLUMNS = [
    "theta0_deg",
    "theta0_rad",
    "T_exact_s",
    "T0_small_angle_s",
    "T_small_angle_s",
    "T_series_s",
    "T_kidd_fogg_s",
    "T_lima_arun_s",
]


def main(argv=None):
    args = _example_support.parse_args(__doc__, "period_table.csv", argv)

    w0 = pendula.natural_frequency(9.8, 4.9)
    t0 = pendula.small_angle_period(w0)
    theta0 = np.radians(DEGREES)
    t_exact = pendula.period(theta0, 0.0, w0)  # array in, array out
    k = np.sin(theta0 / 2)
    c = np.cos(theta0 / 2)
    approx = {
        "small_angle": np.full_like(theta0, t0),
        "series": pendula.period_series(k**2, w0),
        "kidd_fogg": t0 / np.sqrt(c),
        "lima_arun": -t0 * np.log(c) / (1 - c),
    }
    print(f"w0 = {w0:.12f} 1/s, small-angle period T0 = {t0:.12f} s")
    print("Released from rest; relative errors (approximation - exact)/exact")
    print(f"{'theta0 [deg]':>12} {'T exact [s]':>16} {'T/T0':>8} " + " ".join(f"{name:>12}" for name in approx))
    rows = []
    for i, deg in enumerate(DEGREES):
        errs = {name: (a[i] - t_exact[i]) / t_exact[i] for name, a in approx.items()}
        print(
            f"{deg:12.3f} {t_exact[i]:16.10f} {t_exact[i] / t0:8.4f} " + " ".join(f"{e:12.3e}" for e in errs.values())
        )
        rows.append([deg, theta0[i], t_exact[i], t0] + [approx[n][i] for n in approx])

    print("\nAny initial state (the text covers only Omega0 = 0 and theta0 = 0):")
    print(f"{'theta0 [rad]':>14} {'Omega0 [rad/s]':>15} {'E/E_sep':>10} {'period or time per turn [s]':>28}")
    for th0, om0 in [(0.5, 1.0), (0.0, 1.999 * w0), (0.0, 2.001 * w0), (1.0, 4.0), (np.pi - 1e-10, 0.0)]:
        m = np.sin(th0 / 2) ** 2 + (om0 / (2 * w0)) ** 2
        print(f"{th0:14.10f} {om0:15.8f} {m:10.6f} {pendula.period(th0, om0, w0):28.16e}")

    _example_support.write_csv(args.out, "period_table.csv", COLUMNS, rows)


if __name__ == "__main__":
    main()
