"""The units people read: one table from the SI unit of a stored quantity to the unit engineers
use on pages, in the report's CSV files, the summary and the echo of a constraint.

Files (HDF5) stay SI with CF units; everything a person reads goes through this table, so a
thickness reads 2.8 mm and not 0.0028 m, a stress 1806 MPa and not 1.806e+09 Pa, a temperature
200 °C and not 473.15 K. Each entry has two spellings: ``text``, the one a user writes in a
config (``degC``, ``N*m``, ``kg*m^2``: it parses back with :func:`clutchlab.units.to_si`), used
in CSV headers and limits; ``label``, the typeset one used on pages (``°C``, ``N·m``, ``kg·m²``).

Temperatures: a stored ``K`` is either an absolute temperature (shown in °C, offset −273.15) or a
difference (a rise: shown in K, no offset). The kind is the variable's CF ``units_metadata``
attribute (``temperature: on_scale`` or ``temperature: difference``) where it has one, else the
name: a name ending in ``_rise`` is a difference, any other ``K`` quantity absolute.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Unit",
    "TABLE",
    "unit",
    "unit_of",
    "temperature_kind",
    "value",
    "column",
    "label",
    "text",
    "limit_text",
]


@dataclass(frozen=True)
class Unit:
    """A display unit: shown value = SI value × ``scale`` + ``offset``."""

    text: str  # as a user writes it in a config and as a CSV header carries it ("degC", "N*m")
    label: str  # as a page prints it ("°C", "N·m")
    scale: float = 1.0
    offset: float = 0.0

    def __call__(self, v):
        """The SI value(s) ``v`` in this unit (NaN stays NaN)."""
        return (
            np.asarray(v, dtype=float) * self.scale + self.offset
            if np.ndim(v)
            else (float(v) * self.scale + self.offset)
        )


#: SI unit (as the study tables spell it) -> the unit engineers read
TABLE: dict[str, Unit] = {
    "m": Unit("mm", "mm", 1e3),
    "m^2": Unit("m^2", "m²"),
    "kg": Unit("kg", "kg"),
    "kg m^2": Unit("kg*m^2", "kg·m²"),
    "kg/m^3": Unit("kg/m^3", "kg/m³"),
    "N": Unit("kN", "kN", 1e-3),
    "N/m": Unit("N/mm", "N/mm", 1e-3),
    "N m": Unit("N*m", "N·m"),
    "N m s^2": Unit("N*m*s^2", "N·m·s²"),
    "N m/rad": Unit("N*m/rad", "N·m/rad"),
    "N s/m": Unit("N*s/mm", "N·s/mm", 1e-3),
    "Pa": Unit("MPa", "MPa", 1e-6),
    "rad": Unit("deg", "deg", 180.0 / math.pi),
    "rad/s": Unit("rpm", "rpm", 30.0 / math.pi),
    "rad/s^2": Unit("rad/s^2", "rad/s²"),
    "rad/s^3": Unit("rad/s^3", "rad/s³"),
    "s": Unit("ms", "ms", 1e3),
    "J": Unit("kJ", "kJ", 1e-3),
    "J/m^2": Unit("kJ/m^2", "kJ/m²", 1e-3),
    "W": Unit("kW", "kW", 1e-3),
    "W/m^2": Unit("kW/m^2", "kW/m²", 1e-3),
    "W/(m^2 K)": Unit("W/(m^2*K)", "W/(m²·K)"),
    "1/K": Unit("1/K", "1/K"),
    # a rate of engagements: per hour; a specific wear rate (VDI 2241's q_V) in cm³/kWh
    "1/s": Unit("1/h", "1/h", 3600.0),
    "m^3/J": Unit("cm^3/(kW*h)", "cm³/kWh", 3.6e12),
    "1": Unit("-", "-"),
}
#: temperatures: an absolute one in °C, a difference (a rise) in K
ABSOLUTE_TEMPERATURE = Unit("degC", "°C", 1.0, -273.15)
TEMPERATURE_DIFFERENCE = Unit("K", "K")
#: quantities that read better in another unit than their SI unit's (a minute-long interval in ms,
#: a spring force of a few newtons in kN would be unreadable)
BY_NAME: dict[str, Unit] = {
    "startup_time": Unit("s", "s"),
    "engagement_interval": Unit("s", "s"),
    "spring_force": Unit("N", "N"),
    "spring_preload": Unit("N", "N"),
}


def _key(si_unit: str) -> str:
    """The table's spelling of a unit: "N*m" and "N m" alike, "W/(m^2*K)" as "W/(m^2 K)"."""
    return " ".join(str(si_unit).replace("*", " ").replace("·", " ").split())


