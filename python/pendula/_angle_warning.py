"""The warning for an amplitude angle that looks like degrees (pendula.AngleWarning).

Used by the functions of ``undamped`` where theta0 is an amplitude; the test
for a swinging state asks the Fortran core for m (no second formula here).
"""

import math
import warnings

import numpy as np

from . import _fortran
from ._codes import OK


class AngleWarning(UserWarning):
    """An amplitude angle above 2 pi rad: probably degrees given as radians.

    Raised (as a warning) by :func:`period`, :func:`amplitude`,
    :func:`small_angle` and :func:`small_angle_error` when abs(theta0) > 2 pi
    and the pendulum swings (the state is a libration or the separatrix):
    ``period(90)`` means 90 rad, which is what 90 - 14 * 2 pi = 2.04 rad
    gives, and is almost surely meant as 90 degrees.  Rotations (omega0 fast
    enough to go over the top) and trajectory angles (``energy``,
    ``undamped``) never warn: there theta counts turns legitimately.

    The result is still computed for the angle as given.  Pass radians
    (``numpy.radians``) or, when large angles are meant, silence it with
    ``warnings.filterwarnings("ignore", category=pendula.AngleWarning)``.

    Examples
    --------
    >>> import warnings, pendula
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     T = pendula.period(90)
    >>> caught[0].category.__name__
    'AngleWarning'
    """


def warn_if_degrees(theta0, omega0, w0):
    """AngleWarning where abs(theta0) > 2 pi and the state swings (m <= 1).
    Flat float64 inputs of n or 1 elements; called from a public function
    through one helper, hence stacklevel 4 (the user's line)."""
    if theta0.size == 0 or (theta0.max() <= 2 * np.pi and theta0.min() >= -2 * np.pi):
        return  # two reductions, no temporaries: the common case costs ~1 ns per element less
    big = np.abs(theta0) > 2 * np.pi
    n = max(theta0.size, omega0.size, w0.size)
    m, _, code, _ = _fortran.parameter_f2py(n, theta0, omega0, w0)
    if code != OK:
        return  # bad input: the caller's kernel raises for it
    swings = np.broadcast_to(big, m.shape) & (m <= 1)
    if swings.any():
        x = float(np.broadcast_to(theta0, m.shape)[int(np.flatnonzero(swings)[0])])
        warnings.warn(
            AngleWarning(
                f"theta0 = {x!r} rad is more than 2 pi for a swinging pendulum: it looks like degrees "
                f"(radians expected; numpy.radians({x!r}) = {math.radians(x)!r}).  If large angles are meant, "
                f"silence this with warnings.filterwarnings('ignore', category=pendula.AngleWarning)"
            ),
            stacklevel=4,
        )
