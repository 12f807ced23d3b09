"""Sprag clutch under transient impact (the source paper (002)): impact torque, gripping angle
with race deflection, Hertz contact and shaft stresses.

All functions are pure and broadcast over numpy arrays; SI units (m, N, Pa, rad, s).

Geometry (the source paper (002), Fig. 2, Table 1): O is the clutch centre, A the centre of the
sprag's inner arc (radius ``r_i``), B the centre of its outer arc (``r_o``), ``|AB| = Z``. The sprag
touches the inner race (radius ``R_i``) on the ray OA and the outer race (``R_o``) on the ray OB, so
``|OA| = R_i + r_i`` and ``|OB| = R_o - r_o``; ψ = ∠AOB. A sprag is a two-force member: the load
acts along the chord between the contact points, at the gripping angle V to the radius at the inner
contact and W at the outer one, with V = W + ψ and ``R_i sin V = R_o sin W``.

References
----------
.. [1] "Analysis on the transient impact and wedging performance of the sprag clutch in the
   turbine starter", Aeronautical Science & Technology 35(3), 2024: the source paper (002),
   eqs. (1)-(8), Tables 1-2.
.. [2] Harris, T. A., Kotzalas, M. N., Rolling Bearing Analysis, 5th ed., 2007: Palmgren's
   line-contact approach δ = 3.84e-5 Q^0.9 / l^0.8 (mm, N; steel).
"""

from __future__ import annotations

import numpy as np

from . import status as st
from .published import SPRAG_CLUTCH, SPRAG_TABLE2

__all__ = [
    "impact_speed",
    "impact_torque",
    "steady_torque",
    "peak_torque",
    "rise_time_for_peak",
    "inertia_for_peak",
    "rest_geometry",
    "contact_approach",
    "race_deflections",
    "gripping_angle",
    "contact_stress",
    "shaft_stress",
    "statics",
    "fit_compliance_factor",
    "SEED_GEOMETRY",
]

#: the source paper (002), Table 1 [m], sprag count; steel (E, ν not printed: bearing steel 206 GPa, 0.3 assumed)
SEED_GEOMETRY = dict(
    inner_bore_radius=15.875e-3,
    inner_race_radius=22.225e-3,
    outer_race_radius=30.5562e-3,
    outer_rim_radius=38.735e-3,
    sprag_inner_radius=4.4958e-3,
    sprag_outer_radius=4.5212e-3,
    centre_distance=0.7468e-3,
    sprag_length=16.891e-3,
    sprags=18.0,
)
STEEL = dict(youngs_modulus=206e9, poisson_ratio=0.3)

_PALMGREN = 3.84e-5 * 1e-3 / 1e3**0.8  # δ [m] = _PALMGREN * Q[N]^0.9 / l[m]^0.8 (steel)
_E_STAR_STEEL = 206e9 / (2.0 * (1.0 - 0.3**2))  # reduced modulus the Palmgren constant belongs to


# --------------------------------------------------------------------------- impact torque (eqs 1-5)

# per-input rules of the impact model (sign, finite, plausible magnitude: clutchlab.plausible)
_IMPACT_RULES = {
    "time": st.nonnegative_in("s"),
    "rise_time": st.positive_in("s"),
    "power": st.positive_in("W"),
    "inertia": st.positive_in("kg m^2"),
    "damping": st.positive_in("N m s^2"),
    "initial_speed": st.nonnegative_in("rad/s"),
    "peak": st.positive_in("N m"),
}


def _impact(compute, **inputs):
    return st.nan_screened(compute, inputs, {k: _IMPACT_RULES[k] for k in inputs})


def impact_speed(time, *, power, inertia, damping, initial_speed=0.0):
    """Output speed ω(t) under constant input power and quadratic damping (equations (3)–(5)).

    J ω dω/dt + C ω² = P₀ is linear in ω²:  ω² = [P₀ − (P₀ − C ω₀²) e^(−2Ct/J)] / C.

    Parameters
    ----------
    time : float or array_like [s]
        Time t ≥ 0 since the start of the impact.
    power : float or array_like [W]
        Constant input power P₀ > 0.
    inertia : float or array_like [kg m²]
        Output-side inertia J_r > 0.
    damping : float or array_like [N m s²]
        Quadratic damping coefficient C_t > 0.
    initial_speed : float or array_like [rad/s]
        Output speed ω₀ ≥ 0 at t = 0.

    Returns
    -------
    numpy.ndarray [rad/s]
        ω(t); NaN where t, ω₀ < 0, P₀, J, C ≤ 0, or an input is not finite or plausible
        (:mod:`clutchlab.plausible`).

    Notes
    -----
    Erratum: eq. (4) of [1] is printed garbled; this is its exact solution, equivalent to
    T = P₀/ω.

    References
    ----------
    Source paper (002), eqs. (1)–(5) ([1] in the module docstring).
    """
    return _impact(
        _impact_speed,
        time=time,
        power=power,
        inertia=inertia,
        damping=damping,
        initial_speed=initial_speed,
    )


def _impact_speed(*, time, power, inertia, damping, initial_speed):
    p0, c = np.asarray(power, float), np.asarray(damping, float)
    w2 = (
        p0
        - (p0 - c * np.square(initial_speed)) * np.exp(-2.0 * c * np.asarray(time, float) / inertia)
    ) / c
    return np.sqrt(w2)


def impact_torque(time, *, power, inertia, damping, initial_speed=0.0):
    """Clutch torque T(t) = P₀ / ω(t) of the impact (equations (2), (4), (5) of [1]).

    Infinite at t = 0 for ω₀ = 0, hence the finite rise time t₀ of :func:`peak_torque` (the curve
    is used for t ≥ t₀).

    Parameters
    ----------
    time : float or array_like [s]
        Time t ≥ 0 since the start of the impact.
    power : float or array_like [W]
        Constant input power P₀ > 0.
    inertia : float or array_like [kg m²]
        Output-side inertia J_r > 0.
    damping : float or array_like [N m s²]
        Quadratic damping coefficient C_t > 0.
    initial_speed : float or array_like [rad/s]
        Output speed ω₀ ≥ 0 at t = 0.

    Returns
    -------
    numpy.ndarray [N m]
        T(t); NaN where an input is invalid (as :func:`impact_speed`).

    References
    ----------
    Source paper (002), eqs. (2), (4), (5) ([1] in the module docstring).
    """
    return _impact(
        _impact_torque,
        time=time,
        power=power,
        inertia=inertia,
        damping=damping,
        initial_speed=initial_speed,
    )


