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


TWO_PI = 2 * math.pi


@pytest.mark.parametrize(
    "text, expected",
    [
        # a frequency without an angle is revolutions per time (x 2 pi)
        ("91.67 Hz", 91.67 * TWO_PI),
        ("0.09167 kHz", 91.67 * TWO_PI),
        ("91670 mHz", 91.67 * TWO_PI),
        ("5500 1/min", 5500 * TWO_PI / 60),
        ("5500 min^-1", 5500 * TWO_PI / 60),
        # with an angle: as written
        ("5500 rpm", 5500 * TWO_PI / 60),
        ("91.67 rps", 91.67 * TWO_PI),
        ("91.67 rev/s", 91.67 * TWO_PI),
        ("5500 rev/min", 5500 * TWO_PI / 60),
        ("5500 turn/min", 5500 * TWO_PI / 60),
        ("91.67 cycle/s", 91.67 * TWO_PI),
        ("360 deg/s", TWO_PI),
        ("576 rad/s", 576.0),
        ("576", 576.0),  # a bare number: SI rad/s
    ],
)
def test_an_angular_speed_given_as_a_frequency_is_revolutions_per_time(text, expected):
    assert to_si(text, "rad/s") == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    "text, kind, expected",
    [
        ("40 degC", "absolute", 313.15),
        ("40 °C", "absolute", 313.15),
        ("104 degF", "absolute", 313.15),
        ("313.15 K", "absolute", 313.15),
        ("563.67 degR", "absolute", 313.15),
        ("-273.15 degC", "absolute", 0.0),
        # a difference: degC, K and delta_degC alike, degF x 5/9, never an offset
        ("10 degC", "difference", 10.0),
        ("10 K", "difference", 10.0),
        ("10 delta_degC", "difference", 10.0),
        ("18 degF", "difference", 10.0),
        ("18 delta_degF", "difference", 10.0),
        (10, "difference", 10.0),
        ("10", "difference", 10.0),
    ],
)
def test_temperatures_are_read_by_their_kind(text, kind, expected):
    assert to_si(text, "K", kind) == pytest.approx(expected, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize(
    "text, unit, expected",
    [
        ("0.01 1/degC", "1/K", 0.01),  # inside a compound unit a temperature is a difference
        ("0.01 1/degF", "1/K", 0.018),
        ("40 W/(m^2*degC)", "W/(m^2*K)", 40.0),
        ("40 W/(m^2*K)", "W/(m^2*K)", 40.0),
    ],
)
def test_a_temperature_in_a_compound_unit_is_a_difference(text, unit, expected):
    assert to_si(text, unit) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    "bad, kind, fragment",
    [
        (40, "absolute", "needs a unit"),
        (313.15, "absolute", "needs a unit"),
        ("40", "absolute", "needs a unit"),
        ("500 delta_degC", "absolute", "difference"),
        ("900 delta_degF", "absolute", "difference"),
        ("40 C", "absolute", "coulomb"),
    ],
)
def test_an_absolute_temperature_needs_a_unit_on_the_scale(bad, kind, fragment):
    with pytest.raises(UnitError, match=fragment):
        to_si(bad, "K", kind)


def test_a_temperature_needs_its_kind():
    with pytest.raises(ValueError):
        to_si("40 degC", "K")


