"""Accuracy of pendula.rk4 and pendula.cvode: the table of docs/guide/integrators.md.

Each row measures, with the tests' own references and scenarios (tests/python/
test_integrators.py, loaded from its file): the mpmath Taylor-series table at 30 digits
(tests/data/integrators_reference.csv, from tools/gen/gen_integrators_reference.py), SciPy
DOP853 at rtol 1e-13 on the text's 601-point grid, the exact undamped solution
(pendula.undamped), the linear closed form (pendula.linear_damped), the slow-manifold
solution of stiff damping, the exact period 4K(k^2)/w0 and the damped half-swing ratio, and
the RK4 stability limits.  Errors are max |difference| over the outputs, in rad (or s, or
relative where the row says so).  Lives in benchmarks/ beside the speed tables (it shares
their command line and --out files, harness.py); it takes a few seconds.

    python benchmarks/accuracy_integrators.py [--out DIR]   (writes DIR/accuracy_integrators.md)
"""

import math
import sys

import harness
import mpmath as mp
import numpy as np

import pendula
from pendula.textbook import text_listing_rk4

# test_integrators imports the tests' helpers module by name: give it the file's module
sys.modules.setdefault("helpers", harness.load_test_module("helpers"))
T = harness.load_test_module("test_integrators")
W0, GAMMAS, T_TEXT, TABLE = T.W0, T.GAMMAS, T.T_TEXT, T.TABLE
HAVE_CVODE = pendula.build_info()["cvode"]
NO_CVODE = "— (no CVODE in this build)"


def _e(x, digits=1):
    """x in e-notation with `digits` decimals, exponent without + and leading zeros."""
    return f"{x:.{digits}e}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def _sup(a, b):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))


def _both(fn):
    """fn(b) for the text's two dampings, as 'x / y'."""
    return " / ".join(_e(fn(b)) for b in GAMMAS)


def _table_index(b):
    return np.rint(TABLE[b][:, 0] / 0.05).astype(int)


def rk4_rows(dop):
    want = TABLE[0.01][10]
    hs = [0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001]
    err = []
    for h in hs:
        r = pendula.rk4([0.0, 10.0], 0.0, 2.0, W0, GAMMAS[0.01], h)
        err.append(max(abs(r.theta[1] - want[1]), abs(r.omega[1] - want[2])))
    slope = np.polyfit(np.log(hs), np.log(err), 1)[0]
    dop_vs_table = max(_sup(dop[b][0][_table_index(b)], TABLE[b][:, 1]) for b in GAMMAS)
    text = {b: pendula.rk4(T_TEXT, 0.0, 2.0, W0, GAMMAS[b], 0.05) for b in GAMMAS}
    _, th_fixed, om_fixed = text_listing_rk4(30.0, 0.05, 0.0, 2.0, W0, GAMMAS[0.01], typo=False)
    _, th_typo, _ = text_listing_rk4(30.0, 0.05, 0.0, 2.0, W0, GAMMAS[0.01], typo=True)
    r = text[0.01]
    return [
        ["SciPy DOP853 rtol 1e-13 vs mpmath at t = 0, 1, …, 30 s, b = 0.01 and 0.05", f"{_e(dop_vs_table)} rad"],
        [
            f"RK4 error at t = 10 s vs mpmath, h = {', '.join(map(str, hs))} s",
            f"{', '.join(_e(x) for x in err)} → slope **{slope:.3f}**",
        ],
        [
            "text scenario, RK4 h = 0.05 s, sup over the 601 outputs vs DOP853, b = 0.01 / 0.05",
            f"θ: {_both(lambda b: _sup(text[b].theta, dop[b][0]))} rad; "
            f"Ω: {_both(lambda b: _sup(text[b].omega, dop[b][1]))} rad/s",
        ],
        [
            "the text's listing (section 2.2), b = 0.01: line 67 fixed vs `pendula.rk4` / as printed vs DOP853",
            f"{_e(max(_sup(th_fixed, r.theta), _sup(om_fixed, r.omega)))} / {_sup(th_typo, dop[0.01][0]):.2f} rad",
        ],
    ]