def _impact_torque(*, time, power, inertia, damping, initial_speed):
    with np.errstate(divide="ignore"):
        return power / _impact_speed(
            time=time, power=power, inertia=inertia, damping=damping, initial_speed=initial_speed
        )


def steady_torque(*, power, damping):
    """Steady impact torque T(∞) = √(P₀ C_t).

    Parameters
    ----------
    power : float or array_like [W]
        Constant input power P₀ > 0.
    damping : float or array_like [N m s²]
        Quadratic damping coefficient C_t > 0.

    Returns
    -------
    numpy.ndarray [N m]
        T(∞); NaN where an input is not positive, finite and plausible.

    Notes
    -----
    Erratum: section 2.1 of [1] prints "T_e = P₀C_t", which is garbled: the steady state of
    eq. (3) gives ω² = P₀/C and T = P₀/ω = √(P₀ C).

    References
    ----------
    Source paper (002), eq. (3) and section 2.1 ([1] in the module docstring).
    """
    return _impact(_steady_torque, power=power, damping=damping)


def _steady_torque(*, power, damping):
    return np.sqrt(np.asarray(power, float) * damping)


def peak_torque(*, rise_time, power, inertia, damping, initial_speed=0.0):
    """Peak torque T₀ = T(t₀) reached at the end of the rise time t₀.

    Rises with P₀, J and C and falls with ω₀ and t₀ (Fig. 4 b–e of [1]).

    Parameters
    ----------
    rise_time : float or array_like [s]
        Rise time t₀ > 0.
    power : float or array_like [W]
        Constant input power P₀ > 0.
    inertia : float or array_like [kg m²]
        Output-side inertia J_r > 0.
    damping : float or array_like [N m s²]
        Quadratic damping coefficient C_t > 0.
    initial_speed : float or array_like [rad/s]
        Output speed ω₀ ≥ 0 at t = 0.

    Returns
    -------
    numpy.ndarray [N m]
        T₀; NaN where an input is invalid (as :func:`impact_speed`).

    References
    ----------
    Source paper (002), section 1.1 and Fig. 4 ([1] in the module docstring).
    """
    return _impact(
        _peak_torque,
        rise_time=rise_time,
        power=power,
        inertia=inertia,
        damping=damping,
        initial_speed=initial_speed,
    )


def _peak_torque(*, rise_time, power, inertia, damping, initial_speed):
    return _impact_torque(
        time=rise_time, power=power, inertia=inertia, damping=damping, initial_speed=initial_speed
    )


def rise_time_for_peak(*, peak, power, inertia, damping, initial_speed=0.0):
    """Rise time t₀ at which T(t₀) equals ``peak``: the inverse of :func:`peak_torque`.

    t₀ = J/(2C) ln[(P₀ − Cω₀²)/(P₀ − C (P₀/T₀)²)].

    Parameters
    ----------
    peak : float or array_like [N m]
        Peak torque T₀ > 0.
    power : float or array_like [W]
        Constant input power P₀ > 0.
    inertia : float or array_like [kg m²]
        Output-side inertia J_r > 0.
    damping : float or array_like [N m s²]
        Quadratic damping coefficient C_t > 0.
    initial_speed : float or array_like [rad/s]
        Output speed ω₀ ≥ 0 at t = 0.

    Returns
    -------
    numpy.ndarray [s]
        t₀; NaN unless √(P₀C) < T₀ < P₀/ω₀, or where an input is invalid (as
        :func:`impact_speed`).

    References
    ----------
    Source paper (002), eqs. (3)–(5) inverted ([1] in the module docstring).
    """
    return _impact(
        _rise_time_for_peak,
        peak=peak,
        power=power,
        inertia=inertia,
        damping=damping,
        initial_speed=initial_speed,
    )


def _rise_time_for_peak(*, peak, power, inertia, damping, initial_speed):
    p0, c = np.asarray(power, float), np.asarray(damping, float)
    w = p0 / np.asarray(peak, float)
    num, den = p0 - c * np.square(initial_speed), p0 - c * w * w
    ok = (den > 0) & (num > den)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(ok, inertia / (2.0 * c) * np.log(num / den), np.nan)


def inertia_for_peak(*, peak, rise_time, power, damping):
    """Output inertia J for which T(t₀) = ``peak`` from rest (ω₀ = 0).

    J = 2 C t₀ / −ln(1 − P₀C/T₀²).

    Parameters
    ----------
    peak : float or array_like [N m]
        Peak torque T₀ > 0.
    rise_time : float or array_like [s]
        Rise time t₀ > 0.
    power : float or array_like [W]
        Constant input power P₀ > 0.
    damping : float or array_like [N m s²]
        Quadratic damping coefficient C > 0.

    Returns
    -------
    numpy.ndarray [kg m²]
        J; NaN unless T₀ > √(P₀C), or where an input is not positive, finite and plausible.

    References
    ----------
    Source paper (002), eqs. (3)–(5) inverted ([1] in the module docstring).
    """
    return _impact(_inertia_for_peak, peak=peak, rise_time=rise_time, power=power, damping=damping)


def _inertia_for_peak(*, peak, rise_time, power, damping):
    x = np.asarray(power, float) * damping / np.square(peak)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(x < 1, -2.0 * damping * rise_time / np.log1p(-x), np.nan)


# --------------------------------------------------------------------------- geometry and deflection

