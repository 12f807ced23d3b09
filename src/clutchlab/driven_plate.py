"""Driven-plate hub: torsional damper springs (eqs. 4–9) and the hub spline check of the source
paper (000).

Every function returns NaN where an input is not finite, not physical (a negative torque, a
count that is not a whole number in [1, 1000], a non-positive length or modulus) or of an
implausible magnitude (:mod:`clutchlab.plausible`).

References
----------
.. [1] Zhao P. (2026), "Design and engagement simulation of diaphragm spring clutch for
   unmanned helicopters", the source paper (000), section 3.2.2 (spline) and eqs. (4)–(9)
   (damper springs).
"""

from __future__ import annotations

import numpy as np

from . import status as st

__all__ = [
    "damper_design_torque",
    "damper_total_force",
    "damper_spring_force",
    "damper_wire_diameter",
    "damper_angular_stiffness",
    "damper_spring_rate",
    "damper_coil_count",
    "spline_stresses",
]

MAX_FACTOR = 1e3  # the empirical factors of eqs. (4) and (7) (2 and 13 in [1])

# per-input rules (sign, finite, plausible magnitude)
_RULES = {
    "max_engine_torque": st.nonnegative_in("N m"),
    "design_torque": st.nonnegative_in("N m"),
    "torque": st.nonnegative_in("N m"),
    "factor": st.positive_in("1", hi=MAX_FACTOR),
    "spring_radius": st.positive_in("m"),
    "total_force": st.nonnegative_in("N"),
    "spring_force": st.nonnegative_in("N"),
    "spring_count": st.count(1),
    "teeth": st.count(1),
    "coil_diameter": st.positive_in("m"),
    "wire_diameter": st.positive_in("m"),
    "allowable_shear_stress": st.positive_in("Pa"),
    "shear_modulus": st.positive_in("Pa"),
    "angular_stiffness": st.nonnegative_in("N m/rad"),
    "spring_rate": st.positive_in("N/m"),
    "outer_diameter": st.positive_in("m"),
    "inner_diameter": st.positive_in("m"),
    "tooth_width": st.positive_in("m"),
    "length": st.positive_in("m"),
}


def _screened(compute, relations=None, **inputs):
    return st.nan_screened(compute, inputs, {**{k: _RULES[k] for k in inputs}, **(relations or {})})


def damper_design_torque(max_engine_torque, factor=2.0):
    """Maximum damper torque T_j = factor·T_emax.

    Parameters
    ----------
    max_engine_torque : float or array_like [N m]
        Engine maximum torque T_emax ≥ 0.
    factor : float or array_like [-]
        Ratio T_j/T_emax, in (0, 1000]; the paper takes 2 against the load shocks of a UAV
        helicopter.

    Returns
    -------
    numpy.ndarray [N m]
        T_j (346 N·m for the source paper's design); NaN where an input is invalid.

    References
    ----------
    Source paper (000), section 3.2.3 ([1] in the module docstring): T_j = 2·T_emax.
    """
    return _screened(
        lambda max_engine_torque, factor: factor * np.asarray(max_engine_torque, dtype=float),
        max_engine_torque=max_engine_torque,
        factor=factor,
    )


def damper_total_force(design_torque, spring_radius):
    """Total force on all damper springs P_total = T_j / R₁, equation (4) of [1].

    Parameters
    ----------
    design_torque : float or array_like [N m]
        Damper design torque T_j ≥ 0.
    spring_radius : float or array_like [m]
        Radius R₁ of the damper springs' pitch circle.

    Returns
    -------
    numpy.ndarray [N]
        P_total; NaN where an input is invalid.

    Notes
    -----
    Erratum: Table 2 of [1] labels this value (6654 N) "single spring working pressure";
    it is the total over all springs (eq. 4). R₁ is not printed; 6654 N implies R₁ = 52.0 mm.

    References
    ----------
    Source paper (000), eq. (4) and Table 2 ([1] in the module docstring).
    """
    return _screened(
        lambda design_torque, spring_radius: np.asarray(design_torque, dtype=float) / spring_radius,
        design_torque=design_torque,
        spring_radius=spring_radius,
    )


