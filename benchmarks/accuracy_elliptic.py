"""Accuracy of the elliptic functions against mpmath: the table of docs/guide/elliptic.md.

The references are the tests' (tests/data/elliptic_refs.npz, made by
tools/gen/gen_elliptic_refs.py with mpmath at 60 digits, 340 for the complement forms,
at the exact double inputs, with each problem's condition number).  Per region: the
worst relative error / (eps * cond) of sn, cn, dn, am through ``ellipj``/``ellipjm1``
and through the plan (scalar parameter) path; then K, E (ulps) and F (ulps * cond).
Lives in benchmarks/ beside the speed tables because it shares their command line and
--out files (harness.py); it takes a few seconds.

    python benchmarks/accuracy_elliptic.py [--out DIR]     (writes DIR/accuracy_elliptic.md)
"""
import numpy as np

import harness
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
    f_err = [T._rel((pendula.ellipfm1 if c else pendula.ellipf)(phi, p), fr) / cond
             for phi, p, c, fr, cond in T.DATA["f"]]
    fmt = lambda e: (f"{float(np.max(e)):.2f}", f"{float(np.median(e)):.2f}")  # noqa: E731
    return [["K (`ellipk`, `ellipkm1`), ulps", len(ke), *fmt(k_err)],
            ["E (`ellipe`, `ellipem1`), ulps", len(ke), *fmt(e_err)],
            ["F (`ellipf`, `ellipfm1`), ulps / cond", len(f_err), *fmt(f_err)]]


def main():
    args = harness.parser(__doc__, "(no effect: the measurement is quick)", "write accuracy_elliptic.md into DIR").parse_args()
    jac = jacobi_rows()
    ints = integral_rows()
    md = "\n\n".join([
        harness.markdown_table(["region", "points", "`ellipj`", "plan (scalar m)"], jac),
        harness.markdown_table(["integral", "points", "worst", "median"], ints)])
    print(md)
    harness.write_outputs(args.out, "accuracy_elliptic", md,
                          [(["region", "points", "ellipj", "plan"], jac),
                           (["integral", "points", "worst", "median"], ints)])


if __name__ == "__main__":
    main()
