import math

import pytest

from clutchlab.units import UnitError, to_si


@pytest.mark.parametrize(
    "text, unit, expected",
    [
        ("2.3 mm", "m", 2.3e-3),
        ("206 GPa", "Pa", 206e9),
        ("5500 rpm", "rad/s", 5500 * 2 * math.pi / 60),
        ("173 N·m", "N m", 173.0),
        ("173 N*m", "N m", 173.0),
        ("0.021 kg·m²", "kg m^2", 0.021),
        ("11 °", "rad", math.radians(11)),
        ("4.6 g", "kg", 4.6e-3),
        ("0.4", "1", 0.4),
        (2.5, "m", 2.5),
        (3, "Pa", 3.0),
    ],
)
def test_to_si(text, unit, expected):
    assert to_si(text, unit) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("bad", ["2.3 kg", "abc mm", "nan", True, None, [1.0]])
def test_bad_quantities(bad):
    with pytest.raises(UnitError):
        to_si(bad, "m")
