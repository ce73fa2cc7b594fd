"""What the chaos tools share: their result contract (codes, message, inputs, ok),
and work estimates."""

import math

import numpy as np

from ._arrays import real_scalar
from ._codes import OK

_PARAMS = ("amplitude", "frequency", "phase", "gamma", "w0")


class _Outcome:
    """The batch contract's fields of a result: codes, message, inputs and the ok mask."""

    @property
    def ok(self):
        """Mask of the states that succeeded."""
        return np.asarray(self.codes) == OK


def _work(n, steps, periods):
    return n * steps * periods


def _positive(x, name):
    v = real_scalar(x, name)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} = {v!r} is out of range: it must be finite and > 0")
    return v
