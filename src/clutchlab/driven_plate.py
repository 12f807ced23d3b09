"""Driven-plate hub: torsional damper springs (eqs. 4–9) and the hub spline check of seed 000.

References
----------
.. [1] Zhao P. (2026), seed 000, section 3.2.2 (spline) and eqs. (4)–(9) (damper springs).
"""

from __future__ import annotations

import numpy as np

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


def damper_design_torque(max_engine_torque, factor=2.0):
    """Maximum damper torque T_j = factor·T_emax [N·m] (the paper takes factor = 2)."""
    return factor * np.asarray(max_engine_torque, dtype=float)


def damper_total_force(design_torque, spring_radius):
    """Total force on all damper springs P_total = T_j / R₁, eq. (4) of [1] [N].

    Erratum: Table 2 of [1] labels this value (6654 N) "single spring working pressure";
    it is the total over all springs (eq. 4). R₁ is not printed; 6654 N implies R₁ = 52.0 mm.
    """
    return np.asarray(design_torque, dtype=float) / spring_radius


def damper_spring_force(total_force, spring_count):
    """Force on one damper spring P = P_total / z, eq. (5) of [1] [N]."""
    return np.asarray(total_force, dtype=float) / spring_count


def damper_wire_diameter(spring_force, coil_diameter, allowable_shear_stress):
    """Wire diameter d₁ = ∛(8·P·D_c / (π·τ)), eq. (6) of [1] corrected [m].

    Erratum: eq. (6) is printed with a square root, which is dimensionally wrong; the torsion
    stress of a helical spring τ = 8·P·D_c/(π·d³) gives the cube root used here (no Wahl factor,
    as in the paper).
    """
    return np.cbrt(
        8.0
        * np.asarray(spring_force, dtype=float)
        * coil_diameter
        / (np.pi * allowable_shear_stress)
    )


def damper_angular_stiffness(design_torque, factor=13.0):
    """Damper angular stiffness C_a = factor·T_j, eq. (7) of [1] (upper limit, factor 13) [N·m/rad].

    The rule is empirical: T_j in N·m gives C_a in N·m/rad.
    """
    return factor * np.asarray(design_torque, dtype=float)


def damper_spring_rate(angular_stiffness, spring_radius, spring_count):
    """Linear rate of one damper spring C = C_a / (R₁²·z), eq. (8) of [1] in SI [N/m].

    Erratum: eq. (8) is printed as C = C_a / (1000·R₁²·z) with R₁ in mm, and Table 2 gives the
    result (416) as "N/m"; in consistent units the value is 415.9 N/mm = 4.159e5 N/m.
    """
    return np.asarray(angular_stiffness, dtype=float) / (
        np.asarray(spring_radius) ** 2 * spring_count
    )


def damper_coil_count(shear_modulus, wire_diameter, coil_diameter, spring_rate):
    """Active coils i = G·d₁⁴ / (8·D_c³·C), eq. (9) of [1] [-] (D₂ there is the coil diameter D_c)."""
    return (
        np.asarray(shear_modulus, dtype=float)
        * np.asarray(wire_diameter) ** 4
        / (8.0 * np.asarray(coil_diameter) ** 3 * spring_rate)
    )


def spline_stresses(torque, *, teeth, outer_diameter, inner_diameter, tooth_width, length):
    """Mean bearing (crushing) and root shear stress of a straight-sided spline [Pa].

    With mean diameter d_m = (D + d)/2 and working tooth height h = (D − d)/2, the tangential
    force on all teeth is 2T/d_m; bearing σ_p = 2T/(d_m·n·h·l), shear τ = 2T/(d_m·n·t·l).
    Section 3.2.2 of [1] gives 8.9 MPa bearing at T_emax = 173 N·m (reproduced: 8.97 MPa) and
    15 MPa shear, which this formula reaches only with twice that torque (15.7 MPa at
    T_j = 346 N·m, the damper design torque); the paper does not say which torque it used.

    Returns
    -------
    tuple of numpy.ndarray
        (bearing stress, shear stress) [Pa].
    """
    d_m = 0.5 * (np.asarray(outer_diameter) + inner_diameter)
    tooth_height = 0.5 * (np.asarray(outer_diameter) - inner_diameter)
    force = 2.0 * np.asarray(torque, dtype=float) / d_m
    return force / (teeth * tooth_height * length), force / (teeth * tooth_width * length)
