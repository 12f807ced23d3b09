"""Quantities written by engineers ("2.3 mm", "5500 rpm", "206 GPa", "40 degC") converted to SI.

A bare number is taken as already in SI, except where that cannot be what was meant (an absolute
temperature: "40" is refused, give "40 degC" or "313.15 K"). Parsing uses pint, the maintained
standard for unit-aware arithmetic in Python; the registry is built lazily so that importing
clutchlab (e.g. inside a chunk job) does not pay for it.

pint treats the radian as dimensionless and the joule as a newton metre, so it would read a
friction coefficient of "20 deg" as 0.349, a speed of "91.67 Hz" as 91.67 rad/s and a torque of
"173 J" as 173 N m. :func:`to_si` looks at the unit expression, not only at its dimension:

* an angular speed (SI rad/s) given as a frequency without an angle (Hz, kHz, 1/min) is
  revolutions per time and multiplied by 2π; rpm, rps, rad/s, deg/s, rev/s, turn/min are read as
  written; per second alone (1/s, 1/ms) is refused: engineers write rev/s and rad/s so alike;
* an angle unit (deg, rad, rev) on a quantity without an angle is refused, and so is a unit
  without an angle on an angle (an angle given as a bare number is SI, radians) or on another
  quantity with an angle in it (N m/rad, rad/s²);
* a coefficient of the angular speed squared (SI N m s², per (rad/s)²) refuses Hz and minutes
  (they would be per revolutions: 1 N m/Hz² is 0.0253 N m s², not 1);
* a torque (SI N m and its compounds) must be written as a force times a length (N*m, kN*m,
  lbf*ft): an energy unit (J, kJ, kWh) is refused; an energy or work accepts J, kJ and N*m alike;
* temperatures have a kind: an absolute temperature needs a unit (degC and degF are read with
  their offset; a difference unit such as delta_degC is refused), a temperature difference reads
  degC, K and delta_degC as the same difference and degF as 5/9 K (never an offset); inside a
  compound unit (1/K, W/(m^2 K)) a temperature is always a difference;
* a dimensionless quantity takes a bare number or a scale such as % (20 % = 0.2), ppm, permille;
  a count takes a bare whole number only;
* names pint reads otherwise than engineers mean (U, grad, mil, any horsepower, PS, pct, k, M
  alone) are refused saying what to write, and so is a number inside the unit (mm*1.0: pint
  would evaluate it) or punctuation after it; a near miss of a spelling (Nmm, MPA) names the
  spelling meant.
"""

from __future__ import annotations

import functools
import math
import numbers
import re
import sys

__all__ = ["UnitError", "to_si", "KINDS"]

_REPLACE = {
    "⁻¹": "**-1",  # (before ¹, ², ³ alone: m⁻² is m**-2)
    "⁻²": "**-2",
    "⁻³": "**-3",
    "℃": " degC",
    "℉": " degF",
    "−": "-",  # (the Unicode minus)
    "º": "°",  # (the ordinal sign and the ring, written for a degree)
    "˚": "°",
    "·": "*",
    "⋅": "*",
    "²": "**2",
    "³": "**3",
    "⁴": "**4",
    "µ": "u",
    "μ": "u",
    "°": " deg",  # (after º and ˚: they become °)
}

#: what a quantity is beyond its SI unit: an absolute temperature or a temperature difference
#: (SI unit K), a count (a whole number, SI unit 1, no unit accepted)
KINDS = ("absolute", "difference", "count")

# one number, then (optionally) a unit expression with no number in it: pint alone would evaluate
# "2 3 mm" as 6 mm and "2,3 mm" as 23 mm, both silent misreads of what an engineer wrote
_NUMBER = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$", re.S)

# an exponent is one number, e.g. m^2, s**-1, m^(-2): pint evaluates an exponent's expression with
# Python integers, so a tower ("2**2**2", "m^2^3", "m²²" once ² is read as **2) is refused before
# pint sees it — "2²²²²²" = 2^(2^65536) never ends and fills the memory
_EXPONENT = re.compile(r"\*\*|\^")
_ONE_NUMBER = re.compile(
    r"\s*(?:\(\s*[+-]?[\d.]+(?:[eE][+-]?\d+)?\s*\)|[+-]?[\d.]+(?:[eE][+-]?\d+)?)"
)


