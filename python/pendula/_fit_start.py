"""Starting values of a motion fit from the recorded swing itself.

The half period from the zero crossings of theta (linearly interpolated
between samples), w0 from the period-amplitude relation of each half swing
(T/2 = 2 K(sin^2(A/2)) / w0, text eq. 1.53), gamma from the logarithmic
decrement of the successive extrema (the envelope of a lightly damped swing
decays as exp(-gamma t / 2)), and the state at t_ref from the data there and
the energy of the first swing.  Only rough values are needed: the least
squares refine them.
"""

import math

import numpy as np


def _crossings(t, y):
    """Times where y changes sign, linearly interpolated."""
    s = np.signbit(y)
    i = np.nonzero(s[1:] != s[:-1])[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


def _fft_period(t, y):
    """The period of the strongest Fourier component of y resampled uniformly."""
    n = max(64, 4 * t.size)
    grid = np.linspace(t[0], t[-1], n)
    spec = np.abs(np.fft.rfft(np.interp(grid, t, y) - np.mean(y)))
    k = int(np.argmax(spec[1:])) + 1
    return (grid[-1] - grid[0]) * n / (n - 1) / k


def _noise(y):
    """A rough noise level of y: the median absolute second difference / sqrt(6)
    (exact for white noise on a straight line; larger where the signal curves)."""
    if y.size < 5:
        return 0.0
    return float(np.median(np.abs(np.diff(y, 2)))) / math.sqrt(6.0)


def start_values(t, theta, omega, t_ref, offset, noise=None):
    """Rough (theta0, omega0, w0, gamma) of the swing theta(t) - offset.

    Only the half swings well above the noise (noise: the data's sigma, or
    estimated) count: a strongly damped record ends in noise whose zero
    crossings carry no period.  Raises ValueError when the data hold no half
    swing to time (the caller may then give p0)."""
    from .elliptic import ellipk

    y = theta - offset
    noise = _noise(y) if noise is None else float(noise)
    tc = _crossings(t, y)
    amps, times = [], []
    for a, b in zip(tc[:-1], tc[1:]):
        inside = (t > a) & (t < b)
        if not inside.any():
            break
        k = int(np.argmax(np.abs(y[inside])))
        if np.abs(y[inside])[k] < 5.0 * noise:
            break  # the swing has decayed into the noise: later crossings are noise
        amps.append(float(np.abs(y[inside])[k]))
        times.append(float(t[inside][k]))
    tc = tc[: len(amps) + 1]
    if tc.size >= 2:
        halves = np.diff(tc)
        amps, times = np.array(amps), np.array(times)
        amps = np.clip(amps, 1e-12, math.pi - 1e-9)
        w0 = float(np.median(2.0 * ellipk(np.sin(amps / 2) ** 2) / halves))
        if amps.size >= 2 and np.all(amps > 0):
            slope = np.polyfit(times, np.log(amps), 1)[0]
            gamma = max(-2.0 * slope, 0.0)
        else:
            gamma = 0.0
        amp0 = float(amps[0])
    elif tc.size == 1 or 0 < int(np.argmax(np.abs(y))) < y.size - 1:
        # less than a full swing: a crossing or a turning point inside the record
        period = _fft_period(t, y)
        amp0 = float(np.clip(np.max(np.abs(y)), 1e-12, math.pi - 1e-9))
        w0 = 4.0 * float(ellipk(math.sin(amp0 / 2) ** 2)) / period
        gamma = 0.0
    else:
        raise ValueError(
            "cannot find a starting period: theta does not cross its centre twice; "
            "record at least one full swing or give p0={'w0': ...}"
        )
    theta0 = float(np.interp(t_ref, t, y))
    if omega is not None:
        omega0 = float(np.interp(t_ref, t, omega))
    else:
        # |Omega0| from the energy of the first swing, its sign from the data's slope near t_ref.
        e = 2.0 * w0**2 * (math.cos(theta0) - math.cos(max(amp0, abs(theta0))))
        near = np.argsort(np.abs(t - t_ref))[: max(3, min(8, t.size // 20))]
        slope = np.polyfit(t[near] - t[near].mean(), y[near], 1)[0] if near.size >= 2 else 0.0
        omega0 = math.copysign(math.sqrt(max(e, 0.0)), slope)
    return theta0, omega0, w0, gamma