def cvode_rows(dop):
    if not HAVE_CVODE:
        return [["CVODE rows", NO_CVODE]]
    rows = []
    c = {b: pendula.cvode(T_TEXT, 0.0, 2.0, W0, GAMMAS[b], rtol=1e-10, atol=1e-12) for b in GAMMAS}
    fine = {b: pendula.rk4(T_TEXT, 0.0, 2.0, W0, GAMMAS[b], 1e-3) for b in GAMMAS}
    rows.append(
        [
            "CVODE rtol 1e-10 vs RK4 h = 1e-3 s on the text scenario, b = 0.01 / 0.05",
            f"{_both(lambda b: _sup(c[b].theta, fine[b].theta))} rad "
            f"(RK4 h = 1e-3 vs DOP853: {_both(lambda b: _sup(fine[b].theta, dop[b][0]))} rad)",
        ]
    )
    cells = []
    for method in ("adams", "bdf"):
        worst = 0.0
        for b in GAMMAS:
            ref = TABLE[b][[0, 10, 20, 30]]
            m = pendula.cvode(ref[:, 0], 0.0, 2.0, W0, GAMMAS[b], rtol=1e-10, atol=1e-12, method=method)
            worst = max(worst, _sup(m.theta[1:], ref[1:, 1]), _sup(m.omega[1:], ref[1:, 2]))
        cells.append(f"{_e(worst)} ({method.capitalize() if method == 'adams' else 'BDF'})")
    rows.append(["CVODE rtol 1e-10 vs mpmath at t = 10, 20, 30 s, both b, θ and Ω", ", ".join(cells)])
    return rows


def exact_rows():
    t = np.linspace(0.0, 30.0, 301)
    rk, cv = 0.0, 0.0
    for theta0, omega0 in [(0.5, 0.0), (2.5, 0.3), (0.0, 2.0), (0.1, 3.0)]:
        th_ex, om_ex = pendula.undamped(t, theta0, omega0, W0)
        rk = max(rk, _sup(pendula.rk4(t, theta0, omega0, W0, 0.0, 0.01).theta, th_ex))
        if HAVE_CVODE:
            c = pendula.cvode(t, theta0, omega0, W0, 0.0, rtol=1e-11, atol=1e-13)
            scale = max(1.0, float(np.max(np.abs(th_ex))))
            cv = max(cv, _sup(c.theta, th_ex) / scale, _sup(c.omega, om_ex) / scale)
    rows = [
        [
            "γ = 0 vs `pendula.undamped` (libration, near separatrix, rotation), t ≤ 30 s",
            f"RK4 h = 0.01: {_e(rk)} rad; CVODE rtol 1e-11: "
            + (f"{_e(cv)} × max(1, max\\|θ\\|)" if HAVE_CVODE else NO_CVODE),
        ]
    ]
    t = np.linspace(0.0, 20.0, 201)
    rk, cv = 0.0, 0.0
    for ratio in (0.1, 1.0, 2.0, 5.0):
        th_lin, _ = pendula.linear_damped(t, 1e-4, 2e-4, W0, ratio * W0)
        rk = max(rk, _sup(pendula.rk4(t, 1e-4, 2e-4, W0, ratio * W0, 0.01).theta, th_lin) / 1e-4)
        if HAVE_CVODE:
            c = pendula.cvode(t, 1e-4, 2e-4, W0, ratio * W0, rtol=1e-11, atol=1e-17)
            cv = max(cv, _sup(c.theta, th_lin) / 1e-4)
    rows.append(
        [
            "θ0 = 1e-4 vs `pendula.linear_damped`, γ/w0 = 0.1, 1, 2, 5, t ≤ 20 s",
            f"RK4 h = 0.01: {_e(rk)} θ0; CVODE rtol 1e-11: " + (f"{_e(cv)} θ0" if HAVE_CVODE else NO_CVODE),
        ]
    )
    return rows


