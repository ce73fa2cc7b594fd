"""The honesty grid of the scenes, shared by tests/python/test_scene.py
and benchmarks/bench_tradeoff.py (no pytest here; importable as a module).

How the grid is made (fixed seed, so every run tests the same scenes):
- w0 = sqrt(2) (the text's g = 9.8, l = 4.9); scene i takes its damping class
  from i mod 6: gamma = 0 for three of the six classes, then gamma/w0
  log-uniform in [1e-4, 1e-1], in [1e-1, 1.99] or in [2, 20] (critical,
  gamma = 2 w0 exactly, for every 4th scene of that last class);
- amplitude class from (i // 6) mod 5: small (|theta0| log-uniform in
  [1e-3, 5e-2]), medium ([5e-2, 1]), large ([1, 2.8]), near pi
  (pi - 10^U(-6, -1) undamped, pi - 10^U(-4, -1) damped), and over the top (gamma = 0: energy 1 + 10^U(-6, 0)
  times the separatrix energy; damped: Omega0 up to 3 w0 from the bottom);
  Omega0 is 0 or of random size and sign;
- window: t[-1] = P T0 with P = 10^U(0, 3) small-angle periods (1 to 1000;
  every 7th scene exactly 1000), 41 equally spaced output times (gamma = 0)
  or 201 (damped);
- tol = 10^U(-10, -3).
References: the exact solution evaluated with mpmath at 30 digits (gamma = 0,
from the formulas of DLMF 22 for sn/cn/dn, independent of pendula's elliptic
code), otherwise a converged integration: pendula.rk4 (the integrator, not the
scene solver) at h and h/2 with h <= T0/200 halved until its own error (the
h, h/2 difference / 15) is <= tol/20, Richardson-extrapolated; where RK4 is
rounding-bound first (long unwrapped rotations), SciPy DOP853 at rtol 1e-13
and 2.5e-14, its error estimated by their difference.  The test requires
every reference error <= tol/20.
"""

import numpy as np

W0 = float(np.sqrt(2.0))
T0 = 2 * np.pi / W0


