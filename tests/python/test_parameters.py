"""One convention for the pendulum's parameters: every function that needs the
pendulum takes w0= or g= and length= (default: the text's g = 9.8, length =
4.9, the same as Scene's), every function with damping takes gamma= or b= and
mass=, and redundant values are accepted exactly when Scene accepts them."""

import inspect
import math
import re

import numpy as np
import pytest
from helpers import ROOT

import pendula
from pendula import _codes

EPS = np.finfo(float).eps
W0_TEXT = math.sqrt(2.0)  # sqrt(9.8/4.9): fl(9.8) = 2 fl(4.9) exactly, so w0 = fl(sqrt(2))

# name -> (positional arguments before the pendulum, result -> flat numbers)
PENDULUM_FUNCS = {
    "undamped": ((np.array([0.0, 0.7, 3.0]), 1.0, 0.4), None),
    "small_angle": ((np.array([0.0, 0.7, 3.0]), 0.1, 0.2), None),
    "small_angle_error": ((np.array([1.0, 30.0]), 0.1, 0.2), None),
    "period": ((np.array([0.1, 1.0, 3.0]), 0.2), None),
    "amplitude": ((np.array([0.1, 1.0, 3.0]), 0.2), None),
    "elliptic_parameter": ((np.array([0.1, 1.0, 3.0]), 0.2), None),
    "energy": ((np.array([0.1, 1.0, 3.0]), 0.2), None),
    "equilibria": ((np.array([0, 1, 2]),), None),
    "small_angle_period": ((), None),
    "period_series": ((np.array([0.0, 0.3, 1.0]),), None),
    "linear_damped": ((np.array([0.0, 0.7, 3.0]), 0.1, 0.2), None),
    "linear_damped_envelope": ((np.array([0.0, 0.7, 3.0]), 0.1, 0.2), None),
}


def _flat(result):
    if isinstance(result, str):
        return [result]
    if isinstance(result, tuple):
        return [x for r in result for x in _flat(r)]
    if isinstance(result, pendula.DampingRegime):
        return [v for v in vars(result).values()]
    return list(np.asarray(result).reshape(-1))


def _call(name, **kw):
    return _flat(getattr(pendula, name)(*PENDULUM_FUNCS[name][0], **kw))


def test_the_default_pendulum_is_defined_once_in_fortran():
    """_codes carries the Fortran parameters; Scene's defaults are the same numbers."""
    text = (ROOT / "src" / "core" / "pendula_physics.f90").read_text() if (ROOT / "src").is_dir() else None
    if text is not None:
        for name, value in (
            ("PENDULA_G_DEFAULT", _codes.G_DEFAULT),
            ("PENDULA_LENGTH_DEFAULT", _codes.LENGTH_DEFAULT),
            ("PENDULA_PARAM_RTOL", _codes.PARAM_RTOL),
        ):
            m = re.search(name + r"\s*=\s*([0-9.e+-]+)_wp", text)
            assert m and float(m.group(1)) == value, name
    sig = inspect.signature(pendula.Scene.__init__).parameters
    assert (sig["g"].default, sig["length"].default) == (_codes.G_DEFAULT, _codes.LENGTH_DEFAULT)
    assert pendula.natural_frequency() == W0_TEXT


def test_period_default_is_scenes():
    """The inconsistency this convention removed: period(1.0) was 6.70 (w0 = 1)
    while the Scene of the same start gave 4.74 (the text's pendulum)."""
    for theta0 in (0.1, 1.0, 3.0):
        scene = pendula.solve(pendula.Scene(theta0, want="period")).period
        assert abs(pendula.period(theta0) - scene) <= 2 * EPS * scene
    assert round(pendula.period(1.0), 2) == 4.74
    assert pendula.period(1.0, g=9.8, length=4.9) == pendula.period(1.0)


@pytest.mark.parametrize("name", sorted(PENDULUM_FUNCS))
def test_every_way_to_give_the_pendulum_agrees(name):
    default = _call(name)
    assert _call(name, w0=W0_TEXT) == default
    assert _call(name, g=9.8, length=4.9) == default
    assert _call(name, g=9.8) == default  # the other one takes the text's value
    assert _call(name, length=4.9) == default
    assert _call(name, w0=W0_TEXT, g=9.8, length=4.9) == default  # redundant, consistent
    other = pendula.natural_frequency(9.8, 1.0)
    assert _call(name, g=9.8, length=1.0) == _call(name, w0=other)
    assert _call(name, g=9.8, length=1.0) != default


