"""Heat of a dry-clutch engagement (issue 20): per-area loading, the split of the friction heat
between the parts, their bulk temperature rise, the flash temperature of the friction face, and a
sequence of engagements with cooling between them.

Every slip joule is heat at the friction faces (eq. 11's slip work W). A single-plate clutch
(seed 000) has two: flywheel | lining | driven plate | lining | pressure plate. A multi-plate dry
clutch of n faces (n even) stacks n/2 driven plates, each lined on both sides, with n/2 − 1
intermediate (centre) plates between them: flywheel | driven | intermediate | driven | … |
pressure plate, so the flywheel and the pressure plate each carry one face (the outer ones), every
intermediate plate two and every driven plate two (n = 2 + 2(n/2 − 1)). Every face carries the
same clamp force (the stack is in series) and the same slip (driven plates on the output hub,
intermediate plates on the flywheel), so each takes W/n. At a face the heat divides between the
metal part and the lining so that both surfaces reach the same temperature; for two
semi-infinite bodies heated together this gives the share of each body in proportion to its
thermal effusivity e = √(ρck) (Blok's partition; e.g. Limpert, *Brake Design and Safety*, ch. 3,
for the brake rotor/pad pair): the metal takes γ = e_m/(e_m + e_lining) of its face's W/n. So the
flywheel and the pressure plate take γW/n each, every intermediate plate 2γW/n and every driven
plate 2(1 − γ)W/n (:func:`plate_shares`; n = 2: γW/2, γW/2 and (1 − γ)W). The shares sum to one
by construction, so the heat into the parts equals the slip work to rounding.

- **bulk temperature rise** (lumped): ΔT_i = Q_i/(m_i c_i), the part's mass and specific heat;
- **flash (surface) temperature** of the friction face: the metal face as a semi-infinite body
  under the heat flux q(t) = γ P(t)/(nA) [W/m²] (P the slip power, A one face's area, γ the metal's
  share; the same on every metal face of the stack, the intermediate plates' too, while the heat
  has not crossed half their thickness), by Duhamel's integral
  ΔT(t) = 1/(e√π) ∫₀ᵗ q(τ)/√(t−τ) dτ. Constant flux: ΔT = 2q√(t/(πρck));
  a ramp q = bt: ΔT = (4/3)·b·t^{3/2}/(e√π). :func:`duhamel_surface_temperature` integrates q
  piecewise linear between its samples exactly against the kernel (exact for constant and
  ramp flux; second order in the sample spacing for a smooth flux);
- **repeated engagements**: each adds ΔT_bulk; between them the part cools towards ambient by
  Newton's law with time constant τ = m c/(h A_cool). After engagement n (interval t_i, factor
  r = exp(−t_i/τ)) the rise over ambient is ΔT·(1 − rⁿ)/(1 − r), tending to ΔT/(1 − r).

Material values are documented defaults (:data:`MATERIALS`), assumptions to be replaced by the
drivetrain's own data sheets.
"""

from __future__ import annotations

import math

import numpy as np

from . import status as st

__all__ = [
    "MATERIALS",
    "effusivity",
    "face_shares",
    "plate_shares",
    "lining_area",
    "specific_loading",
    "bulk_rise",
    "duhamel_surface_temperature",
    "surface_temperature_constant",
    "surface_temperature_ramp",
    "sequence_temperatures",
    "periodic_temperature",
    "engagements_to_limit",
    "max_engagement_rate",
    "engagement_heat",
    "face_temperature_rise",
    "part_effusivities",
    "kernel_modes",
]