def _exponents_are_numbers(unit: str) -> bool:
    """Whether every exponent of a unit expression is one number, not raised to a power again."""
    for op in _EXPONENT.finditer(unit):
        operand = _ONE_NUMBER.match(unit, op.end())
        if operand is None or _EXPONENT.match(unit[operand.end() :].lstrip()):
            return False
    return True


# unit names whose meaning depends on the country (pint takes the US one): refused, with a spelling
# that says which is meant
_AMBIGUOUS = {
    "ton": "the US short ton (907 kg) or the tonne? write t (tonne) or short_ton",
    "tons": "the US short ton (907 kg) or the tonne? write t (tonne) or short_ton",
    "tonf": "a short ton-force or a tonne-force? write kN (or tf: tonne-force)",
    "ton_force": "a short ton-force or a tonne-force? write kN (or tf: tonne-force)",
    "hp": "a mechanical (745.7 W) or a metric (735.5 W) horsepower? write W or kW",
    "Nm": "Nm is not read as a newton metre: write N*m",
    "kNm": "kNm is not read as a kilonewton metre: write kN*m",
    "U": "U is read as the enzyme unit, not a revolution (U/min): write rpm or rev/min",
    "grad": "grad is the gradian (400 to a turn), not a degree (Grad): write deg, or gon for "
    "the gradian",
    "Grad": "Grad is read as a gigaradian, not a degree: write deg",
    "mil": "a thousandth of an inch or an angular mil (pint: 1/6400 of a turn)? write in or mm "
    "for a length, mrad or deg for an angle",
    "mils": "a thousandth of an inch or an angular mil? write in or mm, or mrad or deg",
    "pct": "pct is read as a picocarat (a mass): write %",
    "u": "µ alone is read as the atomic mass unit: write the unit after its prefix (µm)",
    "dB": "a logarithmic unit: write a plain number",
    "PS": "PS is read as petasiemens, not a metric horsepower (735.5 W): write W or kW",
    "k": "k alone is read as Boltzmann's constant: write the prefix on its unit (kN*s/mm)",
    "M": "M alone is read as molar: write the prefix on its unit (MPa, MN)",
    "MM": "MM is read as megamolar: write mm",
}

# any horsepower, prefixed or not (mhp: a milli-horsepower to pint, a metric one to some)
_HORSEPOWER = re.compile(r"^[A-Za-z]?(hp|horsepower)$")

# near misses of a unit's spelling, and the spelling meant
_SPELLINGS = {
    "nmm": "N*mm",
    "ncm": "N*cm",
    "kp": "kgf",
    "kpm": "kgf*m",
    "mpa": "MPa",
    "gpa": "GPa",
    "kpa": "kPa",
    "kn": "kN",
    "kj": "kJ",
    "kw": "kW",
    "rpm": "rpm",
    "degc": "degC",
    "degf": "degF",
    "celsius": "degC",
    "fahrenheit": "degF",
    "lbft": "lbf*ft",
    "lbfft": "lbf*ft",
    "ozin": "ozf*in",
    "m2": "m^2",
    "mm2": "mm^2",
    "cm2": "cm^2",
    "m3": "m^3",
    "mm3": "mm^3",
    "cm3": "cm^3",
    "ws": "W*s",
    "r": "rev (r/min is rpm)",
    "nms": "N*m*s",
}

# temperature units with an offset, and the difference each means inside a difference
_OFFSET = {
    "degree_Celsius": "delta_degree_Celsius",
    "degree_Fahrenheit": "delta_degree_Fahrenheit",
    "degree_Reaumur": "delta_degree_Reaumur",
}


class UnitError(ValueError):
    """A quantity could not be parsed, has the wrong dimension or a unit of the wrong kind."""


@functools.lru_cache(maxsize=1)
def _registry():
    import pint

    ureg = pint.UnitRegistry()
    ureg.define("rev = revolution")  # rev/s, rev/min: read as written (revolutions)
    return ureg


