"""Status codes of the Fortran core and their Python exceptions.

The table mirrors ``pendula_status`` (src/core/pendula_status.f90): argument
problems become ``ValueError``, solver failures ``RuntimeError``, a feature
missing from this build ``NotImplementedError``.
"""

OK = 0
ERR_NONFINITE = 1
ERR_DOMAIN = 2
ERR_SIZE = 3
ERR_ORDER = 4
ERR_UNSTABLE = 5
ERR_SOLVER = 6
ERR_UNAVAILABLE = 7
ERR_MAXSTEPS = 8
ERR_CANCELLED = 9


class PendulaSolverError(RuntimeError):
    """An integrator failed (CVODE error flag, step budget exhausted)."""


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
}


def _text(msg):
    if isinstance(msg, (bytes, bytearray)):
        msg = msg.decode("ascii", "replace")
    elif hasattr(msg, "tobytes"):  # numpy character array from f2py
        msg = msg.tobytes().decode("ascii", "replace")
    return str(msg).strip().strip("\x00").strip()


def raise_for_status(code, msg):
    """Raise the exception for a Fortran status ``code`` (no-op when OK)."""
    code = int(code)
    if code == OK:
        return
    exc = _EXCEPTIONS.get(code, RuntimeError)
    raise exc(_text(msg) or f"pendula error code {code}")
