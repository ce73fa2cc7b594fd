"""Accuracy of the elliptic functions against mpmath: the table of docs/guide/elliptic.md.

The references are the tests' (tests/data/elliptic_refs.npz, made by
tools/gen/gen_elliptic_refs.py with mpmath at 60 digits, 340 for the complement forms,
at the exact double inputs, with each problem's condition number).  Per region: the
worst relative error / (eps * cond) of sn, cn, dn, am through ``ellipj``/``ellipjm1``
and through the plan (scalar parameter) path; then K, E (ulps) and F (ulps * cond); the
plain error at |u| from 1e2 to 1e6 (where u * eps would be up to 1e6 eps); and the identities
sn^2 + cn^2 = 1, dn^2 + m sn^2 = 1 on seeded random u in every region, both paths.
Lives in benchmarks/ beside the speed tables because it shares their command line and
--out files (harness.py); it takes a few seconds.

    python benchmarks/accuracy_elliptic.py [--out DIR]     (writes DIR/accuracy_elliptic.md)
"""

import harness
import numpy as np

import pendula

T = harness.load_test_module("test_elliptic")

REGIONS = [  # (label, region in the data, selection on the parameter p passed)
    ("m < 0 (down to −1e10)", "mneg", None),
    ("0 ≤ m < 1 generic, \\|u\\| ≤ 12", "generic", None),
    ("1 − m in (1e-10, 1e-3] (complement)", "near1", lambda p: p > 1e-10),
    ("1 − m ≤ 1e-10, down to 5e-324 (complement)", "near1", lambda p: p <= 1e-10),
    ("m = 1 − 10^−(3…15) passed as m", "near1m", None),
    ("m > 1 (up to 1e6)", "mgt1", None),
    ("\\|u\\| from 1e2 to 1e6 (m < 0, 0 ≤ m < 1, m > 1, 1 − m ≥ 1e-12)", "largeu", None),
    ("m = 0, m = 1 exactly", "m0|m1", None),
]


def _worst(rows, path):
    u, p, comp, ref, cond, _ = T._jac_table()
    worst = 0.0
    for i in rows:
        if path == "elementwise":
            got = (pendula.ellipjm1 if comp[i] else pendula.ellipj)(u[i], p[i])
        else:
            fn = T._plan_into(comp[i])
            got = [g[0] for g in T._into(fn, np.array([u[i]]), p[i])]
        worst = max(worst, float((T._rel(got, ref[i]) / cond[i]).max()))
    return worst


def jacobi_rows():
    u, p, comp, ref, cond, region = T._jac_table()
    rows = []
    for label, reg, select in REGIONS:
        sel = np.isin(region, reg.split("|"))
        if select is not None:
            sel &= select(p)
        idx = np.flatnonzero(sel)
        rows.append([label, len(idx), f"{_worst(idx, 'elementwise'):.2f}", f"{_worst(idx, 'plan'):.2f}"])
    return rows


def integral_rows():
    ke = T.DATA["ke"]
    k_err = [T._rel((pendula.ellipkm1 if c else pendula.ellipk)(p), kr) for p, c, kr, _ in ke]
    e_err = [T._rel((pendula.ellipem1 if c else pendula.ellipe)(p), er) for p, c, _, er in ke]
    f_err = [
        T._rel((pendula.ellipfm1 if c else pendula.ellipf)(phi, p), fr) / cond for phi, p, c, fr, cond in T.DATA["f"]
    ]
    fmt = lambda e: (f"{float(np.max(e)):.2f}", f"{float(np.median(e)):.2f}")  # noqa: E731
    return [
        ["K (`ellipk`, `ellipkm1`), ulps", len(ke), *fmt(k_err)],
        ["E (`ellipe`, `ellipem1`), ulps", len(ke), *fmt(e_err)],
        ["F (`ellipf`, `ellipfm1`), ulps / cond", len(f_err), *fmt(f_err)],
    ]


