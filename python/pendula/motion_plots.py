"""Plots of your own pendulum: a motion (θ(t), Ω(t), phase plane) and the phase portrait.

matplotlib is optional: importing pendula never imports it; these functions
import it when called and raise ImportError naming the extra to install when it
is missing.  They draw with matplotlib's object API (``matplotlib.figure.Figure``
on the Agg canvas: no pyplot state, no display needed, safe from threads) and
return the Figure; ``ax=`` draws into Axes you already have and returns their
figure instead.  Units: θ in rad, Ω in rad/s, t in s, w0 in 1/s.
"""

import math

import numpy as np

from ._arrays import as_real, integer_arg, real_scalar
from ._errors import number
from .physics import pendulum_w0

KINDS = ("time", "phase", "both")
EXTRA = "examples"  # the pyproject extra that brings matplotlib

_T_LABEL = "time t  (s)"
_THETA_T = "θ(t)  (rad)"
_OMEGA_T = "Ω(t)  (rad/s)"
_THETA = "θ  (rad)"
_OMEGA = "Ω  (rad/s)"


def _matplotlib(fname):
    """matplotlib's Figure and Axes classes, or ImportError naming the extra."""
    try:
        from matplotlib.axes import Axes
        from matplotlib.figure import Figure
    except ImportError:
        raise ImportError(
            f"pendula.{fname} needs matplotlib, an optional dependency: "
            f"pip install 'pendula[{EXTRA}]' (or pip install matplotlib)"
        ) from None
    return Figure, Axes


def _axes_list(ax, n, what, axes_cls):
    """``ax`` (one Axes or a sequence of them) as a list of exactly ``n`` Axes."""
    axs = list(np.ravel(np.asarray(ax, dtype=object))) if isinstance(ax, (list, tuple, np.ndarray)) else [ax]
    bad = [type(a).__name__ for a in axs if not isinstance(a, axes_cls)]
    if bad:
        raise TypeError(f"ax must be a matplotlib Axes or a sequence of them, got {bad[0]}")
    if len(axs) != n:
        raise ValueError(
            f"ax: {what} draws {n} panel(s), got {len(axs)} Axes "
            f"(pass {n} Axes, e.g. fig.subplots({n}, 1), or ax=None for a new figure)"
        )
    return axs


def _series(x, name, n=None):
    arr = as_real(x, name)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {arr.shape}")
    if n is not None and arr.size != n:
        raise ValueError(f"{name} has {arr.size} values but t has {n}: they must have the same length")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or Inf (value {arr[~np.isfinite(arr)][0]!r})")
    return arr


def _motion_data(result, t, theta, omega):
    """(t, theta, omega or None, default label) from a result, a Scene or the arrays."""
    given = [k for k, v in (("t", t), ("theta", theta), ("omega", omega)) if v is not None]
    if result is None:
        missing = [k for k in ("t", "theta") if k not in given]
        if missing:
            raise TypeError(
                f"plot_motion needs a result, or the arrays t and theta (and omega): {' and '.join(missing)} missing"
            )
        label = None
    else:
        if given:
            raise ValueError(f"give a result or the arrays t, theta, omega, not both ({', '.join(given)} given)")
        from . import scene as _scene

        if isinstance(result, _scene.Scene):
            result = _scene.solve(result)
        if not all(hasattr(result, k) for k in ("t", "theta", "omega")):
            raise TypeError(
                f"result must be a SceneResult, IntegrationResult or Scene, got "
                f"{type(result).__name__} (or pass the arrays t=, theta=, omega=)"
            )
        t, theta, omega = result.t, result.theta, result.omega
        if t is None or theta is None or np.ndim(theta) != 1:
            raise ValueError(
                f"result holds no single time series of theta to plot (theta has shape "
                f"{np.shape(theta)}): solve the Scene with want='state' or 'theta', or pass "
                f"one state of a batch as arrays, t=r.t, theta=r.theta[i], omega=r.omega[i]"
            )
        label = getattr(result, "model", None) or getattr(result, "method", None)
    t = _series(t, "t")
    theta = _series(theta, "theta", t.size)
    omega = None if omega is None else _series(omega, "omega", t.size)
    return t, theta, omega, label


def _check_kind(kind):
    if not isinstance(kind, str):
        raise TypeError(f"kind must be one of {', '.join(map(repr, KINDS))}, got {type(kind).__name__}")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(map(repr, KINDS))}, got {kind!r}")


def _check_label(label, name="label"):
    if label is not None and not isinstance(label, str):
        raise TypeError(f"{name} must be a str or None, got {type(label).__name__}")