@pytest.mark.parametrize(
    "text, unit, kind, expected",
    [
        ("20 %", "1", None, 0.2),  # a percentage is a hundredth
        ("200 permille", "1", None, 0.2),
        ("0.2", "1", None, 0.2),
        ("11 deg", "rad", None, math.radians(11)),
        ("0.03 turn", "rad", None, 0.03 * TWO_PI),
        ("11 gon", "rad", None, 11 * math.pi / 200),
        (0.19, "rad", None, 0.19),
        ("4498 N*m/rad", "N m/rad", None, 4498.0),
        ("78.5 N*m/deg", "N m/rad", None, 78.5 * 180 / math.pi),
        ("173 N*m", "N m", None, 173.0),
        ("0.173 kN*m", "N m", None, 173.0),
        ("127.6 lbf*ft", "N m", None, 127.6 * 1.3558179483314004),
        ("17.64 kgf*m", "N m", None, 17.64 * 9.80665),
        ("5.8 kJ", "J", None, 5800.0),  # work: J and N m alike
        ("5.8 kN*m", "J", None, 5800.0),
        ("5800 W*s", "J", None, 5800.0),
        (12, "1", "count", 12.0),
        ("12", "1", "count", 12.0),
        # a coefficient of the speed squared per (rad/s)^2, per rpm^2 or per (rev/s)^2
        ("2e-5 N*m*s^2", "N m s^2", None, 2e-5),
        ("2e-5 N*m/(rad/s)^2", "N m s^2", None, 2e-5),
        ("1 N*m/rpm^2", "N m s^2", None, (30 / math.pi) ** 2),
        ("2 N*m/(rev/s)^2", "N m s^2", None, 2 / TWO_PI**2),
        ("1 N*m/(rev/min)^2", "N m s^2", None, (30 / math.pi) ** 2),
        ("1 N*m*min^2/rev^2", "N m s^2", None, (30 / math.pi) ** 2),
        ("35 N*min/mm", "N s/m", None, 35 * 60 / 1e-3),  # a damping, not a speed coefficient
    ],
)
def test_units_of_the_right_kind(text, unit, kind, expected):
    assert to_si(text, unit, kind) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    "bad, unit, kind, fragment",
    [
        ("20 deg", "1", None, "angle"),  # pint: 0.349
        ("0.35 rad", "1", None, "angle"),
        ("0.1 rev", "1", None, "angle"),
        ("20 °", "1", None, "angle"),
        ("11 %", "rad", None, "angle"),
        ("0.2 dimensionless", "rad", None, "angle"),
        ("4498 N*m", "N m/rad", None, "no angle"),
        ("100 1/s^2", "rad/s^2", None, "no angle"),
        ("173 J", "N m", None, "not written as a torque"),  # pint: 173 N m
        ("0.173 kJ", "N m", None, "not written as a torque"),
        ("1e-4 kWh", "N m", None, "not written as a torque"),
        ("173 W*s", "N m", None, "not written as a torque"),
        ("173 kg*m^2/s^2", "N m", None, "not written as a torque"),
        ("127.6 foot_pound", "N m", None, "not written as a torque"),
        ("0.7 kg*m^2", "N m s^2", None, "not written as a torque"),
        ("1 N*m/Hz^2", "N m s^2", None, "per revolutions"),  # per (rev/s)^2: 39.5x
        ("1 N*m/rad^2", "N m s^2", None, "a torque per speed squared"),
        ("12 %", "1", "count", "count"),
        ("12 dimensionless", "1", "count", "count"),
        ("1.5 ton*m^2", "kg m^2", None, "short ton"),  # pint: the US short ton
        ("134 hp", "W", None, "horsepower"),  # mechanical or metric?
        ("2 tonf", "N", None, "tonne-force"),
        ("2.3 mil", "m", None, "angle"),  # pint: an angular mil, not a thou
    ],
)
def test_units_of_the_wrong_kind_are_refused(bad, unit, kind, fragment):
    with pytest.raises(UnitError, match=fragment):
        to_si(bad, unit, kind)


@pytest.mark.parametrize(
    "bad, unit",
    [
        ("1 2²²²²²", "1"),  # pint read 2**2**2**2**2**2 = 2^(2^65536): minutes, then 21 GB
        ("1 m²²²²²²", "m"),
        ("1 m^2^3", "m^8"),
        ("1 m**(2*2)**(3*3)", "m"),
        ("1 m^", "m"),
    ],
)
def test_an_exponent_is_one_number_and_a_tower_is_refused_at_once(bad, unit):
    """A unit's exponent is one number: a power of a power is refused before pint evaluates its
    tower with Python integers (an unbounded computation that a CI worker was killed for)."""
    import time

    to_si("1 m", "m")  # (pint's registry loaded outside the timing)
    start = time.perf_counter()
    with pytest.raises(UnitError, match="an exponent is one number"):
        to_si(bad, unit)
    assert time.perf_counter() - start < 1.0
    assert to_si("2 (m^2)^3", "m^6") == 2.0 and to_si("4 m^(-2)", "1/m^2") == 4.0


