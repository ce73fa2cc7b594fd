"""Status codes of the Fortran core and their Python exceptions.

The codes are those of ``pendula_status`` (src/core/pendula_status.f90), read
from ``pendula._codes`` (generated from it at build time): argument problems
become ``ValueError``, solver failures ``RuntimeError``, a feature missing
from this build ``NotImplementedError``, an allocation that failed
``MemoryError`` (its message names the size asked for).
"""

import numbers
import re

import numpy as np

from ._codes import (  # noqa: F401
    ERR_CANCELLED,
    ERR_DOMAIN,
    ERR_MAXSTEPS,
    ERR_MEMORY,
    ERR_NONFINITE,
    ERR_ORDER,
    ERR_SIZE,
    ERR_SOLVER,
    ERR_UNAVAILABLE,
    ERR_UNSTABLE,
    OK,
)


class PendulaSolverError(RuntimeError):
    """An integrator failed: a CVODE error flag, or a step budget exhausted.

    A ``RuntimeError``; raised by ``cvode``, ``solve`` and ``run_model`` (and
    by a batch call when every state failed so).

    Parameters
    ----------
    message : str
        What failed and what to change (window, tol, max_steps).

    Attributes
    ----------
    pendula_code : int
        The Fortran status code (``pendula._codes``), when raised for one.

    Examples
    --------
    >>> import pendula
    >>> try:
    ...     pendula.cvode([0.0, 1e6], 1.0, 0.0, 1.0, 0.0, max_steps=10)
    ... except pendula.PendulaSolverError as exc:
    ...     print(type(exc).__name__, isinstance(exc, RuntimeError))
    PendulaSolverError True
    """


_EXCEPTIONS = {
    ERR_NONFINITE: ValueError,
    ERR_DOMAIN: ValueError,
    ERR_SIZE: ValueError,
    ERR_ORDER: ValueError,
    ERR_UNSTABLE: ValueError,
    ERR_SOLVER: PendulaSolverError,
    ERR_UNAVAILABLE: NotImplementedError,
    ERR_MAXSTEPS: PendulaSolverError,
    ERR_CANCELLED: KeyboardInterrupt,
    ERR_MEMORY: MemoryError,
}


def _text(msg):
    """A Fortran character result from f2py (bytes or a numpy character
    array) as a str without its blank or NUL padding."""
    if isinstance(msg, (bytes, bytearray)):
        msg = msg.decode("ascii", "replace")
    elif hasattr(msg, "tobytes"):  # numpy character array from f2py
        msg = msg.tobytes().decode("ascii", "replace")
    return str(msg).strip().strip("\x00").strip()


def raise_for_status(code, msg):
    """Raise the exception for a Fortran status ``code`` (no-op when OK);
    the exception carries the code as ``pendula_code``."""
    code = int(code)
    if code == OK:
        return
    exc = _EXCEPTIONS.get(code, RuntimeError)(_text(msg) or f"pendula error code {code}")
    exc.pendula_code = code  # the batch layer reports it per state
    raise exc


# -- messages: one convention for numbers and state indices -----------------------------------------------
# A state of a batch is named by its 0-based NumPy index in the batch (the
# broadcast shape), written like an element: ``theta0[3]``, ``w0[1, 2]``;
# numbers are written as Python writes a float or an int (never a NumPy repr).
_FORTRAN_STATE = re.compile(r"^state \d+ of \d+(?: \(\d+ failed, see codes\))?: ")
_NAME_IS = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*) = ")


def number(x):
    """``x`` as Python writes it (``-1.0``, ``3``): never ``np.float64(-1.0)``."""
    if isinstance(x, (bool, np.bool_)):
        return str(bool(x))
    if isinstance(x, (numbers.Integral, np.integer)):
        return str(int(x))
    try:
        return repr(float(x))
    except (TypeError, ValueError):
        return repr(x)


def index_text(i, shape):
    """The flat C-order state ``i`` of a batch of ``shape`` as ``[i]`` / ``[i, j]``."""
    where = np.unravel_index(int(i), shape) if shape else ()
    return "[" + ", ".join(str(int(j)) for j in where) + "]"


def for_state(detail, i, shape, names=None):
    """A one-state message ``detail`` (``"w0 = -1 is ..."``, or the Fortran
    batch form ``"state 3 of 5: w0 = -1 ..."``) for state ``i`` of a batch:
    ``"w0[2] = -1 is ..."``, or ``"state [2]: ..."`` when it names no
    argument of the call (``names``: the call's per-state arguments; None: any)."""
    detail = _FORTRAN_STATE.sub("", str(detail), count=1)
    at = index_text(i, shape)
    m = _NAME_IS.match(detail)
    if m and (names is None or m.group(1) in names):
        return f"{m.group(1)}{at} = {detail[m.end() :]}"
    return f"state {at}: {detail}"


def batch_summary(codes, first_detail, shape, names=None):
    """The summary message of a batch whose flat ``codes`` have failures:
    how many failed and the first one's message, indexed (see ``for_state``)."""
    bad = np.flatnonzero(np.asarray(codes).reshape(-1) != OK)
    n = int(np.asarray(codes).size)
    head = "every state failed" if bad.size == n else f"{bad.size} of {n} states failed"
    return f"{head} (see codes); the first: {for_state(first_detail, int(bad[0]), shape, names)}"


def raise_if_all_failed(codes, code, message):
    """The one rule for when a batch raises: every state of a non-empty batch
    failed (there is no answer to return).  Raises the first state's exception."""
    codes = np.asarray(codes)
    if codes.size and not (codes == OK).any():
        raise_for_status(code, message)