# per-input rules of the helpers (sign, finite, plausible magnitude: clutchlab.plausible); a
# temperature rise or margin is a difference [K]: any size from 0 to the plausible top
_RISE = st.nonnegative_in("K", lo=0.0)
_RULES = {
    "density": st.positive_in("kg/m^3"),
    "specific_heat": st.positive_in("J/(kg K)"),
    "conductivity": st.positive_in("W/(m K)"),
    "effusivity": st.positive_in("W s^0.5/(m^2 K)"),
    "flywheel_effusivity": st.positive_in("W s^0.5/(m^2 K)"),
    "pressure_plate_effusivity": st.positive_in("W s^0.5/(m^2 K)"),
    "lining_effusivity": st.positive_in("W s^0.5/(m^2 K)"),
    "outer_radius": st.positive_in("m"),
    "inner_radius": st.positive_in("m"),
    "faces": st.count(1),
    # a stack of double-lined driven plates: an even count of friction faces (plate_shares)
    "stack_faces": lambda x: st.count(2)(x) & (np.remainder(x, 2.0) == 0.0),
    "metal_effusivity": st.positive_in("W s^0.5/(m^2 K)"),
    "slip_work": st.nonnegative_in("J"),
    "peak_slip_power": st.nonnegative_in("W"),
    "heat": st.nonnegative_in("J"),
    "mass": st.positive_in("kg"),
    "flux": st.nonnegative_in("W/m^2"),
    "rate": st.nonnegative_in("W/m^2", hi=1e15),  # [W/(m² s)]
    "time": st.nonnegative_in("s"),
    "rise": _RISE,
    "margin": st.positive_in("K", lo=0.0),
    "interval": st.positive_in("s"),
    "time_constant": st.positive_in("s"),
    "duhamel_integral": st.nonnegative_in("W s^0.5"),
}
_ANNULUS = {None: lambda a: a["outer_radius"] > a["inner_radius"]}


def _domain(inputs, relations=None):
    return {**{k: _RULES[k] for k in inputs}, **(relations or {})}


# Typical room-temperature handbook values (assumed; replace by the part's data sheet):
# grey cast iron (flywheel, pressure plate): rho 7200 kg/m^3, c 500 J/(kg K), k 50 W/(m K) -- the
# range of EN-GJL-250 in Limpert, Brake Design and Safety (SAE), ch. 3, and ASM Handbook vol. 1;
# steel (driven-plate carrier): rho 7850, c 460, k 45 -- structural carbon steel, ASM Handbook vol. 1;
# organic (resin-bonded) lining: rho 2000, c 1000, k 0.5 -- the middle of the ranges for organic
# friction materials quoted in Limpert, ch. 3 (rho 1800-2500, c 900-1300, k 0.3-1.5).
MATERIALS = {
    "cast_iron": {"density": 7200.0, "specific_heat": 500.0, "conductivity": 50.0},
    "steel": {"density": 7850.0, "specific_heat": 460.0, "conductivity": 45.0},
    "organic_lining": {"density": 2000.0, "specific_heat": 1000.0, "conductivity": 0.5},
}


def effusivity(density, specific_heat, conductivity):
    """Thermal effusivity e = √(ρ c k) [W s^0.5/(m² K)] of density ρ [kg/m³], specific heat c
    [J/(kg K)] and conductivity k [W/(m K)]; NaN where one is not positive, finite and plausible
    (:mod:`clutchlab.plausible`)."""
    inputs = dict(density=density, specific_heat=specific_heat, conductivity=conductivity)
    return st.nan_screened(_effusivity, inputs, _domain(inputs))


def _effusivity(*, density, specific_heat, conductivity):
    return np.sqrt(np.asarray(density) * np.asarray(specific_heat) * np.asarray(conductivity))


def lining_area(outer_radius, inner_radius):
    """Area of one friction face of an annular lining, π(R₂² − R₁²) [m²] (outer and inner radius
    [m]); NaN unless R₂ > R₁ > 0, finite and plausible (a negative area is no lining)."""
    inputs = dict(outer_radius=outer_radius, inner_radius=inner_radius)
    return st.nan_screened(_lining_area, inputs, _domain(inputs, _ANNULUS))


def _lining_area(*, outer_radius, inner_radius):
    return np.pi * (np.square(outer_radius) - np.square(inner_radius))


def face_shares(flywheel_effusivity, pressure_plate_effusivity, lining_effusivity):
    """Shares of the slip work into the flywheel, the pressure plate and the driven plate (its two
    linings): each face takes half, split between metal and lining in proportion to their
    effusivities [W s^0.5/(m² K)]. The three shares sum to one; NaN where an effusivity is not
    positive, finite and plausible."""
    inputs = dict(
        flywheel_effusivity=flywheel_effusivity,
        pressure_plate_effusivity=pressure_plate_effusivity,
        lining_effusivity=lining_effusivity,
    )
    return st.nan_screened(_face_shares, inputs, _domain(inputs))