def to_si(value, si_unit: str, kind: str | None = None) -> float:
    """Convert ``value`` to a float in ``si_unit``.

    Parameters
    ----------
    value : float, int or str
        A bare number (taken as SI already) or a string "number unit", e.g. ``"2.3 mm"``: exactly
        one number (no comma, no arithmetic) followed by a unit expression (``"N m"``,
        ``"kg m^2"``).
    si_unit : str
        Target SI unit in pint/UDUNITS spelling, e.g. ``"m"``, ``"Pa"``, ``"rad/s"``, ``"1"``.
    kind : {None, "absolute", "difference", "count"}
        ``"absolute"`` or ``"difference"`` for a temperature (``si_unit`` K; required there);
        ``"count"`` for a whole number (no unit accepted).

    Returns
    -------
    float
        The value in ``si_unit`` (finite).

    Raises
    ------
    UnitError
        If the string cannot be parsed, its dimension differs from ``si_unit``'s or its unit is of
        the wrong kind (see the module docstring).
    """
    if si_unit == "K" and kind not in ("absolute", "difference"):
        raise ValueError("a temperature (K) needs kind 'absolute' or 'difference'")
    if kind not in (None, *KINDS):
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    if isinstance(value, bool):
        raise UnitError(f"expected a quantity, got the boolean {value!r}")
    if isinstance(value, numbers.Real):
        return _bare(float(value), value, si_unit, kind)
    if not isinstance(value, str):
        raise UnitError(
            f"expected a number or a 'number unit' string, got {type(value).__name__} {value!r}"
        )
    number, unit = _split(value)
    if unit.startswith("/"):  # "1.2e-5 /K": per kelvin
        unit = "1" + unit
    if not unit:  # "3.7": a bare number, SI like 3.7
        return _bare(number, value, si_unit, kind)
    if kind == "count":
        raise UnitError(f"{value!r}: a count is a bare whole number, without a unit")
    try:
        out = _convert(number, unit, value, si_unit, kind)
    except UnitError:
        raise
    except Exception as exc:  # pint's arithmetic on an absurd unit (m^1e308: OverflowError, ...)
        raise UnitError(f"cannot read the unit of {value!r}: {type(exc).__name__}") from None
    return _decimal(_finite(out, value), number)


def _split(value: str) -> tuple[float, str]:
    """The number and the unit text of a "number unit" string."""
    text = value.strip()
    for old, new in _REPLACE.items():
        text = text.replace(old, new)
    if "," in text:
        raise UnitError(
            f"{value!r}: a comma is not read as a decimal point or a thousands separator; "
            "write e.g. '2.3 mm'"
        )
    match = _NUMBER.fullmatch(text)
    if match is not None and re.match(r"[eE](\W|$)", text[match.end(1) :]):
        raise UnitError(f"{value!r}: an exponent needs its digits (2.31e3, 5e-3)")
    if match is None:
        raise UnitError(f"cannot parse quantity {value!r}: expected 'number unit', e.g. '2.3 mm'")
    number = float(match.group(1))
    if number == 0.0 and re.search(r"[1-9]", match.group(1).split("e")[0].split("E")[0]):
        raise UnitError(f"{value!r}: too small for a double (it would be read as 0)")
    return number, match.group(2)


def _bare(number: float, value, si_unit: str, kind) -> float:
    if si_unit == "K" and kind == "absolute":
        raise UnitError(
            f"{value!r}: an absolute temperature needs a unit, e.g. '40 degC', '104 degF' or "
            "'313.15 K' (a bare number would be kelvin)"
        )
    return _finite(number, value)


