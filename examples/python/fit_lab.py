#!/usr/bin/env python3
"""Fitting a measured pendulum: the lab data set of docs/guide/fitting.md, made and fitted.

A 0.750 m pendulum (bob radius 2.0 cm, g = 9.81 m/s^2) measured two ways, with
seeded noise so that every run gives the same numbers:
  periods.csv  periods timed at amplitudes 10..150 deg (photogate: 2 ms per
               period; amplitudes read to 0.5 deg)
  swing.csv    a rotary sensor at 50 Hz for 30 s of a 120 deg release, lightly
               damped (gamma = 0.03 1/s), noise 2 mrad, sensor offset 10 mrad
Writes both CSVs and the figures fit_periods.png and fit_swing.png into --out,
and prints the fits (pendula.fit_period, pendula.fit_motion).  With
--data-dir examples/data it also refreshes the copies kept in the repository.
"""

import argparse
import csv
from pathlib import Path

import numpy as np

import pendula

LENGTH, G, BOB = 0.750, 9.81, 0.020
L_EFF = LENGTH + 2 * BOB**2 / (5 * LENGTH)  # the finite bob (see fit_period's docstring)
W0 = np.sqrt(G / L_EFF)
GAMMA, OFFSET = 0.03, 0.010


def make_data(seed=2026):
    """(periods rows, swing rows) of the synthetic lab."""
    rng = np.random.default_rng(seed)
    deg = np.arange(10.0, 151.0, 10.0)
    true_theta0 = np.radians(deg)
    T = pendula.period(true_theta0, w0=W0) + rng.normal(0.0, 2e-3, deg.size)
    read = deg + rng.normal(0.0, 0.5, deg.size)  # the amplitude as read off the scale
    periods = [[f"{a:.2f}", f"{p:.5f}", "0.002", "0.5"] for a, p in zip(read, T)]
    t = np.arange(0.0, 30.0, 0.02)
    r = pendula.rk4(t, np.radians(120.0), 0.0, W0, GAMMA, h=1e-3)
    theta = r.theta + OFFSET + rng.normal(0.0, 2e-3, t.size)
    swing = [[f"{a:.2f}", f"{b:.5f}", "0.002"] for a, b in zip(t, theta)]
    return periods, swing


def write(folder, name, header, rows):
    folder.mkdir(parents=True, exist_ok=True)
    with open(folder / name, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)
    print(f"wrote {folder / name}")
    return folder / name


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("."), help="folder for the CSVs and figures")
    ap.add_argument("--data-dir", type=Path, default=None, help="also write the CSVs here (examples/data)")
    ap.add_argument("--quick", action="store_true", help="accepted for symmetry with the other examples")
    args = ap.parse_args(argv)
    periods, swing = make_data()
    heads = (["theta0_deg", "period", "sigma_period", "sigma_theta0_deg"], ["t", "theta", "sigma"])
    for folder in [args.out] + ([args.data_dir] if args.data_dir else []):
        write(folder, "periods.csv", heads[0], periods)
        write(folder, "swing.csv", heads[1], swing)

    p = np.array(periods, dtype=float)
    fit = pendula.fit_period(
        np.radians(p[:, 0]),
        p[:, 1],
        sigma_period=p[:, 2],
        sigma_theta0=np.radians(p[:, 3]),
        length=LENGTH,
        bob_radius=BOB,
    )
    print(f"\nPeriods at 10..150 deg, l = {LENGTH} m, bob radius {BOB} m (true g = {G}):\n{fit!r}")
    print(f"  the small-angle formula at 150 deg alone: g = {fit.small_angle['g_per_point'][-1]:.3f} m/s^2")
    fit.plot(args.out / "fit_periods.png")
    s = np.array(swing, dtype=float)
    mot = pendula.fit_motion(s[:, 0], s[:, 1], sigma=s[:, 2], fit_offsets=True, length=L_EFF)
    print(f"\nSwing, 50 Hz for 30 s (true w0 = {W0:.6f} 1/s, gamma = {GAMMA}, offset = {OFFSET}):\n{mot!r}")
    mot.plot(args.out / "fit_swing.png")
    print(f"wrote {args.out / 'fit_periods.png'}\nwrote {args.out / 'fit_swing.png'}")
    for r, name, truth in ((fit, "g", G), (mot, "w0", W0), (mot, "gamma", GAMMA)):
        z = (r[name] - truth) / r.stderr[name]
        print(f"{name}: {r[name]:.6g} +- {r.stderr[name]:.2g}, {z:+.2f} standard errors from the truth")


if __name__ == "__main__":
    main()
