"""Heat of a dry-clutch engagement: per-area loading, the split of the friction heat
between the parts, their bulk temperature rise, the flash temperature of the friction face, and a
sequence of engagements with cooling between them.

Every slip joule is heat at the friction faces (eq. 11's slip work W). A single-plate clutch (the
source paper (000)) has two: flywheel | lining | driven plate | lining | pressure plate. A
multi-plate dry clutch of n faces (n even) stacks n/2 driven plates, each lined on both sides, with
n/2 − 1 intermediate (centre) plates between them: flywheel | driven | intermediate | driven | … |
pressure plate, so the flywheel and the pressure plate each carry one face (the outer ones), every
intermediate plate two and every driven plate two (n = 2 + 2(n/2 − 1)). Every face carries the same
clamp force (the stack is in series) and the same slip (driven plates on the output hub,
intermediate plates on the flywheel), so each takes W/n. At a face the heat divides between the
metal part and the lining so that both surfaces reach the same temperature; for two semi-infinite
bodies heated together this gives the share of each body in proportion to its thermal effusivity e =
√(ρck) (Blok's partition; e.g. Limpert, *Brake Design and Safety*, ch. 3, for the brake rotor/pad
pair): the metal takes γ = e_m/(e_m + e_lining) of its face's W/n. So the flywheel and the pressure
plate take γW/n each, every intermediate plate 2γW/n and every driven plate 2(1 − γ)W/n
(:func:`plate_shares`; n = 2: γW/2, γW/2 and (1 − γ)W). The shares sum to one by construction, so
the heat into the parts equals the slip work to rounding.

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

References
----------
.. [1] Zhao P. (2026), "Design and engagement simulation of diaphragm spring clutch for
   unmanned helicopters", the source paper (000), eq. (11) (slip work) and Table 3 (masses).
.. [2] Limpert R., *Brake Design and Safety*, SAE, ch. 3: heat partition between rotor and pad
   by their effusivities, material values of cast iron and organic friction materials.
.. [3] Carslaw H.S., Jaeger J.C. (1959), *Conduction of Heat in Solids*, 2nd ed., ch. II: the
   semi-infinite solid heated at its surface, Duhamel's theorem.
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
# (a plausible width: the friction area divides the specific loading)
_ANNULUS = {None: lambda a: st.apart(a["outer_radius"], a["inner_radius"])}


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
    """Thermal effusivity e = √(ρ c k) of a material.

    Parameters
    ----------
    density : float or array_like [kg/m³]
        Density ρ.
    specific_heat : float or array_like [J/(kg K)]
        Specific heat c.
    conductivity : float or array_like [W/(m K)]
        Thermal conductivity k.

    Returns
    -------
    numpy.ndarray [W s^0.5/(m² K)]
        e; NaN where an input is not positive, finite and plausible (:mod:`clutchlab.plausible`).

    References
    ----------
    Limpert [2], ch. 3: the effusivity governs the heat partition at a sliding contact.
    """
    inputs = dict(density=density, specific_heat=specific_heat, conductivity=conductivity)
    return st.nan_screened(_effusivity, inputs, _domain(inputs))


def _effusivity(*, density, specific_heat, conductivity):
    return np.sqrt(np.asarray(density) * np.asarray(specific_heat) * np.asarray(conductivity))


def lining_area(outer_radius, inner_radius):
    """Area of one friction face of an annular lining, π(R₂² − R₁²).

    Parameters
    ----------
    outer_radius, inner_radius : float or array_like [m]
        Outer and inner lining radius R₂ > R₁ > 0.

    Returns
    -------
    numpy.ndarray [m²]
        The area; NaN unless R₂ > R₁ > 0, finite and plausible (a negative area is no lining).
    """
    inputs = dict(outer_radius=outer_radius, inner_radius=inner_radius)
    return st.nan_screened(_lining_area, inputs, _domain(inputs, _ANNULUS))


def _lining_area(*, outer_radius, inner_radius):
    return np.pi * (np.square(outer_radius) - np.square(inner_radius))


def face_shares(flywheel_effusivity, pressure_plate_effusivity, lining_effusivity):
    """Shares of the slip work into flywheel, pressure plate and driven plate (single plate).

    Each of the two faces takes half; at a face the heat divides between the metal and the lining
    in proportion to their effusivities (Blok's partition, module docstring).

    Parameters
    ----------
    flywheel_effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity of the flywheel's face.
    pressure_plate_effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity of the pressure plate's face.
    lining_effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity of the linings (both faces of the driven plate).

    Returns
    -------
    tuple of numpy.ndarray [-]
        (flywheel, pressure plate, driven plate) shares, summing to one; NaN where an effusivity
        is not positive, finite and plausible.

    References
    ----------
    Limpert [2], ch. 3 (heat partition by effusivity).
    """
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
    """Shares of the slip work into each part of a dry clutch of ``faces`` friction faces.

    Each face takes 1/n; its metal γ = e_m/(e_m + e_lining), its lining the rest (module
    docstring): the flywheel and the pressure plate γ/n each, every intermediate plate 2γ/n and
    every driven plate 2(1 − γ)/n. Every metal face is of one material (cast iron).

    Parameters
    ----------
    faces : int or array_like [-]
        Number of friction faces n, even and ≥ 2.
    metal_effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity e_m of the metal faces.
    lining_effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity e_lining of the linings.

    Returns
    -------
    dict of numpy.ndarray
        ``flywheel``, ``pressure_plate``, ``intermediate_plate`` (each; 0 with two faces) and
        ``driven_plate`` (each) shares [-]; ``intermediate_plates`` (n/2 − 1) and
        ``driven_plates`` (n/2) counts. NaN where the count is not even or an effusivity not
        positive, finite and plausible.

    References
    ----------
    Limpert [2], ch. 3 (heat partition by effusivity).
    """
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
    """Per-area loading of one engagement on the whole friction area A = z_f·π(R₂² − R₁²).

    Parameters
    ----------
    slip_work : float or array_like [J]
        Slip work W of the engagement, ≥ 0.
    peak_slip_power : float or array_like [W]
        Peak slip power P_max, ≥ 0.
    outer_radius, inner_radius : float or array_like [m]
        Lining radii R₂ > R₁ > 0.
    faces : int or array_like [-]
        Number of friction faces z_f, a whole number in [1, 1000].

    Returns
    -------
    dict of numpy.ndarray
        ``friction_area`` A [m²], ``specific_friction_work`` q_A = W/A [J/m²],
        ``peak_specific_friction_power`` P_max/A [W/m²] and ``status``: ``invalid_input`` (NaN)
        where an input is not finite, of the wrong sign or implausible
        (:mod:`clutchlab.plausible`), ``invalid_geometry`` for swapped radii.

    References
    ----------
    Source paper (000), eq. (11) ([1] in the module docstring): the slip work W.
    """
    inputs = dict(
        slip_work=slip_work,
        peak_slip_power=peak_slip_power,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        faces=faces,
    )
    return st.screened(_loading, inputs, _domain(inputs), geometry=_ANNULUS)


def bulk_rise(heat, mass, specific_heat):
    """Lumped (bulk) temperature rise Q/(m c) of a part that takes the heat Q.

    Parameters
    ----------
    heat : float or array_like [J]
        Heat Q ≥ 0 into the part.
    mass : float or array_like [kg]
        Mass m of the part.
    specific_heat : float or array_like [J/(kg K)]
        Specific heat c of the part.

    Returns
    -------
    numpy.ndarray [K]
        The rise; NaN where Q < 0, m or c ≤ 0, or an input is not finite or plausible
        (:mod:`clutchlab.plausible`).
    """
    inputs = dict(heat=heat, mass=mass, specific_heat=specific_heat)
    return st.nan_screened(_bulk_rise, inputs, _domain(inputs))


def _bulk_rise(*, heat, mass, specific_heat):
    return np.asarray(heat) / (np.asarray(mass) * np.asarray(specific_heat))


def surface_temperature_constant(flux, time, effusivity):
    """Surface temperature rise of a semi-infinite body under a constant flux q from t = 0.

    ΔT = 2q√(t/(πρck)) = 2q√t/(e√π).

    Parameters
    ----------
    flux : float or array_like [W/m²]
        Heat flux q ≥ 0 into the surface.
    time : float or array_like [s]
        Time t ≥ 0 since the start of heating.
    effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity e of the body.

    Returns
    -------
    numpy.ndarray [K]
        ΔT; NaN where q, t < 0, e ≤ 0, or an input is not finite or plausible.

    References
    ----------
    Carslaw and Jaeger [3], ch. II (semi-infinite solid, constant surface flux).
    """
    inputs = dict(flux=flux, time=time, effusivity=effusivity)
    return st.nan_screened(_surface_temperature_constant, inputs, _domain(inputs))


def _surface_temperature_constant(*, flux, time, effusivity):
    return 2.0 * np.asarray(flux) * np.sqrt(time) / (np.asarray(effusivity) * math.sqrt(math.pi))


def surface_temperature_ramp(rate, time, effusivity):
    """Surface temperature rise of a semi-infinite body under a linearly rising flux q = b·t.

    ΔT = (4/3)·b·t^{3/2}/(e√π).

    Parameters
    ----------
    rate : float or array_like [W/(m² s)]
        Rate b ≥ 0 of the flux.
    time : float or array_like [s]
        Time t ≥ 0 since the start of heating.
    effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity e of the body.

    Returns
    -------
    numpy.ndarray [K]
        ΔT; NaN where b, t < 0, e ≤ 0 or an input is not finite or plausible.

    References
    ----------
    Carslaw and Jaeger [3], ch. II (Duhamel's integral of a surface flux).
    """
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
    """Surface temperature rise of a semi-infinite body under a sampled flux, by Duhamel's integral.

    ΔT(t_k) = 1/(e√π) ∫₀^{t_k} q(τ)/√(t_k − τ) dτ at every sample time t_k. q is taken linear
    between samples and each segment integrated exactly against the kernel: with u = t_k − τ and
    q = A + B·u on the segment, ∫ (A u^{-1/2} + B u^{1/2}) du
    = 2A(√u_j − √u_{j+1}) + (2/3)B(u_j^{3/2} − u_{j+1}^{3/2}), written without cancellation.
    Exact for a constant or linearly rising flux; error O(h²) in the spacing h for a smooth flux
    (both tested). Memory and work O(n²) in the samples n.

    Parameters
    ----------
    times : array_like [s]
        Sample times (last axis; leading axes are scenarios), finite, strictly increasing, starting
        at the start of heating.
    flux : array_like [W/m²]
        Heat flux q at ``times``, finite (a cooling flux may be negative).
    effusivity : float or array_like [W s^0.5/(m² K)]
        Effusivity e of the body, per scenario.

    Returns
    -------
    numpy.ndarray [K]
        ΔT at every sample time (shape of ``times`` and ``flux`` broadcast); a scenario with an
        invalid input is NaN.

    References
    ----------
    Carslaw and Jaeger [3], ch. II (Duhamel's theorem).
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
    """Temperature over ambient just after each engagement of a sequence, of a lumped part.

    Each engagement adds ``rise``; between them the part cools exponentially (Newton's law, time
    constant τ = m c/(h A)) for ``interval``: T_n = r·T_{n−1} + ΔT, r = exp(−t_i/τ).

    Parameters
    ----------
    rise : float or array_like [K]
        Bulk rise ΔT ≥ 0 of one engagement.
    interval : float or array_like [s]
        Time t_i > 0 between engagements.
    time_constant : float or array_like [s]
        Cooling time constant τ > 0.
    engagements : int [-]
        Number of engagements (shared by every scenario), a whole number in [1, 1e6].

    Returns
    -------
    numpy.ndarray [K]
        Shape of the broadcast inputs plus a last axis of ``engagements``; NaN for a scenario
        whose input is not finite, of the wrong sign or implausible.

    Raises
    ------
    ValueError
        If ``engagements`` is not a whole number in [1, 1e6].
    """
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
    """Periodic steady state of a sequence of engagements just after an engagement, ΔT/(1 − r).

    The geometric sum of :func:`sequence_temperatures` with r = exp(−t_i/τ).

    Parameters
    ----------
    rise : float or array_like [K]
        Bulk rise ΔT ≥ 0 of one engagement.
    interval : float or array_like [s]
        Time t_i > 0 between engagements (a negative interval is no sequence).
    time_constant : float or array_like [s]
        Cooling time constant τ > 0.

    Returns
    -------
    numpy.ndarray [K]
        The periodic temperature over ambient; NaN where an input is not finite, of the wrong sign
        or implausible.
    """
    inputs = dict(rise=rise, interval=interval, time_constant=time_constant)
    return st.nan_screened(_periodic_temperature, inputs, _domain(inputs))


def _periodic_temperature(*, rise, interval, time_constant):
    return np.asarray(rise) / (1.0 - np.exp(-np.asarray(interval) / np.asarray(time_constant)))


def engagements_to_limit(rise, interval, time_constant, margin):
    """Engagements in a row after which the part first reaches ``margin`` over ambient.

    The least n with ΔT(1 − rⁿ)/(1 − r) ≥ margin, r = exp(−t_i/τ).

    Parameters
    ----------
    rise : float or array_like [K]
        Bulk rise ΔT ≥ 0 of one engagement.
    interval : float or array_like [s]
        Time t_i > 0 between engagements.
    time_constant : float or array_like [s]
        Cooling time constant τ > 0.
    margin : float or array_like [K]
        Material limit minus ambient, > 0.

    Returns
    -------
    numpy.ndarray [-]
        n; inf if the periodic state stays below the margin (or no heat); NaN where an input is not
        finite, of the wrong sign or implausible.
    """
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
    """Largest engagement rate at which the periodic bulk temperature stays at or under the margin.

    The periodic state just after each engagement (:func:`periodic_temperature`)
    ΔT/(1 − exp(−t_i/τ)) ≤ M for t_i ≥ −τ·ln(1 − ΔT/M), so the rate is 1/t_i (× 3600 for
    engagements per hour). The engagement's own duration is neglected against t_i.

    Parameters
    ----------
    rise : float or array_like [K]
        Bulk temperature rise ΔT ≥ 0 of one engagement.
    time_constant : float or array_like [s]
        Cooling time constant τ = m c/(h A) > 0.
    margin : float or array_like [K]
        M, material limit minus ambient, > 0.

    Returns
    -------
    numpy.ndarray [1/s]
        Rate: 0 where ΔT ≥ M (one engagement alone reaches the limit), inf where ΔT = 0;
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
    """Effusivities of the flywheel, pressure-plate and driven-plate faces (:data:`MATERIALS`).

    Returns
    -------
    tuple of float [W s^0.5/(m² K)]
        (flywheel, pressure plate, driven plate): cast iron, cast iron, organic lining.
    """
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

    Parameters
    ----------
    slip_work : float or array_like [J]
        Slip work W of one engagement, ≥ 0.
    peak_slip_power : float or array_like [W]
        Peak slip power, ≥ 0.
    outer_radius, inner_radius : float or array_like [m]
        Lining radii R₂ > R₁ > 0.
    faces : int or array_like [-]
        Number of friction faces n, even (n/2 driven plates lined on both sides, module docstring).
    flywheel_mass : float or array_like [kg]
        Flywheel mass (default 10.3 kg: the source paper (000), Table 3).
    pressure_plate_mass : float or array_like [kg]
        Pressure-plate mass (default 2.5 kg: Table 3).
    driven_plate_mass : float or array_like [kg]
        Mass of each driven plate (default 1.9 kg: Table 3).
    heat_transfer_coefficient : float or array_like [W/(m² K)]
        h of the parts' cooling (default 40: assumed, air moved by the spinning parts in a closed
        bell housing).
    cooling_area : float or array_like [m²]
        Cooling area A of each part (default 0.1: assumed, both sides and the rim of a 225 mm
        plate).
    engagement_interval : float or array_like [s]
        Time between engagements of a sequence (default 60: assumed, a retried start).
    temperature_margin : float or array_like [K]
        Material limit minus ambient (default 210: assumed, 250 °C, the upper service temperature
        of organic linings in Limpert ch. 3, over 40 °C in the housing).
    intermediate_plate_mass : float or array_like [kg]
        Mass of each intermediate plate (default 2.5: assumed, the pressure plate's; unused with
        two faces).

    Returns
    -------
    dict of numpy.ndarray
        ``friction_area`` [m²], ``specific_friction_work`` [J/m²],
        ``peak_specific_friction_power`` [W/m²] (:func:`specific_loading`); ``heat_flywheel``,
        ``heat_pressure_plate``, ``heat_driven_plate`` (each driven plate, n/2 of them),
        ``heat_intermediate_plate`` (each intermediate plate, n/2 − 1 of them; 0 with two faces)
        [J] (:func:`plate_shares` of the slip work: the flywheel's, the pressure plate's and all
        plates' heats sum to it); ``bulk_temperature_rise`` [K] of the hottest part
        (``hottest_part``: index into :data:`PARTS`); ``engagements_to_limit``: engagements in a
        row, ``engagement_interval`` apart, after which that part's bulk temperature first exceeds
        ambient by ``temperature_margin``, cooling by Newton's law with time constant m c/(h A);
        inf if never; ``max_engagement_rate`` [1/s]: the largest rate of engagements at which no
        part's periodic bulk temperature exceeds ambient by more than the margin
        (:func:`max_engagement_rate` of each part, the smallest; every part cooled through the same
        h A; inf where no heat); ``status``: ``invalid_input`` where ``faces`` is odd or an input
        is not finite, not positive or implausible (:mod:`clutchlab.plausible`),
        ``invalid_geometry`` for swapped lining radii (R₂ ≤ R₁).

    References
    ----------
    Source paper (000), eq. (11) (slip work) and Table 3 (masses) ([1] in the module docstring);
    Limpert [2], ch. 3 (heat partition, service temperature of organic linings).
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
    """Exponential modes of the smooth part of Duhamel's kernel (the solver's face temperature).

    The engagement solver integrates the friction-face temperature (friction fade) with these
    modes; the constants of :mod:`clutchlab.engagement._fade` are regenerated by this function.
    Σ w_k e^{−λ_k s} ≈ erf(√(λ_c s))/√s on s ∈ [0, span], fitted by non-negative least squares
    weighted by √s (the error relative to the whole kernel 1/√s), λ_k geometric with ``ratio`` from
    ``top``·λ_c down to 0.1/span; modes of zero weight dropped.

    Parameters
    ----------
    cut : float [1/s]
        λ_c, the rate that splits the kernel 1/√s = erf(√(λ_c s))/√s + erfc(√(λ_c s))/√s (the
        solver takes the second part, on s ≲ 1/λ_c, quasi-statically); finite and > 0.
    span : float [s]
        Length of time over which the fit holds; finite and > 0.
    ratio : float [-]
        Ratio of neighbouring rates, > 1.
    top : float [-]
        Largest rate over λ_c, finite and > 0.

    Returns
    -------
    lam : numpy.ndarray [1/s]
        Rates λ_k.
    weights : numpy.ndarray [s^-0.5]
        Weights w_k.

    Raises
    ------
    ValueError
        If an argument is out of range or more than 1000 modes would be needed.
    """
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
    """Friction-face (flash) temperature rise of the cast-iron faces from a Duhamel integral.

    The flywheel and the pressure plate take the same share γ = e_m/(e_m + e_lining) of their face's
    heat, as do the intermediate plates' faces of a multi-plate clutch. With the solver's integral
    of the slip power I = ∫ P(τ)/√(t − τ) dτ: ΔT = γ·I/(A·e_m·√π), A the friction area of all faces
    (each of the n faces takes P/n on A/n).

    Parameters
    ----------
    duhamel_integral : float or array_like [W s^0.5]
        I ≥ 0.
    outer_radius, inner_radius : float or array_like [m]
        Lining radii R₂ > R₁ > 0.
    faces : int or array_like [-]
        Number of friction faces, a whole number in [1, 1000].

    Returns
    -------
    numpy.ndarray [K]
        ΔT; NaN where I < 0, R₂ ≤ R₁ ≤ 0, ``faces`` not a whole number in [1, 1000], or an input
        not finite or plausible.

    References
    ----------
    Carslaw and Jaeger [3], ch. II (Duhamel's theorem); Limpert [2], ch. 3 (heat partition).
    """
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
