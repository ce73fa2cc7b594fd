"""The text's figures, redrawn from the library, and the figures the text lacks.

Every function here takes an output folder (created if missing) and returns
the list of paths it wrote.  They draw with matplotlib's object API on an Agg
canvas (``matplotlib.figure.Figure``), so no display, no pyplot state and no
backend switch are needed: they work on a headless machine and from threads.

Parameters are the text's throughout: g = 9.8 m/s^2, l = 4.9 m, so
w0 = sqrt(g/l) = sqrt(2) 1/s.  The figure numbers follow the text
("Pendulo - Solucoes Gerais"); the text's figures relied on colours named in
captions, ours carry legends, axis units and file names that say what they
show.  Errata of the text's listings are not copied (see each docstring).

``make_figures(out_dir, quick=False)`` draws them all and reports which could
not be drawn because a part of the library is missing from this build (it
never writes a placeholder).  ``quick=True`` uses fewer points, for tests.
"""
from pathlib import Path

import numpy as np

import pendula as _pd

from .plots import DPI, _figure, basin_map_plot, tradeoff_rows, work_precision_plot  # noqa: F401 (re-exported)

G = 9.8          # m/s^2, the text's g
LENGTH = 4.9     # m, the text's l
MASS = 0.100     # kg, the text's m in §2.2


class FigureUnavailable(RuntimeError):
    """A figure needs a part of the library that this build does not have."""


# --------------------------------------------------------------------------
# small plumbing: library calls with clear "missing" errors, result unpacking
# --------------------------------------------------------------------------

def _need(name):
    fn = getattr(_pd, name, None)
    if fn is None:
        raise FigureUnavailable(f"pendula.{name} is not available in this build")
    return fn


def _w0():
    return _pd.natural_frequency(G, LENGTH)


def _pair(res):
    """(theta, omega) from a tuple or from a result object with .theta/.omega."""
    if hasattr(res, "theta"):
        return np.asarray(res.theta, dtype=float), np.asarray(res.omega, dtype=float)
    return np.asarray(res[0], dtype=float), np.asarray(res[1], dtype=float)


def _exact(t, theta0, omega0, w0):
    return _pair(_need("undamped")(t, theta0, omega0, w0))


def _small(t, theta0, omega0, w0):
    return _pair(_need("small_angle")(t, theta0, omega0, w0))


def _linear(t, theta0, omega0, w0, gamma):
    return _pair(_need("linear_damped")(t, theta0, omega0, w0, gamma))


def _reference(t, theta0, omega0, w0, gamma):
    """A converged solution of the nonlinear damped equation (eq. 2.3) and its label."""
    if getattr(_pd, "cvode", None) is not None and _pd.build_info()["cvode"]:
        res = _pd.cvode(t, theta0, omega0, w0, gamma, rtol=1e-11, atol=1e-13, method="bdf")
        return _pair(res) + ("pendula.cvode (BDF, rtol 1e-11)",)
    res = _need("rk4")(t, theta0, omega0, w0, gamma, 1e-3)
    return _pair(res) + ("pendula.rk4 (h = 0.001 s)",)


def _text_listing(t_end, h, theta0, omega0, w0, gamma):
    """The text's printed RK4 listing (§2.2, with its line-67 typo): t, theta, omega."""
    textbook = getattr(_pd, "textbook", None)
    if textbook is None:
        try:
            from . import textbook  # noqa: F811 (not re-exported by every build)
        except ImportError:
            raise FigureUnavailable("pendula.textbook (the text's printed RK4 listing) "
                                    "is not available in this build") from None
    res = textbook.text_listing_rk4(t_end, h, theta0, omega0, w0, gamma, typo=True)
    if hasattr(res, "theta"):
        return (np.asarray(res.t, dtype=float), np.asarray(res.theta, dtype=float),
                np.asarray(res.omega, dtype=float))
    return tuple(np.asarray(r, dtype=float) for r in res[:3])


def _save(fig, out_dir, name):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.savefig(path, dpi=DPI)
    return path


def _npts(quick, full=2000):
    return 300 if quick else full


def _pi_label(x):
    return f"{x:.2f}π"


# --------------------------------------------------------------------------
# §1.2: complete elliptic integral, period, theta(t) for Omega0 = 0
# --------------------------------------------------------------------------

