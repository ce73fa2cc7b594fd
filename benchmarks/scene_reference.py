"""References for the scene benchmark that share no code with pendula.

theta'' + gamma theta' + w0^2 sin(theta) = 0, theta(0) = theta0, theta'(0) = omega0.

- ``undamped(...)``: gamma = 0 by Jacobi elliptic functions in mpmath (DLMF 22;
  libration, rotation, separatrix and both equilibria), at ``dps`` digits from
  the data exactly as given (w0 is an mpmath number, not a double).
- ``Taylor``: a Taylor-series integrator in fixed-point Python integers
  (``PREC`` bits, ~60 digits), order ``ORDER``; the coefficients follow from the
  recurrences for theta, s = sin(theta), c = cos(theta) (s' = c theta',
  c' = -s theta'); the step is chosen from the two last coefficients (Jorba and
  Zou) so that the tail stays below ``eps`` (absolute, or relative to the
  state's size for events).  Output times inside a step are evaluated from the
  step's polynomial (dense output at full order), events are roots of the theta
  or theta' polynomial refined by bisection.  A state scene whose motion has
  settled within 1e-12 rad of a multiple of 2 pi hands over to the linear
  damped solution in mpmath (the dropped term sin(x) - x is ~ x^3/6, 1e-37),
  and so do the events, whose times then follow in closed form (without it a
  decaying motion under the fixed-point resolution made the step's polynomial
  noise and its root search sweep ~1e20 multiples of 2 pi).

Every function takes plain floats (the scene's data) and returns floats or
mpmath numbers; nothing here imports pendula.
"""

import math
import time

import mpmath as mp

PREC = 200  # fixed-point bits of the Taylor integrator
ORDER = 30  # Taylor order
EPS = 1e-30  # tail bound per step
SETTLED = 1e-12  # hand-over to the linear solution below this size [rad]
ONE = 1 << PREC


class BudgetExceeded(RuntimeError):
    """The Taylor reference would need more steps than allowed."""


def exact_w0(g, length, dps=50):
    """w0 = sqrt(g/l) from the given doubles, as an mpmath number (not rounded to double)."""
    with mp.workdps(dps):
        return mp.sqrt(mp.mpf(g) / mp.mpf(length))


# ---------------------------------------------------------------------------
# undamped: elliptic functions
# ---------------------------------------------------------------------------


def _ellipf_any(phi, m, K):
    # F(phi | m) for any real phi: F(phi + j pi) = F(phi) + 2 j K
    j = mp.nint(phi / mp.pi)
    return 2 * j * K + mp.ellipf(phi - j * mp.pi, m)


def energy_parameter(theta0, omega0, w0):
    """m = (omega0 / (2 w0))^2 + sin^2(theta0 / 2) (m < 1 libration, > 1 rotation)."""
    return (mp.mpf(omega0) / (2 * w0)) ** 2 + mp.sin(mp.mpf(theta0) / 2) ** 2


def undamped(t, theta0, omega0, w0, dps=40):
    """theta(t), omega(t) [lists of mpf] of the undamped pendulum, and its period
    (libration: 4 K(m)/w0; rotation: time per revolution; inf on the separatrix;
    2 pi/w0 at rest at the bottom; inf at rest on top).  w0: an mpmath number."""
    with mp.workdps(dps + 10):
        w0 = mp.mpf(w0)
        th0 = mp.mpf(theta0)
        om0 = mp.mpf(omega0)
        n = mp.nint(th0 / (2 * mp.pi))
        r = th0 - 2 * mp.pi * n  # in [-pi, pi]
        base = 2 * mp.pi * n
        m = energy_parameter(theta0, omega0, w0)
        ts = [mp.mpf(x) for x in t]
        sig = 1 if om0 > 0 else -1
        if m == 0:
            return [base] * len(ts), [mp.mpf(0)] * len(ts), 2 * mp.pi / w0
        if abs(m - 1) < mp.mpf(10) ** (-(dps + 5)):
            if om0 == 0:  # at rest on top
                return [th0] * len(ts), [mp.mpf(0)] * len(ts), mp.inf
            u0 = mp.atanh(mp.sin(r / 2))
            u = [sig * w0 * x + u0 for x in ts]
            return ([base + 2 * mp.asin(mp.tanh(v)) for v in u], [2 * sig * w0 * mp.sech(v) for v in u], mp.inf)
        if m < 1:
            k = mp.sqrt(m)
            K = mp.ellipk(m)
            phi0 = mp.atan2(mp.sin(r / 2) / k, om0 / (2 * k * w0))
            u0 = _ellipf_any(phi0, m, K)
            th, om = [], []
            for x in ts:
                u = u0 + w0 * x
                th.append(base + 2 * mp.asin(k * mp.ellipfun("sn", u, m=m)))
                om.append(2 * k * w0 * mp.ellipfun("cn", u, m=m))
            return th, om, 4 * K / w0
        q = 1 / m  # rotation
        K1 = mp.ellipk(q)
        v0 = _ellipf_any(r / 2, q, K1)
        rate = sig * mp.sqrt(m) * w0
        th, om = [], []
        for x in ts:
            v = v0 + rate * x
            j = mp.nint(v / (2 * K1))
            vr = v - 2 * j * K1
            sn, cn, dn = (mp.ellipfun(f, vr, m=q) for f in ("sn", "cn", "dn"))
            th.append(base + 2 * (j * mp.pi + mp.atan2(sn, cn)))
            om.append(2 * rate * dn)
        return th, om, 2 * K1 / (mp.sqrt(m) * w0)


