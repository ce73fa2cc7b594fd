"""Integer arguments are range-checked exactly before any cast that could wrap."""

import numpy as np
import pytest
from helpers import needs_cvode

import pendula
from pendula._arrays import integer_arg

WRAPPING = [
    2**31,
    2**63,
    2**64 - 1,
    np.uint64(2**63),
    np.uint64(2**64 - 1),
    -(2**63) - 1,
    np.array([2**63], dtype=np.uint64),
    [1, 2**70],
]


@pytest.mark.parametrize("n", WRAPPING, ids=repr)
def test_equilibria_refuses_out_of_range_n(n):
    with pytest.raises(ValueError, match=r"n = .* out of range: it must be an integer in \[-2147483647, 2147483647\]"):
        pendula.equilibria(n)


@pytest.mark.parametrize("n", [True, np.bool_(False), np.array([True]), 1.0, "3"], ids=repr)
def test_equilibria_refuses_bool_and_non_integers(n):
    with pytest.raises(TypeError, match="n must be"):
        pendula.equilibria(n)


@pytest.mark.parametrize("n", [np.int8(-3), np.uint8(250), np.uint64(7), 2**31 - 1, -(2**31 - 1)], ids=repr)
def test_equilibria_accepts_every_integer_type_in_range(n):
    theta, lam, kind = pendula.equilibria(n)
    assert theta == pendula.equilibria(int(n))[0]
    assert kind == ("centre" if int(n) % 2 == 0 else "saddle")


@pytest.mark.parametrize("x", [2**63, np.uint64(2**64 - 1), 0, -1])
def test_integer_arg_scalar_counts(x):
    with pytest.raises(ValueError, match=r"max_steps = -?\d+ is out of range"):
        integer_arg(x, "max_steps", 1, 2**63 - 1, scalar=True)
    with pytest.raises(TypeError, match="max_steps must be an integer, got ndarray"):
        integer_arg(np.array([5]), "max_steps", 1, 2**63 - 1, scalar=True)


@needs_cvode
@pytest.mark.parametrize(
    "kw",
    [
        dict(max_steps=np.uint64(2**64 - 1)),
        dict(max_steps=2**63),
        dict(events=True, max_events=np.uint64(2**63)),
        dict(events=True, max_events=2**64),
    ],
    ids=repr,
)
def test_cvode_counts_do_not_wrap(kw):
    name = "max_events" if "max_events" in kw else "max_steps"
    with pytest.raises(ValueError, match=f"{name} = .* out of range"):
        pendula.cvode([0.0, 1.0], 0.1, 0.0, 1.0, 0.0, **kw)


@pytest.mark.parametrize("kw", [dict(repeat=np.uint64(2**64 - 1)), dict(max_steps=2**64), dict(repeat=True)], ids=repr)
def test_tradeoff_counts_do_not_wrap(kw):
    scene = pendula.Scene(theta0=0.3, t=np.linspace(0.0, 1.0, 5))
    with pytest.raises((ValueError, TypeError), match=next(iter(kw))):
        pendula.tradeoff(scene, **kw)