def _face_shares(*, flywheel_effusivity, pressure_plate_effusivity, lining_effusivity):
    g_fw = flywheel_effusivity / (flywheel_effusivity + lining_effusivity)
    g_pp = pressure_plate_effusivity / (pressure_plate_effusivity + lining_effusivity)
    return 0.5 * g_fw, 0.5 * g_pp, 0.5 * (1.0 - g_fw) + 0.5 * (1.0 - g_pp)


def plate_shares(faces, metal_effusivity, lining_effusivity):
    """Shares of the slip work into each part of a dry clutch of ``faces`` friction faces (even,
    ≥ 2): a dict with the share of the flywheel, the pressure plate, each intermediate plate (0 with
    two faces) and each driven plate, and ``intermediate_plates`` (n/2 − 1), ``driven_plates``
    (n/2) [1]. Each face takes 1/n; its metal γ = e_m/(e_m + e_lining), its lining the rest (module
    docstring): γ/n, γ/n, 2γ/n and 2(1 − γ)/n. Every metal face of one material (cast iron);
    effusivities [W s^0.5/(m² K)]. NaN where the count is not even or an effusivity not positive,
    finite and plausible."""
    inputs = dict(
        faces=faces, metal_effusivity=metal_effusivity, lining_effusivity=lining_effusivity
    )
    domain = _domain(inputs) | {"faces": _RULES["stack_faces"]}
    return st.screened(_plate_shares, inputs, domain)


def _plate_shares(*, faces, metal_effusivity, lining_effusivity):
    n = np.asarray(faces, dtype=float)
    g = metal_effusivity / (metal_effusivity + lining_effusivity)
    return {
        "flywheel": g / n,
        "pressure_plate": g / n,
        "intermediate_plate": np.where(n > 2, 2.0 * g / n, 0.0),
        "driven_plate": 2.0 * (1.0 - g) / n,
        "intermediate_plates": 0.5 * n - 1.0,
        "driven_plates": 0.5 * n,
    }


def _loading(slip_work, peak_slip_power, outer_radius, inner_radius, faces):
    area = faces * _lining_area(outer_radius=outer_radius, inner_radius=inner_radius)
    return {
        "friction_area": area,
        "specific_friction_work": slip_work / area,
        "peak_specific_friction_power": peak_slip_power / area,
        "status": np.zeros(np.shape(area), dtype=np.int8),
    }


def specific_loading(slip_work, peak_slip_power, outer_radius, inner_radius, faces=2):
    """Per-area loading of one engagement on the whole friction area A = z_f·π(R₂² − R₁²):
    specific friction work q_A = W/A [J/m²] and peak specific friction power P_max/A [W/m²].

    Per scenario: slip work [J] and peak power [W] finite and ≥ 0, radii [m] R₂ > R₁ > 0, faces a
    whole number in [1, 1000], all of plausible magnitude (:mod:`clutchlab.plausible`); otherwise
    status ``invalid_input`` (``invalid_geometry`` for swapped radii) and NaN."""
    inputs = dict(
        slip_work=slip_work,
        peak_slip_power=peak_slip_power,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        faces=faces,
    )
    return st.screened(_loading, inputs, _domain(inputs), geometry=_ANNULUS)


def bulk_rise(heat, mass, specific_heat):
    """Lumped (bulk) temperature rise Q/(m c) [K] of a part of mass m [kg] and specific heat c
    [J/(kg K)] that takes the heat Q [J]; NaN where Q < 0, m or c ≤ 0, or one is not finite or
    plausible (:mod:`clutchlab.plausible`)."""
    inputs = dict(heat=heat, mass=mass, specific_heat=specific_heat)
    return st.nan_screened(_bulk_rise, inputs, _domain(inputs))


def _bulk_rise(*, heat, mass, specific_heat):
    return np.asarray(heat) / (np.asarray(mass) * np.asarray(specific_heat))