def unit(si_unit: str, name: str = "", kind: str | None = None) -> Unit:
    """The display unit of a quantity.

    Parameters
    ----------
    si_unit : str
        Its SI unit as stored (CF ``units`` attribute: ``"m"``, ``"N m"``, ``"K"``).
    name : str
        Its name (a few read in their SI unit; a temperature named ``*_rise`` is a difference).
    kind : {"absolute", "difference"} or None
        For a temperature: absolute (°C) or a difference (K); None: from the name.

    Returns
    -------
    Unit
        The unit engineers read; an SI unit not in :data:`TABLE` is shown as it is.
    """
    if name in BY_NAME:
        return BY_NAME[name]
    key = _key(si_unit)
    if key == "K":
        if kind is None:
            kind = "difference" if name.endswith("_rise") else "absolute"
        return TEMPERATURE_DIFFERENCE if kind == "difference" else ABSOLUTE_TEMPERATURE
    return TABLE.get(key, Unit(str(si_unit), str(si_unit)))


def unit_of(ds, name: str) -> Unit:
    """The display unit of variable or coordinate ``name`` of a Dataset (its ``units`` and
    ``units_metadata`` attributes); a flagged variable (status, an option's choice) has none."""
    attrs = ds[name].attrs
    if "flag_meanings" in attrs:
        return Unit("", "")
    return unit(attrs.get("units", "1"), name, temperature_kind(attrs))


def temperature_kind(attrs) -> str | None:
    """ "absolute" or "difference" from a variable's CF ``units_metadata`` attribute; None where
    it has none."""
    meta = str(attrs.get("units_metadata", ""))
    if "on_scale" in meta:
        return "absolute"
    return "difference" if "difference" in meta else None


def value(ds, name: str, v=None):
    """Values of ``name`` (``v``, or the Dataset's own) in its display unit."""
    return unit_of(ds, name)(ds[name].values if v is None else v)


def column(name: str, u: Unit) -> str:
    """A CSV column header carrying its unit: ``sheet_thickness [mm]``; a code without one bare."""
    return f"{name} [{u.text}]" if u.text else name


def label(name: str, u: Unit) -> str:
    """An axis or table label: ``sheet thickness [mm]``."""
    return f"{name.replace('_', ' ')} [{u.label}]" if u.label else name.replace("_", " ")


def text(v, u: Unit, fmt: str = ".4g", typeset: bool = True) -> str:
    """``v`` (SI) as "number unit" in the display unit: ``2.8 mm``, ``200 °C``; a dimensionless
    number bare."""
    shown = u(v)
    number = format(shown, fmt) if np.isfinite(shown) else "NaN"
    spelled = u.label if typeset else u.text
    return number if spelled in ("-", "") else f"{number} {spelled}"


def _si_spelling(units: str) -> str:
    """A UDUNITS exponent spelling as the table's: "rad s-1" as "rad/s", "N m-1" as "N/m"."""
    words = str(units).split()
    num = [w for w in words if not w.endswith("-1")]
    den = [w[:-2] for w in words if w.endswith("-1")]
    return " ".join(num) + ("/" + " ".join(den) if len(den) == 1 else "")


def reported(values, units: str, typeset: bool = True) -> tuple[list, str]:
    """Values of a table that carries its unit per row (the validation table: published and
    computed in ``units``) in the unit engineers read where ``units`` is an SI unit of
    :data:`TABLE` (a stress in Pa shown in MPa); other units ("MPa", "deg", "ms": a paper's own)
    as they are. Returns (values, unit spelling)."""
    key = _key(_si_spelling(units))
    if key in TABLE and key not in ("1",):
        u = TABLE[key]
        if key == "N" and np.nanmax(np.abs(np.asarray(values, dtype=float))) < 100.0:
            u = Unit("N", "N")  # a spring's few newtons, not 0.0037 kN
        return [u(v) for v in values], (u.label if typeset else u.text)
    return list(values), str(units)


def limit_text(output: str, op: str, limit: float, si_unit: str, kind=None) -> str:
    """A constraint as the user would write it: ``peak_surface_temperature max: 200 degC``."""
    u = unit(si_unit, output, kind)
    return f"{output} {op}: {text(limit, u, '.6g', typeset=False)}"
