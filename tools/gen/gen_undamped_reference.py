#!/usr/bin/env python3
"""mpmath references for the undamped pendulum, and the table generator.

Run ``python3 tools/gen/gen_undamped_reference.py`` to (re)write
``tests/data/undamped_reference.csv.gz``; ``--check-ode`` first cross-checks
the closed form below against a direct Taylor integration of the ODE
theta'' = -w0^2 sin(theta) (mpmath.odefun), so the table does not merely
repeat the library's derivation.

Every reference is computed at ``DPS`` decimal digits from the EXACT double
inputs (theta0, omega0, w0, t).  Closed form (derivation in the README):
  m  = sin^2(theta_r/2) + q^2,  q = omega0/(2 w0),  theta_r = theta0 - 2 pi N
  m < 1 (libration): sin(theta/2) = k sn(w0 t + u0 | m), cos(theta/2) = dn,
        Omega = 2 k w0 cn,  u0 = F(atan2(sin(theta_r/2), q) | m)
  m > 1 (rotation):  theta = 2 s am(k w0 t + v0 | 1/m), Omega = 2 s k w0 dn,
        v0 = F(s theta_r/2 | 1/m), s = sign(omega0)
  m = 1 (separatrix): theta = 2 s gd(w0 t + c), Omega = 2 s w0 sech(w0 t + c)
Condition numbers cond_x = sum |x d(.)/dx| over x in {theta0, omega0, w0, t}
are taken by one-sided differences at relative step 1e-22 (max of both sides).
"""

import argparse
import gzip
import os
import sys

import mpmath as mp

DPS = 60
HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "..", "..", "tests", "data", "undamped_reference.csv.gz")
COLUMNS = ["theta0", "omega0", "w0", "t", "theta", "omega", "cond_theta", "cond_omega", "regime", "one_minus_m"]


class State:
    """Everything about one initial state that does not depend on t (at mp.dps)."""

    def __init__(self, theta0, omega0, w0):
        th0, om0, w0 = mp.mpf(theta0), mp.mpf(omega0), mp.mpf(w0)
        self.w0 = w0
        self.N = mp.nint(th0 / (2 * mp.pi))
        thr = th0 - 2 * mp.pi * self.N
        s2 = mp.sin(thr / 2)
        q = om0 / (2 * w0)
        self.m = s2**2 + q**2
        self.mc = mp.cos(thr / 2) ** 2 - q**2
        self.k = mp.sqrt(self.m)
        self.s = mp.sign(q)
        if self.mc > 0:
            self.regime = 1
            self.u0 = mp.ellipf(mp.atan2(s2, q), self.m)
            self.K = mp.ellipk(self.m)
            self.period = 4 * self.K / w0
        elif self.mc < 0:
            self.regime = 3
            self.p = 1 / self.m
            self.v0 = mp.ellipf(self.s * thr / 2, self.p)
            self.K = mp.ellipk(self.p)
            self.period = 2 * self.K / (self.k * w0)
        else:
            self.regime = 2
            self.c = mp.asinh(mp.tan(self.s * thr / 2)) if self.s != 0 else mp.mpf(0)
            self.period = mp.inf

    def at(self, t):
        """(theta, Omega) at time t (any real)."""
        t = mp.mpf(t)
        w0, k = self.w0, self.k
        base = 2 * mp.pi * self.N
        if self.regime == 1:
            u = w0 * t + self.u0
            sn, cn, dn = (mp.ellipfun(f, u, m=self.m) for f in ("sn", "cn", "dn"))
            return base + 2 * mp.atan2(k * sn, dn), 2 * k * w0 * cn
        if self.regime == 3:
            u = k * w0 * t + self.v0
            n = mp.nint(u / (2 * self.K))
            r = u - 2 * self.K * n
            sn, cn, dn = (mp.ellipfun(f, r, m=self.p) for f in ("sn", "cn", "dn"))
            am = n * mp.pi + mp.atan2(sn, cn)
            return base + 2 * self.s * am, 2 * self.s * k * w0 * dn
        if self.s == 0:  # at rest on the separatrix: the upright equilibrium
            return base + 2 * mp.atan(mp.tanh(self.c / 2)), mp.mpf(0)
        x = w0 * t + self.c
        return base + 2 * self.s * 2 * mp.atan(mp.tanh(x / 2)), 2 * self.s * w0 * mp.sech(x)


def reference(theta0, omega0, w0, times, rel_step=mp.mpf("1e-22")):
    """Rows (theta, omega, cond_theta, cond_omega) at each t for one state (exact double inputs)."""
    with mp.workdps(DPS):
        x0 = [mp.mpf(theta0), mp.mpf(omega0), mp.mpf(w0)]
        base = State(*x0)
        vals = [base.at(t) for t in times]
        cond = [[abs(mp.mpf(t) * v[1]), abs(mp.mpf(t) * d2theta(base, t))] for t, v in zip(times, vals)]
        for i in range(3):
            if x0[i] == 0:
                continue
            h = rel_step * abs(x0[i])
            sides = []
            for sgn in (1, -1):
                x = list(x0)
                x[i] = x0[i] + sgn * h
                st = State(*x)
                sides.append([st.at(t) for t in times])
            for j in range(len(times)):
                for c in range(2):
                    d = max(abs(sides[0][j][c] - vals[j][c]), abs(vals[j][c] - sides[1][j][c])) / h
                    cond[j][c] += abs(x0[i]) * d
        return [(v[0], v[1], c[0], c[1]) for v, c in zip(vals, cond)], base