def surface_temperature_constant(flux, time, effusivity):
    """Surface temperature rise of a semi-infinite body under a constant flux q [W/m²] from t = 0:
    2q√(t/(πρck)) = 2q√t/(e√π) [K] at time t [s], effusivity e [W s^0.5/(m² K)]; NaN where
    q, t < 0, e ≤ 0, or one is not finite or plausible."""
    inputs = dict(flux=flux, time=time, effusivity=effusivity)
    return st.nan_screened(_surface_temperature_constant, inputs, _domain(inputs))


def _surface_temperature_constant(*, flux, time, effusivity):
    return 2.0 * np.asarray(flux) * np.sqrt(time) / (np.asarray(effusivity) * math.sqrt(math.pi))


def surface_temperature_ramp(rate, time, effusivity):
    """Surface temperature rise under a linearly rising flux q = b t (b [W/(m² s)]):
    (4/3)·b·t^{3/2}/(e√π) [K] at time t [s]; NaN where b, t < 0, e ≤ 0 or one is not finite or
    plausible."""
    inputs = dict(rate=rate, time=time, effusivity=effusivity)
    return st.nan_screened(_surface_temperature_ramp, inputs, _domain(inputs))


def _surface_temperature_ramp(*, rate, time, effusivity):
    return (
        4.0
        / 3.0
        * np.asarray(rate)
        * np.power(time, 1.5)
        / (np.asarray(effusivity) * math.sqrt(math.pi))
    )


def duhamel_surface_temperature(times, flux, effusivity):
    """Surface temperature rise of a semi-infinite body, ΔT(t_k) = 1/(e√π) ∫₀^{t_k} q(τ)/√(t_k − τ) dτ,
    at every sample time t_k of a flux q sampled at ``times`` (last axis; increasing, starting at the
    start of heating) [K].

    q is taken linear between samples and each segment integrated exactly against the kernel:
    with u = t_k − τ and q = A + B·u on the segment, ∫ (A u^{-1/2} + B u^{1/2}) du
    = 2A(√u_j − √u_{j+1}) + (2/3)B(u_j^{3/2} − u_{j+1}^{3/2}), written without cancellation. Exact
    for a constant or linearly rising flux; error O(h²) in the spacing h for a smooth flux (both
    tested). Leading axes are scenarios; memory and work O(n²) in the samples n. A scenario whose
    times are not finite and strictly increasing, whose flux [W/m²] is not finite (a cooling flux
    may be negative) or whose effusivity [W s^0.5/(m² K)] is not positive and plausible gives NaN.
    """
    t = np.asarray(times, dtype=float)
    q = np.asarray(flux, dtype=float)
    t, q = np.broadcast_arrays(t, q)
    with np.errstate(invalid="ignore"):
        bad = ~(
            np.all(np.isfinite(t) & np.isfinite(q), axis=-1)
            & np.all(np.diff(t, axis=-1) > 0, axis=-1)
            & _RULES["effusivity"](np.asarray(effusivity, dtype=float))
        )
    if np.any(bad):
        with np.errstate(all="ignore"):
            out = _duhamel(t, q, np.where(bad, 1.0, effusivity))
        return np.where(bad[..., None], np.nan, out)
    return _duhamel(t, q, effusivity)


def _duhamel(t, q, effusivity):
    n = t.shape[-1]
    out = np.zeros(t.shape)
    if n < 2:
        return out
    h = np.diff(t, axis=-1)  # (..., n-1)
    slope = np.diff(q, axis=-1) / h
    tk = t[..., 1:, None]  # evaluation times t_1..t_{n-1}
    u0 = np.maximum(tk - t[..., None, :-1], 0.0)  # u at the segment's start
    u1 = np.maximum(tk - t[..., None, 1:], 0.0)  # u at its end (smaller)
    valid = t[..., None, 1:] <= tk  # segments before t_k
    a = q[..., None, :-1] + slope[..., None, :] * u0
    b = -slope[..., None, :]
    s0, s1 = np.sqrt(u0), np.sqrt(u1)
    with np.errstate(invalid="ignore", divide="ignore"):
        d_sqrt = np.where(s0 + s1 > 0, (u0 - u1) / (s0 + s1), 0.0)
    d_32 = d_sqrt * (u0 + s0 * s1 + u1)
    seg = np.where(valid, 2.0 * a * d_sqrt + (2.0 / 3.0) * b * d_32, 0.0)
    out[..., 1:] = seg.sum(axis=-1) / (np.asarray(effusivity)[..., None] * math.sqrt(math.pi))
    return out