def plot_motion(result=None, *, t=None, theta=None, omega=None, kind="time", ax=None, label=None):
    """Plot a motion: θ(t) and Ω(t) against time, its phase plane (θ, Ω), or both.

    Parameters
    ----------
    result : SceneResult, IntegrationResult or Scene, optional
        What to plot: the answer of ``pendula.solve`` / ``run_model`` or of
        ``pendula.rk4`` / ``cvode`` for one initial state, or a ``Scene``
        (solved here with ``pendula.solve``).  Leave it out to pass the arrays.
    t, theta, omega : array_like, optional, keyword-only
        Instead of ``result``: times [s], angles θ [rad] and angular velocities
        Ω [rad/s], 1-D and of one length (e.g. ``pendula.undamped(t, ...)``);
        ``omega`` may be left out for ``kind="time"``.
    kind : {"time", "phase", "both"}, keyword-only
        ``"time"`` (default): θ(t) above Ω(t) (θ(t) alone without Ω);
        ``"phase"``: Ω against θ, the start marked; ``"both"``: the three panels.
    ax : matplotlib Axes or sequence of Axes, optional, keyword-only
        Draw into these (one per panel: 2 for "time", 1 for "time" without Ω
        and for "phase", 3 for "both", in that order) instead of a new figure.
    label : str, optional, keyword-only
        Legend entry of the curves; default: the model or method of ``result``.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure of ``ax``.  Axis labels carry the
        units; the plotted line data are the result's arrays, unchanged.

    Raises
    ------
    ImportError
        matplotlib is not installed (``pip install 'pendula[examples]'``).
    TypeError
        ``result`` is not a result or a Scene, an array is not real numbers,
        ``kind`` or ``label`` is not a str, ``ax`` is not Axes.
    ValueError
        ``kind`` unknown; the arrays are not 1-D of one length, are empty or
        not finite; ``kind`` needs Ω but there is none; ``ax`` has the wrong
        number of Axes; both ``result`` and arrays given; a result with no
        time series (e.g. solved with ``want="period"``).

    Examples
    --------
    >>> import numpy as np, pendula
    >>> scene = pendula.Scene(theta0=0.0, omega0=2.0, t=np.linspace(0, 30, 301), mass=0.1, b=0.01)
    >>> r = pendula.solve(scene)
    >>> fig = pendula.plot_motion(r, kind="both")
    >>> [a.get_ylabel() for a in fig.axes]
    ['θ(t)  (rad)', 'Ω(t)  (rad/s)', 'Ω  (rad/s)']
    >>> fig.axes[0].get_xlabel()
    'time t  (s)'
    >>> t = np.linspace(0, 10, 201)
    >>> th, om = pendula.undamped(t, 2.0, 0.0, np.sqrt(2))
    >>> fig = pendula.plot_motion(t=t, theta=th, omega=om, kind="phase", label="exact")
    >>> fig.savefig("motion.png")   # doctest: +SKIP
    """
    Figure, Axes = _matplotlib("plot_motion")
    _check_kind(kind)
    _check_label(label)
    t, theta, omega, default_label = _motion_data(result, t, theta, omega)
    label = default_label if label is None else label
    if omega is None and kind != "time":
        raise ValueError(
            f"kind={kind!r} needs omega (the angular velocity), and there is none"
            " (the result was solved for theta only, or omega was not given)"
        )
    panels = ["theta", "omega"] if omega is not None else ["theta"]
    panels = {"time": panels, "phase": ["phase"], "both": panels + ["phase"]}[kind]
    if ax is None:
        fig = Figure(figsize=(9.0 if kind == "both" else 7.0, 5.6 if len(panels) > 1 else 4.4), layout="constrained")
        if kind == "both":  # theta(t) above Omega(t) on the left, the phase plane on the right
            gs = fig.add_gridspec(2, 2)
            a_theta = fig.add_subplot(gs[0, 0])
            axs = [a_theta, fig.add_subplot(gs[1, 0], sharex=a_theta), fig.add_subplot(gs[:, 1])]
        else:
            axs = list(fig.subplots(len(panels), 1, squeeze=False, sharex=True)[:, 0])
    else:
        axs = _axes_list(ax, len(panels), f"kind={kind!r}", Axes)
        fig = axs[0].figure
    data = {
        "theta": (t, theta, _T_LABEL, _THETA_T),
        "omega": (t, omega, _T_LABEL, _OMEGA_T),
        "phase": (theta, omega, _THETA, _OMEGA),
    }
    for a, p in zip(axs, panels):
        x, y, xlabel, ylabel = data[p]
        (line,) = a.plot(x, y, lw=1.6, label=label)
        if p == "phase":
            a.plot(x[:1], y[:1], "o", color=line.get_color(), label="_start")
        a.set(xlabel=xlabel, ylabel=ylabel)
        a.grid(True, alpha=0.3)
        if label is not None:
            a.legend(fontsize=8)
    return fig