@pytest.mark.parametrize("name", sorted(PENDULUM_FUNCS))
def test_w0_disagreeing_with_g_and_length_is_refused(name):
    with pytest.raises(ValueError, match=r"w0 = 1\.0 and sqrt\(g/length\) .* disagree: give w0, or g and length"):
        _call(name, w0=1.0, g=9.8, length=4.9)
    with pytest.raises(ValueError, match="w0"):
        _call(name, w0=W0_TEXT * (1 + 1e-11), length=4.9)
    # inside the tolerance (Scene's 1e-12 relative) both descriptions are one pendulum
    assert _call(name, w0=W0_TEXT * (1 + 1e-13), g=9.8) == _call(name, w0=W0_TEXT * (1 + 1e-13))


@pytest.mark.parametrize("name", ["undamped", "period", "energy", "small_angle_period", "linear_damped"])
def test_pendulum_keywords_are_keyword_only_and_positional_w0_still_works(name):
    f = getattr(pendula, name)
    params = inspect.signature(f).parameters
    assert params["g"].kind is params["length"].kind is inspect.Parameter.KEYWORD_ONLY
    assert params["w0"].kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
    names = list(params)
    args = list(PENDULUM_FUNCS[name][0])
    while len(args) < names.index("w0"):  # the optional ones before w0 at their defaults
        args.append(params[names[len(args)]].default)
    assert _flat(f(*args, 1.3)) == _flat(f(*args, w0=1.3))


def test_a_bad_g_or_length_is_named():
    with pytest.raises(ValueError, match="length"):
        pendula.period(1.0, length=-1.0)
    with pytest.raises(ValueError, match=r"\bg\b"):
        pendula.undamped(1.0, 1.0, g=0.0)
    with pytest.raises(TypeError, match=r"\bg\b"):
        pendula.period(1.0, g=np.array([9.8, 9.7]))


DAMPED = {"linear_damped": (1.3, 0.1, 0.2), "linear_damped_envelope": (1.3, 0.1, 0.2), "damping_regime": ()}


@pytest.mark.parametrize("name", sorted(DAMPED))
def test_damping_as_gamma_or_b_and_mass(name):
    f = getattr(pendula, name)
    args = DAMPED[name]
    gamma = pendula.damping_rate(0.05, 0.1)
    ref = _flat(f(*args, w0=1.4, gamma=gamma))
    assert _flat(f(*args, w0=1.4, b=0.05, mass=0.1)) == ref
    assert _flat(f(*args, w0=1.4, gamma=gamma, b=0.05, mass=0.1)) == ref
    assert _flat(f(*args, w0=1.4)) == _flat(f(*args, w0=1.4, gamma=0.0))  # no damping given
    with pytest.raises(ValueError, match="b is given without mass"):
        f(*args, b=0.05)
    with pytest.raises(ValueError, match="mass is given without b"):
        f(*args, mass=0.1)
    with pytest.raises(ValueError, match=r"gamma = 0\.3 and b/mass = .* disagree"):
        f(*args, gamma=0.3, b=0.05, mass=0.1)


@pytest.mark.parametrize("rel", [0.0, 5e-13, 2e-12, 1e-9])
def test_redundant_damping_is_accepted_exactly_where_scene_accepts_it(rel):
    gamma = 0.5 * (1 + rel)
    try:
        pendula.Scene(0.3, t=[0.0, 1.0], gamma=gamma, b=0.05, mass=0.1)
        scene_ok = True
    except ValueError:
        scene_ok = False
    try:
        pendula.linear_damped(1.0, 0.3, gamma=gamma, b=0.05, mass=0.1)
        ours = True
    except ValueError:
        ours = False
    assert ours == scene_ok == (rel < 1e-12)


def test_undamped_linear_model_is_the_small_angle_model():
    """Damping left out means gamma = 0: the linear damped motion is then the
    small-angle motion, for the same (default) pendulum."""
    t = np.linspace(0.0, 10.0, 7)
    th, om = pendula.linear_damped(t, 0.1, 0.2)
    sa, so = pendula.small_angle(t, 0.1, 0.2)
    np.testing.assert_allclose(th, sa, rtol=0, atol=8 * EPS)
    np.testing.assert_allclose(om, so, rtol=0, atol=8 * EPS)


def test_damping_regime_of_the_texts_runs():
    """§2.2: b = 0.01 and 0.05 kg/s, m = 0.1 kg on the text's pendulum: under-damped."""
    for b in (0.01, 0.05):
        r = pendula.damping_regime(b=b, mass=0.1)
        assert r.regime == "underdamped" and r.w0 == W0_TEXT and r.gamma == b / 0.1
