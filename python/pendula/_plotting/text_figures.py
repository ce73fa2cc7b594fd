"""The text's figures 3-15, redrawn from the library (see :mod:`pendula.figures`)."""

import numpy as np

import pendula as _pd

from ..plots import _figure
from .base import (
    _TEXT_H,
    _TEXT_TEND,
    LENGTH,
    MASS,
    G,
    _exact,
    _linear,
    _need,
    _npts,
    _pi_label,
    _reference,
    _save,
    _small,
    _text_listing,
    _w0,
)

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
    k = np.concatenate([np.linspace(0.0, 0.95, n // 2, endpoint=False), 1.0 - np.geomspace(0.05, 1e-6, n // 2)])
    kc = np.sqrt((1.0 - k) * (1.0 + k))
    big_k = ellipk(k * k)
    fig, axs = _figure()
    ax = axs[0, 0]
    ax.plot(k, big_k, lw=2, label="K(k²), pendula.ellipk (eq. 1.46)")
    sel = k > 0.6
    ax.plot(k[sel], np.log(4.0 / kc[sel]), "--", label="asymptote ln(4/√(1−k²)) as k → 1")
    ax.axhline(np.pi / 2, color="grey", lw=0.8, ls=":", label="K(0) = π/2")
    ax.set(
        title="Fig 3 – Complete elliptic integral of the first kind",
        xlabel="modulus k = sin(θ0/2)  (dimensionless)",
        ylabel="K(k²)  (dimensionless)",
        xlim=(0, 1),
        ylim=(0, 1.05 * big_k.max()),
    )
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
    k = np.concatenate([np.linspace(0.0, 0.95, n // 2, endpoint=False), 1.0 - np.geomspace(0.05, 1e-4, n // 2)])
    theta0 = 2.0 * np.arcsin(k)
    t_exact = np.asarray(period(theta0, 0.0, w0), dtype=float)
    t0 = float(_pd.small_angle_period(w0))
    fig, axs = _figure()
    ax = axs[0, 0]
    ax.plot(k, t_exact, lw=2, label="exact T = 4K(k²)/w0, pendula.period (eq. 1.53)")
    ax.plot(k, np.full_like(k, t0), lw=2, label="small-angle T0 = 2π/w0 (eq. 1.8)")
    ax.plot(k, _pd.period_series(k**2, w0), "--", label="series T0 (1 + k²/4 + 9k⁴/64)")
    ax.set(
        title=f"Fig 4 – Period of the simple pendulum (g = {G} m/s², l = {LENGTH} m)",
        xlabel="sin(θ0/2)  (dimensionless)",
        ylabel="period  (s)",
        xlim=(0, 1),
        ylim=(0, min(4 * t0, 1.05 * t_exact.max())),
    )
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
        ax.set(
            title=f"({tag}) θ0 = {_pi_label(frac)} rad;  max |exact − small angle| = "
            f"{np.max(np.abs(th - ths)):.2g} rad",
            ylabel="θ(t)  (rad)",
        )
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
    ax.set(
        title="Fig 8 – θ(t), exact (solid) vs small angle (dashed), Ω0 = 0, w0 = √2 1/s",
        xlabel="time t  (s)",
        ylabel="θ(t)  (rad)",
    )
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
    ax.set(
        title="Fig 9 – θ(t) launched from θ0 = 0 with speed v0 (l = 4.9 m, w0 = √2 1/s)",
        xlabel="time t  (s)",
        ylabel="θ(t)  (rad)",
    )
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
    return _theta_omega_panels(
        out_dir,
        "fig10_overdamped_gamma_3w0_theta_omega.png",
        "Fig 10 – Overdamped, linear (pendula.linear_damped)",
        3.0,
        quick,
    )


def fig11_overdamped_gamma5(out_dir, quick=False):
    """Fig 11: overdamped θ(t) and Ω(t), γ = 5 w0, θ0 = 0.1, Ω0 ∈ {0, 0.5, -0.5} (eq. 2.27)."""
    return _theta_omega_panels(
        out_dir,
        "fig11_overdamped_gamma_5w0_theta_omega.png",
        "Fig 11 – Overdamped, linear (pendula.linear_damped)",
        5.0,
        quick,
    )


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
    return _theta_omega_panels(
        out_dir,
        "fig13_critical_damping_gamma_2w0_theta_omega.png",
        "Fig 13 – Critical damping, linear (pendula.linear_damped)",
        2.0,
        quick,
    )


# --------------------------------------------------------------------------
# §2.2: nonlinear damped, correct integrator vs the text's printed listing
# --------------------------------------------------------------------------


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
        axs[0, 0].plot(
            tl,
            thl,
            color=c,
            lw=1.2,
            ls="--",
            label=f"b = {b} kg/s: text's printed listing (max |Δθ| = {drift:.2f} rad)",
        )
        axs[1, 0].plot(t, om, color=c, lw=2, label=f"b = {b} kg/s: {lab}")
        axs[1, 0].plot(tl, oml, color=c, lw=1.2, ls="--", label=f"b = {b} kg/s: text's printed listing")
    axs[0, 0].set(ylabel="θ(t)  (rad)", title="θ(t)")
    axs[1, 0].set(ylabel="Ω(t)  (rad/s)", xlabel="time t  (s)", title="Ω(t)")
    for ax in axs[:, 0]:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7.5)
    fig.suptitle(
        "Fig 14 – Nonlinear damped pendulum (eq. 2.2), g = 9.8 m/s², l = 4.9 m, m = 0.1 kg,"
        "\nθ0 = 0, Ω0 = 2 rad/s: correct solution (solid) vs the text's listing as printed (dashed)",
        fontsize=10,
    )
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
    fig.suptitle("Fig 15 – Nonlinear damped pendulum, b = 0.05 kg/s (γ = 0.5 1/s), θ0 = 0, Ω0 = 2 rad/s", fontsize=10)
    return [_save(fig, out_dir, "fig15_nonlinear_damped_b0.05_theta_and_phase_plane_vs_text_listing.png")]
