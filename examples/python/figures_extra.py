#!/usr/bin/env python3
"""Figures the text lacks, drawn from the library (PNG files, no display needed).

figA1 the under-damped linear case with its envelope (§2.1.3 is empty in the text);
figA2 the full phase portrait: librations, the separatrix, rotations, every curve a
trajectory of pendula.undamped; figA3 period and time per revolution against energy
through the separatrix; figA4 work-precision diagram (error vs wall time) of every
model on the text's §2.2 scene, from pendula.tradeoff; figA5 how far the text's printed
RK4 listing drifts, against pendula.rk4 at the same step.
"""

from pendula import figures

EXTRA_FIGURES = ["figA1", "figA2", "figA3", "figA4", "figA5"]


def main(argv=None):
    figures.figures_main(argv, EXTRA_FIGURES, __doc__.splitlines()[0], "fewer points per curve and settings (fast)")


if __name__ == "__main__":
    main()
