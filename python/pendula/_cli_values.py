"""Values of the command line: the argparse types (numbers, angles with an optional
unit) and how numbers are written out (times of a grid without binary noise for
people, shortest round-trip decimals for data files).

An angle is a number with an optional unit written right after it: ``1.2`` or
``1.2rad`` (radians, the default), ``90deg`` or ``90°`` (degrees); an angular
velocity likewise: ``0.5``, ``0.5rad/s``, ``30deg/s`` or ``30°/s``.  One parser
for every option, so that ``--theta0 90deg`` means the same in every subcommand.
"""

import argparse
import math
import re

import numpy as np

# unit suffix -> True for degrees
ANGLE_UNITS = {"rad": False, "deg": True, "°": True}
RATE_UNITS = {"rad/s": False, "deg/s": True, "°/s": True}


# What argparse may take as the value of an option although it starts with "-": a minus
# and a digit, so a negative number with an exponent or a unit, or a mistyped one (no
# option of ours starts so).  Its own pattern takes only -12 and -1.5, and would read
# -1e-3 or -90deg as an unknown option.
NEGATIVE_VALUE = re.compile(r"^-\.?\d")


def accept_negative_values(parser):
    """Let ``parser`` read ``-90deg`` or ``-1e-3`` as a value (argparse's own pattern, a
    private attribute stable since Python 2.7, takes only -12 and -1.5)."""
    parser._negative_number_matcher = NEGATIVE_VALUE


def finite(text):
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return x


def positive(text):
    x = finite(text)
    if x <= 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be > 0")
    return x


def nonnegative(text):
    x = finite(text)
    if x < 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be >= 0")
    return x


def count(text):
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if n < 2 or n > 10_000_000:
        raise argparse.ArgumentTypeError(f"{text!r} must be an integer in [2, 10000000]")
    return n


def threads(text):
    """A thread count: an integer in [0, 4096] (0: every core)."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if not 0 <= n <= 4096:
        raise argparse.ArgumentTypeError(f"{text!r} must be an integer in [0, 4096] (0: every core)")
    return n


def _with_unit(text, units, what, examples):
    """The value of ``text`` in rad (or rad/s): a number with at most one unit suffix from ``units``."""
    if not isinstance(text, str):  # a default given as a number
        return float(text)
    s = text.strip()
    for suffix in sorted(units, key=len, reverse=True):  # "deg/s" before "deg"
        if s.lower().endswith(suffix):
            number = s[: -len(suffix)].strip()
            try:
                x = float(number)
            except ValueError:
                break
            if not math.isfinite(x):
                raise argparse.ArgumentTypeError(f"{text!r} is not a finite {what}")
            # degrees by math.radians: 90deg is pi/2 and 180deg is pi to the last bit
            return math.radians(x) if units[suffix] else x
    if s and (s[-1].isalpha() or s[-1] in "°/") and not s.lower().endswith(("inf", "nan", "infinity")):
        raise argparse.ArgumentTypeError(
            f"{text!r} is not {'an' if what[0] in 'aeiou' else 'a'} {what}: give {examples}"
        )
    return finite(text)


def angle(text):
    """An angle in rad: ``1.2``, ``1.2rad``, ``90deg`` or ``90°``."""
    return _with_unit(text, ANGLE_UNITS, "angle", "radians (1.57 or 1.57rad) or degrees (90deg)")


def angular_velocity(text):
    """An angular velocity in rad/s: ``0.5``, ``0.5rad/s``, ``30deg/s`` or ``30°/s``."""
    return _with_unit(text, RATE_UNITS, "angular velocity", "rad/s (0.5 or 0.5rad/s) or degrees per second (30deg/s)")


def grid_times(t):
    """The times of an output grid as text for people: the fewest decimals (the
    same for every point, so columns align) that reproduce each time to within
    its binary noise (4 ulps of the largest time: linspace is off by about one),
    e.g. 0.45 for the 0.44999999999999996 of ``linspace(0, 30, 201)``.  A grid
    that needs more than 12 significant digits is not a decimal grid (steps of
    1/3 s): then each time is its shortest round-trip decimal."""
    t = np.asarray(t, dtype=float)
    if t.size == 0:
        return []
    top = float(np.max(np.abs(t)))
    tol = 4.0 * float(np.spacing(top))
    digits_before = max(1, math.floor(math.log10(top)) + 1) if top > 0 else 1
    for d in range(max(0, 12 - digits_before) + 1):
        if np.all(np.abs(np.round(t, d) - t) <= tol):
            return [f"{x:.{d}f}" for x in t]
    return [data(x) for x in t]


def data(x):
    """A float for a data file: the shortest decimal that reads back as the same double."""
    return repr(float(x))
