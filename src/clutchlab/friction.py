"""Friction-clutch sizing and torque capacity (the source paper (000), eqs. 3, 13–14).

References
----------
.. [1] Zhao P. (2026), "Design and engagement simulation of diaphragm spring clutch for
   unmanned helicopters", the source paper (000), eqs. (3), (13), (14).
"""

from __future__ import annotations

import numpy as np

from . import status as st

__all__ = [
    "STANDARD_GRAVITY",
    "lining_outer_diameter",
    "lining_coefficient",
    "effective_radius",
    "torque_capacity",
    "torque_capacity_eq14_as_printed",
    "reserve_factor",
]

STANDARD_GRAVITY = 9.80665  # m/s²
MAX_FRICTION_COEFFICIENT = 2.0  # dry friction of any clutch pair is below about 1

# per-input rules (sign, finite, plausible magnitude; clutchlab.plausible)
_MU = st.positive_in("1", hi=MAX_FRICTION_COEFFICIENT)
_RULES = {
    "max_engine_torque": st.positive_in("N m"),
    "coefficient": st.positive_in("1"),
    "outer_diameter": st.positive_in("m"),
    "outer_radius": st.positive_in("m"),
    "inner_radius": st.positive_in("m"),
    "clamp_force": st.nonnegative_in("N"),
    "friction_coefficient": _MU,
    "faces": st.count(1),
    "stack_mass": st.nonnegative_in("kg"),
    "gravity": st.nonnegative_in("m/s^2", lo=1e-3, hi=1e3),
    "torque_capacity": st.nonnegative_in("N m"),
}
_ANNULUS = {None: lambda a: a["outer_radius"] > a["inner_radius"]}


def _domain(inputs, relations=None):
    return {**{k: _RULES[k] for k in inputs}, **(relations or {})}


def lining_outer_diameter(max_engine_torque, coefficient):
    """Lining outer diameter D = 100·√(T_emax / A) [mm], equation (3) of [1], returned in metres.

    Parameters
    ----------
    max_engine_torque : float or array_like [N m]
        Engine maximum torque T_emax.
    coefficient : float or array_like [-]
        Design constant A (30…36 for a large single-plate UAV-helicopter clutch). The formula
        is empirical: A carries the units that make D come out in mm for T in N·m.

    Returns
    -------
    numpy.ndarray [m]
        D; NaN where an input is not positive, finite and plausible
        (:mod:`clutchlab.plausible`).

    References
    ----------
    Source paper (000), eq. (3) ([1] in the module docstring): D = 225 mm ⇔ A ≈ 34.17 for
    T_emax = 173 N·m.
    """
    inputs = dict(max_engine_torque=max_engine_torque, coefficient=coefficient)
    return st.nan_screened(_lining_outer_diameter, inputs, _domain(inputs))


def _lining_outer_diameter(*, max_engine_torque, coefficient):
    return 0.1 * np.sqrt(np.asarray(max_engine_torque, dtype=float) / coefficient)


def lining_coefficient(max_engine_torque, outer_diameter):
    """Design constant A of equation (3) of [1]: the inverse of :func:`lining_outer_diameter`.

    A = T_emax / (D[mm]/100)².

    Parameters
    ----------
    max_engine_torque : float or array_like [N m]
        Engine maximum torque T_emax.
    outer_diameter : float or array_like [m]
        Lining outer diameter D.

    Returns
    -------
    numpy.ndarray [-]
        A; NaN where an input is not positive, finite and plausible (:mod:`clutchlab.plausible`).

    References
    ----------
    Source paper (000), eq. (3) ([1] in the module docstring).
    """
    inputs = dict(max_engine_torque=max_engine_torque, outer_diameter=outer_diameter)
    return st.nan_screened(_lining_coefficient, inputs, _domain(inputs))


def _lining_coefficient(*, max_engine_torque, outer_diameter):
    return np.asarray(max_engine_torque, dtype=float) / (10.0 * np.asarray(outer_diameter)) ** 2