MAX_COMPLIANCE_FACTOR = 1e3  # deflection multiplier (1 physical; Table 2's fit: 1.73)
_ANGLE = st.between(0.0, np.pi / 2, lo_open=True)  # (π/2: the pure-torsion limit)
# per-input rules (sign, finite, plausible magnitude: clutchlab.plausible)
_DOMAIN = {
    "torque": st.nonnegative_in("N m"),
    "compliance_factor": st.positive_in("1", lo=1e-6, hi=MAX_COMPLIANCE_FACTOR),
    "contact_allowable": st.positive_in("Pa"),
    "shaft_allowable": st.positive_in("Pa"),
    "gripping_angle_allowable": st.between(0.0, np.pi / 2, lo_open=True),
    "sprags": st.count(1),
    "sprag_length": st.positive_in("m"),
    "centre_distance": st.positive_in("m"),
    "sprag_inner_radius": st.positive_in("m"),
    "sprag_outer_radius": st.positive_in("m"),
    "inner_bore_radius": st.nonnegative_in("m"),
    "inner_race_radius": st.positive_in("m"),
    "outer_race_radius": st.positive_in("m"),
    "outer_rim_radius": st.positive_in("m"),
    "youngs_modulus": st.positive_in("Pa"),
    "poisson_ratio": st.between(-1.0, 0.5, lo_open=True, hi_open=True),
    "load": st.nonnegative_in("N"),
    "load_inner": st.nonnegative_in("N"),
    "load_outer": st.nonnegative_in("N"),
    "V": _ANGLE,
    "W": _ANGLE,
}
# the races in order, inside out: shaft bore, inner race, outer race, outer rim
_RACES = {
    None: lambda a: (
        (a["inner_bore_radius"] < a["inner_race_radius"])
        & (a["inner_race_radius"] < a["outer_race_radius"])
        & (a["outer_race_radius"] < a["outer_rim_radius"])
    )
}
# and the sprag's arcs: its outer arc no larger than the outer race it rolls in
_SPRAG_IN_RACES = {
    None: lambda a: _RACES[None](a) & (a["sprag_outer_radius"] < a["outer_race_radius"])
}


def _domain(names):
    return {k: _DOMAIN[k] for k in names}


def _only_geometry(rest) -> None:
    """Refuse a keyword that is not a key of a geometry dict (a misspelt argument)."""
    unknown = set(rest) - set(SEED_GEOMETRY) - set(STEEL)
    if unknown:
        raise TypeError(f"unknown geometry argument(s): {', '.join(sorted(unknown))}")


def _full_geometry(geometry):
    """The source paper (002)'s geometry and steel, updated by ``geometry`` (unknown: TypeError)."""
    _only_geometry(geometry)
    return {**SEED_GEOMETRY, **STEEL, **geometry}


def _chord_angles(psi, r_in, r_out):
    """V and W of the contact chord for central angle ψ between contacts on radii r_in, r_out."""
    v = np.arctan2(r_out * np.sin(psi), r_out * np.cos(psi) - r_in)
    return v, v - psi


def _central_angle(oa, ob, z):
    """ψ of the triangle OAB; the sprag's reach ends where OA = OB (ψ maximal, sprag radial):
    beyond it (OB > OA) the angle is held at that maximum and the caller flags roll-over."""
    ob = np.minimum(ob, oa)
    c = (oa * oa + ob * ob - z * z) / (2.0 * oa * ob)
    return np.arccos(np.clip(c, -1.0, 1.0))


def rest_geometry(
    *,
    inner_race_radius,
    outer_race_radius,
    sprag_inner_radius,
    sprag_outer_radius,
    centre_distance,
    **rest,
):
    """Unloaded angles ψ₀, V₀, W₀ and the radial overlap d₀ = OA − OB of a sprag in its races.

    The sprag spans the races only for 0 < d₀ < Z (d₀ ≥ Z: it does not reach both races; d₀ ≤ 0: it
    stands past radial). The source paper (002)'s geometry gives ψ₀ = 0.642°, V₀ = 2.354°.

    Parameters
    ----------
    inner_race_radius : float or array_like [m]
        Inner race radius R_i.
    outer_race_radius : float or array_like [m]
        Outer race radius R_o > R_i.
    sprag_inner_radius : float or array_like [m]
        Radius r_i of the sprag's inner arc.
    sprag_outer_radius : float or array_like [m]
        Radius r_o of the sprag's outer arc.
    centre_distance : float or array_like [m]
        Distance Z = ``|AB|`` of the arcs' centres.
    **rest : dict
        Further keys of a geometry dict (:data:`SEED_GEOMETRY`, the steel's), ignored here;
        another name is a TypeError (a misspelt argument is not dropped).

    Returns
    -------
    dict of numpy.ndarray
        ``psi``, ``V``, ``W`` [rad], ``overlap`` [m]; NaN where a radius is not positive, finite and
        plausible or the races are out of order (R_i < R_o).

    References
    ----------
    Source paper (002), Fig. 2 and Table 1 ([1] in the module docstring); the geometry of eq. (6)
    (module docstring).
    """
    _only_geometry(rest)
    inputs = dict(
        inner_race_radius=inner_race_radius,
        outer_race_radius=outer_race_radius,
        sprag_inner_radius=sprag_inner_radius,
        sprag_outer_radius=sprag_outer_radius,
        centre_distance=centre_distance,
    )
    return st.screened(
        _rest_geometry,
        inputs,
        {**_domain(inputs), None: lambda a: a["inner_race_radius"] < a["outer_race_radius"]},
    )


def _rest_geometry(
    *,
    inner_race_radius,
    outer_race_radius,
    sprag_inner_radius,
    sprag_outer_radius,
    centre_distance,
    **_,
):
    oa = inner_race_radius + sprag_inner_radius
    ob = outer_race_radius - sprag_outer_radius
    psi = _central_angle(oa, ob, centre_distance)
    v, w = _chord_angles(psi, inner_race_radius, outer_race_radius)
    return dict(psi=psi, V=v, W=w, overlap=oa - ob)


def contact_approach(load, *, sprag_length, youngs_modulus=206e9, poisson_ratio=0.3):
    """Mutual approach of a steel line contact, δ = 3.84e-5 Q^0.9 / l^0.8 (mm, N) (Palmgren, [2]).

    Scaled as (E*_steel / E*)^0.9 for other moduli (the power of Q/(l E*) in that formula).

    Parameters
    ----------
    load : float or array_like [N]
        Contact load Q ≥ 0.
    sprag_length : float or array_like [m]
        Contact length l > 0.
    youngs_modulus : float or array_like [Pa]
        Young's modulus E > 0 of both bodies.
    poisson_ratio : float or array_like [-]
        Poisson's ratio ν ∈ (−1, 0.5).

    Returns
    -------
    numpy.ndarray [m]
        δ; NaN where an input is out of range, not finite or not plausible.

    References
    ----------
    Harris and Kotzalas [2] (Palmgren's line-contact approach).
    """
    inputs = dict(
        load=load,
        sprag_length=sprag_length,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
    )
    return st.nan_screened(_contact_approach, inputs, _domain(inputs))


