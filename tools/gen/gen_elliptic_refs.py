"""Generate tests/data/elliptic_refs.npz: mpmath references for pendula's elliptic functions.

Every reference is computed at the EXACT double inputs (mpmath.mpf(float)) with
mp.dps = 50, together with the condition number of the problem,
    cond = max(1, (|x df/dx| + |p df/dp|) / |f|),
where p is the parameter the caller passes (m, or mc = 1 - m for the complement
forms).  Tests report relative error / (eps * cond).

Run (about a minute on 2 cores):  python3 tools/gen/gen_elliptic_refs.py
"""

import os
import sys
from multiprocessing import Pool

import mpmath as mp
import numpy as np

DPS = 60
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "..", "tests", "data", "elliptic_refs.npz")


def _jac(u, m, mc):
    """sn, cn, dn, am at parameter m = 1 - mc (mpf, both exact), u (mpf); real parts.

    For 1/2 < m < 1 mpmath's theta series (nome near 1) fail, so use Jacobi's
    imaginary transformation (DLMF 22.6.1 with 22.6.12 on i u): sn(u|m) =
    i sc(-i u|mc), cn(u|m) = nc(-i u|mc), dn(u|m) = dc(-i u|mc), after reducing u
    modulo 2K(m) (sn, cn change sign, dn does not).
    """
    if 0.5 < m < 1:
        k = mp.ellipk(m)
        n = mp.nint(u / (2 * k))
        r = u - 2 * n * k
        z = -1j * r
        s1 = mp.ellipfun("sn", z, m=mc)
        c1 = mp.ellipfun("cn", z, m=mc)
        d1 = mp.ellipfun("dn", z, m=mc)
        sg = -1 if int(n) % 2 else 1
        sn0 = mp.re(1j * s1 / c1)
        cn0 = mp.re(1 / c1)
        dn = mp.re(d1 / c1)
        am = n * mp.pi + mp.atan2(sn0, cn0)
        return sg * sn0, sg * cn0, dn, am
    sn = mp.re(mp.ellipfun("sn", u, m=m))
    cn = mp.re(mp.ellipfun("cn", u, m=m))
    dn = mp.re(mp.ellipfun("dn", u, m=m))
    if m >= 1:
        am = mp.atan2(sn, cn)
    else:
        k = mp.ellipk(m)
        n = mp.nint(u / (2 * k))
        sg = -1 if int(n) % 2 else 1
        am = n * mp.pi + mp.atan2(sg * sn, sg * cn)
    return sn, cn, dn, am


def jac_row(args):
    """args = (u, p, complement).  Returns [u, p, comp, sn, cn, dn, am, cond x4]."""
    u, p, comp = args
    # 1 - mc must be exact in mpmath: 1100 bits cover the smallest subnormal mc
    dps = 340 if comp else DPS
    with mp.workdps(dps):
        U = mp.mpf(u)
        P = mp.mpf(p)
        M, MC = (1 - P, P) if comp else (P, 1 - P)
        vals = _jac(U, M, MC)
        sn, cn, dn, am = vals
        du = [cn * dn, -sn * dn, -M * sn * cn, dn]
        # derivative in the parameter p by a central difference at high precision
        h = abs(P) * mp.mpf(10) ** (-25) if P != 0 else mp.mpf(10) ** (-30)
        sgn = -1 if comp else 1
        lo = _jac(U, M - sgn * h, MC + sgn * h)
        hi = _jac(U, M + sgn * h, MC - sgn * h)
        conds = []
        for f, fu, fl, fh in zip(vals, du, lo, hi):
            fp = (fh - fl) / (2 * h)
            if f == 0:
                conds.append(mp.inf)
            else:
                conds.append(max(1, (abs(U * fu) + abs(P * fp)) / abs(f)))
        return [u, p, float(comp)] + [float(v) for v in vals] + [float(c) for c in conds]


def _kc(mc):
    with mp.workdps(340):
        return float(mp.ellipk(1 - mp.mpf(mc)))