def damper_spring_force(total_force, spring_count):
    """Force on one damper spring P = P_total / z, equation (5) of [1].

    Parameters
    ----------
    total_force : float or array_like [N]
        Total force P_total ≥ 0 on all damper springs.
    spring_count : int or array_like [-]
        Number of damper springs z, a whole number in [1, 1000] (4 in [1]).

    Returns
    -------
    numpy.ndarray [N]
        P; NaN where an input is invalid.

    References
    ----------
    Source paper (000), eq. (5) ([1] in the module docstring).
    """
    return _screened(
        lambda total_force, spring_count: np.asarray(total_force, dtype=float) / spring_count,
        total_force=total_force,
        spring_count=spring_count,
    )


def damper_wire_diameter(spring_force, coil_diameter, allowable_shear_stress):
    """Wire diameter d₁ = ∛(8·P·D_c / (π·τ)), equation (6) of [1] corrected.

    Parameters
    ----------
    spring_force : float or array_like [N]
        Force P ≥ 0 on one damper spring.
    coil_diameter : float or array_like [m]
        Mean coil diameter D_c (11…15 mm in [1]).
    allowable_shear_stress : float or array_like [Pa]
        Allowable torsion stress τ of the spring wire (65Mn in [1]; not printed).

    Returns
    -------
    numpy.ndarray [m]
        d₁; NaN where an input is invalid.

    Notes
    -----
    Erratum: eq. (6) is printed with a square root, which is dimensionally wrong; the torsion
    stress of a helical spring τ = 8·P·D_c/(π·d³) gives the cube root used here (no Wahl factor,
    as in the paper).

    References
    ----------
    Source paper (000), eq. (6) ([1] in the module docstring), corrected as in the Notes.
    """
    return _screened(
        _wire_diameter,
        spring_force=spring_force,
        coil_diameter=coil_diameter,
        allowable_shear_stress=allowable_shear_stress,
    )


def _wire_diameter(spring_force, coil_diameter, allowable_shear_stress):
    return np.cbrt(
        8.0
        * np.asarray(spring_force, dtype=float)
        * coil_diameter
        / (np.pi * allowable_shear_stress)
    )


def damper_angular_stiffness(design_torque, factor=13.0):
    """Damper angular stiffness C_a = factor·T_j, equation (7) of [1] (upper limit, factor 13).

    The rule is empirical: T_j in N·m gives C_a in N·m/rad.

    Parameters
    ----------
    design_torque : float or array_like [N m]
        Damper design torque T_j ≥ 0.
    factor : float or array_like [1/rad]
        Ratio C_a/T_j, in (0, 1000]; at most 13 in [1].

    Returns
    -------
    numpy.ndarray [N m/rad]
        C_a (4498 N·m/rad for the source paper's design); NaN where an input is invalid.

    References
    ----------
    Source paper (000), eq. (7) ([1] in the module docstring).
    """
    return _screened(
        lambda design_torque, factor: factor * np.asarray(design_torque, dtype=float),
        design_torque=design_torque,
        factor=factor,
    )


def damper_spring_rate(angular_stiffness, spring_radius, spring_count):
    """Linear rate of one damper spring C = C_a / (R₁²·z), equation (8) of [1] in SI.

    Parameters
    ----------
    angular_stiffness : float or array_like [N m/rad]
        Damper angular stiffness C_a ≥ 0.
    spring_radius : float or array_like [m]
        Radius R₁ of the damper springs' pitch circle.
    spring_count : int or array_like [-]
        Number of damper springs z, a whole number in [1, 1000].

    Returns
    -------
    numpy.ndarray [N/m]
        C; NaN where an input is invalid.

    Notes
    -----
    Erratum: eq. (8) is printed as C = C_a / (1000·R₁²·z) with R₁ in mm, and Table 2 gives the
    result (416) as "N/m"; in consistent units the value is 415.9 N/mm = 4.159e5 N/m.

    References
    ----------
    Source paper (000), eq. (8) and Table 2 ([1] in the module docstring), corrected as in the
    Notes.
    """
    return _screened(
        lambda angular_stiffness, spring_radius, spring_count: (
            np.asarray(angular_stiffness, dtype=float)
            / (np.asarray(spring_radius) ** 2 * spring_count)
        ),
        angular_stiffness=angular_stiffness,
        spring_radius=spring_radius,
        spring_count=spring_count,
    )