def _contact_approach(*, load, sprag_length, youngs_modulus, poisson_ratio):
    e_star = youngs_modulus / (2.0 * (1.0 - np.square(poisson_ratio)))
    q = np.maximum(load, 0.0)
    return _PALMGREN * q**0.9 / sprag_length**0.8 * (_E_STAR_STEEL / e_star) ** 0.9


def race_deflections(
    load_inner,
    load_outer,
    *,
    sprags,
    sprag_length,
    inner_bore_radius,
    inner_race_radius,
    outer_race_radius,
    outer_rim_radius,
    youngs_modulus=206e9,
    poisson_ratio=0.3,
    **rest,
):
    """Radial displacement of the race surfaces under the smeared sprag pressure.

    Lamé thick cylinders, plane stress: inner shaft under external pressure
    p_i = n N_i/(2π R_i l) (u_i < 0), outer race under internal pressure p_o = n N_o/(2π R_o l)
    (u_o > 0).

    Parameters
    ----------
    load_inner : float or array_like [N]
        Normal load N_i ≥ 0 per sprag at the inner contact.
    load_outer : float or array_like [N]
        Normal load N_o ≥ 0 per sprag at the outer contact.
    sprags : int or array_like [-]
        Sprag count n, a whole number in [1, 1000].
    sprag_length : float or array_like [m]
        Sprag (contact) length l.
    inner_bore_radius : float or array_like [m]
        Bore radius R_id ≥ 0 of the inner shaft.
    inner_race_radius : float or array_like [m]
        Inner race radius R_i.
    outer_race_radius : float or array_like [m]
        Outer race radius R_o.
    outer_rim_radius : float or array_like [m]
        Outer radius R_od of the outer race; 0 ≤ R_id < R_i < R_o < R_od.
    youngs_modulus : float or array_like [Pa]
        Young's modulus E of the races.
    poisson_ratio : float or array_like [-]
        Poisson's ratio ν ∈ (−1, 0.5).
    **rest : dict
        Further keys of a geometry dict (:data:`SEED_GEOMETRY`, the steel's), ignored here;
        another name is a TypeError (a misspelt argument is not dropped).

    Returns
    -------
    u_inner : numpy.ndarray [m]
        Radial displacement of the inner race surface (negative: inwards).
    u_outer : numpy.ndarray [m]
        Radial displacement of the outer race surface (positive: outwards). Both NaN where an
        input is out of range, not finite or not plausible.

    References
    ----------
    Source paper (002), eq. (6) (the deflection it needs; module docstring); Lamé's thick
    cylinder.
    """
    _only_geometry(rest)
    inputs = dict(
        load_inner=load_inner,
        load_outer=load_outer,
        sprags=sprags,
        sprag_length=sprag_length,
        inner_bore_radius=inner_bore_radius,
        inner_race_radius=inner_race_radius,
        outer_race_radius=outer_race_radius,
        outer_rim_radius=outer_rim_radius,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
    )
    return st.nan_screened(_race_deflections, inputs, {**_domain(inputs), **_RACES})


def _race_deflections(
    load_inner,
    load_outer,
    *,
    sprags,
    sprag_length,
    inner_bore_radius,
    inner_race_radius,
    outer_race_radius,
    outer_rim_radius,
    youngs_modulus=206e9,
    poisson_ratio=0.3,
    **_,
):
    e, nu = youngs_modulus, poisson_ratio
    a, b = inner_bore_radius, inner_race_radius
    p_i = sprags * load_inner / (2.0 * np.pi * b * sprag_length)
    u_i = -p_i * b / e * ((b * b + a * a) / (b * b - a * a) - nu)
    a, b = outer_race_radius, outer_rim_radius
    p_o = sprags * load_outer / (2.0 * np.pi * a * sprag_length)
    u_o = p_o * a / e * ((b * b + a * a) / (b * b - a * a) + nu)
    return u_i, u_o


def _normal_loads(torque, v, w, r_in, r_out, sprags):
    """Normal load per sprag at the inner and outer contact: N = T cot(angle) / (n R) [N]."""
    return torque / (sprags * r_in * np.tan(v)), torque / (sprags * r_out * np.tan(w))


UNSETTLED_RADII = 1e-4


def _deformed(torque, v, g, compliance_factor, inner_passes=3):
    """Deformed radii and the new (ψ, V, W) for an assumed gripping angle V (one map of the fixed
    point). The outer angle W = asin(R̄_i sin V / R̄_o) needs the deformed radii, which need the
    loads: three passes (contraction ~1e-3 per pass). They are not exact to rounding: the loads of
    the last pass and the radii they give disagree by up to 8.7e-7 relative (5.7e-6 near
    roll-over, measured), well below the model's own uncertainty (a fitted compliance
    factor); the outer fixed point for V is then solved to 1e-12 rad for this map."""
    n, length = g["sprags"], g["sprag_length"]
    mat = dict(youngs_modulus=g["youngs_modulus"], poisson_ratio=g["poisson_ratio"])
    ri_bar, ro_bar = g["inner_race_radius"], g["outer_race_radius"]
    for _ in range(inner_passes):
        ri_prev, ro_prev = ri_bar, ro_bar
        w = np.arcsin(ri_bar * np.sin(v) / ro_bar)
        n_i, n_o = _normal_loads(torque, v, w, ri_bar, ro_bar, n)
        u_i, u_o = _race_deflections(n_i, n_o, **g)
        ri_bar = g["inner_race_radius"] + compliance_factor * u_i
        ro_bar = g["outer_race_radius"] + compliance_factor * u_o
    # change of the radii in the last pass: ~1e-6 relative on the physical branch; far above that
    # the races' load-deflection loop does not settle (loads so large that the radii move by their
    # own size): the roots found there are not states of the clutch
    unsettled = ~(
        np.maximum(
            np.abs(ri_bar - ri_prev) / g["inner_race_radius"],
            np.abs(ro_bar - ro_prev) / g["outer_race_radius"],
        )
        <= UNSETTLED_RADII
    )
    d_i = compliance_factor * _contact_approach(load=n_i, sprag_length=length, **mat)
    d_o = compliance_factor * _contact_approach(load=n_o, sprag_length=length, **mat)
    # the contact approach shortens the sprag's effective arc radii (the r̄ of the source paper (002), eq. 7)
    si_bar, so_bar = g["sprag_inner_radius"] - d_i, g["sprag_outer_radius"] - d_o
    oa, ob = ri_bar + si_bar, ro_bar - so_bar
    psi = _central_angle(oa, ob, g["centre_distance"])
    v_new, w_new = _chord_angles(psi, ri_bar, ro_bar)
    return dict(
        V=v_new,
        W=w_new,
        psi=psi,
        inner_race_radius=ri_bar,
        outer_race_radius=ro_bar,
        sprag_inner_radius=si_bar,
        sprag_outer_radius=so_bar,
        overlap=oa - ob,
        load_inner=n_i,
        load_outer=n_o,
        unsettled=unsettled,
    )