def effective_radius(outer_radius, inner_radius, assumption="uniform_pressure"):
    """Friction radius of an annular face.

    ``uniform_pressure`` (new lining): R_eff = (2/3)(R₂³ − R₁³)/(R₂² − R₁²), the integral of
    eqs. (13)–(14) of [1]; ``uniform_wear`` (worn-in lining): R_eff = (R₁ + R₂)/2.

    Parameters
    ----------
    outer_radius, inner_radius : float or array_like [m]
        Outer and inner lining radius R₂ > R₁ > 0.
    assumption : {"uniform_pressure", "uniform_wear"}
        Pressure distribution over the face.

    Returns
    -------
    numpy.ndarray [m]
        R_eff; NaN where a radius is not positive, finite and plausible
        (:mod:`clutchlab.plausible`) or R₂ ≤ R₁ (swapped radii are no lining).

    Raises
    ------
    ValueError
        For an unknown ``assumption``.

    References
    ----------
    Source paper (000), eqs. (13)–(14) ([1] in the module docstring): R_eff = 95.0 mm for the
    lining of 225/150 mm under uniform pressure.
    """
    if assumption not in ("uniform_pressure", "uniform_wear"):
        raise ValueError(
            f"assumption must be 'uniform_pressure' or 'uniform_wear', got {assumption!r}"
        )
    inputs = dict(outer_radius=outer_radius, inner_radius=inner_radius)
    return st.nan_screened(
        _effective_radius, inputs, _domain(inputs, _ANNULUS), extra={"assumption": assumption}
    )


def _effective_radius(*, outer_radius, inner_radius, assumption):
    ro = np.asarray(outer_radius, dtype=float)
    ri = np.asarray(inner_radius, dtype=float)
    if assumption == "uniform_pressure":
        return (2.0 / 3.0) * (ro**3 - ri**3) / (ro**2 - ri**2)
    if assumption == "uniform_wear":
        return 0.5 * (ro + ri)
    raise ValueError(f"assumption must be 'uniform_pressure' or 'uniform_wear', got {assumption!r}")


def torque_capacity(
    clamp_force,
    friction_coefficient,
    outer_radius,
    inner_radius,
    *,
    faces=2,
    assumption="uniform_pressure",
    stack_mass=0.0,
    gravity=STANDARD_GRAVITY,
):
    """Friction torque capacity T = z_f·μ·(F + m·g)·R_eff.

    Parameters
    ----------
    clamp_force : float or array_like [N]
        Axial clamp (spring) force F.
    friction_coefficient : float or array_like [-]
        Friction coefficient μ, in (0, 2].
    outer_radius, inner_radius : float or array_like [m]
        Lining radii R₂, R₁.
    faces : int or array_like [-]
        Number of friction faces z_f (2 for a single driven plate), a whole number in [1, 1000].
    assumption : {"uniform_pressure", "uniform_wear"}
        Pressure distribution for :func:`effective_radius`.
    stack_mass : float or array_like [kg]
        Mass m of driven plate, pressure plate and diaphragm that adds its weight to the clamp
        force on a vertical shaft; 0 for a horizontal shaft.
    gravity : float or array_like [m/s²]
        Acceleration of gravity g.

    Returns
    -------
    numpy.ndarray [N m]
        T; NaN where an input is not finite or not physical (F, m < 0; μ outside (0, 2]; a face
        count that is not a whole number in [1, 1000]; R₂ ≤ R₁ or R₁ ≤ 0) or of an implausible
        magnitude (:mod:`clutchlab.plausible`).

    Raises
    ------
    ValueError
        For an unknown ``assumption``.

    Notes
    -----
    Erratum for eq. (14) of [1]: as printed, M = (μ·m·g + F)·R_eff puts μ on the weight term
    only, omits μ on F, counts one face, and defines R₁, R₂ as diameters while using them as
    radii. The physically consistent capacity is the one computed here (193.5 N·m for the
    source paper's design). The paper's value is available from
    :func:`torque_capacity_eq14_as_printed` (239.3 N·m).

    References
    ----------
    Source paper (000), eqs. (13)–(14) ([1] in the module docstring), corrected as in the Notes.
    """
    inputs = dict(
        clamp_force=clamp_force,
        friction_coefficient=friction_coefficient,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        faces=faces,
        stack_mass=stack_mass,
        gravity=gravity,
    )
    effective_radius(1.0, 0.5, assumption)  # (refuses an unknown assumption)
    return st.nan_screened(
        _torque_capacity, inputs, _domain(inputs, _ANNULUS), extra={"assumption": assumption}
    )