def sequence_temperatures(rise, interval, time_constant, engagements):
    """Temperature over ambient just after each of ``engagements`` engagements (last axis) of a
    lumped part: each adds ``rise`` [K]; between them it cools exponentially (Newton's law,
    time constant τ = m c/(h A) [s]) for ``interval`` [s]: T_n = r·T_{n−1} + ΔT, r = exp(−t_i/τ).
    ``engagements`` (shared) is a whole number in [1, 1e6] (ValueError otherwise); a scenario with
    a rise < 0, an interval or τ ≤ 0, or one not finite or plausible gives NaN."""
    if not (
        np.isscalar(engagements) and 1 <= engagements <= 1e6 and engagements == int(engagements)
    ):
        raise ValueError(f"engagements must be a whole number in [1, 1e6], got {engagements!r}")
    inputs = dict(rise=rise, interval=interval, time_constant=time_constant)
    return st.nan_screened(
        _sequence_temperatures, inputs, _domain(inputs), extra={"engagements": engagements}
    )


def _sequence_temperatures(*, rise, interval, time_constant, engagements):
    rise, r = np.broadcast_arrays(
        np.asarray(rise, dtype=float),
        np.exp(-np.asarray(interval, dtype=float) / np.asarray(time_constant, dtype=float)),
    )
    out = np.empty(rise.shape + (int(engagements),))
    temp = np.zeros(rise.shape)
    for i in range(int(engagements)):
        temp = temp * r + rise if i else rise.copy()
        out[..., i] = temp
    return out


def periodic_temperature(rise, interval, time_constant):
    """The sequence's periodic steady state just after an engagement, ΔT/(1 − r) [K] (geometric
    sum), r = exp(−t_i/τ) (rise ΔT [K], interval t_i and time constant τ [s]); NaN where ΔT < 0,
    t_i or τ ≤ 0, or one is not finite or plausible (a negative interval is no sequence)."""
    inputs = dict(rise=rise, interval=interval, time_constant=time_constant)
    return st.nan_screened(_periodic_temperature, inputs, _domain(inputs))


def _periodic_temperature(*, rise, interval, time_constant):
    return np.asarray(rise) / (1.0 - np.exp(-np.asarray(interval) / np.asarray(time_constant)))


def engagements_to_limit(rise, interval, time_constant, margin):
    """Engagements in a row after which the part first reaches ``margin`` [K] over ambient (the
    material limit minus ambient): the least n with ΔT(1 − rⁿ)/(1 − r) ≥ margin; inf if the
    periodic state stays below it (or no heat). Rise ΔT [K], interval and time constant [s]; NaN
    where ΔT < 0, interval, τ or margin ≤ 0, or one is not finite or plausible."""
    inputs = dict(rise=rise, interval=interval, time_constant=time_constant, margin=margin)
    return st.nan_screened(_engagements_to_limit, inputs, _domain(inputs))