def _geometry(kw):
    g = {**SEED_GEOMETRY, **STEEL}
    g.update({k: v for k, v in kw.items() if k in g})
    return {k: np.asarray(v, float) for k, v in g.items()}


def gripping_angle(torque, *, compliance_factor=1.0, tol=1e-12, max_iter=60, **geometry):
    """Gripping angle V under torque with race deflection and contact approach (equation (6)).

    Eq. (6) is cited from the Aero-engine Design Manual vol. 13 but not printed. Reconstruction:
    loads along the contact chord N_i = T cot V/(n R̄_i), N_o = T cot W/(n R̄_o); races deflect as
    Lamé cylinders under the smeared pressure (:func:`race_deflections`); the contacts approach by
    Palmgren's line-contact law (:func:`contact_approach`); the deformed OA = R̄_i + r̄_i,
    OB = R̄_o − r̄_o give ψ and tan V = R̄_o sin ψ/(R̄_o cos ψ − R̄_i). The deflection is
    ``compliance_factor`` times the physical one (1 = physical; :func:`fit_compliance_factor` fits
    it to Table 2 at 750 N·m: 1.726).

    The fixed point V = V_new(V) is solved as a root of G(V) = V − V_new(V), which increases
    strictly (more V, less load, less deflection, smaller V_new), by vectorised regula falsi
    (Illinois) on the bracket [V₀, 80°]: no per-scenario Python loop.

    Parameters
    ----------
    torque : float or array_like [N m]
        Torque T ≥ 0 through the clutch.
    compliance_factor : float or array_like [-]
        Multiplier of the physical deflection, in [1e-6, 1000].
    tol : float
        Bracket width [rad] at which a scenario is converged, in (0, 0.1].
    max_iter : int
        Bracketing steps at most, a whole number in [1, 1000].
    **geometry : float or array_like
        The keys of :data:`SEED_GEOMETRY` (radii and lengths [m], the sprag count [-]) and
        ``youngs_modulus`` [Pa], ``poisson_ratio`` [-]; missing ones take the source paper (002)'s
        values (Table 1; bearing steel 206 GPa, 0.3 assumed). An unknown key raises TypeError.

    Returns
    -------
    dict of numpy.ndarray
        ``V``, ``W``, ``psi`` [rad]; deformed radii ``inner_race_radius``, ``outer_race_radius``,
        ``sprag_inner_radius``, ``sprag_outer_radius`` [m]; ``load_inner``, ``load_outer`` [N];
        ``status`` (ok, invalid_geometry: the sprag does not span the races at rest, or the races
        are out of order (0 ≤ R_id < R_i < R_o < R_od, r_o < R_o); roll_over: the loaded races open
        past the sprag's reach; not_converged; invalid_input: an input not finite, not physical
        (T < 0, a sprag count that is not whole, ν outside (−1, 0.5), ...) or of an implausible
        magnitude (:mod:`clutchlab.plausible`)); ``n_iterations`` (bracketing steps taken). At zero
        torque the result is the rest geometry (:func:`rest_geometry`) with zero loads.

    Raises
    ------
    ValueError
        If ``tol`` or ``max_iter`` is out of range.
    TypeError
        For an unknown geometry keyword.

    Notes
    -----
    With the physical compliance (factor 1) V comes out about 11 % below Table 2 of [1] and the
    stresses 6–12 % above; the fitted factor reproduces every Table 2 number within 0.4 %.

    References
    ----------
    Source paper (002), eq. (6) (cited, not printed), Table 1 (geometry) and Table 2 (V at 267.5
    and 750 N·m) ([1] in the module docstring); Harris and Kotzalas [2].
    """
    _check_fixed_point(tol, max_iter)
    inputs = dict(torque=torque, compliance_factor=compliance_factor, **_full_geometry(geometry))
    return st.screened(
        _gripping_angle,
        inputs,
        _domain(inputs),
        geometry=_SPRAG_IN_RACES,
        extra=dict(tol=tol, max_iter=max_iter),
    )


def _check_fixed_point(tol, max_iter):
    if not (np.isscalar(tol) and 0 < tol <= 0.1):
        raise ValueError(f"tol must be a bracket width in (0, 0.1] rad, got {tol!r}")
    if not (np.isscalar(max_iter) and 1 <= max_iter <= 1000 and max_iter == int(max_iter)):
        raise ValueError(f"max_iter must be a whole number in [1, 1000], got {max_iter!r}")