def large_u_rows():
    """Plain error (absolute for sn, cn, dn; relative for am) in eps over the large-u points."""
    u, p, comp, ref, cond, region = T._jac_table()
    idx = np.flatnonzero((region == "largeu") & ~comp)
    err = np.array([np.abs(np.asarray(pendula.ellipj(u[i], p[i])) - ref[i]) for i in idx]) / T.EPS
    err[:, 3] /= np.abs(ref[idx, 3])
    umax = float(np.abs(u[idx]).max())
    return [
        [name, len(idx), f"{umax:.0e}", f"{float(err[:, j].max()):.2f}"]
        for j, name in enumerate(["sn (absolute)", "cn (absolute)", "dn (absolute)", "am (relative)"])
    ]


IDENTITY_M = [-1e10, -3.0, -0.1, 0.0, 0.3, 0.9, 0.999999, 1.0, 1.5, 1e4]
IDENTITY_P = [1e-3, 1e-10, 1e-100, 1e-300, 5e-324]  # complements, through ellipjm1


def identity_rows(n=20000, seed=7):
    """Worst |sn^2 + cn^2 - 1| / eps and |dn^2 + m sn^2 - 1| / (eps max(1, |m|)) on n random u
    in [-50, 50] per parameter: a scalar parameter (the plan path) and an array one (elementwise)."""
    u = np.random.default_rng(seed).uniform(-50, 50, n)
    worst = {"plan": [0.0, 0.0], "elementwise": [0.0, 0.0]}
    cases = [(pendula.ellipj, m, m, max(1.0, abs(m))) for m in IDENTITY_M] + [
        (pendula.ellipjm1, p, 1.0 - p, 1.0) for p in IDENTITY_P
    ]
    for fn, par, m, scale in cases:
        for path, arg in (("plan", par), ("elementwise", np.full(n, par))):
            sn, cn, dn, _ = fn(u, arg)
            # for a complement, dn^2 - p sn^2 - cn^2 = dn^2 + m sn^2 - 1 without forming 1 - p
            second = dn**2 - par * sn**2 - cn**2 if fn is pendula.ellipjm1 else dn**2 + m * sn**2 - 1
            worst[path][0] = max(worst[path][0], float(np.abs(sn**2 + cn**2 - 1).max() / T.EPS))
            worst[path][1] = max(worst[path][1], float(np.abs(second).max() / (T.EPS * scale)))
    points = n * len(cases)
    return [
        ["sn² + cn² − 1, eps", points, f"{worst['elementwise'][0]:.2f}", f"{worst['plan'][0]:.2f}"],
        ["dn² + m sn² − 1, eps·max(1, \\|m\\|)", points, f"{worst['elementwise'][1]:.2f}", f"{worst['plan'][1]:.2f}"],
    ]


def main():
    args = harness.parser(
        __doc__, "(no effect: the measurement is quick)", "write accuracy_elliptic.md into DIR"
    ).parse_args()
    jac = jacobi_rows()
    ints = integral_rows()
    big = large_u_rows()
    ids = identity_rows()
    md = "\n\n".join(
        [
            harness.markdown_table(["region", "points", "`ellipj`", "plan (scalar m)"], jac),
            harness.markdown_table(["integral", "points", "worst", "median"], ints),
            harness.markdown_table(
                ["\\|u\\| from 1e2 to 1e6: plain error", "points", "\\|u\\| up to", "worst, eps"], big
            ),
            harness.markdown_table(
                ["identity, random u in [−50, 50], every region", "points", "`ellipj` (array m)", "plan (scalar m)"],
                ids,
            ),
        ]
    )
    print(md)
    harness.write_outputs(
        args.out,
        "accuracy_elliptic",
        md,
        [
            (["region", "points", "ellipj", "plan"], jac),
            (["integral", "points", "worst", "median"], ints),
            (["function", "points", "u_max", "worst_eps"], big),
            (["identity", "points", "ellipj", "plan"], ids),
        ],
    )


if __name__ == "__main__":
    main()