def _convert(number: float, unit: str, value, si_unit: str, kind) -> float:
    """``number`` in the unit expression ``unit`` converted to ``si_unit`` (kinds checked)."""
    ureg = _registry()
    if not _exponents_are_numbers(unit):
        raise UnitError(
            f"cannot read the unit of {value!r}: an exponent is one number (e.g. m^2, s^-1; "
            "m^6, not m^2^3)"
        )
    for word in re.findall(r"[A-Za-z_]+", unit):
        if word in _AMBIGUOUS:
            raise UnitError(f"{value!r}: {_AMBIGUOUS[word]}")
        if _HORSEPOWER.match(word):
            raise UnitError(f"{value!r}: {_AMBIGUOUS['hp']}")
    given = _parse(ureg, unit, value)
    _check_no_arithmetic(unit, value)
    names = dict(given._units)
    target = ureg.parse_units("dimensionless" if si_unit == "1" else si_unit)
    if _dims(ureg, given) != _dims(ureg, target):  # (an angle is a ratio to pint: not told here)
        raise UnitError(
            f"{value!r} is {_kind_name(ureg, given)}; this value is "
            f"{_SI_NAMES.get(si_unit) or _kind_name(ureg, target)} (in {si_unit}, or another unit "
            "of it)" + _division_hint(unit)
        )
    _check_speed_coefficient(ureg, given, target, value, si_unit)
    if _is_speed_coefficient(target) and _radians(ureg, given) == -2:
        target = target / ureg.radian**2  # per (rad/s)^2 or per rpm^2: SI N m s^2 is per (rad/s)^2
    factor = _angle_factor(ureg, given, target, value, si_unit)
    t = dict(target._units)
    if t.get("newton") == 1 and t.get("meter") == 1:  # a torque (N m, per angle, per speed²)
        _check_torque(ureg, names, value)
    if si_unit == "K":
        given = _temperature_unit(ureg, names, value, kind)
    out = float(ureg.Quantity(number, given).to(target).magnitude) * factor
    if number != 0.0 and abs(out) < sys.float_info.min and si_unit != "K":  # (0 K: -273.15 degC)
        raise UnitError(f"{value!r}: too small for a double in {si_unit} (it would be read as 0)")
    return out


# what a unit's dimensions are called (pint's own notation for the others)
_KIND_NAMES = {
    "[length]": "a length",
    "[mass]": "a mass",
    "[time]": "a time",
    "[temperature]": "a temperature",
    "1 / [time]": "a speed or a rate (per time)",
    "[length] / [time]": "a linear speed",
    "[length] / [time] ** 2": "an acceleration",
    "[length] ** 2": "an area",
    "[length] ** 3": "a volume",
    "[mass] * [length] / [time] ** 2": "a force",
    "[mass] * [length] ** 2 / [time] ** 2": "a torque or an energy",
    "[mass] / [length] / [time] ** 2": "a pressure or a stress",
    "[mass] * [length] ** 2": "a moment of inertia",
    "[mass] * [length] ** 2 / [time] ** 3": "a power",
    "[mass] / [time] ** 2": "a stiffness (force per length)",
    "[mass] / [time]": "a damping (force per speed)",
    "dimensionless": "a ratio, a count or an angle",
    "[current] * [time]": "an electric charge (C is the coulomb: degC is the Celsius degree)",
    "[current] ** 2 * [time] ** 4 / [mass] / [length] ** 2": (
        "a capacitance (F is the farad: degF is the Fahrenheit degree)"
    ),
    "[mass] / [time] ** 3": "a heat flux (power per area)",
    "[mass] / [time] ** 3 / [temperature]": "a heat transfer coefficient",
    "1 / [temperature]": "a coefficient per temperature",
    "1 / [time] ** 2": "an angular acceleration",
    "[mass] / [length] ** 3": "a density",
    "[length] * [time] ** 2 / [mass]": "a volume per work (a specific wear rate)",
    "[mass] * [length]": (
        "a mass times a length (a torque is a force times a length: N*m, lbf*ft, kgf*m)"
    ),
}


# what the SI units of clutchlab's values are (those pint's dimensions do not tell apart: an angle
# is dimensionless to it, so a torsional stiffness is a torque)
_SI_NAMES = {
    "rad/s": "a rotational speed",
    "N m": "a torque",
    "J": "an energy",
    "N m/rad": "a torsional stiffness",
    "rad": "an angle",
    "1": "a ratio or a count",
    "1/s": "a rate (per time)",
    "N m s^2": "a torque per speed squared",
}


