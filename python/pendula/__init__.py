"""pendula: the simple pendulum, exact where mathematics allows.

A Fortran library with a Python API (f2py).  Special functions (complete and
incomplete elliptic integrals, Jacobi elliptic functions), the undamped
pendulum in closed form for any initial state, the linear damped pendulum in
closed form, the nonlinear damped pendulum by RK4 and SUNDIALS CVODE, and
scenes answered by the cheapest model that meets a tolerance.

Units throughout: angles in rad, angular velocities in rad/s, times in s,
rates (w0, gamma) in 1/s, g in m/s^2, lengths in m, masses in kg, b in kg/s.
"""

from __future__ import annotations

import os as _os

# The batch kernels' OpenMP threads sleep between calls instead of spinning
# (libgomp's default spins up to ~300,000 rounds after each parallel region,
# burning a core that the caller's own work, or another process, needs).
# libgomp reads its settings once, when it is loaded -- here, with the
# extension -- so OMP_WAIT_POLICY=passive is set for that moment only, and
# only when the user chose neither OMP_WAIT_POLICY nor GOMP_SPINCOUNT; the
# environment is restored at once (child processes see the user's).  The
# policy is process-wide: another library's libgomp threads in this process
# sleep too, unless libgomp was loaded before pendula.
_passive = not {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT"} & set(_os.environ)
if _passive:
    _os.environ["OMP_WAIT_POLICY"] = "passive"
try:
    from . import _fortran  # noqa: F401
finally:
    if _passive:
        del _os.environ["OMP_WAIT_POLICY"]
del _passive

from ._config import HAVE_CVODE as _HAVE_CVODE, VERSION as __version__
from . import _config
from ._errors import PendulaSolverError  # noqa: F401 (public: in __all__)
from . import physics as _physics
from .physics import *  # noqa: F401,F403

# Each concern module defines __all__; the package's public API is their union.
from . import elliptic as _elliptic
from .elliptic import *  # noqa: F401,F403
from . import undamped as _undamped
from .undamped import *  # noqa: E702,F401,F403
from . import linear as _linear
from .linear import *  # noqa: E702,F401,F403
from . import integrate as _integrate_api
from .integrate import *  # noqa: E702,F401,F403
from . import scene as _scene_api
from .scene import *  # noqa: E702,F401,F403
from . import _tradeoff
from ._tradeoff import *  # noqa: E702,F401,F403

# the function pendula.sweep shadows its module's attribute (the module stays in sys.modules)
from . import sweep as _sweep_api
from .sweep import *  # noqa: E702,F401,F403
from . import driven as _driven_api
from .driven import *  # noqa: E702,F401,F403
from . import chaos as _chaos_api
from .chaos import *  # noqa: E702,F401,F403

# the function pendula.taylor shadows its module's attribute, as sweep does
from . import taylor as _taylor_api
from .taylor import *  # noqa: E702,F401,F403

# plot helpers: matplotlib is imported only when one is called
from . import motion_plots as _motion_plots
from .motion_plots import *  # noqa: E702,F401,F403

# fits of measured pendulums: SciPy is imported only when one is called
from . import fit as _fit_api
from .fit import *  # noqa: E702,F401,F403

__all__ = sorted(
    set(
        _physics.__all__
        + ["PendulaSolverError", "build_info", "have_cvode"]
        + _elliptic.__all__
        + _undamped.__all__
        + _linear.__all__
        + _integrate_api.__all__
        + _scene_api.__all__
        + _tradeoff.__all__
        + _sweep_api.__all__
        + _taylor_api.__all__
        + _motion_plots.__all__
        + _fit_api.__all__
        + _driven_api.__all__
        + _chaos_api.__all__
    )
)


def _kernel_info():
    """build_info()["kernel"]: the batch kernels' compiled variant in use and those available."""
    from ._fortran import kernel_path_f2py

    names = ("baseline", "v3", "v4")
    path, available = kernel_path_f2py()
    return {"path": names[int(path)], "available": [p for p, a in zip(names, available) if a]}


def build_info() -> dict:
    """What this build contains, as meson configured it.

    Returns
    -------
    dict
        ``version``; ``cvode`` (bool: the CVODE integrator is built);
        ``sundials``: ``version`` (str or None), ``origin`` (``"prefix"``,
        ``"system"`` or ``"none"``), ``prefix`` (str or None) and
        ``optimised`` (True, False, or None when not known -- Debian's
        packaged SUNDIALS 6.4.1 is not, and makes CVODE about 2.3x slower);
        ``compiler``: the Fortran compiler, meson's ``buildtype``,
        ``optimization`` and ``b_ndebug``, and pendula's own Fortran flags;
        ``kernel``: ``path``, the compiled variant of the batch kernels this
        process runs (``"baseline"``, ``"v3"`` for x86-64-v3 = AVX2, ``"v4"``
        for x86-64-v4 = AVX-512), chosen when the library loads from the
        CPU's features, and ``available``, the paths this build and CPU
        offer.  The environment variable ``PENDULA_KERNEL`` (``baseline``,
        ``v3`` or ``v4``), set before pendula is imported, asks for one (the
        best available one below it when the CPU lacks it).  Every path
        gives the same bits; only the speed differs.

    Examples
    --------
    >>> import pendula
    >>> info = pendula.build_info()
    >>> sorted(info)
    ['compiler', 'cvode', 'kernel', 'sundials', 'version']
    >>> info["kernel"]["path"] in info["kernel"]["available"]
    True
    >>> info["version"] == pendula.__version__
    True
    """
    return {
        "version": __version__,
        "cvode": bool(_HAVE_CVODE),
        "sundials": dict(_config.SUNDIALS),
        "compiler": {k: (list(v) if isinstance(v, list) else v) for k, v in _config.COMPILER.items()},
        "kernel": _kernel_info(),
    }


def have_cvode() -> bool:
    """True when this build includes the SUNDIALS CVODE integrator.

    Returns
    -------
    bool
        ``build_info()["cvode"]``.

    Notes
    -----
    A thin alias kept for existing code: ``build_info()`` is the one way to
    ask what this build contains.

    Examples
    --------
    >>> import pendula
    >>> pendula.have_cvode() == pendula.build_info()["cvode"]
    True
    """
    return build_info()["cvode"]
