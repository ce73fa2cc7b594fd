"""pendula.AngleWarning: an amplitude |theta0| > 2 pi on a swinging pendulum is
almost surely degrees given as radians (period(90)); rotations and trajectory
angles are legitimate and never warn."""

import math
import warnings

import numpy as np
import pytest

import pendula

EPS = np.finfo(float).eps

# the functions where theta0 is an amplitude: name -> call with theta0 (and omega0)
AMPLITUDE_FUNCS = {
    "period": lambda th, om=0.0: pendula.period(th, om, w0=1.0),
    "amplitude": lambda th, om=0.0: pendula.amplitude(th, om, w0=1.0),
    "small_angle": lambda th, om=0.0: pendula.small_angle(1.0, th, om, w0=1.0),
    "small_angle_error": lambda th, om=0.0: pendula.small_angle_error(5.0, th, om, w0=1.0),
}
# the functions where any angle is a state or a point of a trajectory
STATE_FUNCS = {
    "undamped": lambda th, om=0.0: pendula.undamped(1.0, th, om, w0=1.0),
    "energy": lambda th, om=0.0: pendula.energy(th, om, w0=1.0),
    "elliptic_parameter": lambda th, om=0.0: pendula.elliptic_parameter(th, om, w0=1.0),
    "regime": lambda th, om=0.0: pendula.regime(th, om, w0=1.0),
}


def _caught(fn, *args):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fn(*args)
    return result, [w for w in caught if issubclass(w.category, pendula.AngleWarning)]


def test_angle_warning_is_a_public_user_warning():
    assert issubclass(pendula.AngleWarning, UserWarning)
    assert "AngleWarning" in pendula.__all__


@pytest.mark.parametrize("name", sorted(AMPLITUDE_FUNCS))
def test_degrees_as_radians_warn_once_naming_theta0_and_how_to_silence(name):
    _, caught = _caught(AMPLITUDE_FUNCS[name], 90.0)
    assert len(caught) == 1
    msg = str(caught[0].message)
    assert "theta0 = 90.0" in msg and "degrees" in msg and "numpy.radians" in msg
    assert "filterwarnings('ignore', category=pendula.AngleWarning)" in msg
    assert caught[0].filename == __file__  # points at the caller's line, not into pendula
    # an array with one such element warns once, naming that element
    _, caught = _caught(AMPLITUDE_FUNCS[name], np.array([0.1, -45.0, 30.0]))
    assert len(caught) == 1 and "theta0 = -45.0" in str(caught[0].message)


@pytest.mark.parametrize("name", sorted(AMPLITUDE_FUNCS))
def test_no_warning_within_two_pi_or_for_a_rotation(name):
    fn = AMPLITUDE_FUNCS[name]
    for theta0 in (0.0, 1.0, -3.0, math.pi, 2 * math.pi, -2 * math.pi, 6.2):
        assert not _caught(fn, theta0)[1], theta0
    # going over the top: theta0 counts turns legitimately (m > 1)
    assert not _caught(fn, 90.0, 3.0)[1]
    assert not _caught(fn, np.array([7.0, -50.0]), np.array([2.5, -2.5]))[1]
    # the separatrix is not a rotation: the pendulum still swings up to the top
    assert _caught(fn, 3 * math.pi)[1]


@pytest.mark.parametrize("name", sorted(STATE_FUNCS))
def test_states_and_trajectory_angles_never_warn(name):
    assert not _caught(STATE_FUNCS[name], 90.0)[1]
    assert not _caught(STATE_FUNCS[name], np.array([1e3, -1e6]))[1]


def test_silenced_by_the_filter_the_message_gives():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", category=pendula.AngleWarning)
        pendula.period(90)
    assert not caught


def test_the_warning_does_not_change_the_answer():
    """The angle is used as given: 90 rad swings like 90 - 14 * 2 pi rad."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pendula.AngleWarning)
        big = pendula.period(90.0, w0=1.0)
        amp = pendula.amplitude(90.0, w0=1.0)
    reduced = 90.0 - 14 * 2 * math.pi
    assert abs(big - pendula.period(reduced, w0=1.0)) <= 64 * EPS * big
    assert abs(amp - abs(reduced)) <= 64 * EPS


def test_bad_input_raises_instead_of_warning():
    """A non-finite or invalid state is refused by its own check, not warned about."""
    for kw in (dict(theta0=math.inf), dict(theta0=90.0, w0=-1.0), dict(theta0=90.0, omega0=math.nan)):
        with warnings.catch_warnings():
            warnings.simplefilter("error", pendula.AngleWarning)
            with pytest.raises(ValueError):
                pendula.period(**kw)