def stiff_and_event_rows():
    gamma = 1e4 * W0
    hmax = pendula.rk4_max_stable_step(W0, gamma)
    if not HAVE_CVODE:
        return [["γ = 1e4 w0 (stiff): RK4's largest stable step", f"{hmax:.3e} s"]]
    t = np.array([0.0, 100.0, 1000.0, 5000.0, 20000.0])
    c = pendula.cvode(t, 0.5, 0.0, W0, gamma, rtol=1e-9, atol=1e-12, method="bdf")
    slow = 2 * np.arctan(math.tan(0.25) * np.exp(-(W0**2) * t / gamma))
    rows = [
        [
            "γ = 1e4 w0 (stiff), BDF rtol 1e-9 vs tan(θ/2) = tan(θ0/2) e^{−w0² t/γ}, t ≤ 2e4 s",
            f"{_e(float(np.max(np.abs(c.theta[1:] / slow[1:] - 1))))} relative, "
            f"{c.stats['steps']} steps (RK4's largest stable step: {hmax:.3e} s)",
        ]
    ]
    theta0 = 2.0
    period = float(4 * mp.ellipk(math.sin(theta0 / 2) ** 2) / W0)
    c = pendula.cvode([0.0, 5.3 * period], theta0, 0.0, W0, 0.0, rtol=1e-11, atol=1e-13, events=True)
    tz, _ = c.events.zero_crossings
    tt, th = c.events.turning_points
    dt = max(_sup(tz, period / 4 + period / 2 * np.arange(len(tz))), _sup(tt, period / 2 * np.arange(1, len(tt) + 1)))
    rows.append(
        [
            f"events, γ = 0, θ0 = 2, rtol 1e-11: {len(tz)} zero crossings and {len(tt)} turning "
            "points vs T = 4K(sin²(θ0/2))/w0",
            f"times {_e(dt)} s; amplitudes {_e(_sup(np.abs(th), theta0))} rad",
        ]
    )
    gamma = 0.1
    wd = math.sqrt(W0**2 - gamma**2 / 4)
    c = pendula.cvode([0.0, 60.0], 1e-3, 0.0, W0, gamma, rtol=1e-11, atol=1e-16, events=True)
    _, th = c.events.turning_points
    tz, _ = c.events.zero_crossings
    ratio = float(np.max(np.abs(np.abs(th[1:] / th[:-1]) / math.exp(-gamma * math.pi / (2 * wd)) - 1)))
    spacing = float(np.max(np.abs(np.diff(tz) / (math.pi / wd) - 1)))
    rows.append(
        [
            "events, θ0 = 1e-3, γ = 0.1: half-swing ratio vs e^{−γπ/(2ω_d)}, spacing vs π/ω_d",
            f"{_e(ratio)} / {_e(spacing)} relative",
        ]
    )
    return rows


def stability_rows():
    gamma = 1e4 * W0
    lam = -gamma / 2 - math.sqrt(gamma**2 / 4 - W0**2)
    root = float(mp.findroot(lambda x: x**3 + 4 * x**2 + 12 * x + 24, -2.78))  # R(x) = 1, x < 0
    real = pendula.rk4_max_stable_step(W0, gamma) * lam
    imag = pendula.rk4_max_stable_step(W0, 0.0) * W0
    worst = 0.0
    for g in (0.3 * W0, 1.9 * W0):
        z = pendula.rk4_max_stable_step(W0, g) * complex(-g / 2, math.sqrt(W0**2 - g**2 / 4))
        worst = max(worst, abs(abs(1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) - 1))
    return [
        [
            "RK4 stability limit h λ: real axis (γ = 1e4 w0) vs the root of x³+4x²+12x+24",
            f"{-real:.12f} (relative {_e(abs(real / root - 1))})",
        ],
        [
            "… imaginary axis (γ = 0) vs 2√2; complex λ (γ/w0 = 0.3, 1.9): \\|R(h λ)\\| − 1 at h_max",
            f"relative {_e(abs(imag / (2 * math.sqrt(2)) - 1))}; {_e(worst)}",
        ],
    ]


def main():
    args = harness.parser(
        __doc__, "(no effect: the measurement takes seconds)", "write accuracy_integrators.md into DIR"
    ).parse_args()
    dop = {b: T.dop853(T_TEXT, 0.0, 2.0, W0, GAMMAS[b]) for b in GAMMAS}
    rows = rk4_rows(dop) + cvode_rows(dop) + exact_rows() + stiff_and_event_rows() + stability_rows()
    md = harness.markdown_table(["check", "measured"], rows, align="ll")
    print(md)
    harness.write_outputs(args.out, "accuracy_integrators", md, [(["check", "measured"], rows)])


if __name__ == "__main__":
    main()