def damper_coil_count(shear_modulus, wire_diameter, coil_diameter, spring_rate):
    """Active coils i = G·d₁⁴ / (8·D_c³·C), equation (9) of [1] (D₂ there is the coil diameter D_c).

    Parameters
    ----------
    shear_modulus : float or array_like [Pa]
        Shear modulus G of the spring wire.
    wire_diameter : float or array_like [m]
        Wire diameter d₁, smaller than the coil diameter.
    coil_diameter : float or array_like [m]
        Mean coil diameter D_c.
    spring_rate : float or array_like [N/m]
        Rate C of one spring.

    Returns
    -------
    numpy.ndarray [-]
        i (6 in [1] needs d₁ ≈ 5.34…5.40 mm; τ and G are not printed); NaN where an input is
        invalid or d₁ ≥ D_c.

    References
    ----------
    Source paper (000), eq. (9) ([1] in the module docstring).
    """
    return _screened(
        _coil_count,
        {None: lambda a: a["wire_diameter"] < a["coil_diameter"]},
        shear_modulus=shear_modulus,
        wire_diameter=wire_diameter,
        coil_diameter=coil_diameter,
        spring_rate=spring_rate,
    )


def _coil_count(shear_modulus, wire_diameter, coil_diameter, spring_rate):
    return (
        np.asarray(shear_modulus, dtype=float)
        * np.asarray(wire_diameter) ** 4
        / (8.0 * np.asarray(coil_diameter) ** 3 * spring_rate)
    )


def spline_stresses(torque, *, teeth, outer_diameter, inner_diameter, tooth_width, length):
    """Mean bearing (crushing) and root shear stress of a straight-sided spline.

    With mean diameter d_m = (D + d)/2 and working tooth height h = (D − d)/2, the tangential
    force on all teeth is 2T/d_m; bearing σ_p = 2T/(d_m·n·h·l), shear τ = 2T/(d_m·n·t·l).
    Section 3.2.2 of [1] gives 8.9 MPa bearing at T_emax = 173 N·m (reproduced: 8.97 MPa) and
    15 MPa shear, which this formula reaches only with twice that torque (15.7 MPa at
    T_j = 346 N·m, the damper design torque); the paper does not say which torque it used.

    Parameters
    ----------
    torque : float or array_like [N m]
        Torque T ≥ 0 through the spline.
    teeth : int or array_like [-]
        Number of teeth n, a whole number in [1, 1000].
    outer_diameter, inner_diameter : float or array_like [m]
        Outer and inner spline diameter D > d > 0.
    tooth_width : float or array_like [m]
        Tooth thickness t > 0.
    length : float or array_like [m]
        Working tooth length l > 0.

    Returns
    -------
    tuple of numpy.ndarray [Pa]
        (bearing stress, shear stress); NaN where an input is invalid.

    References
    ----------
    Source paper (000), section 3.2.2 ([1] in the module docstring): 10 teeth, D = 35 mm,
    d = 28 mm, t = 4 mm, l = 35 mm; 8.9 MPa and 15 MPa.
    """
    return _screened(
        _spline_stresses,
        {None: lambda a: a["outer_diameter"] > a["inner_diameter"]},
        torque=torque,
        teeth=teeth,
        outer_diameter=outer_diameter,
        inner_diameter=inner_diameter,
        tooth_width=tooth_width,
        length=length,
    )


def _spline_stresses(torque, teeth, outer_diameter, inner_diameter, tooth_width, length):
    d_m = 0.5 * (np.asarray(outer_diameter) + inner_diameter)
    tooth_height = 0.5 * (np.asarray(outer_diameter) - inner_diameter)
    force = 2.0 * np.asarray(torque, dtype=float) / d_m
    return force / (teeth * tooth_height * length), force / (teeth * tooth_width * length)
