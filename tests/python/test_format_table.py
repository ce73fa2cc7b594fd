"""The power-of-five table in src/core/pendula_format_digits.f90 is the output
of tools/gen/gen_pow5_table.py (exact rational arithmetic), verbatim, and each
entry is 5**(22 q) to within 2**-106 -- checked here again with Python integers,
independently of the generator's own assertion."""

import contextlib
import io
from fractions import Fraction

from helpers import ROOT, load_generator, needs_source

pytestmark = needs_source


def _generated():
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        load_generator("gen_pow5_table").main()
    return out.getvalue()


def test_table_in_source_is_the_generator_output():
    source = (ROOT / "src" / "core" / "pendula_format_digits.f90").read_text()
    assert _generated() in source


def test_table_entries_are_powers_of_five_to_106_bits():
    gen = load_generator("gen_pow5_table")
    for q in range(gen.Q_MIN, gen.Q_MAX + 1):
        hi, lo, ex = gen.entry(q)
        assert 1 <= hi < 2 and abs(lo) <= 2.0**-53
        exact = Fraction(5) ** (gen.STEP * q)
        approx = (Fraction(hi) + Fraction(lo)) * Fraction(2) ** ex
        assert abs(approx - exact) <= exact / 2**106, q