def _gripping_angle(torque, *, compliance_factor, tol, max_iter, **geometry):
    g = _geometry(geometry)
    torque = np.asarray(torque, float)
    shape = np.broadcast_shapes(
        torque.shape, np.shape(compliance_factor), *(v.shape for v in g.values())
    )
    g = {k: np.broadcast_to(v, shape).ravel() for k, v in g.items()}
    t = np.broadcast_to(torque, shape).ravel()
    c = np.broadcast_to(np.asarray(compliance_factor, float), shape).ravel()
    rest = _rest_geometry(**g)
    valid = (rest["overlap"] > 0) & (rest["overlap"] < g["centre_distance"]) & (t >= 0)

    lo = np.where(valid, rest["V"], 0.1)
    # unloaded (T = 0): the rest geometry itself (no load, no deflection), bracket closed at V₀
    hi = np.where(valid & (t == 0), lo, np.deg2rad(80.0))

    def f(v):
        with np.errstate(
            invalid="ignore"
        ):  # beyond roll-over the deformed geometry has no angles (NaN)
            return v - _deformed(t, v, g, c)["V"]

    f_lo, f_hi = f(lo), f(hi)
    side = np.zeros(lo.shape, np.int8)
    iterations = np.zeros(lo.shape, np.int32)
    for _ in range(int(max_iter)):
        active = valid & (hi - lo > tol)
        if not active.any():
            break
        iterations += active
        with np.errstate(
            divide="ignore", invalid="ignore"
        ):  # inactive (e.g. unloaded) lanes: unused
            x = np.where(active, (lo * f_hi - hi * f_lo) / (f_hi - f_lo), lo)
        x = np.where(active & ~((x > lo) & (x < hi)), 0.5 * (lo + hi), x)
        fx = f(x)
        right = active & (fx > 0)  # root left of x
        left = active & (fx <= 0)
        hi, f_hi = np.where(right, x, hi), np.where(right, fx, f_hi)
        lo, f_lo = np.where(left, x, lo), np.where(left, fx, f_lo)
        # Illinois: halve the stale end's value when the same side moves twice
        f_lo = np.where(right & (side == 1), 0.5 * f_lo, f_lo)
        f_hi = np.where(left & (side == -1), 0.5 * f_hi, f_hi)
        side = np.where(right, 1, np.where(left, -1, side)).astype(np.int8)
        if (fx == 0).any():
            hi = np.where(active & (fx == 0), x, hi)
            lo = np.where(active & (fx == 0), x, lo)
    v = 0.5 * (lo + hi)
    with np.errstate(invalid="ignore"):
        out = _deformed(t, v, g, c)
        out["V"] = v
        out["W"] = np.arcsin(out["inner_race_radius"] * np.sin(v) / out["outer_race_radius"])
    out["psi"] = v - out["W"]
    code = np.full(v.shape, st.CODE["ok"], dtype=st.DTYPE)
    code[valid & (hi - lo > tol)] = st.CODE["not_converged"]
    # roll-over: the loaded races open past the sprag's reach (deformed overlap ≤ 0), or the loads are
    # so far beyond it that the deformed geometry is no state of the clutch (radii that do not
    # settle, a sprag longer than it is wide): the roots found there are spurious (a status that
    # grows back to above_allowable at 50x the roll-over torque)
    beyond = (
        (out["overlap"] <= 0)
        | ~(out["overlap"] < g["centre_distance"])
        | out.pop("unsettled")
        | ~(out["sprag_inner_radius"] > 0)
        | ~(out["sprag_outer_radius"] > 0)
        | ~(out["load_inner"] >= 0)
        | ~(out["load_outer"] >= 0)
    )
    code[valid & beyond] = st.CODE["roll_over"]
    code[~valid] = st.CODE["invalid_geometry"]
    bad = code != st.CODE["ok"]
    res = {k: np.where(bad, np.nan, val).reshape(shape) for k, val in out.items() if k != "overlap"}
    res["status"] = code.reshape(shape)
    res["n_iterations"] = iterations.reshape(
        shape
    )  # bracketing steps taken (Illinois regula falsi)
    return res


# --------------------------------------------------------------------------- stresses (eqs 7-8)


def contact_stress(
    torque,
    *,
    V,
    W,
    sprags,
    sprag_length,
    inner_race_radius,
    outer_race_radius,
    sprag_inner_radius,
    sprag_outer_radius,
    youngs_modulus=206e9,
    poisson_ratio=0.3,
    **rest,
):
    """Hertz line-contact stress at the inner and outer contact (equation (7) of [1]).

    σ_ci = √[T cot V (1/r̄_i + 1/R̄_i) / (π n l R̄_i · 2(1−ν²)/E)],
    σ_co = √[T cot W (1/r̄_o − 1/R̄_o) / (π n l R̄_o · 2(1−ν²)/E)] (concave outer race).
    Pass the deformed radii (:func:`gripping_angle`) as eq. (7) does, or the rest radii; one steel
    for all three parts (eq. (7) allows E₁, E₂, E₃: the paper prints none).

    Parameters
    ----------
    torque : float or array_like [N m]
        Torque T ≥ 0.
    V : float or array_like [rad]
        Gripping angle at the inner contact, in (0, π/2].
    W : float or array_like [rad]
        Gripping angle at the outer contact, in (0, π/2].
    sprags : int or array_like [-]
        Sprag count n.
    sprag_length : float or array_like [m]
        Sprag (contact) length l.
    inner_race_radius : float or array_like [m]
        Inner race radius R̄_i.
    outer_race_radius : float or array_like [m]
        Outer race radius R̄_o > R̄_i.
    sprag_inner_radius : float or array_like [m]
        Radius r̄_i of the sprag's inner arc.
    sprag_outer_radius : float or array_like [m]
        Radius r̄_o < R̄_o of the sprag's outer arc.
    youngs_modulus : float or array_like [Pa]
        Young's modulus E.
    poisson_ratio : float or array_like [-]
        Poisson's ratio ν.
    **rest : dict
        Further keys of a geometry dict (:data:`SEED_GEOMETRY`, the steel's), ignored here;
        another name is a TypeError (a misspelt argument is not dropped).

    Returns
    -------
    inner : numpy.ndarray [Pa]
        σ_ci.
    outer : numpy.ndarray [Pa]
        σ_co. Both NaN where T < 0, V or W outside (0, π/2], a length or E not positive, the races
        out of order (R_i < R_o, r̄_o < R̄_o), or an input not finite or plausible.

    Notes
    -----
    The square root covers the whole fraction; the printed layout of eq. (7) is ambiguous.

    References
    ----------
    Source paper (002), eq. (7) and Table 2 ([1] in the module docstring).
    """
    _only_geometry(rest)
    inputs = dict(
        torque=torque,
        V=V,
        W=W,
        sprags=sprags,
        sprag_length=sprag_length,
        inner_race_radius=inner_race_radius,
        outer_race_radius=outer_race_radius,
        sprag_inner_radius=sprag_inner_radius,
        sprag_outer_radius=sprag_outer_radius,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
    )
    inside = {
        None: lambda a: (
            (a["inner_race_radius"] < a["outer_race_radius"])
            & (a["sprag_outer_radius"] < a["outer_race_radius"])
        )
    }
    return st.nan_screened(_contact_stress, inputs, {**_domain(inputs), **inside})


