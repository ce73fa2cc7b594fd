#!/usr/bin/env python3
"""The text's figures 3-15, regenerated from the library (PNG files, no display needed).

fig03 K(k); fig04 period vs sin(theta0/2); fig05-08 theta(t) exact vs small-angle;
fig09 launch-speed series; fig10-11 overdamped gamma = 3, 5 w0; fig12 overdamped
phase plane; fig13 critical damping; fig14-15 nonlinear damped, correct integrator
with the text's printed (mistyped) RK4 listing overlaid.  The drawing code is in
pendula/figures.py: each figure is one short function you can read and adapt.
"""
import argparse

from pendula import figures

TEXT_FIGURES = [f"fig{n:02d}" for n in range(3, 16)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=".", help="folder for the PNG files (default: .)")
    ap.add_argument("--quick", action="store_true", help="fewer points per curve (fast)")
    args = ap.parse_args(argv)
    written, missing = figures.make_figures(args.out, quick=args.quick, only=TEXT_FIGURES)
    for path in written:
        print(f"wrote {path}")
    for key, why in missing.items():
        print(f"not drawn: {key}: {why}")
    failed = [key for key, why in missing.items() if why.startswith("FAILED")]
    if failed:
        raise SystemExit(f"figure(s) failed: {', '.join(failed)}")


if __name__ == "__main__":
    main()
