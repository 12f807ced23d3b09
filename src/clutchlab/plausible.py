"""Plausible magnitudes of the quantities a clutch model takes, by SI unit.

One table for the config (a value outside is refused, naming the key) and for the public physics
functions (a scenario with a value outside gets status ``invalid_input``): a number outside these
bounds is a typing or unit slip (``2.3 Mm`` for a sheet thickness, ``1e20`` shoes), never a
helicopter or UAV drivetrain clutch, and feeding it to a solver gives overflow, a hang or a
number that looks valid. The bounds are wide on purpose: they catch absurd magnitudes, not
unusual designs. A parameter may narrow them (its own ``minimum``/``maximum`` in the study table).

A zero is judged by the parameter's own minimum (an air gap of 0 m is fine); the lower bound here
applies to the magnitude of a non-zero value.
"""

from __future__ import annotations

import numpy as np

__all__ = ["RANGES", "PARAMETERS", "COUNT_MAX", "bounds", "within"]

#: SI unit -> (smallest non-zero magnitude, largest magnitude), with the reason
RANGES: dict[str, tuple[float, float]] = {
    # 0.1 µm (a penetration depth, a deflection) to 10 m (past any rotor-drive clutch)
    "m": (1e-7, 10.0),
    "m^2": (1e-10, 100.0),
    # a fraction of a gram (a sprag, a roller) to 10 t (a whole drivetrain)
    "kg": (1e-6, 1e4),
    # a wedge ring (1e-5) to a large rotor referred to the clutch shaft
    "kg m^2": (1e-9, 1e5),
    # a UAV servo clutch to a heavy helicopter's main rotor shaft (~1e5 N m)
    "N m": (1e-6, 1e7),
    "N": (1e-6, 1e9),
    # rubber (1e6 Pa) to diamond (1.2e12 Pa): moduli and allowable stresses
    "Pa": (1e5, 1.2e12),
    # 1e5 rad/s is 955 000 rpm: past any turbine shaft
    "rad/s": (1e-6, 1e5),
    # a nanosecond to a day (engagement intervals, start-up times)
    "s": (1e-9, 86_400.0),
    # angles of a clutch's geometry: at most a turn
    "rad": (1e-9, 2 * np.pi),
    # absolute temperatures: 1 K to 3 000 K (past the melting point of steel)
    "K": (1.0, 3000.0),
    # temperature differences (a rise; the key is not a unit: a difference is stored in K with
    # units_metadata "temperature: difference"): a microkelvin to 3 000 K
    "delta_K": (1e-6, 3000.0),
    "1/K": (1e-9, 10.0),
    "W/(m^2*K)": (1e-3, 1e6),
    "N m s^2": (1e-12, 1e6),
    "N m/rad": (1e-3, 1e9),
    "N s/m": (1e-6, 1e10),
    "W": (1e-3, 1e9),
    "kg/m^3": (1.0, 1e5),
    # energies: a nanojoule to a terajoule (a heavy rotor at speed holds ~1e8 J)
    "J": (1e-9, 1e12),
    "J/m^2": (1e-9, 1e13),
    "W/m^2": (1e-6, 1e13),
    # heat: specific heats, conductivities, effusivities of solids (and of air, for the low ends)
    "J/(kg K)": (10.0, 1e5),
    "W/(m K)": (1e-3, 1e4),
    "W s^0.5/(m^2 K)": (1.0, 1e6),
    # Duhamel's integral of a slip power, and the face temperature per unit of it
    "W s^0.5": (1e-9, 1e13),
    "K/(W s^0.5)": (1e-12, 1e6),
    # linear spring rates; Hertz contact stiffness k of k·δ^1.5 (3.4e5 N/mm^1.5 = 1.1e10 in SI)
    "N/m": (1e-3, 1e13),
    "N/m^1.5": (1.0, 1e15),
    # specific wear rate of a friction lining (worn volume per friction work, VDI 2241 q_V):
    # 0.2 cm^3/kWh is 5.6e-14 m^3/J; 1e-18 to 1e-9 spans every dry and wet pair and then some
    "m^3/J": (1e-18, 1e-9),
    # a rate of events (engagements per hour: 1/h = 2.8e-4 1/s): one a year to a kilohertz
    "1/s": (1e-8, 1e3),
    # dimensionless parameters: ratios and coefficients; narrower per parameter (a friction
    # coefficient <= 2, a count <= COUNT_MAX)
    "1": (1e-12, 1e6),
}

_MM, _DEG = 1e-3, np.pi / 180
_UNIT = 0.0  # (as a lower bound: the unit's own)