def _check_no_arithmetic(unit: str, value) -> None:
    """A unit has no number in it but its exponents and the 1 of 1/min (pint would evaluate
    mm*1.0 or mm*10**0), and ends in a unit or its abbreviation's full stop (in.), not in other
    punctuation (2.3 mm;) or a second % (20 %%: 0.002 to pint)."""
    rest = re.sub(r"(\*\*|\^)\s*\(?\s*[+-]?\d+(\.\d+)?\s*\)?", "", unit)
    rest = re.sub(r"(?<![\w.])1\s*/", "", rest)
    if re.search(r"\d", rest) or re.search(r"[;:!?]\s*$|%\s*[%.]\s*$", unit):
        raise UnitError(
            f"cannot read the unit of {value!r}: write one number, then the unit alone, with no "
            "number in it but its exponents (m^2, 1/min) and nothing after it"
        )


def _division_hint(unit: str) -> str:
    """A hint where a / is followed by a product without parentheses (W/m^2*K is W*K/m^2)."""
    after = unit.split("/")[1] if "/" in unit else ""
    if not after.lstrip().startswith("(") and len(re.findall(r"[A-Za-z_]+", after)) > 1:
        return (
            ": a / divides by the next unit only; put what divides in parentheses, e.g. "
            "W/(m^2*K), cm^3/(kW*h)"
        )
    return ""


def _kind_name(ureg, unit) -> str:
    """What ``unit``'s dimensions are called ("a length"), or pint's notation for them."""
    dims = str(ureg.Quantity(1, unit).dimensionality)
    return _KIND_NAMES.get(dims, f"of no kind this config uses (its dimensions: {dims})")


def _parse(ureg, unit: str, value):
    """The pint unit of the unit text ``unit`` (of the config value ``value``)."""
    try:
        return ureg.parse_units(unit)
    except Exception as exc:  # pint raises several unrelated exception types
        unknown = getattr(exc, "unit_names", None)  # (pint's UndefinedUnitError)
        if unknown:
            unknown = [unknown] if isinstance(unknown, str) else list(unknown)
            names = ", ".join(repr(u) for u in unknown)
            meant = [_SPELLINGS[u.lower()] for u in unknown if u.lower() in _SPELLINGS]
            hint = f"write {', '.join(meant)}" if meant else "e.g. mm, rpm, deg, MPa, N*m, degC"
            raise UnitError(
                f"cannot read the unit of {value!r}: {names} is not a unit ({hint}; the config "
                "page lists the spellings)"
            ) from None
        raise UnitError(
            f"cannot read the unit of {value!r}: write one number, then units joined by * and / "
            "(e.g. 2.1e6 N*s/m, 2000 rpm, 0.01 1/K, 11.5 deg, 40 degC)"
        ) from None


def _dims(ureg, unit):
    return ureg.Quantity(1, unit).dimensionality


def _radians(ureg, unit) -> int:
    """Exponent of the radian in ``unit``'s root units (0: no angle in it)."""
    return int(dict(ureg.get_root_units(unit)[1]._units).get("radian", 0))


def _angle_factor(ureg, given, target, value, si_unit: str) -> float:
    """1, or 2π for an angular speed given as a frequency; refuses an angle where none belongs
    and a missing angle where one does."""
    have, want = _radians(ureg, given), _radians(ureg, target)
    if have == want:
        return 1.0
    time = dict(ureg.get_root_units(target)[1]._units).get("second", 0)
    if have == 0 and want == 1 and time == -1 and len(target._units) <= 2:
        if (
            len(given._units) == 1
            and next(iter(given._units.items()))[1] == -1
            and next(iter(given._units)).endswith("second")
        ):  # (1/s, 1/ms, 1/ks: per a time in seconds)
            raise UnitError(
                f"{value!r}: per second is a rotational frequency n in rev/s (DIN's "
                "n = 9.5 s^-1) or an angular speed ω in rad/s (ω = 60 s^-1)? write rev/s, rps "
                "or rad/s (Hz and 1/min are read as revolutions)"
            )
        return 2.0 * math.pi  # Hz, 1/min, kHz: revolutions per time
    if have != 0 and want != 0:
        raise UnitError(
            f"{value!r} has an angle to the power {have} in its unit, and this value to the "
            f"power {want}: write it in {si_unit}, or another unit of it"
        )
    if want == 0:
        plain = "a plain number" if si_unit == "1" else f"{si_unit}, without an angle"
        raise UnitError(
            f"{value!r} has an angle in its unit and this quantity has none: pint would read the "
            f"angle as a number (20 deg as 0.349); write {plain}"
        )
    if si_unit == "rad":
        raise UnitError(
            f"{value!r}: an angle takes an angle unit (deg, rad, rev) or a bare number (rad)"
        )
    raise UnitError(
        f"{value!r} has no angle in its unit; write it with the angle, e.g. in {si_unit}"
    )