def _engagements_to_limit(*, rise, interval, time_constant, margin):
    rise, r, margin = np.broadcast_arrays(
        np.asarray(rise, dtype=float),
        np.exp(-np.asarray(interval, dtype=float) / np.asarray(time_constant)),
        np.asarray(margin, dtype=float),
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        x = 1.0 - margin * (1.0 - r) / rise  # r^n <= x
        n = np.where(r > 0, np.ceil(np.log(np.maximum(x, 1e-300)) / np.log(r) - 1e-12), 1.0)
    n = np.where(rise >= margin, 1.0, np.where(x <= 0, np.inf, np.maximum(n, 1.0)))
    n = np.where(rise == 0, np.inf, n)
    return np.where(np.isfinite(rise) & (rise >= 0) & np.isfinite(margin), n, np.nan)


def max_engagement_rate(rise, time_constant, margin):
    """Largest engagement rate [1/s] at which the periodic bulk temperature just after each
    engagement (:func:`periodic_temperature`) stays at or under the margin M: the periodic state
    ΔT/(1 − exp(−t_i/τ)) ≤ M for t_i ≥ −τ·ln(1 − ΔT/M), so the rate is 1/t_i (× 3600 for
    engagements per hour). The engagement's own duration is neglected against t_i.

    Parameters
    ----------
    rise : array_like
        Bulk temperature rise ΔT of one engagement [K], ≥ 0.
    time_constant : array_like
        Cooling time constant τ = m c/(h A) [s], > 0.
    margin : array_like
        M, material limit minus ambient [K], > 0.

    Returns
    -------
    numpy.ndarray
        Rate [1/s]: 0 where ΔT ≥ M (one engagement alone reaches the limit), inf where ΔT = 0;
        NaN where an input is not finite, of the wrong sign or implausible
        (:mod:`clutchlab.plausible`).
    """
    inputs = dict(rise=rise, time_constant=time_constant, margin=margin)
    return st.nan_screened(_max_engagement_rate, inputs, _domain(inputs))


def _max_engagement_rate(*, rise, time_constant, margin):
    rise, tau, margin = np.broadcast_arrays(
        np.asarray(rise, dtype=float), np.asarray(time_constant, float), np.asarray(margin, float)
    )
    x = rise / margin
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = -1.0 / (tau * np.log1p(-x))  # (log1p: exact for a small rise)
    return np.where(x >= 1.0, 0.0, np.where(rise == 0, np.inf, rate))


# the parts of a dry clutch that take the friction heat (codes of ``hottest_part``: append only),
# and their materials (driven plate: its faces are the linings; its heat capacity mostly the steel
# carrier's; intermediate plates of a multi-plate clutch: cast iron, like the pressure plate)
PARTS = ("flywheel", "pressure_plate", "driven_plate", "intermediate_plate")
FACE_MATERIAL = {
    "flywheel": "cast_iron",
    "pressure_plate": "cast_iron",
    "driven_plate": "organic_lining",
    "intermediate_plate": "cast_iron",
}
BULK_MATERIAL = {
    "flywheel": "cast_iron",
    "pressure_plate": "cast_iron",
    "driven_plate": "steel",
    "intermediate_plate": "cast_iron",
}


def part_effusivities() -> tuple[float, float, float]:
    """Effusivities of the flywheel, pressure plate and driven-plate faces (:data:`MATERIALS`)
    [W s^0.5/(m² K)]."""
    return tuple(
        float(_effusivity(**MATERIALS[FACE_MATERIAL[p]]))
        for p in ("flywheel", "pressure_plate", "driven_plate")
    )


def _engagement_heat(
    slip_work,
    peak_slip_power,
    outer_radius,
    inner_radius,
    faces,
    flywheel_mass,
    pressure_plate_mass,
    driven_plate_mass,
    heat_transfer_coefficient,
    cooling_area,
    engagement_interval,
    temperature_margin,
    intermediate_plate_mass,
):
    out = _loading(slip_work, peak_slip_power, outer_radius, inner_radius, faces)
    e_metal, _, e_lining = part_effusivities()
    shares = _plate_shares(faces=faces, metal_effusivity=e_metal, lining_effusivity=e_lining)
    masses = {
        "flywheel": flywheel_mass,
        "pressure_plate": pressure_plate_mass,
        "driven_plate": driven_plate_mass,
        "intermediate_plate": intermediate_plate_mass,
    }
    rises, capacities, rates = [], [], []
    for part in PARTS:  # heat into each plate of the kind, and its bulk rise
        out[f"heat_{part}"] = shares[part] * slip_work
        capacity = masses[part] * MATERIALS[BULK_MATERIAL[part]]["specific_heat"]
        rises.append(out[f"heat_{part}"] / capacity)
        capacities.append(capacity * np.ones_like(slip_work))
        rates.append(  # the rate this part allows (every part cools through the same h A)
            _max_engagement_rate(
                rise=rises[-1],
                time_constant=capacity / (heat_transfer_coefficient * cooling_area),
                margin=temperature_margin,
            )
        )
    # the binding part's: the largest rate that keeps every part's periodic state under the margin
    out["max_engagement_rate"] = np.min(np.stack(rates), axis=0)
    rise = np.stack(rises)
    hottest = np.argmax(rise, axis=0)
    capacity = np.choose(hottest, capacities)
    out["bulk_temperature_rise"] = np.take_along_axis(rise, hottest[None], 0)[0]
    out["hottest_part"] = hottest.astype(np.int8)
    out["engagements_to_limit"] = _engagements_to_limit(
        rise=out["bulk_temperature_rise"],
        interval=engagement_interval,
        time_constant=capacity / (heat_transfer_coefficient * cooling_area),
        margin=temperature_margin,
    )
    return out


def engagement_heat(
    slip_work,
    peak_slip_power,
    outer_radius,
    inner_radius,
    faces=2,
    *,
    flywheel_mass=10.3,
    pressure_plate_mass=2.5,
    driven_plate_mass=1.9,
    heat_transfer_coefficient=40.0,
    cooling_area=0.1,
    engagement_interval=60.0,
    temperature_margin=210.0,
    intermediate_plate_mass=2.5,
):
    """Heat of one engagement of a dry clutch of ``faces`` friction faces and of a sequence of them.

    Returns per scenario: ``friction_area`` [m²], ``specific_friction_work`` [J/m²],
    ``peak_specific_friction_power`` [W/m²] (:func:`specific_loading`); ``heat_flywheel``,
    ``heat_pressure_plate``, ``heat_driven_plate`` (each driven plate, n/2 of them),
    ``heat_intermediate_plate`` (each intermediate plate, n/2 − 1 of them; 0 with two faces) [J]
    (:func:`plate_shares` of the slip work: the flywheel's, the pressure plate's and all plates'
    heats sum to it); ``bulk_temperature_rise`` [K] of the hottest part (``hottest_part``: index
    into :data:`PARTS`); ``engagements_to_limit``: engagements in a row, ``engagement_interval`` [s]
    apart, after which that part's bulk temperature first exceeds ambient by ``temperature_margin``
    [K] (material limit minus ambient), cooling by Newton's law with time constant
    m c/(h A) (h ``heat_transfer_coefficient`` [W/(m² K)], A ``cooling_area`` [m²]); inf if never;
    ``max_engagement_rate`` [1/s]: the largest rate of engagements at which no part's periodic
    bulk temperature exceeds ambient by more than the margin (:func:`max_engagement_rate` of each
    part, the smallest; every part cooled through the same h A; inf where no heat).

    Defaults: masses of seed 000 Table 3 (flywheel 10.3 kg, pressure plate 2.5 kg, driven plate
    1.9 kg); h = 40 W/(m² K) (assumed: air moved by the spinning parts in a closed bell housing),
    A = 0.1 m² (assumed: both sides and the rim of a 225 mm plate), 60 s between engagements
    (assumed: a retried start), margin 210 K (assumed: 250 °C, the upper service temperature of
    organic linings in Limpert ch. 3, over 40 °C in the housing); intermediate plates 2.5 kg each
    (assumed: the pressure plate's mass; unused with two faces). ``faces`` must be even (n/2
    driven plates lined on both sides, module docstring): an odd count gives status
    ``invalid_input``, as do non-finite, non-positive or implausible inputs
    (:mod:`clutchlab.plausible`); swapped lining radii (R₂ ≤ R₁) give ``invalid_geometry``.
    """
    domain = {
        "slip_work": _RULES["slip_work"],
        "peak_slip_power": _RULES["peak_slip_power"],
        "inner_radius": _RULES["inner_radius"],
        "outer_radius": _RULES["outer_radius"],
        "faces": _RULES["stack_faces"],
        "flywheel_mass": _RULES["mass"],
        "pressure_plate_mass": _RULES["mass"],
        "driven_plate_mass": _RULES["mass"],
        "intermediate_plate_mass": _RULES["mass"],
        "heat_transfer_coefficient": st.positive_in("W/(m^2*K)"),
        "cooling_area": st.positive_in("m^2"),
        "engagement_interval": _RULES["interval"],
        "temperature_margin": _RULES["margin"],
    }
    inputs = dict(
        slip_work=slip_work,
        peak_slip_power=peak_slip_power,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        faces=faces,
        flywheel_mass=flywheel_mass,
        pressure_plate_mass=pressure_plate_mass,
        driven_plate_mass=driven_plate_mass,
        heat_transfer_coefficient=heat_transfer_coefficient,
        cooling_area=cooling_area,
        engagement_interval=engagement_interval,
        temperature_margin=temperature_margin,
        intermediate_plate_mass=intermediate_plate_mass,
    )
    return st.screened(_engagement_heat, inputs, domain, geometry=_ANNULUS)


def kernel_modes(cut=4000.0, span=10.0, ratio=2.5, top=4.0):
    """The exponential modes of the smooth part of Duhamel's kernel that the engagement solver
    integrates for the friction-face temperature (friction fade; constants of
    :mod:`clutchlab.engagement._fade`, which this regenerates): (λ_k [1/s], w_k [s^-0.5]) with
    Σ w_k e^{−λ_k s} ≈ erf(√(λ_c s))/√s on s ∈ [0, span], by non-negative least squares weighted by
    √s (the error relative to the whole kernel 1/√s), λ_k geometric with ``ratio`` from
    ``top``·λ_c down to 0.1/span; modes of zero weight dropped. ``cut`` [1/s], ``span`` [s] and
    ``top`` must be finite and > 0, ``ratio`` > 1, at most 1000 modes (ValueError otherwise)."""
    from scipy.optimize import nnls

    for name, v in (("cut", cut), ("span", span), ("top", top)):
        if not (np.isscalar(v) and 0 < v < np.inf):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    if not (np.isscalar(ratio) and 1 < ratio < np.inf):
        raise ValueError(f"ratio must be a finite number > 1, got {ratio!r}")
    n_modes = np.log(max(top * cut * span / 0.1, 1.0)) / np.log(ratio) + 1
    if not n_modes <= 1000:
        raise ValueError(f"cut, span, top and ratio ask for {n_modes:.3g} modes (at most 1000)")
    from scipy.special import erf

    n = int(np.ceil(np.log(top * cut * span / 0.1) / np.log(ratio))) + 1
    lam = np.geomspace(top * cut, 0.1 / span, n)
    s = np.concatenate([np.linspace(0.0, 20.0 / cut, 400), np.geomspace(1e-7, span, 2000)])
    with np.errstate(divide="ignore", invalid="ignore"):
        target = np.where(s > 0, erf(np.sqrt(cut * s)) / np.sqrt(s), 2.0 * np.sqrt(cut / np.pi))
    weight = np.sqrt(np.maximum(s, 1.0 / cut))
    w, _ = nnls(np.exp(-np.outer(s, lam)) * weight[:, None], target * weight)
    return lam[w > 0], w[w > 0]


def face_temperature_rise(duhamel_integral, outer_radius, inner_radius, faces=2):
    """Friction-face (flash) temperature rise of the cast-iron faces (flywheel and pressure plate take
    the same share γ = e_m/(e_m + e_lining) of their face's heat, as do the intermediate plates'
    faces of a multi-plate clutch) from the solver's Duhamel integral of the slip power,
    I = ∫ P(τ)/√(t − τ) dτ [W s^0.5]: ΔT = γ·I/(A·e_m·√π), A the friction area of all faces (each
    of the n faces takes P/n on A/n) [K]. Lining radii [m]; NaN where I < 0, R₂ ≤ R₁ ≤ 0,
    faces not a whole number in [1, 1000], or an input not finite or plausible."""
    inputs = dict(
        duhamel_integral=duhamel_integral,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        faces=faces,
    )
    return st.nan_screened(_face_temperature_rise, inputs, _domain(inputs, _ANNULUS))


def _face_temperature_rise(*, duhamel_integral, outer_radius, inner_radius, faces):
    e_fw, e_pp, e_lining = part_effusivities()
    gamma = e_pp / (e_pp + e_lining)
    area = faces * _lining_area(outer_radius=outer_radius, inner_radius=inner_radius)
    return gamma * np.asarray(duhamel_integral) / (area * e_pp * math.sqrt(math.pi))