def fig03_complete_elliptic_K(out_dir, quick=False):
    """Fig 3: K(k²) against the modulus k = sin(θ0/2) (listing 1.1, eq. 1.46).

    The text stops at k = 0.9875; we go to 1 - 1e-6 with points clustered at
    k = 1 and overlay the logarithmic asymptote ln(4/k'), k' = sqrt(1 - k²).
    """
    ellipk = _need("ellipk")
    n = _npts(quick, 1200)
    k = np.concatenate([np.linspace(0.0, 0.95, n // 2, endpoint=False),
                        1.0 - np.geomspace(0.05, 1e-6, n // 2)])
    kc = np.sqrt((1.0 - k) * (1.0 + k))
    big_k = ellipk(k * k)
    fig, axs = _figure()
    ax = axs[0, 0]
    ax.plot(k, big_k, lw=2, label="K(k²), pendula.ellipk (eq. 1.46)")
    sel = k > 0.6
    ax.plot(k[sel], np.log(4.0 / kc[sel]), "--", label="asymptote ln(4/√(1−k²)) as k → 1")
    ax.axhline(np.pi / 2, color="grey", lw=0.8, ls=":", label="K(0) = π/2")
    ax.set(title="Fig 3 – Complete elliptic integral of the first kind",
           xlabel="modulus k = sin(θ0/2)  (dimensionless)",
           ylabel="K(k²)  (dimensionless)", xlim=(0, 1), ylim=(0, 1.05 * big_k.max()))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left")
    return [_save(fig, out_dir, "fig03_complete_elliptic_K_vs_k.png")]


def fig04_period_vs_amplitude(out_dir, quick=False):
    """Fig 4: period T = 4K(k²)/w0 (eq. 1.53) and T0 = 2π/w0 (eq. 1.8) against k = sin(θ0/2).

    Adds the first two terms of the amplitude series T0 (1 + k²/4 + 9k⁴/64),
    to show where the usual textbook correction stops helping.
    """
    period = _need("period")
    w0 = _w0()
    n = _npts(quick, 800)
    k = np.concatenate([np.linspace(0.0, 0.95, n // 2, endpoint=False),
                        1.0 - np.geomspace(0.05, 1e-4, n // 2)])
    theta0 = 2.0 * np.arcsin(k)
    t_exact = np.asarray(period(theta0, 0.0, w0), dtype=float)
    t0 = float(_pd.small_angle_period(w0))
    fig, axs = _figure()
    ax = axs[0, 0]
    ax.plot(k, t_exact, lw=2, label="exact T = 4K(k²)/w0, pendula.period (eq. 1.53)")
    ax.plot(k, np.full_like(k, t0), lw=2, label="small-angle T0 = 2π/w0 (eq. 1.8)")
    ax.plot(k, _pd.period_series(k**2, w0), "--",
            label="series T0 (1 + k²/4 + 9k⁴/64)")
    ax.set(title=f"Fig 4 – Period of the simple pendulum (g = {G} m/s², l = {LENGTH} m)",
           xlabel="sin(θ0/2)  (dimensionless)", ylabel="period  (s)", xlim=(0, 1),
           ylim=(0, min(4 * t0, 1.05 * t_exact.max())))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left")
    return [_save(fig, out_dir, "fig04_period_exact_vs_small_angle_vs_sin_half_theta0.png")]


_FIG5_8_SETS = {
    "fig05": ("small", (0.01, 0.10)),
    "fig06": ("medium", (0.25, 0.50)),
    "fig07": ("large", (0.75, 0.90)),
}


def _theta_vs_small_angle(out_dir, key, quick):
    label, fractions = _FIG5_8_SETS[key]
    w0 = _w0()
    t = np.linspace(0.0, 3 * 2 * np.pi / w0, _npts(quick))  # three small-angle periods, as the text
    fig, axs = _figure(len(fractions), 1, size=(7.0, 6.4), sharex=True)
    for ax, frac, tag in zip(axs[:, 0], fractions, "ab"):
        theta0 = frac * np.pi
        th, _ = _exact(t, theta0, 0.0, w0)
        ths, _ = _small(t, theta0, 0.0, w0)
        ax.plot(t, th, lw=2, label="exact, pendula.undamped (eq. 1.52)")
        ax.plot(t, ths, "--", lw=1.5, label="small angle θ0 cos(w0 t) (eq. 1.18)")
        ax.set(title=f"({tag}) θ0 = {_pi_label(frac)} rad;  max |exact − small angle| = "
                     f"{np.max(np.abs(th - ths)):.2g} rad", ylabel="θ(t)  (rad)")
        ax.grid(True, alpha=0.3)
    axs[-1, 0].set_xlabel("time t  (s)")
    axs[-1, 0].legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, fontsize=8)
    num = key[3:]
    fig.suptitle(f"Fig {int(num)} – θ(t) for {label} initial angles θ0 (Ω0 = 0, w0 = √2 1/s)")
    return [_save(fig, out_dir, f"{key}_theta_exact_vs_small_angle_{label}_theta0.png")]


def fig05_theta_small_theta0(out_dir, quick=False):
    """Fig 5: θ(t) exact vs small-angle for θ0 = 0.01π and 0.10π (listing 1.3)."""
    return _theta_vs_small_angle(out_dir, "fig05", quick)


def fig06_theta_medium_theta0(out_dir, quick=False):
    """Fig 6: θ(t) exact vs small-angle for θ0 = 0.25π and 0.50π (listing 1.3)."""
    return _theta_vs_small_angle(out_dir, "fig06", quick)


def fig07_theta_large_theta0(out_dir, quick=False):
    """Fig 7: θ(t) exact vs small-angle for θ0 = 0.75π and 0.90π (listing 1.3)."""
    return _theta_vs_small_angle(out_dir, "fig07", quick)


def fig08_theta_all_theta0(out_dir, quick=False):
    """Fig 8: all six θ0 of figs 5–7 on one plot (listing 1.4).

    Listing 1.4 passes θ0/2 as the small-angle amplitude and, mis-indented,
    draws the small-angle curve for the first θ0 only; here every θ0 has its
    exact curve (solid) and its small-angle curve (dashed, same colour).
    """
    w0 = _w0()
    t = np.linspace(0.0, 3 * 2 * np.pi / w0, _npts(quick))
    fig, axs = _figure(size=(8.0, 5.2))
    ax = axs[0, 0]
    for i, frac in enumerate((0.01, 0.10, 0.25, 0.50, 0.75, 0.90)):
        theta0 = frac * np.pi
        th, _ = _exact(t, theta0, 0.0, w0)
        ths, _ = _small(t, theta0, 0.0, w0)
        c = f"C{i}"
        ax.plot(t, th, color=c, lw=1.8, label=f"θ0 = {_pi_label(frac)}: exact")
        ax.plot(t, ths, color=c, lw=1.0, ls="--", label=f"θ0 = {_pi_label(frac)}: small angle")
    ax.set(title="Fig 8 – θ(t), exact (solid) vs small angle (dashed), Ω0 = 0, w0 = √2 1/s",
           xlabel="time t  (s)", ylabel="θ(t)  (rad)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, fontsize=8)
    return [_save(fig, out_dir, "fig08_theta_exact_vs_small_angle_all_theta0.png")]


# --------------------------------------------------------------------------
# §1.3: launch from the bottom with speed v0
# --------------------------------------------------------------------------

def fig09_launch_speed_series(out_dir, quick=False):
    """Fig 9: θ(t) for θ0 = 0 and v0 = 1, 1.5, 1.9, 1.999 × w0·l (eq. 1.66, listing 1.5).

    Ω0 = v0/l; the amplitude is θmax = 2 asin(v0 / (2 w0 l)) (eq. 1.57).
    Listing 1.5 names θmax/2 "theta_max"; here the amplitudes are the true θmax.
    """
    w0 = _w0()
    t = np.linspace(0.0, 6 * 2 * np.pi / w0, _npts(quick, 3000))
    fig, axs = _figure(size=(8.0, 4.8))
    ax = axs[0, 0]
    for c in (1.0, 1.5, 1.9, 1.999):
        omega0 = c * w0  # v0 = c w0 l  ->  Omega0 = v0 / l
        th, _ = _exact(t, 0.0, omega0, w0)
        theta_max = 2 * np.arcsin(c / 2)
        ax.plot(t, th, lw=1.6, label=f"v0 = {c:g} w0·l  (θmax = {theta_max:.3f} rad)")
    ax.axhline(np.pi, color="grey", lw=0.8, ls=":")
    ax.axhline(-np.pi, color="grey", lw=0.8, ls=":", label="±π (the top)")
    ax.set(title="Fig 9 – θ(t) launched from θ0 = 0 with speed v0 (l = 4.9 m, w0 = √2 1/s)",
           xlabel="time t  (s)", ylabel="θ(t)  (rad)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3, fontsize=8)
    return [_save(fig, out_dir, "fig09_theta_launch_speed_v0_series.png")]


# --------------------------------------------------------------------------
# §2.1: linear damped (closed form)
# --------------------------------------------------------------------------

_OMEGA0_SET = (0.0, 0.5, -0.5)


def _theta_omega_panels(out_dir, name, title, gamma_over_w0, quick, theta0=0.1, omega0s=_OMEGA0_SET):
    w0 = _w0()
    gamma = gamma_over_w0 * w0
    t = np.linspace(0.0, 2 * 2 * np.pi / w0, _npts(quick))  # two small-angle periods, as the text
    fig, axs = _figure(2, 1, size=(7.0, 6.4), sharex=True)
    for om0 in omega0s:
        th, om = _linear(t, theta0, om0, w0, gamma)
        lab = f"θ0 = {theta0:g} rad, Ω0 = {om0:g} rad/s"
        axs[0, 0].plot(t, th, lw=1.8, label=lab)
        axs[1, 0].plot(t, om, lw=1.8, label=lab)
    axs[0, 0].set(title=f"γ = {gamma_over_w0:g} w0 = {gamma:.4g} 1/s (w0 = √2 1/s)", ylabel="θ(t)  (rad)")
    axs[1, 0].set(xlabel="time t  (s)", ylabel="Ω(t)  (rad/s)")
    for ax in axs[:, 0]:
        ax.grid(True, alpha=0.3)
        ax.axhline(0, color="grey", lw=0.6)
        ax.legend(fontsize=8)
    fig.suptitle(title)
    return [_save(fig, out_dir, name)]


def fig10_overdamped_gamma3(out_dir, quick=False):
    """Fig 10: overdamped θ(t) and Ω(t), γ = 3 w0, θ0 = 0.1, Ω0 ∈ {0, 0.5, -0.5} (eq. 2.27)."""
    return _theta_omega_panels(out_dir, "fig10_overdamped_gamma_3w0_theta_omega.png",
                               "Fig 10 – Overdamped, linear (pendula.linear_damped)", 3.0, quick)


def fig11_overdamped_gamma5(out_dir, quick=False):
    """Fig 11: overdamped θ(t) and Ω(t), γ = 5 w0, θ0 = 0.1, Ω0 ∈ {0, 0.5, -0.5} (eq. 2.27)."""
    return _theta_omega_panels(out_dir, "fig11_overdamped_gamma_5w0_theta_omega.png",
                               "Fig 11 – Overdamped, linear (pendula.linear_damped)", 5.0, quick)


def fig12_overdamped_phase_plane(out_dir, quick=False):
    """Fig 12: overdamped θ(t) and phase plane (θ, Ω), θ0 = 0, Ω0 = 0.5 rad/s, γ = 3 w0."""
    w0 = _w0()
    gamma = 3.0 * w0
    t = np.linspace(0.0, 2 * 2 * np.pi / w0, _npts(quick, 1000))
    th, om = _linear(t, 0.0, 0.5, w0, gamma)
    fig, axs = _figure(2, 1, size=(7.0, 6.4))
    lab = "θ0 = 0, Ω0 = 0.5 rad/s, γ = 3 w0"
    axs[0, 0].plot(t, th, lw=1.8, label=lab)
    axs[0, 0].set(title="θ(t)", xlabel="time t  (s)", ylabel="θ(t)  (rad)")
    axs[1, 0].plot(th, om, ".", ms=2.5, label=lab + f" (dots every {t[1] - t[0]:.2g} s)")
    axs[1, 0].plot(th[:1], om[:1], "o", color="C3", label="initial state")
    axs[1, 0].plot([0], [0], "k+", ms=10, label="equilibrium (0, 0)")
    axs[1, 0].set(title="phase plane", xlabel="θ  (rad)", ylabel="Ω  (rad/s)")
    for ax in axs[:, 0]:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Fig 12 – Overdamped, linear: θ(t) and phase plane (pendula.linear_damped)")
    return [_save(fig, out_dir, "fig12_overdamped_gamma_3w0_theta_and_phase_plane.png")]


def fig13_critical_damping(out_dir, quick=False):
    """Fig 13: critically damped θ(t) and Ω(t), γ = 2 w0, θ0 = 0.1, Ω0 ∈ {0, 0.5, -0.5} (eq. 2.45)."""
    return _theta_omega_panels(out_dir, "fig13_critical_damping_gamma_2w0_theta_omega.png",
                               "Fig 13 – Critical damping, linear (pendula.linear_damped)", 2.0, quick)


# --------------------------------------------------------------------------
# §2.2: nonlinear damped, correct integrator vs the text's printed listing
# --------------------------------------------------------------------------

_TEXT_H = 0.05     # s, the text's step
_TEXT_TEND = 30.0  # s


def _nonlinear_runs(b):
    w0 = _w0()
    gamma = _pd.damping_rate(b, MASS)
    tl, thl, oml = _text_listing(_TEXT_TEND, _TEXT_H, 0.0, 2.0, w0, gamma)
    t = np.linspace(0.0, _TEXT_TEND, 601)
    th, om, lab = _reference(t, 0.0, 2.0, w0, gamma)
    return t, th, om, lab, tl, thl, oml


def fig14_nonlinear_damped(out_dir, quick=False):
    """Fig 14: nonlinear damped θ(t), Ω(t) for b = 0.01, 0.05 kg/s (m = 0.1 kg, θ0 = 0, Ω0 = 2 rad/s).

    Solid: a converged integration (CVODE when built, else RK4 at h = 1e-3 s).
    Dashed: the text's listing as printed (h = 0.05 s, line 67 reads
    ``m2 = m1 * h * k1 / 2.0`` for ``m1 + h * k1 / 2.0``), which is not
    consistent with the ODE; the text's own fig 14 was drawn from it.
    """
    fig, axs = _figure(2, 1, size=(8.0, 7.0), sharex=True)
    for i, b in enumerate((0.01, 0.05)):
        t, th, om, lab, tl, thl, oml = _nonlinear_runs(b)
        c = f"C{i}"
        drift = float(np.max(np.abs(np.interp(t, tl, thl) - th)))
        axs[0, 0].plot(t, th, color=c, lw=2, label=f"b = {b} kg/s: {lab}")
        axs[0, 0].plot(tl, thl, color=c, lw=1.2, ls="--",
                       label=f"b = {b} kg/s: text's printed listing (max |Δθ| = {drift:.2f} rad)")
        axs[1, 0].plot(t, om, color=c, lw=2, label=f"b = {b} kg/s: {lab}")
        axs[1, 0].plot(tl, oml, color=c, lw=1.2, ls="--", label=f"b = {b} kg/s: text's printed listing")
    axs[0, 0].set(ylabel="θ(t)  (rad)", title="θ(t)")
    axs[1, 0].set(ylabel="Ω(t)  (rad/s)", xlabel="time t  (s)", title="Ω(t)")
    for ax in axs[:, 0]:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7.5)
    fig.suptitle("Fig 14 – Nonlinear damped pendulum (eq. 2.2), g = 9.8 m/s², l = 4.9 m, m = 0.1 kg,"
                 "\nθ0 = 0, Ω0 = 2 rad/s: correct solution (solid) vs the text's listing as printed (dashed)",
                 fontsize=10)
    return [_save(fig, out_dir, "fig14_nonlinear_damped_theta_omega_correct_vs_text_listing.png")]


def fig15_nonlinear_damped_phase_plane(out_dir, quick=False):
    """Fig 15: nonlinear damped θ(t) and phase plane for b = 0.05 kg/s, with the text's listing overlaid."""
    b = 0.05
    t, th, om, lab, tl, thl, oml = _nonlinear_runs(b)
    fig, axs = _figure(2, 1, size=(7.5, 7.0))
    axs[0, 0].plot(t, th, lw=2, label=f"correct: {lab}")
    axs[0, 0].plot(tl, thl, "--", lw=1.2, label="text's printed listing (h = 0.05 s, typo line 67)")
    axs[0, 0].set(title="θ(t)", xlabel="time t  (s)", ylabel="θ(t)  (rad)")
    axs[1, 0].plot(th, om, lw=1.5, label=f"correct: {lab}")
    axs[1, 0].plot(thl, oml, ".", ms=2, color="C1", label="text's printed listing (points every h)")
    axs[1, 0].plot([0], [2.0], "o", color="C3", label="initial state (0, 2 rad/s)")
    axs[1, 0].set(title="phase plane", xlabel="θ  (rad)", ylabel="Ω  (rad/s)")
    for ax in axs[:, 0]:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Fig 15 – Nonlinear damped pendulum, b = 0.05 kg/s (γ = 0.5 1/s), θ0 = 0, Ω0 = 2 rad/s",
                 fontsize=10)
    return [_save(fig, out_dir, "fig15_nonlinear_damped_b0.05_theta_and_phase_plane_vs_text_listing.png")]


# --------------------------------------------------------------------------
# What the text lacks
# --------------------------------------------------------------------------

def figA1_underdamped_linear(out_dir, quick=False):
    """§2.1.3 (empty in the text): underdamped linear θ(t) with its envelope.

    θ0 = 0.1 rad, Ω0 = 0, γ = 0.1, 0.5, 1.0 × w0; dotted: the envelope
    ±R e^{-γt/2} (pendula.linear_damped_envelope), legend: Q, ω_d and the
    logarithmic decrement from pendula.damping_regime.
    """
    w0 = _w0()
    t = np.linspace(0.0, 5 * 2 * np.pi / w0, _npts(quick))
    theta0, omega0 = 0.1, 0.0
    fig, axs = _figure(size=(8.0, 4.8))
    ax = axs[0, 0]
    for i, r in enumerate((0.1, 0.5, 1.0)):
        gamma = r * w0
        th, _ = _linear(t, theta0, omega0, w0, gamma)
        info = _need("damping_regime")(w0, gamma)
        c = f"C{i}"
        ax.plot(t, th, color=c, lw=1.8, label=f"γ = {r:g} w0 (Q = {info.quality_factor:.3g}, "
                f"ω_d = {info.omega_d:.3f} 1/s, log decrement {info.log_decrement:.3g})")
        env = _need("linear_damped_envelope")(t, theta0, omega0, w0, gamma)
        ax.plot(t, env, color=c, lw=0.9, ls=":")
        ax.plot(t, -env, color=c, lw=0.9, ls=":")
    ax.plot([], [], color="grey", ls=":", label="envelope ±R e^(−γt/2), pendula.linear_damped_envelope")
    ax.set(title="Underdamped linear pendulum (§2.1.3, empty in the text), θ0 = 0.1 rad, Ω0 = 0",
           xlabel="time t  (s)", ylabel="θ(t)  (rad)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    return [_save(fig, out_dir, "figA1_underdamped_linear_theta_with_envelope.png")]


def figA2_phase_portrait(out_dir, quick=False):
    """Full phase portrait of the undamped pendulum: librations, separatrix, rotations.

    Every curve is a trajectory from pendula.undamped (not a contour of the
    energy), so the figure also shows that the closed form covers all three
    regimes.  Centres at (2nπ, 0), saddles at ((2n+1)π, 0) with their
    linearised eigenvalues from pendula.equilibria (text §1.1).
    """
    w0 = _w0()
    n = _npts(quick, 1500)
    fig, axs = _figure(size=(9.0, 5.6))
    ax = axs[0, 0]
    shifts = (-2 * np.pi, 0.0, 2 * np.pi)
    period = _need("period")
    first = True
    for theta0 in (0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 2.9):  # librations, Omega0 = 0
        tp = float(period(theta0, 0.0, w0))
        t = np.linspace(0.0, tp, n)
        th, om = _exact(t, theta0, 0.0, w0)
        for s in shifts:
            ax.plot(th + s, om, color="C0", lw=1.1, label="librations (E < 2mgl)" if first else None)
            first = False
    # separatrix: m = 1, launched from the bottom at Omega0 = +-2 w0
    t = np.linspace(-12.0, 12.0, n) / w0
    first = True
    for sgn in (1.0, -1.0):
        th, om = _exact(t, 0.0, sgn * 2 * w0, w0)
        for s in shifts:
            ax.plot(th + s, om, color="C3", lw=1.8, label="separatrix (E = 2mgl)" if first else None)
            first = False
    # rotations: from theta0 = -3 pi (or +3 pi) across the window
    first = True
    for r in (1.05, 1.3, 1.7):
        for sgn in (1.0, -1.0):
            om0 = sgn * 2 * r * w0
            t_rev = float(period(0.0, om0, w0))
            t = np.linspace(0.0, 3 * t_rev, n)
            th, om = _exact(t, -sgn * 3 * np.pi, om0, w0)
            ax.plot(th, om, color="C2", lw=1.1, label="rotations (E > 2mgl)" if first else None)
            first = False
    # equilibria (n pi, 0) and their linearisation from the library (text §1.1)
    eq_theta, eq_lambda, eq_kind = _need("equilibria")(np.arange(-3, 4), w0)
    for kind, marker, text in (("centre", "o", "centres (2nπ, 0): eigenvalues ±i w0, stable"),
                               ("saddle", "x", "saddles ((2n+1)π, 0): eigenvalues ±w0, unstable")):
        sel = eq_kind == kind
        ax.plot(eq_theta[sel], 0 * eq_theta[sel], marker, color="k", ms=5 if marker == "o" else 8,
                mew=2, label=text)
    ax.set(title="Phase portrait of the undamped pendulum, w0 = √2 1/s (all from pendula.undamped)",
           xlabel="θ  (rad)", ylabel="Ω  (rad/s)", xlim=(-3 * np.pi, 3 * np.pi))
    ax.set_xticks(np.arange(-3, 4) * np.pi, [f"{i}π" if i not in (0, 1, -1) else
                                             {0: "0", 1: "π", -1: "−π"}[i] for i in range(-3, 4)])
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3, fontsize=8)
    return [_save(fig, out_dir, "figA2_phase_portrait_librations_separatrix_rotations.png")]


def figA3_period_vs_energy(out_dir, quick=False):
    """Period (libration) and revolution time (rotation) against E / E_sep through the separatrix.

    E_sep = 2 m g l is the energy of the separatrix; starting from the bottom
    (θ0 = 0) with Ω0, E/E_sep = m = (Ω0 / 2w0)².  The time diverges
    logarithmically at E = E_sep from both sides (right panel).
    """
    period = _need("period")
    w0 = _w0()
    t0 = 2 * np.pi / w0
    n = _npts(quick, 800) // 2
    d = np.geomspace(1e-12, 1.0, n)
    m_lib = np.concatenate([np.linspace(0.0, 0.9, n // 2, endpoint=False), 1.0 - np.geomspace(0.1, 1e-12, n)])
    m_rot = 1.0 + np.concatenate([np.geomspace(1e-12, 0.1, n, endpoint=False), np.linspace(0.1, 3.0, n // 2)])
    t_lib = np.asarray(period(0.0, 2 * w0 * np.sqrt(m_lib), w0), dtype=float)
    t_rot = np.asarray(period(0.0, 2 * w0 * np.sqrt(m_rot), w0), dtype=float)
    fig, axs = _figure(1, 2, size=(10.0, 4.6))
    ax = axs[0, 0]
    ax.plot(m_lib, t_lib / t0, lw=2, label="libration: period T (pendula.period)")
    ax.plot(m_rot, t_rot / t0, lw=2, label="rotation: time per revolution")
    ax.axvline(1.0, color="C3", ls=":", label="separatrix E = 2mgl")
    ax.set(title="Period / revolution time vs energy", xlabel="E / E_sep = (Ω0 / 2w0)²  (θ0 = 0)",
           ylabel="time / T0  (T0 = 2π/w0 = 4.443 s)", ylim=(0, 4), xlim=(0, 4))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax = axs[0, 1]
    lib_d = 1.0 - m_lib[m_lib > 0.5]
    ax.semilogx(lib_d, t_lib[m_lib > 0.5] / t0, lw=2, label="libration, E < E_sep")
    ax.semilogx(m_rot - 1.0, t_rot / t0, lw=2, label="rotation, E > E_sep")
    ax.semilogx(d, (2 / w0) * np.log(16 / d) / t0, "k--", lw=0.9,
                label="(2/w0) ln(16/|1−E/E_sep|) (libration asymptote)")
    ax.semilogx(d, (1 / w0) * np.log(16 / d) / t0, "k:", lw=0.9,
                label="(1/w0) ln(16/|1−E/E_sep|) (rotation asymptote)")
    ax.set(title="near the separatrix (log scale)", xlabel="|1 − E/E_sep|",
           ylabel="time / T0", xlim=(1e-12, 0.5))
    ax.grid(True, alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.suptitle("Undamped pendulum, w0 = √2 1/s: the period diverges logarithmically at the separatrix")
    return [_save(fig, out_dir, "figA3_period_and_revolution_time_vs_energy_through_separatrix.png")]


def figA5_text_listing_error(out_dir, quick=False):
    """|θ − θ_reference|(t) of the text's printed listing and of pendula.rk4 at the same h = 0.05 s.

    The text's §2.2 scene (m = 0.1 kg, b = 0.01 and 0.05 kg/s, θ0 = 0,
    Ω0 = 2 rad/s, t ≤ 30 s): the printed listing (line-67 typo) is off by
    order 1 rad, the correct RK4 at the same step by ~1e-6 rad.
    """
    fig, axs = _figure(size=(8.0, 4.8))
    ax = axs[0, 0]
    w0 = _w0()
    floor = 1e-16
    for i, b in enumerate((0.01, 0.05)):
        gamma = _pd.damping_rate(b, MASS)
        tl, thl, _ = _text_listing(_TEXT_TEND, _TEXT_H, 0.0, 2.0, w0, gamma)
        keep = tl <= _TEXT_TEND + 1e-9
        tl, thl = tl[keep], thl[keep]
        th_ref, _, lab = _reference(tl, 0.0, 2.0, w0, gamma)
        th_rk4, _ = _pair(_need("rk4")(tl, 0.0, 2.0, w0, gamma, _TEXT_H))
        c = f"C{i}"
        ax.semilogy(tl, np.maximum(np.abs(thl - th_ref), floor), color=c, lw=1.6,
                    label=f"b = {b} kg/s: text's printed listing (typo line 67)")
        ax.semilogy(tl, np.maximum(np.abs(th_rk4 - th_ref), floor), color=c, lw=1.2, ls="--",
                    label=f"b = {b} kg/s: pendula.rk4, same h = 0.05 s")
    ax.set(title="How far the text's §2.2 listing drifts: |θ − θ_ref| (reference: " + lab + ")",
           xlabel="time t  (s)", ylabel="|θ − θ_ref|  (rad)", ylim=(1e-12, 10))
    ax.title.set_fontsize(10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    return [_save(fig, out_dir, "figA5_text_listing_error_vs_time_vs_correct_rk4.png")]


def figA4_work_precision(out_dir, quick=False):
    """Work-precision diagram (error vs wall time, log-log) on the text's §2.2 scene, b = 0.01 kg/s.

    Every applicable model of pendula.tradeoff at several settings, against a
    converged reference (the scenes module chooses and documents it).
    """
    scene_cls = getattr(_pd, "Scene", None)
    tradeoff = getattr(_pd, "tradeoff", None)
    if scene_cls is None or tradeoff is None:
        raise FigureUnavailable("pendula.Scene / pendula.tradeoff (the scenes module) are not available")
    t = np.linspace(0.0, _TEXT_TEND, 61 if quick else 301)
    scene = scene_cls(theta0=0.0, omega0=2.0, t=t, g=G, length=LENGTH, mass=MASS, b=0.01, tol=1e-6)
    table = tradeoff(scene, repeat=1 if quick else 3)
    rows = tradeoff_rows(table)
    note = str(getattr(table, "reference", "") or "")
    note = ("reference: " + note) if note else None
    path = Path(out_dir) / "figA4_work_precision_text_scene_b0.01.png"
    return [work_precision_plot(rows, path, title="Work-precision on the text's §2.2 scene\n(b = 0.01 kg/s, "
                                                  "m = 0.1 kg, θ0 = 0, Ω0 = 2 rad/s, t ≤ 30 s, tol 1e-6 rad)",
                                tol=getattr(scene, "tol", None), note=note)]


# --------------------------------------------------------------------------

FIGURES = [
    ("fig03", fig03_complete_elliptic_K),
    ("fig04", fig04_period_vs_amplitude),
    ("fig05", fig05_theta_small_theta0),
    ("fig06", fig06_theta_medium_theta0),
    ("fig07", fig07_theta_large_theta0),
    ("fig08", fig08_theta_all_theta0),
    ("fig09", fig09_launch_speed_series),
    ("fig10", fig10_overdamped_gamma3),
    ("fig11", fig11_overdamped_gamma5),
    ("fig12", fig12_overdamped_phase_plane),
    ("fig13", fig13_critical_damping),
    ("fig14", fig14_nonlinear_damped),
    ("fig15", fig15_nonlinear_damped_phase_plane),
    ("figA1", figA1_underdamped_linear),
    ("figA2", figA2_phase_portrait),
    ("figA3", figA3_period_vs_energy),
    ("figA4", figA4_work_precision),
    ("figA5", figA5_text_listing_error),
]


def make_figures(out_dir, quick=False, only=None):
    """Draw every figure (or those whose key is in ``only``) into ``out_dir``.

    Returns ``(written, missing)``: the list of paths written and a dict
    {figure key: reason} for figures this build cannot draw (a part of the
    library missing) or that failed (reason starting with "FAILED:"); no
    placeholder is ever written for those.
    """
    keys = {k for k, _ in FIGURES}
    if only is not None:
        bad = sorted(set(only) - keys)
        if bad:
            raise ValueError(f"unknown figure key(s) {bad}; known: {sorted(keys)}")
    written, missing = [], {}
    for key, fn in FIGURES:
        if only is not None and key not in only:
            continue
        try:
            written.extend(fn(out_dir, quick=quick))
        except FigureUnavailable as exc:
            missing[key] = str(exc)
        except Exception as exc:  # one broken figure must not cost the others
            missing[key] = f"FAILED: {type(exc).__name__}: {exc}"
    return written, missing


def figures_main(argv, only, description, quick_help="fewer points per curve (fast)"):
    """The command line of the figure scripts (examples/python/figures_*.py):
    --out DIR and --quick, draw the figures whose keys are in ``only``, report
    each file written and each figure not drawn; SystemExit if one failed."""
    import argparse

    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--out", default=".", help="folder for the PNG files (default: .)")
    ap.add_argument("--quick", action="store_true", help=quick_help)
    args = ap.parse_args(argv)
    written, missing = make_figures(args.out, quick=args.quick, only=only)
    for path in written:
        print(f"wrote {path}")
    for key, why in missing.items():
        print(f"not drawn: {key}: {why}")
    failed = [key for key, why in missing.items() if why.startswith("FAILED")]
    if failed:
        raise SystemExit(f"figure(s) failed: {', '.join(failed)}")


__all__ = ["make_figures", "figures_main", "FIGURES", "FigureUnavailable", "tradeoff_rows", "work_precision_plot"] + [fn.__name__ for _, fn in FIGURES]