def _is_speed_coefficient(target) -> bool:
    """Whether the SI unit ``target`` is a torque per angular speed squared (N m s^2)."""
    return dict(target._units) == {"newton": 1, "meter": 1, "second": 2}


def _check_speed_coefficient(ureg, given, target, value, si_unit: str) -> None:
    """A coefficient of the angular speed squared (SI N m s², per (rad/s)²) refuses a frequency
    or a time in minutes or hours: per Hz² or min² it would be per (rev/s)² or (rev/min)², and
    read literally it would be (2π)² = 39.5 times too large (1 N m/Hz² is 0.0253 N m s²). Per
    (rad/s)² or per rpm² it is read as written."""
    if not _is_speed_coefficient(target) or _radians(ureg, given) != 0:
        return  # (an angle in the unit says what turns: per (rev/min)^2, per (rad/s)^2)
    cycles = [
        n for n in dict(given._units) if n.endswith("hertz") or n in ("minute", "hour", "day")
    ]
    if cycles:
        raise UnitError(
            f"{value!r}: a coefficient of the speed squared is per (rad/s)^2; per {cycles[0]} "
            f"it would be per revolutions: write the angle, e.g. N*m/(rev/s)^2 or N*m/rpm^2, "
            f"or {si_unit}"
        )


def _check_torque(ureg, names: dict, value) -> None:
    """A torque is a force times a length: refuse an energy unit (J, kJ, kWh) or a unit without
    a force in it (pint reads 173 J as 173 N m)."""
    force = ureg.get_dimensionality("newton")
    if not any(ureg.get_dimensionality(n) == force for n in names):
        raise UnitError(
            f"{value!r} is not written as a torque: give a force times a length (N*m, kN*m, "
            "lbf*ft); a unit with no force in it (J, kWh, kg*m^2/s^2) is taken for work and "
            "energy, not for a torque"
        )


def _temperature_unit(ureg, names: dict, value, kind: str):
    """The unit a temperature of ``kind`` is read in: an absolute one refuses a difference unit;
    a difference reads degC/degF as differences (no offset)."""
    delta = [n for n in names if n.startswith("delta_")]
    if kind == "absolute":
        if delta:
            raise UnitError(
                f"{value!r} is a temperature difference, and this is an absolute temperature: "
                "give e.g. '40 degC' or '313.15 K'"
            )
        return ureg.Unit(_container(names))
    return ureg.Unit(_container({_OFFSET.get(n, n): e for n, e in names.items()}))


def _container(names: dict):
    from pint.util import UnitsContainer

    return UnitsContainer(names)


def _finite(out: float, value) -> float:
    if not math.isfinite(out):
        raise UnitError(
            f"{value!r} is not finite (beyond a double; write .inf where infinity is meant and "
            "the parameter takes it)"
        )
    return out


def _decimal(out: float, number: float) -> float:
    """A value converted by a power of ten (mm, kN, MPa, ms) to 15 significant digits: the
    conversion's last-digit noise dropped (2.6 mm is 0.0026 m, not 0.0026000000000000003, so
    that ``.sel(x=2.6e-3)`` finds it). Any other conversion (deg, rpm, degF) as it is:
    ``np.deg2rad(65)`` finds 65 deg."""
    if number == 0.0 or out == 0.0:
        return out
    exponent = math.log10(abs(out / number))
    if abs(exponent - round(exponent)) > 1e-9:
        return out
    rounded = float(f"{out:.15g}")
    return rounded if math.isfinite(rounded) else out  # (near the largest double: as it is)
