"""Generate tests/data/integrators_reference.csv: the text's section 2.2 scenario
(g = 9.8, l = 4.9, m = 0.1 kg, b in {0.01, 0.05} kg/s, theta0 = 0, Omega0 = 2 rad/s)
integrated by mpmath's Taylor-series ODE solver (mpmath.odefun) at 30 digits.

The parameters are the exact doubles the tests pass (w0 = sqrt(9.8/4.9),
gamma = b/m), so the table is the true solution of the problem the library is
given, to ~1e-25.  Columns: b, gamma, t, theta, omega.  Takes ~1 min:
    python3 tools/gen/gen_integrators_reference.py
"""

import math
import pathlib

import mpmath as mp

mp.mp.dps = 30
OUT = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "integrators_reference.csv"


def main():
    w0 = math.sqrt(9.8 / 4.9)
    w0sq = mp.mpf(w0) ** 2
    rows = []
    for b in (0.01, 0.05):
        gamma = b / 0.1
        g = mp.mpf(gamma)
        f = mp.odefun(lambda t, y: [y[1], -g * y[1] - w0sq * mp.sin(y[0])], 0, [mp.mpf(0), mp.mpf(2)])
        for k in range(0, 31):
            y = f(mp.mpf(k))
            rows.append(f"{b!r},{gamma!r},{k},{mp.nstr(y[0], 22)},{mp.nstr(y[1], 22)}")
    OUT.write_text(
        "# mpmath.odefun (30 digits) reference for the text's section 2.2 scenario;"
        " made by tools/gen/gen_integrators_reference.py\n"
        "b,gamma,t,theta,omega\n" + "\n".join(rows) + "\n"
    )


if __name__ == "__main__":
    main()