def jacobi_inputs(rng):
    rows = []
    # generic 0 < m < 1, moderate u
    for _ in range(160):
        rows.append((float(rng.uniform(-12, 12)), float(rng.uniform(0, 1)), False, "generic"))
    # m < 0 down to -1e10
    for _ in range(100):
        m = -(10 ** rng.uniform(-3, 10))
        rows.append((float(rng.uniform(-6, 6) / np.sqrt(1 - m) * rng.choice([1, 4])), float(m), False, "mneg"))
    # 1 - m from 1e-3 to 1e-300 (complement), u up to 4K
    for _ in range(160):
        mc = 10 ** rng.uniform(-300, -3)
        k = _kc(mc)
        rows.append((float(rng.uniform(-4.2, 4.2) * k), float(mc), True, "near1"))
    for mc in [5e-324, 1e-310, 2.2250738585072014e-308, 1e-200, 1e-100, 1e-20, 1e-10]:
        k = _kc(mc)
        for f in [0.3, 0.5, 0.99, 1.0, 1.01, 1.5, 2.0, 3.1]:
            rows.append((k * f, mc, True, "near1"))
    # m > 1
    for _ in range(100):
        m = 1 + 10 ** rng.uniform(-6, 6)
        rows.append((float(rng.uniform(-5, 5) / np.sqrt(m)), float(m), False, "mgt1"))
    # large u
    for _ in range(60):
        rows.append((float(rng.choice([-1, 1]) * 10 ** rng.uniform(2, 6)), float(rng.uniform(0, 1)), False, "largeu"))
    for _ in range(30):
        rows.append((float(10 ** rng.uniform(2, 6)), float(10 ** rng.uniform(-12, -3)), True, "largeu"))
    # exact m = 0, m = 1
    for u in [0.0, 1e-300, 0.5, 1.0, 3.0, 30.0, 400.0, 1e5]:
        rows.append((u, 0.0, False, "m0"))
        rows.append((u, 1.0, False, "m1"))
    # 1 - m from 1e-3 to 1e-10 (complement form) and m near 1 passed as m itself
    for _ in range(60):
        mc = 10 ** rng.uniform(-10, -3)
        rows.append((float(rng.uniform(-4.2, 4.2) * _kc(mc)), float(mc), True, "near1"))
    for _ in range(40):
        m = 1 - 10 ** rng.uniform(-15, -3)
        rows.append((float(rng.uniform(-4.2, 4.2) * _kc(1 - m)), float(m), False, "near1m"))
    # large u with m < 0 and m > 1 (double-double scaling of u)
    for _ in range(30):
        rows.append(
            (float(rng.choice([-1, 1]) * 10 ** rng.uniform(2, 6)), float(-(10 ** rng.uniform(-2, 3))), False, "largeu")
        )
    for _ in range(30):
        rows.append(
            (float(rng.choice([-1, 1]) * 10 ** rng.uniform(2, 6)), float(1 + 10 ** rng.uniform(-2, 2)), False, "largeu")
        )
    return rows


def k_rows():
    rows = []
    for m in list(np.linspace(-0.99, 0.99, 23)) + [-1e10, -1e5, -10.0, 0.0, 0.5, 0.9, 0.999]:
        rows.append((float(m), False))
    for mc in [1e-3, 1e-10, 1e-20, 1e-100, 1e-300, 5e-324, 1e-310, 0.1, 0.5, 0.9, 1.0, 2.0]:
        rows.append((mc, True))
    return rows


def k_row(args):
    p, comp = args
    with mp.workdps(340 if comp else DPS):
        m = 1 - mp.mpf(p) if comp else mp.mpf(p)
        return [p, float(comp), float(mp.ellipk(m)), float(mp.ellipe(m))]


def f_inputs(rng):
    rows = []
    for _ in range(80):
        rows.append((float(rng.uniform(-1.6, 1.6)), float(rng.uniform(-5, 1)), False))
    for _ in range(40):
        rows.append((float(rng.uniform(-30, 30)), float(rng.uniform(0, 1)), False))
    for _ in range(40):
        rows.append((float(rng.uniform(-1.5707, 1.5707)), float(10 ** rng.uniform(-300, -1)), True))
    for _ in range(40):
        m = 1 + 10 ** rng.uniform(-3, 3)
        ph = float(np.arcsin(rng.uniform(-1, 1) / np.sqrt(m)))
        rows.append((ph, float(m), False))
    for _ in range(20):
        rows.append((float(rng.uniform(-1.5, 1.5)), float(-(10 ** rng.uniform(0, 10))), False))
    return rows


def f_row(args):
    phi, p, comp = args
    with mp.workdps(340 if comp else DPS):
        P = mp.mpf(p)
        m = 1 - P if comp else P
        ph = mp.mpf(phi)
        f = mp.re(mp.ellipf(ph, m))
        if m > 1 and abs(ph) > mp.pi / 2:
            f = None
        d = 1 / mp.sqrt(1 - m * mp.sin(ph) ** 2)
        h = abs(P) * mp.mpf(10) ** (-25) if P != 0 else mp.mpf(10) ** (-30)
        mm = (lambda q: 1 - q) if comp else (lambda q: q)
        fp = (mp.re(mp.ellipf(ph, mm(P + h))) - mp.re(mp.ellipf(ph, mm(P - h)))) / (2 * h)
        cond = max(1, (abs(ph * d) + abs(P * fp)) / abs(f)) if f else 1
        return [phi, p, float(comp), float(f), float(cond)]


def main():
    rng = np.random.default_rng(20261122)
    jin = jacobi_inputs(rng)
    fin = f_inputs(rng)
    with Pool(2) as pool:
        jr = pool.map(jac_row, [r[:3] for r in jin], chunksize=4)
        kr = pool.map(k_row, k_rows())
        fr = pool.map(f_row, fin, chunksize=4)
    np.savez_compressed(
        OUT, jac=np.array(jr), jac_region=np.array([r[3] for r in jin]), ke=np.array(kr), f=np.array(fr)
    )
    print("wrote", OUT, len(jr), len(kr), len(fr))


if __name__ == "__main__":
    sys.exit(main())