def make_grid(n=240, seed=20261122):
    rng = np.random.default_rng(seed)
    scenes = []
    for i in range(n):
        dclass = i % 6
        aclass = (i // 6) % 5
        if dclass in (0, 2, 4):
            gamma = 0.0
        elif dclass == 1:
            gamma = W0 * 10 ** rng.uniform(-4, -1)
        elif dclass == 3:
            gamma = W0 * 10 ** rng.uniform(-1, np.log10(1.99))
        else:
            gamma = 2 * W0 if (i // 6) % 4 == 0 else W0 * 10 ** rng.uniform(np.log10(2), np.log10(20))
        if dclass == 5 and gamma == 0:
            gamma = 2 * W0
        sgn = rng.choice([-1.0, 1.0])
        if aclass == 0:
            theta0 = sgn * 10 ** rng.uniform(-3, np.log10(5e-2))
        elif aclass == 1:
            theta0 = sgn * 10 ** rng.uniform(np.log10(5e-2), 0)
        elif aclass == 2:
            theta0 = sgn * rng.uniform(1, 2.8)
        else:
            # near the top: to pi - 1e-6 for the exact solution; damped scenes stop at
            # pi - 1e-4, since closer starts amplify every rounding error by ~1/(pi - |theta0|)
            # while the pendulum hangs there, beyond what any double-precision integration
            # (the reference included) can resolve at tol = 1e-10
            theta0 = sgn * (np.pi - 10 ** rng.uniform(-6 if gamma == 0 else -4, -1))
        omega0 = 0.0
        if aclass < 4 and rng.uniform() < 0.5:
            # Omega0 up to the size of the swing, kept inside libration for gamma = 0
            omega0 = rng.uniform(-1, 1) * W0 * min(abs(theta0), 0.5) * (0.5 if aclass == 3 else 1.0)
            if aclass == 3:
                omega0 = rng.choice([-1, 1]) * 2 * W0 * np.cos(theta0 / 2) * rng.uniform(0, 0.9)
        if aclass == 4:
            theta0 = rng.uniform(-1, 1)
            if gamma == 0:
                excess = 10 ** rng.uniform(-6, 0)
                omega0 = sgn * 2 * W0 * np.sqrt(np.cos(theta0 / 2) ** 2 + excess)
            else:
                omega0 = sgn * W0 * rng.uniform(2.05, 3.0)
        periods = 1000.0 if i % 7 == 3 else float(10 ** rng.uniform(0, 3))
        tol = float(10 ** rng.uniform(-10, -3))
        npts = 41 if gamma == 0 else 201
        t = np.linspace(0.0, periods * T0, npts)
        scenes.append(
            dict(index=i, theta0=float(theta0), omega0=float(omega0), gamma=float(gamma), periods=periods, tol=tol, t=t)
        )
    return scenes


def mp_undamped(t, theta0, omega0, w0, dps=30):
    """theta(t), Omega(t) of theta'' + w0^2 sin theta = 0 by mpmath (any regime but m = 1)."""
    import mpmath as mp

    with mp.workdps(dps):
        th0, om0, w = mp.mpf(theta0), mp.mpf(omega0), mp.mpf(w0)
        n = mp.nint(th0 / (2 * mp.pi))
        center = 2 * mp.pi * n
        thr = th0 - center
        m = mp.sin(thr / 2) ** 2 + (om0 / (2 * w)) ** 2
        k = mp.sqrt(m)
        out_th, out_om = [], []
        if m < 1:
            phi0 = mp.atan2(mp.sin(thr / 2), om0 / (2 * w))  # am(u0): sn = sin(thr/2)/k, cn = om0/(2 k w)
            u0 = mp.ellipf(phi0, m)
            for tt in t:
                u = w * mp.mpf(tt) + u0
                sn = mp.ellipfun("sn", u, m=m)
                cn = mp.ellipfun("cn", u, m=m)
                out_th.append(float(center + 2 * mp.asin(k * sn)))
                out_om.append(float(2 * k * w * cn))
        else:
            p = 1 / m
            s = mp.sign(om0)
            kk = mp.ellipk(p)
            v0 = mp.ellipf(s * thr / 2, p)
            for tt in t:
                u = k * w * mp.mpf(tt) + v0
                j = mp.nint(u / (2 * kk))
                r = u - 2 * j * kk
                am = j * mp.pi + mp.atan2(mp.ellipfun("sn", r, m=p), mp.ellipfun("cn", r, m=p))
                out_th.append(float(center + 2 * s * am))
                out_om.append(float(2 * s * k * w * mp.ellipfun("dn", u, m=p)))
        return np.array(out_th), np.array(out_om)


def rk4_reference(t, theta0, omega0, w0, gamma, want=0.0):
    """Converged integration: pendula.rk4 at h and h/2, Richardson-extrapolated,
    h halved (from T0/200) until the estimated error of the reference, the
    (h, h/2) difference / 15, is <= want (at most 6 halvings; stopped early
    when a halving no longer cuts it 4x -- rounding-bound -- or beyond 2e7 steps);
    still above want (rounding-bound): SciPy DOP853 at rtol 1e-13 and 2.5e-14
    instead, its error estimated by their difference, when that is smaller.

    Returns theta, omega at t and the estimated error of the reference."""
    import pendula

    hmax = pendula.rk4_max_stable_step(w0, gamma)
    h = min(2 * np.pi / w0 / 200, 0.4 * hmax)
    tt = np.concatenate(([0.0], t)) if t[0] > 0 else t
    r1 = pendula.rk4(tt, theta0, omega0, w0, gamma, h)
    last = np.inf
    for _ in range(7):
        r2 = pendula.rk4(tt, theta0, omega0, w0, gamma, h / 2)
        err = max(np.max(np.abs(r2.theta - r1.theta)), np.max(np.abs(r2.omega - r1.omega)) / w0) / 15
        # done when converged to want, or when halving no longer pays (rounding-bound: the
        # h^4 law would cut err 16x) or the run gets long
        if err <= want or err > last / 4 or t[-1] / h > 2e7:
            break
        last = err
        h, r1 = h / 2, r2
    th = r2.theta + (r2.theta - r1.theta) / 15
    om = r2.omega + (r2.omega - r1.omega) / 15
    if t[0] > 0:
        th, om = th[1:], om[1:]
    if err > want:
        # rounding-bound (e.g. the unwrapped angle of a long rotation): SciPy's DOP853,
        # whose few long steps round far less, at two tolerances; their difference is
        # its error estimate
        from scipy.integrate import solve_ivp

        def rhs(_, y):
            return [y[1], -gamma * y[1] - w0 * w0 * np.sin(y[0])]

        sols = [
            solve_ivp(rhs, (0.0, t[-1]), [theta0, omega0], method="DOP853", t_eval=t, rtol=r, atol=1e-16)
            for r in (1e-13, 2.5e-14)
        ]
        e2 = max(np.max(np.abs(sols[0].y[0] - sols[1].y[0])), np.max(np.abs(sols[0].y[1] - sols[1].y[1])) / w0)
        if e2 < err:
            th, om, err = sols[1].y[0], sols[1].y[1], e2
    return th, om, err


def run_grid(scenes=None, verbose=False):
    """Solve every scene and measure its true error; returns a list of dicts."""
    import pendula

    scenes = make_grid() if scenes is None else scenes
    rows = []
    for sc in scenes:
        s = pendula.Scene(theta0=sc["theta0"], omega0=sc["omega0"], t=sc["t"], gamma=sc["gamma"], tol=sc["tol"])
        res = pendula.solve(s)
        if sc["gamma"] == 0:
            th, om = mp_undamped(sc["t"], sc["theta0"], sc["omega0"], s.w0)
            ref_err = 0.0
        else:
            th, om, ref_err = rk4_reference(sc["t"], sc["theta0"], sc["omega0"], s.w0, sc["gamma"], sc["tol"] / 20)
        err = max(np.max(np.abs(res.theta - th)), np.max(np.abs(res.omega - om)) / s.w0)
        m = np.sin(sc["theta0"] / 2) ** 2 + (sc["omega0"] / (2 * s.w0)) ** 2
        row = dict(
            sc,
            model=res.model,
            est=res.error_estimate,
            err=float(err),
            ratio=float(err / sc["tol"]),
            ref_err=ref_err,
            tol_met=res.tol_met,
            m=float(m),
            cost=res.cost,
            reason=res.reason,
        )
        row.pop("t")
        rows.append(row)
        if verbose:
            print(
                f"{sc['index']:4d} g/w0={sc['gamma'] / s.w0:8.2e} th0={sc['theta0']:+.6f} om0={sc['omega0']:+.3f} "
                f"P={sc['periods']:7.1f} tol={sc['tol']:.1e} {res.model:11s} est={res.error_estimate:.1e} "
                f"err={err:.1e} r={err / sc['tol']:.2g} ref={ref_err:.0e} {res.cost['python_wall_time']:.3f}s"
            )
    return rows
