#!/usr/bin/env python3
"""The text's figures 3-15, regenerated from the library (PNG files, no display needed).

fig03 K(k); fig04 period vs sin(theta0/2); fig05-08 theta(t) exact vs small-angle;
fig09 launch-speed series; fig10-11 overdamped gamma = 3, 5 w0; fig12 overdamped
phase plane; fig13 critical damping; fig14-15 nonlinear damped, correct integrator
with the text's printed (mistyped) RK4 listing overlaid.  The drawing code is in
pendula/figures.py: each figure is one short function you can read and adapt.
"""

from pendula import figures

TEXT_FIGURES = [f"fig{n:02d}" for n in range(3, 16)]


def main(argv=None):
    figures.figures_main(argv, TEXT_FIGURES, __doc__.splitlines()[0])


if __name__ == "__main__":
    main()