#: study parameter (or output, for a constraint's limit) -> (smallest non-zero, largest) magnitude
#: [SI] narrower than its unit's range:
#: the widest a helicopter or UAV clutch takes, so that a value written without its unit where the
#: unit mattered is refused, not read in SI (``cushion_travel: 0.6`` meant in mm is 0.6 m,
#: ``youngs_modulus: 206000`` meant in MPa is 206 kPa, ``ramp_time: 500`` meant in ms is 500 s,
#: ``shoe_mass: 178`` meant in g is 178 kg). Not every slip is caught: ``rated_speed: 2000`` meant
#: in rpm is 19 100 rpm, a speed some clutches run at, and ``ramp_time: 150`` meant in ms is a
#: slow but possible ramp of 150 s.
PARAMETERS: dict[str, tuple[float, float]] = {
    # lengths: a spring sheet of at most 20 mm, gaps and travels of at most 20 mm, a clutch of at
    # most 2 m across, sprags and rollers of at most 100-200 mm, an ADAMS penetration of 50 mm
    "outer_radius": (_UNIT, 1.0),
    "load_radius_outer_offset": (_UNIT, 50 * _MM),
    "load_radius_inner_offset": (_UNIT, 50 * _MM),
    "lining_outer_radius": (_UNIT, 1.0),
    "lining_inner_radius": (_UNIT, 1.0),
    "air_gap": (_UNIT, 20 * _MM),
    "cushion_travel": (_UNIT, 20 * _MM),
    "shoe_radius": (_UNIT, 1.0),
    "drum_radius": (_UNIT, 1.0),
    "sprag_length": (_UNIT, 200 * _MM),
    "centre_distance": (_UNIT, 50 * _MM),
    "sprag_inner_radius": (_UNIT, 100 * _MM),
    "sprag_outer_radius": (_UNIT, 100 * _MM),
    "inner_bore_radius": (_UNIT, 1.0),
    "inner_race_radius": (_UNIT, 1.0),
    "outer_race_radius": (_UNIT, 1.0),
    "outer_rim_radius": (_UNIT, 1.0),
    "roller_diameter": (_UNIT, 100 * _MM),
    "contact_radius": (_UNIT, 1.0),
    "penetration_depth": (_UNIT, 50 * _MM),
    "claw_clearance": (_UNIT, 50 * _MM),
    # moduli of engineering solids (polymers such as PTFE from 0.1 GPa) and allowable stresses
    # from 10 MPa
    "youngs_modulus": (1e8, 1.2e12),
    "contact_allowable": (1e7, 1.2e12),
    "shaft_allowable": (1e7, 1.2e12),
    # a roller's wedge angle and a sprag's allowable gripping angle: a few degrees (a bare 1 is
    # 57 deg)
    "wedge_angle": (0.1 * _DEG, 45 * _DEG),
    "gripping_angle_allowable": (0.1 * _DEG, 30 * _DEG),
    # shaft speeds at the clutch: at most 6 000 rad/s (57 300 rpm: a small UAV engine's 40 000 rpm
    # and more)
    "engine_speed": (_UNIT, 6000.0),
    "rated_speed": (_UNIT, 6000.0),
    "idle_speed": (_UNIT, 6000.0),
    "initial_speed": (_UNIT, 6000.0),
    # times: an engagement ramp of at most 5 min (a belt-tensioning helicopter clutch takes tens
    # of seconds), its window 10 min, an engine start-up 10 min
    "ramp_time": (_UNIT, 300.0),
    "end_time": (_UNIT, 600.0),
    "rise_time": (_UNIT, 60.0),
    "control_stop_time": (_UNIT, 10.0),
    "startup_time": (_UNIT, 600.0),
    # masses: a shoe of at most 20 kg, a clutch's plates and flywheel of at most 1 t
    "shoe_mass": (_UNIT, 20.0),
    "stack_mass": (_UNIT, 1000.0),
    "flywheel_mass": (_UNIT, 1000.0),
    "pressure_plate_mass": (_UNIT, 1000.0),
    "driven_plate_mass": (_UNIT, 1000.0),
    "intermediate_plate_mass": (_UNIT, 1000.0),
    # the smallest (largest) values whose scenario the physics still takes with the others at
    # the source papers' (below them a derived load, stiffness or capacity leaves its own unit's
    # range): a spring sheet or a roller of 0.1 mm, a wear allowance of 1 µm, a friction
    # coefficient of 0.001 (a lubricated contact), ratios and factors of 0.01 or 0.1, an engine of
    # 1e-5 kg m^2, a hub of 0.1 % to 99.9 % of the plate's inertia, a rated torque of 1e6 N m
    "sheet_thickness": (0.1 * _MM, 20 * _MM),
    "wear_allowance": (1e-6, 20 * _MM),
    "roller_length": (0.1 * _MM, 200 * _MM),
    "friction_coefficient": (1e-3, 2.0),
    "cone_height_ratio": (0.01, 10.0),
    "service_factor": (0.1, 20.0),
    "engine_inertia": (1e-5, 1e5),
    "hub_fraction": (1e-3, 0.999),
    "max_torque": (_UNIT, 1e6),
    # outputs a constraint may limit: a lining's wear per engagement of at most 1 mm, a spring's
    # deflection at its operating point of at most 50 mm, gripping and backlash angles of at most
    # 45 deg
    "wear_per_engagement": (_UNIT, 1 * _MM),
    "deflection_operating": (_UNIT, 50 * _MM),
    "gripping_angle": (_UNIT, 45 * _DEG),
    "backlash_angle": (_UNIT, 45 * _DEG),
}

#: the most elements a count may have (sprags, rollers, shoes, friction faces)
COUNT_MAX = 1000


def bounds(unit: str) -> tuple[float, float]:
    """Smallest non-zero and largest plausible magnitude of a quantity in SI ``unit``.

    Parameters
    ----------
    unit : str
        SI unit as the study tables spell it (``"m"``, ``"N m"``, ``"rad/s"``, ``"1"``).

    Returns
    -------
    (float, float)
        The bounds; ``(0, inf)`` for a unit without a stated range.
    """
    return RANGES.get(unit, (0.0, np.inf))


def within(x, unit: str):
    """True where ``x`` is zero or finite with a magnitude within :func:`bounds` of ``unit``.

    Parameters
    ----------
    x : array_like
        Values in SI ``unit``.
    unit : str
        SI unit as the study tables spell it.

    Returns
    -------
    numpy.ndarray of bool
        The mask, shaped like ``x``.
    """
    lo, hi = bounds(unit)
    a = np.abs(np.asarray(x, dtype=float))
    with np.errstate(invalid="ignore"):
        return (a == 0) | (np.isfinite(a) & (a >= lo) & (a <= hi))
