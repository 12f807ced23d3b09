"""Quantities written by engineers ("2.3 mm", "5500 rpm", "206 GPa") converted to SI.

A bare number is taken as already in SI. Parsing uses pint, the maintained standard for
unit-aware arithmetic in Python; the registry is built lazily so that importing clutchlab
(e.g. inside a chunk job) does not pay for it.
"""

from __future__ import annotations

import functools
import math
import numbers
import re

__all__ = ["UnitError", "to_si"]

_REPLACE = {"·": "*", "⋅": "*", "²": "**2", "³": "**3", "⁴": "**4", "µ": "u", "μ": "u", "°": " deg"}


# one number, then (optionally) a unit expression with no number in it: pint alone would evaluate
# "2 3 mm" as 6 mm and "2,3 mm" as 23 mm, both silent misreads of what an engineer wrote
_NUMBER = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$", re.S)


class UnitError(ValueError):
    """A quantity could not be parsed or has the wrong dimension."""


@functools.lru_cache(maxsize=1)
def _registry():
    import pint

    return pint.UnitRegistry()


def to_si(value, si_unit: str) -> float:
    """Convert ``value`` to a float in ``si_unit``.

    Parameters
    ----------
    value : float, int or str
        A bare number (taken as SI already) or a string "number unit", e.g. ``"2.3 mm"``: exactly
        one number (no comma, no arithmetic) followed by a unit expression (``"N m"``, ``"kg m^2"``).
    si_unit : str
        Target SI unit in pint/UDUNITS spelling, e.g. ``"m"``, ``"Pa"``, ``"rad/s"``, ``"1"``.

    Raises
    ------
    UnitError
        If the string cannot be parsed or its dimension differs from ``si_unit``'s.
    """
    if isinstance(value, bool):
        raise UnitError(f"expected a quantity, got the boolean {value!r}")
    if isinstance(value, numbers.Real):
        out = float(value)
    elif isinstance(value, str):
        text = value.strip()
        for old, new in _REPLACE.items():
            text = text.replace(old, new)
        if "," in text:
            raise UnitError(
                f"{value!r}: a comma is not read as a decimal point or a thousands separator; "
                "write e.g. '2.3 mm'"
            )
        match = _NUMBER.fullmatch(text)
        if match is None:
            raise UnitError(
                f"cannot parse quantity {value!r}: expected 'number unit', e.g. '2.3 mm'"
            )
        number, unit = float(match.group(1)), match.group(2)
        if not unit:  # "3.7": a bare number, SI like 3.7
            return _finite(number, value)
        ureg = _registry()
        try:
            q = ureg.Quantity(number, ureg.parse_units(unit) if unit else "dimensionless")
        except Exception as exc:  # pint raises several unrelated exception types
            raise UnitError(f"cannot parse the unit of {value!r}: {exc}") from None
        target = "dimensionless" if si_unit == "1" else si_unit
        try:
            out = float(q.to(target).magnitude)
        except Exception:
            raise UnitError(
                f"{value!r} has units of {q.dimensionality}, expected something convertible to {si_unit!r}"
            ) from None
    else:
        raise UnitError(
            f"expected a number or a 'number unit' string, got {type(value).__name__} {value!r}"
        )
    return _finite(out, value)


def _finite(out: float, value) -> float:
    if not math.isfinite(out):
        raise UnitError(f"{value!r} is not finite")
    return out