def undamped_events(t_end, theta0, omega0, w0, dps=40):
    """(times, kinds) of the events in (0, t_end] of the undamped pendulum, from the
    elliptic solution above: a libration theta = 2 pi n + 2 asin(k sn u), u = u0 + w0 t,
    passes the bottom where sn u = 0 (u = 2 j K, kind 2) and turns where cn u = 0
    (u = (2 j + 1) K, kind 1); a rotation, 2 am(v) with v = v0 + rate t, passes the bottom
    where v = 2 j K(1/m) and never turns.  None at rest, on the separatrix or at rest on
    top (the Taylor integrator answers those)."""
    with mp.workdps(dps + 10):
        w0, th0, om0, t_end = mp.mpf(w0), mp.mpf(theta0), mp.mpf(omega0), mp.mpf(t_end)
        r = th0 - 2 * mp.pi * mp.nint(th0 / (2 * mp.pi))
        m = energy_parameter(theta0, omega0, w0)
        if m == 0 or abs(m - 1) < mp.mpf(10) ** (-(dps + 5)):
            return None
        if m < 1:
            k = mp.sqrt(m)
            K = mp.ellipk(m)
            u0 = _ellipf_any(mp.atan2(mp.sin(r / 2) / k, om0 / (2 * k * w0)), m, K)
            step, rate, first, kinds = K, w0, u0, (2, 1)  # u = j K: j even a crossing, odd a turn
        else:
            q = 1 / m
            K = mp.ellipk(q)
            step, rate = 2 * K, (1 if om0 > 0 else -1) * mp.sqrt(m) * w0
            first, kinds = _ellipf_any(r / 2, q, K), (2, 2)
        # a start at rest is itself a turning point at t = 0, not an event after t[0]: u0 = +-K
        # only to the working precision, so events within 1e-20 of a quarter period count as t = 0
        floor = mp.mpf(10) ** -20 * abs(step / rate)
        times, out_kinds = [], []
        j = mp.floor(first / step) + (-1 if rate > 0 else 1)  # the first step lands on floor(first/step)
        while True:
            j += 1 if rate > 0 else -1
            t = (j * step - first) / rate
            if t > t_end:
                break
            if t > floor:
                times.append(t), out_kinds.append(kinds[int(j) % 2])
        return times, out_kinds


# ---------------------------------------------------------------------------
# damped (and events): Taylor series in fixed point
# ---------------------------------------------------------------------------


def _fix(x):
    return int(mp.floor(mp.mpf(x) * ONE))


def _mpf(a):
    return mp.mpf(a) / ONE


