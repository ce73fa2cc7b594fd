"""The figures the text lacks: A1-A5 (see :mod:`pendula.figures`)."""

from pathlib import Path

import numpy as np

import pendula as _pd

from ..plots import _figure, tradeoff_rows, work_precision_plot
from .base import (
    _TEXT_H,
    _TEXT_TEND,
    LENGTH,
    MASS,
    FigureUnavailable,
    G,
    _exact,
    _linear,
    _need,
    _npts,
    _pair,
    _reference,
    _save,
    _text_listing,
    _w0,
)


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
        ax.plot(
            t,
            th,
            color=c,
            lw=1.8,
            label=f"γ = {r:g} w0 (Q = {info.quality_factor:.3g}, "
            f"ω_d = {info.omega_d:.3f} 1/s, log decrement {info.log_decrement:.3g})",
        )
        env = _need("linear_damped_envelope")(t, theta0, omega0, w0, gamma)
        ax.plot(t, env, color=c, lw=0.9, ls=":")
        ax.plot(t, -env, color=c, lw=0.9, ls=":")
    ax.plot([], [], color="grey", ls=":", label="envelope ±R e^(−γt/2), pendula.linear_damped_envelope")
    ax.set(
        title="Underdamped linear pendulum (§2.1.3, empty in the text), θ0 = 0.1 rad, Ω0 = 0",
        xlabel="time t  (s)",
        ylabel="θ(t)  (rad)",
    )
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
    for kind, marker, text in (
        ("centre", "o", "centres (2nπ, 0): eigenvalues ±i w0, stable"),
        ("saddle", "x", "saddles ((2n+1)π, 0): eigenvalues ±w0, unstable"),
    ):
        sel = eq_kind == kind
        ax.plot(eq_theta[sel], 0 * eq_theta[sel], marker, color="k", ms=5 if marker == "o" else 8, mew=2, label=text)
    ax.set(
        title="Phase portrait of the undamped pendulum, w0 = √2 1/s (all from pendula.undamped)",
        xlabel="θ  (rad)",
        ylabel="Ω  (rad/s)",
        xlim=(-3 * np.pi, 3 * np.pi),
    )
    ax.set_xticks(
        np.arange(-3, 4) * np.pi,
        [f"{i}π" if i not in (0, 1, -1) else {0: "0", 1: "π", -1: "−π"}[i] for i in range(-3, 4)],
    )
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
    ax.set(
        title="Period / revolution time vs energy",
        xlabel="E / E_sep = (Ω0 / 2w0)²  (θ0 = 0)",
        ylabel="time / T0  (T0 = 2π/w0 = 4.443 s)",
        ylim=(0, 4),
        xlim=(0, 4),
    )
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax = axs[0, 1]
    lib_d = 1.0 - m_lib[m_lib > 0.5]
    ax.semilogx(lib_d, t_lib[m_lib > 0.5] / t0, lw=2, label="libration, E < E_sep")
    ax.semilogx(m_rot - 1.0, t_rot / t0, lw=2, label="rotation, E > E_sep")
    ax.semilogx(
        d, (2 / w0) * np.log(16 / d) / t0, "k--", lw=0.9, label="(2/w0) ln(16/|1−E/E_sep|) (libration asymptote)"
    )
    ax.semilogx(d, (1 / w0) * np.log(16 / d) / t0, "k:", lw=0.9, label="(1/w0) ln(16/|1−E/E_sep|) (rotation asymptote)")
    ax.set(title="near the separatrix (log scale)", xlabel="|1 − E/E_sep|", ylabel="time / T0", xlim=(1e-12, 0.5))
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
        ax.semilogy(
            tl,
            np.maximum(np.abs(thl - th_ref), floor),
            color=c,
            lw=1.6,
            label=f"b = {b} kg/s: text's printed listing (typo line 67)",
        )
        ax.semilogy(
            tl,
            np.maximum(np.abs(th_rk4 - th_ref), floor),
            color=c,
            lw=1.2,
            ls="--",
            label=f"b = {b} kg/s: pendula.rk4, same h = 0.05 s",
        )
    ax.set(
        title="How far the text's §2.2 listing drifts: |θ − θ_ref| (reference: " + lab + ")",
        xlabel="time t  (s)",
        ylabel="|θ − θ_ref|  (rad)",
        ylim=(1e-12, 10),
    )
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
    return [
        work_precision_plot(
            rows,
            path,
            title="Work-precision on the text's §2.2 scene\n(b = 0.01 kg/s, "
            "m = 0.1 kg, θ0 = 0, Ω0 = 2 rad/s, t ≤ 30 s, tol 1e-6 rad)",
            tol=getattr(scene, "tol", None),
            note=note,
        )
    ]
