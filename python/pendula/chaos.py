"""Chaos tools of the driven pendulum: Poincare sections, bifurcation diagrams,
Lyapunov exponents, periodic orbits and basins of attraction.

Every tool is a Fortran batch (src/driven: many initial states or parameter
values per call, blocks of SIMD lanes on every core), started at t = 0 and
sampled stroboscopically on the RK4 grid of N steps per drive period
(pendula.driven); each takes ``threads`` and ``progress`` and stops on
Ctrl-C.  See docs/guide/driven.md.
"""

from ._chaos_lyapunov import LyapunovResult, lyapunov
from ._chaos_orbits import FAILED, UNSETTLED, Basins, PeriodicOrbits, basins, find_periodic_orbit, periodic_orbits
from ._chaos_sections import Section, bifurcation, poincare

__all__ = [
    "Section",
    "poincare",
    "bifurcation",
    "LyapunovResult",
    "lyapunov",
    "PeriodicOrbits",
    "periodic_orbits",
    "find_periodic_orbit",
    "Basins",
    "basins",
    "UNSETTLED",
    "FAILED",
]