def _coefficients(th, om, s0, c0, G, W2, order):
    a = [th, om]
    ja = [0, om]
    s = [s0]
    c = [c0]
    for k in range(order - 1):
        # (k+2)(k+1) a[k+2] = -gamma (k+1) a[k+1] - w0^2 s[k]
        a.append(-((G * (k + 1) * a[k + 1] + W2 * s[k]) >> PREC) // ((k + 2) * (k + 1)))
        ja.append((k + 2) * a[k + 2])
        if k + 1 < order:
            kk = k + 1
            ss = sum(ja[j] * c[kk - j] for j in range(1, kk + 1)) >> PREC
            cs = sum(ja[j] * s[kk - j] for j in range(1, kk + 1)) >> PREC
            s.append(ss // kk)
            c.append(-cs // kk)
    return a


def _horner(a, H):
    acc = 0
    for x in reversed(a):
        acc = ((acc * H) >> PREC) + x
    return acc


def _deriv(a):
    return [k * a[k] for k in range(1, len(a))]


class Taylor:
    """Fixed-point Taylor integrator of the damped pendulum (see the module doc).

    w0, gamma: mpmath numbers or floats, taken exactly.  max_steps: raise
    BudgetExceeded beyond it.  relative: scale the tail bound by the state's
    size (events of a decaying motion keep their relative accuracy)."""

    def __init__(self, w0, gamma, order=ORDER, eps=EPS, max_steps=10**9, relative=False, max_seconds=math.inf):
        with mp.workprec(PREC + 40):
            self.w0 = mp.mpf(w0)
            self.gamma = mp.mpf(gamma)
            self.G = _fix(self.gamma)
            self.W2 = _fix(self.w0**2)
            self.two_pi = _fix(2 * mp.pi)
        self.order, self.eps, self.max_steps, self.relative = order, eps, max_steps, relative
        self.max_seconds = max_seconds
        self.steps = 0

    def _step(self, th, om):
        with mp.workprec(PREC + 40):
            x = _mpf(th)
            s0, c0 = _fix(mp.sin(x)), _fix(mp.cos(x))
        a = _coefficients(th, om, s0, c0, self.G, self.W2, self.order)
        eps = self.eps
        if self.relative:
            n = round(th / self.two_pi)
            size = max(abs(th - n * self.two_pi), abs(om) / float(self.w0)) / ONE
            eps = eps * min(1.0, max(size, 1e-300))
        h = math.inf
        for k in (self.order - 1, self.order):
            ak = abs(a[k]) / ONE
            if ak > 0:
                h = min(h, (eps / ak) ** (1.0 / k))
        return a, h

    def _settled(self, th, om):
        n = round(th / self.two_pi)
        return (abs(th - n * self.two_pi) < SETTLED * ONE and abs(om) < SETTLED * float(self.w0) * ONE), n

    def solve(self, t, theta0, omega0, events=False, handover=True):
        """theta, omega at the (increasing, >= 0) times t as mpf lists; with events,
        also (times, kinds) of the turning points (kind 1, omega = 0) and the zero
        crossings (kind 2, theta = 0 mod 2 pi: passes through the bottom, as pendula's
        scenes count them) in (0, t[-1]]."""
        deadline = time.perf_counter() + self.max_seconds
        th, om = _fix(theta0), _fix(omega0)
        t_now = 0
        targets = [_fix(x) for x in t]
        t_end = targets[-1] if targets else 0
        out_th, out_om, ev = [], [], []
        i = 0
        while i < len(targets) and targets[i] <= t_now:
            out_th.append(th), out_om.append(om)
            i += 1
        while t_now < t_end:
            settled, n = self._settled(th, om)
            if handover and settled:
                rest = _linear(self, th, om, n, t_now, targets[i:])
                out_th.extend(rest[0]), out_om.extend(rest[1])
                if events:
                    ev.extend(_linear_events(self, th, om, n, t_now, t_end))
                break
            self.steps += 1
            if self.steps > self.max_steps or (self.steps == 100 and 100 * t_end > self.max_steps * t_now):
                # over budget, or predicted to be from the first 100 steps
                raise BudgetExceeded(f"more than {self.max_steps} Taylor steps")
            if time.perf_counter() > deadline:
                raise BudgetExceeded(f"more than {self.max_seconds} s")
            a, h = self._step(th, om)
            H = min(_fix(min(h, 1e300)) if h < math.inf else t_end - t_now, t_end - t_now)
            H = max(H, 1)
            while i < len(targets) and targets[i] <= t_now + H:
                d = targets[i] - t_now
                out_th.append(_horner(a, d)), out_om.append(_horner(_deriv(a), d))
                i += 1
            if events:
                ev.extend(_roots(_deriv(a), H, t_now, 1))
                # zero crossings are passes through the bottom, theta = 0 mod 2 pi: the
                # roots of theta - 2 pi k for every k the step's samples span
                vals = [_horner(a, H * j // 16) for j in range(17)]
                ks = range(min(vals) // self.two_pi, max(vals) // self.two_pi + 2)
                if len(ks) > 64:  # the step's polynomial cannot sweep that far: a broken step
                    raise BudgetExceeded(f"a step spans {len(ks)} multiples of 2 pi at t = {float(_mpf(t_now))}")
                for k in ks:
                    ev.extend(_roots([a[0] - k * self.two_pi] + list(a[1:]), H, t_now, 2))
            th, om = _horner(a, H), _horner(_deriv(a), H)
            t_now += H
        ev.sort()
        conv = lambda v: [_mpf(x) for x in v]
        with mp.workprec(PREC):
            res = (conv(out_th), conv(out_om))
            if events:
                return res + ([_mpf(x) for x, _ in ev], [k for _, k in ev])
        return res


def _roots(a, H, t0, kind, pieces=16):
    # sign changes of the polynomial on [0, H] (sampled at `pieces` points), refined by bisection
    out = []
    xs = [H * j // pieces for j in range(pieces + 1)]
    vs = [_horner(a, x) for x in xs]
    for j in range(pieces):
        lo, hi, flo = xs[j], xs[j + 1], vs[j]
        if vs[j + 1] != 0 and (flo == 0 or (flo < 0) == (vs[j + 1] < 0)):
            continue
        while hi - lo > 1:
            mid = (lo + hi) // 2
            fm = _horner(a, mid)
            if (fm < 0) == (flo < 0) and fm != 0:
                lo, flo = mid, fm
            else:
                hi = mid
        if t0 + hi > 0:
            out.append((t0 + hi, kind))
    return out


def _linear(tay, th, om, n, t_now, targets):
    # x'' + gamma x' + w0^2 x = 0 from (x, v) at t_now, x = theta - 2 pi n:
    # x(tau) = e^{-gamma tau/2} [x cosh(mu tau) + (v + gamma x/2) sinh(mu tau)/mu]
    with mp.workprec(PREC + 40):
        x0 = _mpf(th - n * tay.two_pi)
        v0 = _mpf(om)
        g2 = tay.gamma / 2
        mu2 = g2**2 - tay.w0**2
        mu = mp.sqrt(mu2) if mu2 >= 0 else mp.mpc(0, mp.sqrt(-mu2))
        base = _mpf(n * tay.two_pi)
        tt, oo = [], []
        for T in targets:
            tau = _mpf(T - t_now)
            e = mp.exp(-g2 * tau)
            if mu == 0:
                ch, sh, msh = mp.mpf(1), tau, mp.mpf(0)
            else:
                ch, sh, msh = mp.cosh(mu * tau), mp.sinh(mu * tau) / mu, mu * mp.sinh(mu * tau)
            b = v0 + g2 * x0
            x = mp.re(e * (x0 * ch + b * sh))
            # x' = -gamma/2 x + e (x0 mu sinh + b cosh)
            v = mp.re(-g2 * x + e * (x0 * msh + b * ch))
            tt.append(_fix(base + x)), oo.append(_fix(v))
        return tt, oo


def _linear_events(tay, th, om, n, t_now, t_end):
    # the events in (t_now, t_end] of the linear motion from (x, v) at t_now, x = theta - 2 pi n:
    # zero crossings are the roots of x, turning points those of v = x', which obeys the same
    # equation from (v, -gamma v - w0^2 x); both have the form e^{-gamma tau/2} (y0 C + b S)
    # with b = y'(0) + gamma y0/2 (C, S = cos, sin/w; cosh, sinh/mu; or 1, tau)
    out = []
    with mp.workprec(PREC + 40):
        x0, v0 = _mpf(th - n * tay.two_pi), _mpf(om)
        g2 = tay.gamma / 2
        d2 = tay.w0**2 - g2**2
        t0, span = _mpf(t_now), _mpf(t_end - t_now)
        for kind, y0, y1 in ((2, x0, v0), (1, v0, -tay.gamma * v0 - tay.w0**2 * x0)):
            b = y1 + g2 * y0
            if y0 == 0 and b == 0:
                continue
            if d2 > 0:  # y0 cos(w tau) + (b/w) sin(w tau) = R cos(w tau - phi)
                w = mp.sqrt(d2)
                phi = mp.atan2(b / w, y0)
                j = mp.ceil((-phi - mp.pi / 2) / mp.pi)
                while True:
                    tau = (phi + mp.pi / 2 + j * mp.pi) / w
                    if tau > span:
                        break
                    if tau > 0:
                        out.append((_fix(t0 + tau), kind))
                    j += 1
                continue
            if d2 == 0:
                tau = -y0 / b if b != 0 else mp.mpf(-1)
            else:
                mu = mp.sqrt(-d2)
                r = -y0 * mu / b if b != 0 else mp.mpf(2)
                tau = mp.atanh(r) / mu if -1 < r < 1 else mp.mpf(-1)
            if 0 < tau <= span:
                out.append((_fix(t0 + tau), kind))
    return out
