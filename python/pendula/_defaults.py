"""The Python layer's defaults and shared names: one home each, read everywhere else.

Facts of the Fortran core (the text's pendulum G_DEFAULT, LENGTH_DEFAULT; the
scene work budget STEP_CAP) live in ``pendula._codes``, generated from the
Fortran; this module re-exports them next to the choices the Python layer makes
itself (tolerances, step budgets, method, the thread policy), so that a
signature, a docstring's default and the command line all read one value.
"""

import numbers
import os

from ._codes import CVODE_ADAMS, CVODE_BDF, G_DEFAULT, LENGTH_DEFAULT, STEP_CAP

__all__ = [
    "G_DEFAULT",
    "LENGTH_DEFAULT",
    "STEP_CAP",
    "TOL",
    "CVODE_RTOL",
    "CVODE_ATOL",
    "CVODE_METHOD",
    "CVODE_MAX_STEPS",
    "CVODE_METHODS",
    "RK4_MAX_STEPS",
    "TAYLOR_TOL",
    "TAYLOR_MAX_STEPS",
    "MAX_EVENTS",
    "SWEEP_H",
    "CHUNK_STATES",
    "STAT_NAMES",
    "THREADS",
    "SERIAL_WORK",
    "POOL_STATE_WORK",
    "WELL_NONE",
    "SETTLE_MARGIN",
    "check_threads",
    "choose_threads",
]

TOL = 1e-6
"""A scene's tolerance [rad] when none is given (``Scene``, ``pendula solve``)."""
CVODE_RTOL = 1e-8
"""CVODE's relative tolerance when none is given (``cvode``, ``sweep``)."""
CVODE_ATOL = 1e-10
"""CVODE's absolute tolerance when none is given (``cvode``, ``sweep``)."""
CVODE_METHOD = "adams"
"""CVODE's linear multistep method when none is given ("adams" or "bdf")."""
CVODE_METHODS = {"adams": CVODE_ADAMS, "bdf": CVODE_BDF}
"""CVODE method names -> the Fortran codes (``pendula._codes``)."""
CVODE_MAX_STEPS = 10_000_000
"""CVODE's step budget per state when none is given."""
RK4_MAX_STEPS = 2_000_000_000
"""RK4's step budget per state when none is given (``rk4``, ``sweep``)."""
TAYLOR_TOL = 1e-12
"""The Taylor model's accuracy at the outputs [rad] when none is given (``taylor``)."""
TAYLOR_MAX_STEPS = 1_000_000_000
"""The Taylor model's step budget per state when none is given (``taylor``)."""
MAX_EVENTS = 100_000
"""Events kept per state by ``cvode(..., events=True)`` when none is given."""
SWEEP_H = 0.01
"""The RK4 step [s] of ``sweep`` and ``pendula sweep`` when none is given."""
CHUNK_STATES = 4096
"""States per chunk of a sweep: ~0.1-0.5 s of RK4 work for a few hundred steps."""
STAT_NAMES = ("steps", "rhs_evals", "jac_evals", "err_test_fails", "nonlin_iters", "nonlin_fails", "root_evals")
"""The integrators' counters, in the order the Fortran glue returns them."""

THREADS = None
"""The ``threads`` default of every many-state call: None = chosen from the
predicted work (``choose_threads``).  0 asks for the OpenMP default
(OMP_NUM_THREADS or every core), n > 0 for n threads."""
SERIAL_WORK = 2e6
"""Predicted work (RK4 steps summed over the states, a CVODE step or a scene
counted in RK4 steps) below which ``threads=None`` runs on one thread: waking
an OpenMP team or a thread pool costs ~0.1-10 ms on a loaded machine, while
2e6 RK4 steps take ~10-30 ms on one core (5-15 ns a step in the batch kernel),
so below it threads cannot pay (200 states of 100 steps: 0.7 ms on one
thread, 4.9 ms with threads=0 on a busy 2-core machine)."""

POOL_STATE_WORK = 3000.0
"""The least work of one state on the Python thread pool (scenes, CVODE with
events), in RK4 steps: its ~30 us of Python around the Fortran call.  A batch
of more than SERIAL_WORK / POOL_STATE_WORK such states takes threads without
asking Fortran for each state's prediction."""

WELL_NONE = -(2**31)
"""The ``well`` of a state that has none (failed, or still above or at the
separatrix at t[-1]): never a number of turns."""
SETTLE_MARGIN = 1e-9
"""A state is settled in its well when its energy at t[-1] is below the
separatrix energy 2 w0^2 by more than this fraction of it."""

# GNU OpenMP is not fork-safe: a child forked after its parent ran a
# multi-threaded region hangs in its own first one (the thread pool it
# inherits has no threads).  The pid that started the pool is remembered; a
# forked child runs its batches on one thread (same results, bit for bit).
_pool_pid = None


def check_threads(threads):
    """Validate ``threads`` (None, or an int in [0, 4096]); TypeError/ValueError naming it."""
    if threads is None:
        return None
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads must be an integer or None, got {type(threads).__name__}")
    if threads < 0 or threads > 4096:
        raise ValueError(
            f"threads = {int(threads)} is out of range: it must be None (chosen from the work), "
            f"0 (the OpenMP default) or in [1, 4096]"
        )
    return int(threads)


def choose_threads(threads, work):
    """The thread count for a call of predicted ``work`` (RK4-step units).

    None: 1 below ``SERIAL_WORK``, else 0 (the OpenMP default); an int as
    given (validated).  In a process forked after its parent used threads,
    always 1 (GNU OpenMP is not fork-safe).  Returns an int >= 0, 0 meaning
    the OpenMP default.
    """
    global _pool_pid
    threads = check_threads(threads)
    if threads is None:
        threads = 1 if not work > SERIAL_WORK else 0  # NaN work: threads
    if threads == 1:
        return 1
    pid = os.getpid()
    if _pool_pid is None:
        _pool_pid = pid
    return threads if _pool_pid == pid else 1


def default_threads():
    """Threads for ``threads=0`` on a Python thread pool: OMP_NUM_THREADS when
    set (as the OpenMP kernels), else the CPUs this process may run on."""
    env = os.environ.get("OMP_NUM_THREADS", "").split(",")[0].strip()
    if env.isdigit() and int(env) > 0:
        return int(env)
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1