def _levels(levels):
    arr = as_real(levels, "levels")
    if arr.ndim > 1 or arr.size > 100:
        raise ValueError(f"levels must be a number or a 1-D sequence of at most 100 numbers, got shape {arr.shape}")
    arr = np.atleast_1d(arr)
    if not np.all(np.isfinite(arr) & (arr > 0)):
        bad = np.flatnonzero(~(np.isfinite(arr) & (arr > 0)))[0]
        raise ValueError(f"levels[{bad}] = {number(arr[bad])} is out of range: levels (E/E_sep) must be finite and > 0")
    return arr[arr != 1.0]  # E = E_sep is the separatrix, always drawn


def _pair_range(theta_range):
    if isinstance(theta_range, (str, bytes)) or not hasattr(theta_range, "__len__") or len(theta_range) != 2:
        raise TypeError(f"theta_range must be a pair (lo, hi) of angles in rad, got {theta_range!r}")
    lo, hi = (real_scalar(x, "theta_range") for x in theta_range)
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
        raise ValueError(f"theta_range must be finite with hi > lo, got ({lo!r}, {hi!r})")
    if hi - lo > 200 * math.pi:
        raise ValueError(f"theta_range spans {(hi - lo) / (2 * math.pi):.4g} wells: at most 100 (hi - lo <= 200 pi)")
    return lo, hi


def _positive(x, name):
    v = real_scalar(x, name)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be finite and > 0, got {v!r}")
    return v