@pytest.mark.parametrize(
    "given, si_unit, fragment",
    [
        # the kind is told before a missing angle or a torque written as an energy
        ("4498 N/m", "N m/rad", "is a stiffness (force per length); this value is a torsional"),
        ("4498 N*m/s", "N m/rad", "is a power"),
        ("150 oz*in", "N m", "a mass times a length"),
        ("173 Nm", "N m", "write N*m"),
        ("173 N-m", "N m", "units joined by * and /"),
        ("40 F", "K", "farad"),
        ("40 W/m^2", "W/(m^2*K)", "a heat flux"),
        ("570 rad/s^2", "rad/s", "an angular acceleration"),
    ],
)
def test_a_unit_of_another_kind_is_told_in_words(given, si_unit, fragment):
    kind = "absolute" if si_unit == "K" else None
    with pytest.raises(UnitError) as exc:
        to_si(given, si_unit, kind)
    assert fragment in str(exc.value)


def test_a_damping_in_kg_per_s_is_read():
    """N s/m is kg/s: no torque in it (it used to be refused as a torque written as an energy)."""
    assert to_si("2.1e3 kg/s", "N s/m") == pytest.approx(2100.0)


@pytest.mark.parametrize(
    "given, si_unit, fragment",
    [
        # per second: DIN writes a rotational frequency n and an angular speed ω both in s^-1
        ("570 1/s", "rad/s", "write rev/s, rps or rad/s"),
        ("570 s^-1", "rad/s", "write rev/s, rps or rad/s"),
        ("570 s⁻¹", "rad/s", "write rev/s, rps or rad/s"),
        # names read otherwise than an engineer writes them
        ("89 mil", "rad", "mrad or deg for an angle"),
        ("11 grad", "rad", "write deg, or gon for the gradian"),
        ("11 Grad", "rad", "gigaradian"),
        ("134 mhp", "W", "write W or kW"),
        ("134 bhp", "W", "write W or kW"),
        ("1e-400 mm", "m", "too small for a double"),
        ("1e-310 mm", "m", "too small for a double in m"),
        # near misses named with the spelling meant
        ("5 Nmm", "N m", "write N*mm"),
        ("5 MPA", "Pa", "write MPa"),
        ("5 RPM", "rad/s", "write rpm"),
        ("80 lb*ft", "N m", "lbf*ft"),
        ("2.1*10^6 N*s/m", "N s/m", "write one number, then units joined by * and /"),
        ("2 000 rpm", "rad/s", "e.g. 2.1e6 N*s/m, 2000 rpm"),
        # a / followed by a product: what divides goes in parentheses
        ("40 W/m^2*K", "W/(m^2*K)", "put what divides in parentheses"),
        ("0.2 cm^3/kW*h", "m^3/J", "this value is a volume per work (a specific wear rate)"),
        ("1e999 kg*m^2", "kg m^2", "write .inf where infinity is meant"),
        ("4498 N*m/rad^2", "N m/rad", "an angle to the power -2 in its unit"),
        ("2.31e", "m", "an exponent needs its digits"),
        ("12 pct", "1", "picocarat (a mass): write %"),
        ("0.12 µ", "m", "atomic mass unit"),
        ("1.2 dB", "1", "a logarithmic unit"),
        ("136 PS", "W", "not a metric horsepower"),
        ("2.1 k N*s/mm", "N s/m", "Boltzmann's constant"),
        ("10 MM", "m", "write mm"),
        # no arithmetic and nothing after the unit (pint would drop or evaluate it)
        ("2.3 mm;", "m", "nothing after it"),
        ("20 %%", "1", "nothing after it"),
        ("0.0333 1/ms", "rad/s", "write rev/s, rps or rad/s"),
        ("2000 r/min", "rad/s", "write rev (r/min is rpm)"),
        ("2.3 mm*1.0", "m", "no number in it but its exponents"),
        ("2.3 mm*10**0", "m", "no number in it but its exponents"),
    ],
)
def test_a_unit_an_engineer_may_mean_otherwise_is_refused_saying_what_to_write(
    given, si_unit, fragment
):
    with pytest.raises(UnitError) as exc:
        to_si(given, si_unit)
    assert fragment in str(exc.value), str(exc.value)
    assert "[" not in str(exc.value).split("(its dimensions")[0], str(exc.value)