def d2theta(state, t):
    """theta'' = -w0^2 sin(theta): the t-derivative of Omega."""
    th, _ = state.at(t)
    return -(state.w0**2) * mp.sin(th)


def random_state(rng, regime, log_gap):
    """Double inputs (theta0, omega0, w0) with |1 - m| ~ 10**log_gap in the given regime."""
    import math

    gap = 10.0**log_gap
    m = 1.0 - gap if regime == 1 else 1.0 + gap
    w0 = 10.0 ** rng.uniform(-1, 1)
    turns = int(rng.integers(-2, 3)) if rng.uniform() < 0.5 else 0
    if regime == 1:
        f = rng.uniform() if rng.uniform() < 0.8 else float(rng.choice([0.0, 1.0]))
        pot = f * m  # sin^2(theta_r/2)
        thr = 2 * math.asin(math.sqrt(pot)) * rng.choice([-1, 1])
        q = math.sqrt(max(m - pot, 0.0)) * rng.choice([-1, 1])
    else:
        pot = rng.uniform() if rng.uniform() < 0.8 else float(rng.choice([0.0, 1.0]))
        thr = 2 * math.asin(math.sqrt(pot)) * rng.choice([-1, 1])
        q = math.sqrt(m - pot) * rng.choice([-1, 1])
    return thr + 2 * math.pi * turns, 2 * w0 * q, w0


def sample_times(rng, period, n):
    """n times over +-100 periods: one within the first period, the rest log-spread, some negative."""
    out = [rng.uniform(0, 1) * period]
    for _ in range(n - 1):
        t = period * 10.0 ** rng.uniform(-1, 2)
        out.append(-t if rng.uniform() < 0.25 else t)
    return out


def generate(n_states, times_per_state, seed):
    import numpy as np

    rng = np.random.default_rng(seed)
    rows = []
    for i in range(n_states):
        regime = 1 if i % 2 == 0 else 3
        log_gap = rng.uniform(-15, 0 if regime == 1 else 2)
        theta0, omega0, w0 = random_state(rng, regime, log_gap)
        with mp.workdps(DPS):
            st = State(theta0, omega0, w0)
            per = float(st.period)
        times = [float(t) for t in sample_times(rng, per, times_per_state)]
        refs, st = reference(theta0, omega0, w0, times)
        for t, (th, om, ct, co) in zip(times, refs):
            rows.append([theta0, omega0, w0, t, th, om, ct, co, st.regime, 1 - st.m])
    # exact separatrix states: theta0 = 0, omega0 = +-2 w0 (m == 1 in doubles and in fact)
    for w0 in (1.0, 2.0**0.5, 0.3, 7.5):
        for sgn in (1, -1):
            times = [0.1, 1.0, 5.0, -3.0, 40.0, 800.0]
            times = [x / w0 for x in times]
            refs, st = reference(0.0, sgn * 2 * w0, w0, times)
            for t, (th, om, ct, co) in zip(times, refs):
                rows.append([0.0, sgn * 2 * w0, w0, t, th, om, ct, co, st.regime, 1 - st.m])
    return rows


def fmt(x):
    return repr(float(x))


def write_table(rows, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with gzip.open(path, "wt") as f:
        f.write("# generated by tools/gen/gen_undamped_reference.py (mpmath, dps=%d)\n" % DPS)
        f.write(",".join(COLUMNS) + "\n")
        for r in rows:
            # inputs exactly (repr), references to 20 digits, condition numbers to 6
            f.write(",".join(fmt(x) if j < 4 else mp.nstr(x, 20 if j < 6 else 6) for j, x in enumerate(r)) + "\n")


def read_table(path=TABLE):
    import numpy as np

    with gzip.open(path, "rt") as f:
        data = np.loadtxt(f, delimiter=",", comments="#", skiprows=2)
    return {c: data[:, j] for j, c in enumerate(COLUMNS)}


def check_ode(verbose=True):
    """Closed form vs direct Taylor integration of the ODE (mpmath.odefun) for a few states."""
    worst = 0
    states = [
        (2.5, 0.7, 1.3),
        (-0.4, -1.1, 0.8),
        (1.0, 3.0, 1.0),
        (0.3, -2.5, 1.2),
        (3.0, 0.0, 1.0),
        (0.0, 2.0, 1.0),
        (7.0, -0.2, 0.5),
    ]
    with mp.workdps(30):
        for th0, om0, w0 in states:
            st = State(th0, om0, w0)
            wv = mp.mpf(w0)
            f = mp.odefun(lambda t, y: [y[1], -(wv**2) * mp.sin(y[0])], 0, [mp.mpf(th0), mp.mpf(om0)])
            for t in (0.5, 2.0, 6.0):
                a = f(t)
                b = st.at(t)
                err = max(abs(a[0] - b[0]), abs(a[1] - b[1]))
                worst = max(worst, err)
                if verbose:
                    print(f"  state {th0, om0, w0} t={t}: |closed form - ODE| = {mp.nstr(err, 3)}")
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--states", type=int, default=3000)
    ap.add_argument("--times", type=int, default=4)
    ap.add_argument("--seed", type=int, default=20261122)
    ap.add_argument("--out", default=TABLE)
    ap.add_argument("--check-ode", action="store_true")
    a = ap.parse_args()
    if a.check_ode:
        w = check_ode()
        print("worst |closed form - ODE| =", mp.nstr(w, 3))
        if w > 1e-20:
            sys.exit("closed form disagrees with the ODE")
    rows = generate(a.states, a.times, a.seed)
    write_table(rows, a.out)
    print(f"wrote {len(rows)} rows to {a.out}")


if __name__ == "__main__":
    main()