def _portrait_curves(w0, levels, theta_range, n):
    """The level curves E/E_sep = e of the undamped pendulum, exactly: a list of
    (family, e, theta [rad], Omega [rad/s]) with family "libration", "separatrix"
    or "rotation"; E/E_sep = sin^2(theta/2) + (Omega/2w0)^2."""
    lo, hi = theta_range
    th = np.linspace(lo, hi, n)
    curves = []
    # 4m + 1 points: the turning points (phi = pi/2, 3 pi/2) and the crossings of theta = 0 are samples
    phi = np.linspace(0.0, 2.0 * np.pi, 4 * ((n - 1) // 4) + 1)
    for e in sorted(levels):
        if e < 1.0:
            # theta = 2 asin(sqrt(e) sin phi), Omega = 2 w0 sqrt(e) cos phi: closed, smooth at the turning points
            rel = 2.0 * np.arcsin(math.sqrt(e) * np.sin(phi))
            om = 2.0 * w0 * math.sqrt(e) * np.cos(phi)
            rel[-1], om[-1] = rel[0], om[0]  # phi = 2 pi is phi = 0: closed exactly, not to sin(2 pi) ~ 1e-16
            amp = 2.0 * math.asin(math.sqrt(e))
            for k in range(math.floor((lo - amp) / (2 * np.pi)), math.ceil((hi + amp) / (2 * np.pi)) + 1):
                if 2 * np.pi * k + amp > lo and 2 * np.pi * k - amp < hi:  # the island shows in the window
                    curves.append(("libration", e, rel + 2 * np.pi * k, om))
        else:
            om = 2.0 * w0 * np.sqrt(e - np.sin(th / 2) ** 2)
            curves += [("rotation", e, th, om), ("rotation", e, th, -om)]
    sep = 2.0 * w0 * np.abs(np.cos(th / 2))
    curves += [("separatrix", 1.0, th, sep), ("separatrix", 1.0, th, -sep)]
    return curves


# light colours outside matplotlib's default cycle: a motion drawn over the portrait stands out
_STYLE = {
    "libration": ("#8fb3d9", 1.1, "librations (E < E_sep)"),
    "separatrix": ("#b03a2e", 1.6, "separatrix (E = E_sep = 2 m g l)"),
    "rotation": ("#93c993", 1.1, "rotations (E > E_sep)"),
}


def plot_phase_portrait(
    *,
    w0=None,
    g=None,
    length=None,
    levels=(0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.5, 2.2),
    theta_range=(-3 * math.pi, 3 * math.pi),
    omega_max=None,
    n=400,
    ax=None,
):
    """Phase portrait of the undamped pendulum: the separatrix and level curves of the energy.

    Every curve is exact: E/E_sep = sin²(θ/2) + (Ω/2w0)² = e, with
    E_sep = 2 m g l the energy of the separatrix (the motion that just reaches
    the top).  Librations (e < 1) circle the centres (2nπ, 0), rotations
    (e > 1) run over the top, marked saddles ((2n+1)π, 0) sit on the
    separatrix.  Overlay a motion with ``plot_motion(r, kind="phase", ax=...)``.

    Parameters
    ----------
    w0 : float, optional, keyword-only
        Natural angular frequency sqrt(g/l) [1/s]; or give ``g`` and ``length``.
        Given none, the text's pendulum (w0 = sqrt(2) 1/s), as everywhere in pendula.
    g : float, optional, keyword-only
        Gravitational acceleration [m/s^2] (default 9.8), with ``length``.
    length : float, optional, keyword-only
        Pendulum length [m] (default 4.9), with ``g``.
    levels : float or sequence of float, keyword-only
        Energies of the level curves as E/E_sep (dimensionless, > 0, at most
        100; 1, the separatrix, is always drawn).
    theta_range : (float, float), keyword-only
        The θ window [rad], default (-3π, 3π); at most 100 wells wide.
    omega_max : float, optional, keyword-only
        The Ω window is ±omega_max [rad/s]; default 1.1 × the largest curve's Ω.
    n : int, keyword-only
        Points per curve, 16 to 100000 (default 400; a libration takes the
        largest 4m + 1 <= n, so that its turning points are samples).
    ax : matplotlib Axes, optional, keyword-only
        Draw into these Axes instead of a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or ``ax.figure``.  Each curve's line has gid
        ``"<family> <e>"`` (family libration, separatrix or rotation).

    Raises
    ------
    ImportError
        matplotlib is not installed (``pip install 'pendula[examples]'``).
    TypeError
        An argument is not a real number (or ``n`` an integer, ``ax`` Axes).
    ValueError
        ``w0``, ``g``, ``length`` or ``omega_max`` not finite and > 0, or ``w0``
        disagreeing with sqrt(g/length); a level not finite and > 0;
        ``theta_range`` not finite with hi > lo, or wider than 100 wells;
        ``n`` outside [16, 100000].

    Examples
    --------
    >>> import numpy as np, pendula
    >>> w0 = pendula.natural_frequency(9.8, 4.9)
    >>> fig = pendula.plot_phase_portrait(w0=w0, levels=[0.5, 1.5])
    >>> ax = fig.axes[0]
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('θ  (rad)', 'Ω  (rad/s)')
    >>> sep = [l for l in ax.get_lines() if l.get_gid() == "separatrix 1"][0]
    >>> float(np.max(np.abs(pendula.energy(sep.get_xdata(), sep.get_ydata(), w0) / (2 * w0**2) - 1))) < 1e-14
    True
    >>> r = pendula.solve(pendula.Scene(theta0=0.0, omega0=3.0, t=np.linspace(0, 20, 401), gamma=0.2))
    >>> fig = pendula.plot_motion(r, kind="phase", ax=ax)   # the damped motion over the portrait
    """
    Figure, Axes = _matplotlib("plot_phase_portrait")
    w0 = pendulum_w0(None if w0 is None else _positive(w0, "w0"), g, length)
    levels = _levels(levels)
    lo, hi = _pair_range(theta_range)
    n = integer_arg(n, "n", 16, 100_000, scalar=True)
    top = 1.1 * 2.0 * w0 * math.sqrt(max([1.0] + list(levels)))
    omega_max = top if omega_max is None else _positive(omega_max, "omega_max")
    if ax is None:
        fig = Figure(figsize=(9.0, 5.4), layout="constrained")
        ax = fig.subplots()
    else:
        ax = _axes_list(ax, 1, "plot_phase_portrait", Axes)[0]
        fig = ax.figure
    seen = set()
    for family, e, th, om in _portrait_curves(w0, levels, (lo, hi), n):
        color, lw, text = _STYLE[family]
        ax.plot(th, om, color=color, lw=lw, gid=f"{family} {e:g}", label=None if family in seen else text)
        seen.add(family)
    k = np.arange(math.floor(lo / np.pi), math.ceil(hi / np.pi) + 1)
    k = k[(k * np.pi >= lo) & (k * np.pi <= hi)]
    ax.plot(k[k % 2 == 0] * np.pi, 0 * k[k % 2 == 0], "ko", ms=5, gid="centres", label="centres (2nπ, 0): stable")
    ax.plot(
        k[k % 2 == 1] * np.pi,
        0 * k[k % 2 == 1],
        "kx",
        ms=8,
        mew=2,
        gid="saddles",
        label="saddles ((2n+1)π, 0): unstable",
    )
    shown = sorted(levels)
    which = (
        "the separatrix"
        if not shown
        else "levels E/E_sep = " + ", ".join(f"{e:g}" for e in shown)
        if len(shown) <= 10
        else f"{len(shown)} levels E/E_sep from {shown[0]:g} to {shown[-1]:g}"
    )
    ax.set(
        xlim=(lo, hi),
        ylim=(-omega_max, omega_max),
        xlabel=_THETA,
        ylabel=_OMEGA,
        title=f"Phase portrait, w0 = {w0:.4g} 1/s: {which}",
    )
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    return fig


__all__ = ["plot_motion", "plot_phase_portrait"]