def _contact_stress(
    torque,
    *,
    V,
    W,
    sprags,
    sprag_length,
    inner_race_radius,
    outer_race_radius,
    sprag_inner_radius,
    sprag_outer_radius,
    youngs_modulus=206e9,
    poisson_ratio=0.3,
    **_,
):
    k = 2.0 * (1.0 - np.square(poisson_ratio)) / youngs_modulus
    ci = (
        torque
        / np.tan(V)
        * (1.0 / sprag_inner_radius + 1.0 / inner_race_radius)
        / (np.pi * sprags * sprag_length * inner_race_radius * k)
    )
    co = (
        torque
        / np.tan(W)
        * (1.0 / sprag_outer_radius - 1.0 / outer_race_radius)
        / (np.pi * sprags * sprag_length * outer_race_radius * k)
    )
    return np.sqrt(ci), np.sqrt(co)


def _von_mises(sr, st_, tau):
    return np.sqrt(sr * sr + st_ * st_ - sr * st_ + 3.0 * tau * tau)


def shaft_stress(
    torque,
    *,
    V,
    W,
    sprags,
    sprag_length,
    inner_bore_radius,
    inner_race_radius,
    outer_race_radius,
    outer_rim_radius,
    **rest,
):
    """Von Mises stress of the inner shaft and the outer race (equation (8) of [1]).

    Plane stress (no axial load): Lamé radial and hoop stress under the smeared sprag pressure
    (p_i = n N_i/(2π R̄_i l) outside the inner shaft, p_o = n N_o/(2π R̄_o l) inside the outer race)
    plus the torsional shear T ρ/J_p.

    Parameters
    ----------
    torque : float or array_like [N m]
        Torque T ≥ 0.
    V : float or array_like [rad]
        Gripping angle at the inner contact, in (0, π/2].
    W : float or array_like [rad]
        Gripping angle at the outer contact, in (0, π/2].
    sprags : int or array_like [-]
        Sprag count n.
    sprag_length : float or array_like [m]
        Sprag (contact) length l.
    inner_bore_radius : float or array_like [m]
        Bore radius R_id ≥ 0 of the inner shaft.
    inner_race_radius : float or array_like [m]
        Inner race radius R_i.
    outer_race_radius : float or array_like [m]
        Outer race radius R_o.
    outer_rim_radius : float or array_like [m]
        Outer radius R_od of the outer race; 0 ≤ R_id < R_i < R_o < R_od.
    **rest : dict
        Further keys of a geometry dict (:data:`SEED_GEOMETRY`, the steel's), ignored here;
        another name is a TypeError (a misspelt argument is not dropped).

    Returns
    -------
    dict of numpy.ndarray [Pa]
        The stress at both surfaces of each part (``inner_bore``, ``inner_surface``,
        ``outer_bore``, ``outer_surface``) and the maxima ``inner``, ``outer`` (at the bores for
        proportions like the source paper's); NaN where T < 0, V or W outside (0, π/2], the races
        out of order, or an input not finite, not physical or not plausible.

    Notes
    -----
    Eq. (8) is not legible in [1]; this is its stated content (Fig. 3, "fourth strength theory").

    References
    ----------
    Source paper (002), eq. (8), Fig. 3 and Table 2 ([1] in the module docstring).
    """
    _only_geometry(rest)
    inputs = dict(
        torque=torque,
        V=V,
        W=W,
        sprags=sprags,
        sprag_length=sprag_length,
        inner_bore_radius=inner_bore_radius,
        inner_race_radius=inner_race_radius,
        outer_race_radius=outer_race_radius,
        outer_rim_radius=outer_rim_radius,
    )
    return st.screened(_shaft_stress, inputs, {**_domain(inputs), **_RACES})


def _shaft_stress(
    torque,
    *,
    V,
    W,
    sprags,
    sprag_length,
    inner_bore_radius,
    inner_race_radius,
    outer_race_radius,
    outer_rim_radius,
    **_,
):
    n_i, n_o = _normal_loads(torque, V, W, inner_race_radius, outer_race_radius, sprags)
    out = {}
    for name, a, b, p, sign in (
        ("inner", inner_bore_radius, inner_race_radius, n_i, -1.0),
        ("outer", outer_race_radius, outer_rim_radius, n_o, 1.0),
    ):
        r_load = b if sign < 0 else a
        press = sprags * p / (2.0 * np.pi * r_load * sprag_length)
        jp = 0.5 * np.pi * (b**4 - a**4)
        k = press * r_load * r_load / (b * b - a * a)  # Lamé: σ = A ∓ B/ρ²
        for where, rho in (("bore", a), ("surface", b)):
            if sign < 0:  # external pressure on (a, b)
                sr, sth = -k * (1.0 - a * a / rho**2), -k * (1.0 + a * a / rho**2)
            else:  # internal pressure on (a, b)
                sr, sth = k * (1.0 - b * b / rho**2), k * (1.0 + b * b / rho**2)
            out[f"{name}_{where}"] = _von_mises(sr, sth, torque * rho / jp)
        out[name] = np.maximum(out[f"{name}_bore"], out[f"{name}_surface"])
    return out


#: The allowables of the source paper (002), Table 2 [Pa, Pa, rad] (:data:`clutchlab.published.SPRAG_CLUTCH`).
ALLOWABLES = dict(
    contact_allowable=SPRAG_CLUTCH["contact_allowable"].value * 1e6,
    shaft_allowable=SPRAG_CLUTCH["shaft_allowable"].value * 1e6,
    gripping_angle_allowable=np.deg2rad(SPRAG_CLUTCH["gripping_angle_allowable"].value),
)
_PEAK = SPRAG_TABLE2[750.0]  # the source paper (002), Table 2, theory column, at the peak torque
_PEAK_V = float(np.deg2rad(_PEAK.gripping_angle))  # [rad]


