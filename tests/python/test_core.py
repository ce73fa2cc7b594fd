"""Core concern: physical parameters (text eqs 1.7, 1.8, 2.1) and error plumbing."""

import math

import numpy as np
import pytest
from helpers import ROOT, needs_source

import pendula


def test_text_parameters_give_sqrt2():
    # g = 9.8 m/s^2, l = 4.9 m as throughout the text: w0 = sqrt(2) to 1 ulp.
    w0 = pendula.natural_frequency(g=9.8, length=4.9)
    assert abs(w0 - math.sqrt(2.0)) <= 1 * np.spacing(math.sqrt(2.0))


def test_small_angle_period_broadcasts_and_is_exact():
    w0 = np.array([[0.5, 1.0], [2.0, math.sqrt(2.0)]])
    t0 = pendula.small_angle_period(w0)
    assert t0.shape == (2, 2)
    np.testing.assert_allclose(t0, 2 * math.pi / w0, rtol=2 * np.finfo(float).eps, atol=0)
    assert isinstance(pendula.small_angle_period(1.0), float)


def test_damping_rate():
    assert pendula.damping_rate(b=0.05, mass=0.1) == pytest.approx(0.5, rel=1e-15)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(g=-9.8, length=4.9), "g"),
        (dict(g=9.8, length=0.0), "length"),
        (dict(g=float("nan"), length=4.9), "g"),
        (dict(g=9.8, length=float("inf")), "length"),
    ],
)
def test_bad_parameters_name_the_argument(kwargs, name):
    with pytest.raises(ValueError) as err:
        pendula.natural_frequency(**kwargs)
    # The Fortran core calls the length 'l' (as the text does).
    msg = str(err.value)
    assert msg.startswith(name[0]) and ("> 0" in msg or "finite" in msg)


def test_bad_types_raise_typeerror():
    with pytest.raises(TypeError):
        pendula.natural_frequency(g="9.8")
    with pytest.raises(TypeError):
        pendula.small_angle_period(np.array([1 + 1j]))


def test_input_not_modified():
    w0 = np.array([1.0, 2.0])
    keep = w0.copy()
    pendula.small_angle_period(w0)
    assert np.array_equal(w0, keep)


def test_build_info():
    info = pendula.build_info()
    assert info["version"] == pendula.__version__
    assert isinstance(info["cvode"], bool) and info["cvode"] == pendula.have_cvode()


@needs_source
def test_message_length_has_one_home():
    """The status message length is written once (src/core/pendula_msg_len.inc):
    no glue routine spells a character length, and every message buffer f2py
    built has that length."""
    import importlib
    import re

    inc = (ROOT / "src" / "core" / "pendula_msg_len.inc").read_text()
    length = int(re.search(r"PENDULA_MSG_LEN\s*=\s*(\d+)", inc).group(1))
    literal = re.compile(r"character\s*\(\s*(len\s*=\s*)?\d", re.I)
    spelled = {
        path.name
        for path in (ROOT / "python" / "f2py").glob("*.f90")
        if any(literal.search(line) for line in path.read_text().splitlines())
    }
    assert not spelled, spelled
    status = (ROOT / "src" / "core" / "pendula_status.f90").read_text()
    assert "include 'pendula_msg_len.inc'" in status
    assert not re.search(r"PENDULA_MSG_LEN\s*=", status)
    seen = 0
    for name, routine in vars(importlib.import_module("pendula._fortran")).items():
        for n in re.findall(r"\bmsg : string\(len=(\d+)\)", getattr(routine, "__doc__", "") or ""):
            assert int(n) == length, f"pendula._fortran.{name}: message buffer of {n} characters, not {length}"
            seen += 1
    assert seen >= 20


def test_period_series_matches_mpmath_and_brackets_the_exact_period():
    """T0 (1 + m/4 + 9 m^2/64) to 4 ulps of the mpmath value at the exact double
    inputs; and, as the first terms of T = T0 2K(m)/pi whose later terms are
    positive and decreasing, 25/256 m^3 <= 1 - series/T <= 25/256 m^3/(1 - m)
    (checked in mpmath, at 30 digits, with the library's value)."""
    import mpmath as mp

    mp.mp.dps = 30
    m = np.concatenate([[0.0, 5e-324, 1e-300, 1e-8, 0.5, 1 - 2**-53, 1.0], np.linspace(0.01, 0.9, 40)])
    w0 = np.full_like(m, math.sqrt(2.0))
    got = pendula.period_series(m, w0)
    for mi, wi, g in zip(m, w0, got):
        ref = 2 * mp.pi / mp.mpf(wi) * (1 + mp.mpf(mi) / 4 + 9 * mp.mpf(mi) ** 2 / 64)
        assert abs(mp.mpf(g) - ref) <= 4 * np.spacing(float(ref)), (mi, g, ref)
        if 1e-3 <= mi <= 0.9:
            exact = 2 * mp.pi / mp.mpf(wi) * 2 * mp.ellipk(mp.mpf(mi)) / mp.pi
            rel = 1 - mp.mpf(g) / exact
            c3 = mp.mpf(25) / 256 * mp.mpf(mi) ** 3
            assert c3 * (1 - 1e-9) <= rel <= c3 / (1 - mp.mpf(mi)), (mi, rel)
    assert isinstance(pendula.period_series(0.1, 2.0), float)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(m=-0.1, w0=1.0), "m"),
        (dict(m=1.5, w0=1.0), "m"),
        (dict(m=float("nan"), w0=1.0), "m"),
        (dict(m=0.1, w0=0.0), "w0"),
        (dict(m=0.1, w0=float("inf")), "w0"),
    ],
)
def test_period_series_rejects_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        pendula.period_series(**kwargs)