def _torque_capacity(
    *,
    clamp_force,
    friction_coefficient,
    outer_radius,
    inner_radius,
    faces,
    stack_mass,
    gravity,
    assumption,
):
    f_total = np.asarray(clamp_force, dtype=float) + np.asarray(stack_mass) * gravity
    return (
        faces
        * friction_coefficient
        * f_total
        * _effective_radius(
            outer_radius=outer_radius, inner_radius=inner_radius, assumption=assumption
        )
    )


def torque_capacity_eq14_as_printed(
    clamp_force,
    friction_coefficient,
    stack_mass,
    outer_radius,
    inner_radius,
    gravity=STANDARD_GRAVITY,
):
    """The capacity of equation (14) of [1] exactly as printed: M = (μ·m·g + F)·R_eff (one face).

    Kept only to reproduce the paper's 239.3 N·m; it is dimensionally consistent but physically
    wrong (see :func:`torque_capacity`). Do not use it for design.

    Parameters
    ----------
    clamp_force : float or array_like [N]
        Axial clamp (spring) force F.
    friction_coefficient : float or array_like [-]
        Friction coefficient μ.
    stack_mass : float or array_like [kg]
        Mass m of the clutch stack whose weight the printed equation multiplies by μ.
    outer_radius, inner_radius : float or array_like [m]
        Lining radii R₂, R₁ (uniform pressure).
    gravity : float or array_like [m/s²]
        Acceleration of gravity g.

    Returns
    -------
    numpy.ndarray [N m]
        M; NaN where an input is invalid (as :func:`torque_capacity`).

    Notes
    -----
    Erratum: μ belongs on the clamp force, and a single-plate clutch has two faces
    (:func:`torque_capacity`).

    References
    ----------
    Source paper (000), eq. (14) as printed ([1] in the module docstring).
    """
    inputs = dict(
        clamp_force=clamp_force,
        friction_coefficient=friction_coefficient,
        stack_mass=stack_mass,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        gravity=gravity,
    )
    return st.nan_screened(_eq14_as_printed, inputs, _domain(inputs, _ANNULUS))


def _eq14_as_printed(
    *, clamp_force, friction_coefficient, stack_mass, outer_radius, inner_radius, gravity
):
    return (friction_coefficient * np.asarray(stack_mass) * gravity + clamp_force) * (
        _effective_radius(
            outer_radius=outer_radius, inner_radius=inner_radius, assumption="uniform_pressure"
        )
    )


def reserve_factor(torque_capacity, max_engine_torque):
    """Clutch reserve (backup) factor β = T_capacity / T_emax.

    Parameters
    ----------
    torque_capacity : float or array_like [N m]
        Torque capacity T_capacity ≥ 0.
    max_engine_torque : float or array_like [N m]
        Engine maximum torque T_emax > 0.

    Returns
    -------
    numpy.ndarray [-]
        β; NaN where an input is not finite, of the wrong sign or implausible
        (:mod:`clutchlab.plausible`).

    References
    ----------
    The usual clutch sizing ratio; the source paper (001) quotes β = 1.88 for its centrifugal
    clutch at 5500 rpm.
    """
    inputs = dict(torque_capacity=torque_capacity, max_engine_torque=max_engine_torque)
    return st.nan_screened(_reserve_factor, inputs, _domain(inputs))


def _reserve_factor(*, torque_capacity, max_engine_torque):
    return np.asarray(torque_capacity, dtype=float) / max_engine_torque
