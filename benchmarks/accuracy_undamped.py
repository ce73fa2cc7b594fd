"""Accuracy of the undamped pendulum against mpmath: the tables of docs/guide/undamped.md.

The reference is the tests' table (tests/data/undamped_reference.csv.gz, made by
tools/gen/gen_undamped_reference.py with mpmath at 60 digits from the exact double
inputs, with cond = sum |x d theta/dx| over x in theta0, Omega0, w0, t): per regime the
worst and median |error| / (eps (cond + |value|)) of theta and Omega, through the light
path (one state per call: ``undamped`` at one time) and the planned path (one state at
>= 32 times: Jacobi plan, blocks); then the worst |d theta| in rad per band of |1 - m|
over +-100 periods; then the small-angle error bound (``small_angle_error``) against the
true worst |small_angle - undamped| on seeded random librating states.  Lives in benchmarks/ beside the speed tables (it shares their
command line and --out files, harness.py); it takes a few seconds.

    python benchmarks/accuracy_undamped.py [--out DIR]     (writes DIR/accuracy_undamped.md)
"""

import harness
import numpy as np

import pendula

REF = harness.load_generator("gen_undamped_reference")
EPS = np.finfo(float).eps
REGIMES = {1: "libration", 2: "separatrix", 3: "rotation"}
BANDS = [(0.0, 1e-12), (1e-12, 1e-9), (1e-9, 1e-6), (1e-6, 1e-4), (1e-4, 1.0), (1.0, np.inf)]


def _ratio(got, want, cond):
    return np.abs(got - want) / (EPS * (cond + np.abs(want)) + 1e-300)


def planned(d):
    """Each state's rows through the one-state path, its times tiled to >= 32 points."""
    keys = np.stack([d["theta0"], d["omega0"], d["w0"]], axis=1)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    th, om = np.empty_like(d["t"]), np.empty_like(d["t"])
    for g, i in enumerate(first):
        rows = np.flatnonzero(inverse.reshape(-1) == g)
        tt = np.tile(d["t"][rows], 32 // len(rows) + 1)
        a, b = pendula.undamped(tt, d["theta0"][i], d["omega0"][i], d["w0"][i])
        th[rows], om[rows] = a[: len(rows)], b[: len(rows)]
    return th, om


def tables(d):
    th_l, om_l = pendula.undamped(d["t"], d["theta0"], d["omega0"], d["w0"])
    th_p, om_p = planned(d)
    r = {
        k: _ratio(v, d[k[:-2]], d["cond_" + k[:-2]])
        for k, v in (("theta_l", th_l), ("omega_l", om_l), ("theta_p", th_p), ("omega_p", om_p))
    }
    regime_rows = []
    for code, name in REGIMES.items():
        s = d["regime"] == code
        cell = lambda q: f"{r[q + '_l'][s].max():.2f} / {r[q + '_p'][s].max():.2f}"  # noqa: E731
        med = lambda q: f"{np.median(r[q + '_l'][s]):.2g}"  # noqa: E731
        regime_rows.append([name, int(s.sum()), cell("theta"), med("theta"), cell("omega"), med("omega")])
    gap = np.abs(d["one_minus_m"])
    err = np.abs(np.concatenate([th_l - d["theta"], th_p - d["theta"]]))
    gap2 = np.concatenate([gap, gap])
    band_rows = []
    for lo, hi in BANDS:
        s = (gap2 >= lo) & (gap2 < hi) & (np.concatenate([d["regime"]] * 2) != 2)
        band_rows.append(
            [
                f"< {hi:g}" if not lo else f"≥ {lo:g}" if hi == np.inf else f"{lo:g} – {hi:g}",
                int(s.sum() // 2),
                f"{err[s].max():.1e}",
            ]
        )
    return regime_rows, band_rows


def bound_rows(n_states=150, seed=21, n_t=4001):
    """Random librating states (m from 1e-8 to 0.9, w0 from 0.1 to 10, windows of 0.1 to 300
    small-angle periods): how often the bound holds, and bound / true worst error."""
    rng = np.random.default_rng(seed)
    m = 10.0 ** rng.uniform(-8, -0.05, n_states)
    share = rng.uniform(size=n_states)  # share of the energy in the angle
    sign = rng.choice([-1.0, 1.0], size=(2, n_states))
    w0 = 10.0 ** rng.uniform(-1, 1, n_states)
    theta0 = sign[0] * 2 * np.arcsin(np.sqrt(share * m))
    omega0 = sign[1] * 2 * w0 * np.sqrt((1 - share) * m)
    tmax = 2 * np.pi / w0 * 10.0 ** rng.uniform(-1, 2.5, n_states)
    held, ratio = np.zeros((2, n_states), bool), np.zeros((2, n_states))
    for i in range(n_states):
        t = np.linspace(-tmax[i], tmax[i], n_t)
        exact = pendula.undamped(t, theta0[i], omega0[i], w0[i])
        model = pendula.small_angle(t, theta0[i], omega0[i], w0[i])
        bound = pendula.small_angle_error(tmax[i], theta0[i], omega0[i], w0[i])
        for j in range(2):
            true = np.max(np.abs(model[j] - exact[j]))
            held[j, i], ratio[j, i] = true <= bound[j], bound[j] / true
    return [
        [name, n_states, f"{int(held[j].sum())}/{n_states}", f"{np.median(ratio[j]):.3g}", f"{ratio[j].max():.3g}"]
        for j, name in enumerate(["θ (rad)", "Ω (rad/s)"])
    ]


def main():
    args = harness.parser(
        __doc__, "(no effect: the measurement is quick)", "write accuracy_undamped.md into DIR"
    ).parse_args()
    d = REF.read_table()
    regime_rows, band_rows = tables(d)
    bounds = bound_rows()
    head = [
        "regime",
        "rows",
        "worst θ error (light / planned)",
        "median θ",
        "worst Ω error (light / planned)",
        "median Ω",
    ]
    md = "\n\n".join(
        [
            "Errors in eps·(cond + \\|value\\|):",
            harness.markdown_table(head, regime_rows),
            harness.markdown_table(["\\|1 − m\\|", "rows", "max \\|Δθ\\| (rad), both paths"], band_rows),
            harness.markdown_table(
                ["small-angle bound on", "states", "bound held", "median bound / true", "worst bound / true"], bounds
            ),
        ]
    )
    print(md)
    harness.write_outputs(
        args.out,
        "accuracy_undamped",
        md,
        [
            (["regime", "rows", "theta worst", "theta median", "omega worst", "omega median"], regime_rows),
            (["band", "rows", "max abs dtheta"], band_rows),
            (["quantity", "states", "held", "median ratio", "worst ratio"], bounds),
        ],
    )


if __name__ == "__main__":
    main()