def statics(
    torque,
    *,
    compliance_factor=1.0,
    contact_allowable=ALLOWABLES["contact_allowable"],
    shaft_allowable=ALLOWABLES["shaft_allowable"],
    gripping_angle_allowable=ALLOWABLES["gripping_angle_allowable"],
    **geometry,
):
    """Gripping angle, contact and shaft stresses, margins and checks for a torque.

    Parameters
    ----------
    torque : float or array_like [N m]
        Torque T ≥ 0.
    compliance_factor : float or array_like [-]
        Multiplier of the physical deflection (:func:`gripping_angle`).
    contact_allowable : float or array_like [Pa]
        Allowable contact stress (3400 MPa: Table 2 of [1]).
    shaft_allowable : float or array_like [Pa]
        Allowable von Mises stress of shaft and race (793 MPa: Table 2).
    gripping_angle_allowable : float or array_like [rad]
        Allowable gripping angle (5°: Table 2).
    **geometry : float or array_like
        The keys of :data:`SEED_GEOMETRY` (radii and lengths [m], the sprag count [-]) and
        ``youngs_modulus`` [Pa], ``poisson_ratio`` [-]; missing ones take the source paper (002)'s
        values (Table 1; bearing steel 206 GPa, 0.3 assumed). An unknown key raises TypeError.

    Returns
    -------
    dict of numpy.ndarray
        ``V``, ``W``, ``psi`` [rad]; ``contact_stress_inner``, ``contact_stress_outer``,
        ``vm_stress_inner``, ``vm_stress_outer`` [Pa]; ``margin_*`` = allowable/value − 1 [-] for
        the five checks (``contact_inner``, ``contact_outer``, ``vm_inner``, ``vm_outer``,
        ``gripping_angle``); ``n_iterations``; ``status``: invalid_input (an input not finite or
        not physical: negative torque, a sprag count that is not whole, ν outside (−1, 0.5), ...),
        invalid_geometry / roll_over / not_converged (no numbers), else pop_out_risk when V exceeds
        its allowable, else above_allowable when a stress does, else ok. Zero torque: the rest
        geometry, zero stresses. Magnitudes outside :mod:`clutchlab.plausible` (a million sprags,
        E = 1e308 Pa) are invalid_input; races out of order (0 ≤ R_id < R_i < R_o < R_od,
        r_o < R_o) invalid_geometry.

    Raises
    ------
    TypeError
        For an unknown geometry keyword.

    References
    ----------
    Source paper (002), eqs. (6)–(8) and Table 2 ([1] in the module docstring).
    """
    inputs = dict(
        torque=torque,
        compliance_factor=compliance_factor,
        contact_allowable=contact_allowable,
        shaft_allowable=shaft_allowable,
        gripping_angle_allowable=gripping_angle_allowable,
        **_full_geometry(geometry),
    )
    return st.screened(_statics, inputs, _domain(inputs), geometry=_SPRAG_IN_RACES)


def _statics(
    torque,
    *,
    compliance_factor,
    contact_allowable,
    shaft_allowable,
    gripping_angle_allowable,
    **geometry,
):
    grip = _gripping_angle(
        torque, compliance_factor=compliance_factor, tol=1e-12, max_iter=60, **geometry
    )
    g = {
        **_geometry(geometry),
        **{
            k: grip[k]
            for k in (
                "inner_race_radius",
                "outer_race_radius",
                "sprag_inner_radius",
                "sprag_outer_radius",
            )
        },
    }
    ci, co = _contact_stress(torque, V=grip["V"], W=grip["W"], **g)
    vm = _shaft_stress(torque, V=grip["V"], W=grip["W"], **g)
    out = dict(
        V=grip["V"],
        W=grip["W"],
        psi=grip["psi"],
        contact_stress_inner=ci,
        contact_stress_outer=co,
        vm_stress_inner=vm["inner"],
        vm_stress_outer=vm["outer"],
    )
    checks = dict(
        contact_inner=(ci, contact_allowable),
        contact_outer=(co, contact_allowable),
        vm_inner=(vm["inner"], shaft_allowable),
        vm_outer=(vm["outer"], shaft_allowable),
        gripping_angle=(grip["V"], gripping_angle_allowable),
    )
    with np.errstate(divide="ignore"):  # unloaded: an infinite margin
        for name, (value, allowable) in checks.items():
            out[f"margin_{name}"] = allowable / value - 1.0
    out["n_iterations"] = grip["n_iterations"]
    code = np.array(grip["status"], copy=True)
    ok = code == st.CODE["ok"]
    stress_bad = np.zeros(code.shape, bool)
    for name in ("contact_inner", "contact_outer", "vm_inner", "vm_outer"):
        stress_bad |= out[f"margin_{name}"] < 0
    code[ok & stress_bad] = st.CODE["above_allowable"]
    code[ok & (out["margin_gripping_angle"] < 0)] = st.CODE["pop_out_risk"]
    out["status"] = code
    return out


def fit_compliance_factor(*, torque=_PEAK.torque, gripping_angle_target=_PEAK_V, **geometry):
    """Compliance factor at which :func:`gripping_angle` gives the target angle at ``torque``.

    V grows monotonically with the factor, so a scalar bracketed root (Brent) finds it.

    Parameters
    ----------
    torque : float [N m]
        Torque (default: 750 N·m, the peak of Table 2 of [1]).
    gripping_angle_target : float [rad]
        Target V in (0, π/2) (default: 5.097°, Table 2's theory column at 750 N·m).
    **geometry : float or array_like
        The keys of :data:`SEED_GEOMETRY` (radii and lengths [m], the sprag count [-]) and
        ``youngs_modulus`` [Pa], ``poisson_ratio`` [-]; missing ones take the source paper (002)'s
        values (Table 1; bearing steel 206 GPa, 0.3 assumed). An unknown key raises TypeError.

    Returns
    -------
    float [-]
        The factor (1.726 for the defaults); NaN where the torque, the target or the geometry is
        invalid (as :func:`statics`).

    Raises
    ------
    ValueError
        Where no factor up to 100 reaches the target, or the target lies beyond the sprag's reach.

    References
    ----------
    Source paper (002), Table 2 ([1] in the module docstring).
    """
    from scipy.optimize import brentq

    inputs = dict(torque=torque, **_full_geometry(geometry))
    _, ok = st.admissible(inputs, {**_domain(inputs), **_SPRAG_IN_RACES})
    if not (ok and _ANGLE(np.asarray(gripping_angle_target, float))):
        return np.nan

    def f(c):
        v = float(gripping_angle(torque, compliance_factor=c, **geometry)["V"])
        return v - gripping_angle_target if np.isfinite(v) else 1.0  # roll-over: past any target

    lo, hi = 0.0, 1.0
    while f(hi) < 0:
        lo, hi = hi, 1.5 * hi
        if hi > 100:
            raise ValueError("no compliance factor up to 100 reaches the target gripping angle")
    c = brentq(f, lo, hi, xtol=1e-13, rtol=1e-13)
    if abs(f(c)) > 1e-9:
        raise ValueError("the target gripping angle lies beyond the sprag's reach (roll-over)")
    return c