@pytest.mark.parametrize(
    "given, si_unit, kind, expected",
    [
        ("3041 N·mm⁻²", "Pa", None, 3.041e9),
        ("40 ℃", "K", "absolute", 313.15),
        ("104 ℉", "K", "absolute", 313.15),
        ("40 W/(m^2*K)", "W/(m^2*K)", None, 40.0),
        ("0.2 cm^3/(kW*h)", "m^3/J", None, 0.2e-6 / 3.6e6),
        ("0 mm", "m", None, 0.0),
        ("5.5E3 rpm", "rad/s", None, 5500 * TWO_PI / 60),
        ("5 m^(-2)", "1/m^2", None, 5.0),
        # the Unicode minus, a leading slash, the ordinal and ring for a degree, in. and ft.
        ("5 m^(−2)", "1/m^2", None, 5.0),
        ("−10 °C", "K", "absolute", 263.15),
        ("1.2e-5 /°C", "1/K", None, 1.2e-5),
        ("40 ºC", "K", "absolute", 313.15),
        ("40˚C", "K", "absolute", 313.15),
        ("0.024 in.", "m", None, 0.0006096),
        ("1 N*m/(1/s)^2", "N m s^2", None, 1.0),
    ],
)
def test_superscript_minus_and_the_degree_signs_are_read(given, si_unit, kind, expected):
    assert to_si(given, si_unit, kind) == pytest.approx(expected, rel=1e-12)


def test_a_converted_value_is_the_decimal_the_user_wrote():
    """2.6 mm was stored as 0.0026000000000000003 m (the conversion's last digit), and a grid's
    0.45 as 0.44999999999999996: ``ds.sel(sheet_thickness=2.6e-3)`` raised KeyError. A value
    converted by a power of ten is kept to 15 digits, so it is the decimal written (near the
    largest double, as it is), and so are a grid's points between decimal ends; any other
    conversion, and a grid's ends, as they are (``np.deg2rad(65)`` finds 65 deg)."""
    import numpy as np

    from clutchlab import config
    from clutchlab.units import to_si

    assert to_si("2.6 mm", "m") == 2.6e-3 and to_si("4.48 mm", "m") == 4.48e-3
    assert to_si("18 mm", "m") == 0.018 and to_si("40 degC", "K", "absolute") == 313.15
    assert to_si("1.7976931348623157e+308 m", "m") == 1.7976931348623157e308
    assert to_si("65 deg", "rad") == np.deg2rad(65)
    sec = config.resolve(
        {
            "studies": ["centrifugal"],
            "centrifugal": {
                "design": "factorial",
                "parameters": {
                    "friction_coefficient": {"min": 0.25, "max": 0.6, "num": 8},
                    "pressure_angle": {"min": "25 deg", "max": "65 deg", "num": 4},
                },
            },
        }
    )["centrifugal"]
    assert sec["factors"]["friction_coefficient"]["values"][4] == 0.45
    assert sec["factors"]["pressure_angle"]["values"][-1] == np.deg2rad(65)
