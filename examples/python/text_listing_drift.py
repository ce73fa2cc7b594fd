#!/usr/bin/env python3
"""How far the text's printed RK4 listing (section 2.2) drifts from the true motion.

The listing's line 67 reads ``m2 = m1 * h * k1 / 2.0`` where classic RK4 needs
``m2 = m1 + h * k1 / 2.0``.  This script runs the listing as printed and as meant
(pendula.textbook.text_listing_rk4), pendula.rk4 at the same h = 0.05 s, and a
tight reference (pendula.cvode at rtol 1e-12, or pendula.rk4 at h = 1e-4 s
without SUNDIALS), on the text's scenario: g = 9.8 m/s^2, l = 4.9 m, m = 0.1 kg,
b = 0.01 and 0.05 kg/s, theta0 = 0, Omega0 = 2 rad/s, t in [0, 30] s.
It then measures the period and decrement of the damped nonlinear motion from
CVODE's events (zero crossings and turning points).

    python3 examples/python/text_listing_drift.py [--out DIR]   (writes text_listing_drift.csv)
"""

import math

import _example_support
import numpy as np

import pendula
from pendula.textbook import text_listing_rk4

W0 = pendula.natural_frequency(9.8, 4.9)
T = np.arange(601) * 0.05


def main(argv=None):
    a = _example_support.parse_args(__doc__, "text_listing_drift.csv", argv, default_out=None)
    rows = []
    print("sup over t in [0, 30] s of |theta - reference| [rad], h = 0.05 s")
    print(
        f"{'b [kg/s]':>9} {'listing as printed':>19} {'at t = 30 s':>12} {'listing fixed':>14} {'pendula.rk4':>12}"
        f"  {'first t with drift > 0.1 rad':>28}"
    )
    for b, gamma in _example_support.text_damping():
        ref, ref_name = _example_support.tight_reference(T, 0.0, 2.0, W0, gamma)
        _, th_typo, _ = text_listing_rk4(30.0, 0.05, 0.0, 2.0, W0, gamma, typo=True)
        _, th_fix, _ = text_listing_rk4(30.0, 0.05, 0.0, 2.0, W0, gamma, typo=False)
        ours = pendula.rk4(T, 0.0, 2.0, W0, gamma, 0.05)
        d_typo = np.abs(th_typo[:601] - ref)
        first = T[np.argmax(d_typo > 0.1)] if np.any(d_typo > 0.1) else float("nan")
        row = dict(
            b=b,
            gamma=gamma,
            reference=ref_name,
            printed_sup=d_typo.max(),
            printed_at_30=d_typo[-1],
            fixed_sup=np.abs(th_fix[:601] - ref).max(),
            rk4_sup=np.abs(ours.theta - ref).max(),
            first_t_over_0_1=first,
        )
        rows.append(row)
        print(
            f"{b:9.2f} {row['printed_sup']:19.3f} {row['printed_at_30']:12.3f} {row['fixed_sup']:14.2e} "
            f"{row['rk4_sup']:12.2e}  {first:28.2f}"
        )
    print(f"(reference: {rows[0]['reference']})")

    if pendula.build_info()["cvode"]:
        gamma = pendula.damping_rate(0.01, 0.1)
        res = pendula.cvode([0.0, 30.0], 0.0, 2.0, W0, gamma, rtol=1e-11, atol=1e-13, events=True)
        tz, _ = res.events.zero_crossings
        tt, amp = res.events.turning_points
        periods = tz[2:] - tz[:-2]
        print("\nb = 0.01 kg/s, from CVODE events: successive full periods [s] (amplitude decays, so they shrink")
        print("toward the small-angle 2 pi / w0 = %.6f s):" % (2 * math.pi / W0))
        print("  " + " ".join(f"{p:.6f}" for p in periods[:8]))
        print("  amplitudes |theta| at turning points [rad]: " + " ".join(f"{abs(x):.5f}" for x in amp[:8]))
        print(
            "  log decrement per half swing ln|theta_k/theta_k+1|: "
            + " ".join(f"{math.log(abs(amp[k] / amp[k + 1])):.5f}" for k in range(min(7, len(amp) - 1)))
        )
    if a.out:
        _example_support.write_csv(a.out, "text_listing_drift.csv", list(rows[0]), [list(r.values()) for r in rows])


if __name__ == "__main__":
    main()
