"""Status codes of the Fortran core and their Python exceptions.

The codes are those of ``pendula_status`` (src/core/pendula_status.f90), read
from ``pendula._codes`` (generated from it at build time): argument problems
become ``ValueError``, solver failures ``RuntimeError``, a feature missing
from this build ``NotImplementedError``, an allocation that failed
``MemoryError`` (its message names the size asked for).
"""
from ._codes import (OK, ERR_NONFINITE, ERR_DOMAIN, ERR_SIZE, ERR_ORDER, ERR_UNSTABLE, ERR_SOLVER,  # noqa: F401
                     ERR_UNAVAILABLE, ERR_MAXSTEPS, ERR_CANCELLED, ERR_MEMORY)


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
    exc.pendula_code = code   # the batch layer reports it per state
    raise exc
