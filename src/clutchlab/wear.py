"""A clutch over its life: the diaphragm's operating point as the lining wears, lining wear per
engagement and life in engagements, and the largest engagement rate the cooling allows.

Wear along the spring curve. As the facings wear by Δ (all faces together), the pressure plate
follows towards the flywheel by Δ and the spring relaxes by Δ at its pressure-plate load radius: the
operating point moves from λ_B to λ_B − Δ on the spring's own Almen–László curve (the source paper
(000), eq. 10). A spring whose B lies on the falling branch (λ_B > λ_A) first gains load towards the
hump A, then loses it; one whose B lies on the rising branch loses load from the first wear on.
Where λ_B − Δ ≤ 0 the spring is unloaded: no clamp load.

Lining wear per engagement. VDI 2241 Blatt 1 writes the worn lining volume as proportional to the
friction work, V = q_V·W, q_V the specific wear rate [m³/J]. The slip work W of an engagement is
shared by the n friction faces of the stack (each takes W/n, :mod:`clutchlab.heat`) and each face
of area A wears q_V·W/(n A) deep, so the plates close up by the sum over the faces,
δ = q_V·W/A per engagement (A one face's area). q_V is taken constant: no temperature law for
q_V with a source was found for this model (the wear of organic linings does rise above a
critical face temperature, but its law is the lining maker's).

Life. With the clamp load following the wear, the slip work changes along the allowance Δ_allow,
W = W(x). The engagements the allowance lasts are N = ∫₀^Δ dx/δ(x) = (A/q_V) ∫₀^Δ dx/W(x),
integrated by Simpson's rule over the new, half-worn and fully worn engagements; for a constant
W this is exactly N = Δ·A/(q_V·W) (the allowance volume over the wear of one engagement).

Thermal duty (:func:`clutchlab.heat.max_engagement_rate`). A part that heats by ΔT per
engagement and cools by Newton's law (time constant τ) between engagements t_i apart reaches
the periodic state ΔT/(1 − exp(−t_i/τ)) just after each
(:func:`clutchlab.heat.periodic_temperature`). It stays at or under the margin M (material limit
minus ambient) for t_i ≥ −τ·ln(1 − ΔT/M), so the largest engagement rate is
1/t_i = −1/(τ·ln(1 − ΔT/M)); 0 where one engagement alone reaches M (ΔT ≥ M), inf where an
engagement heats nothing. The engagement's own duration is neglected against t_i (its heat
arrives at once).

References
----------
.. [1] Zhao P. (2026), "Design and engagement simulation of diaphragm spring clutch for
   unmanned helicopters", the source paper (000), eq. (10) and Fig. 6: B at 0.8–1.0 λ_C on the
   falling branch.
.. [2] VDI 2241 Blatt 1 (1982), "Schaltbare fremdbetätigte Reibkupplungen und -bremsen":
   specific wear rate q_V (worn volume per friction work).
"""

from __future__ import annotations

import numpy as np

from . import diaphragm
from . import status as st

__all__ = [
    "WEAR_FRACTIONS",
    "SPECIFIC_WEAR_RATE",
    "worn_deflection",
    "worn_clamp_load",
    "least_clamp_load",
    "wear_per_engagement",
    "life_engagements",
]

#: the wear states a study reports: new, half worn, fully worn (fractions of the allowance)
WEAR_FRACTIONS = (0.0, 0.5, 1.0)

#: default specific wear rate q_V [m³/J]: 0.2 cm³/kWh, assumed for a resin-bonded (organic) dry
#: lining on cast iron, of the order VDI 2241 Blatt 1 gives for such linings; replace it by the
#: lining maker's value (it scales the life in engagements in inverse proportion)
SPECIFIC_WEAR_RATE = 0.2e-6 / 3.6e6

_RULES = {
    "deflection_operating": st.positive_in("m"),
    "wear": st.nonnegative_in("m"),
    "wear_allowance": st.nonnegative_in("m"),
    "slip_work": st.nonnegative_in("J"),
    "specific_wear_rate": st.positive_in("m^3/J"),
    "outer_radius": st.positive_in("m"),
    "inner_radius": st.positive_in("m"),
}
_ANNULUS = {None: lambda a: a["outer_radius"] > a["inner_radius"]}


def worn_deflection(deflection_operating, wear):
    """Spring deflection at the pressure-plate load point after the facings wore ``wear``: λ_B − Δ.

    The pressure plate follows the wear (module docstring).

    Parameters
    ----------
    deflection_operating : float or array_like [m]
        λ_B of the new clutch, > 0.
    wear : float or array_like [m]
        Δ, the lining wear of all faces together, ≥ 0.

    Returns
    -------
    numpy.ndarray [m]
        λ_B − Δ (≤ 0: the spring is unloaded); NaN where an input is not finite, of the wrong
        sign or implausible (:mod:`clutchlab.plausible`).
    """
    inputs = dict(deflection_operating=deflection_operating, wear=wear)
    domain = {k: _RULES[k] for k in inputs}
    return st.nan_screened(_worn_deflection, inputs, domain)


def _worn_deflection(*, deflection_operating, wear):
    return np.asarray(deflection_operating, dtype=float) - np.asarray(wear, dtype=float)


def worn_clamp_load(wear, *, deflection_operating, **spring):
    """Clamp load of the diaphragm spring after the facings wore ``wear``: equation (10) at λ_B − Δ.

    0 where the spring is unloaded (λ_B − Δ ≤ 0).

    Parameters
    ----------
    wear : float or array_like [m]
        Δ, the lining wear of all faces together, ≥ 0.
    deflection_operating : float or array_like [m]
        λ_B of the new clutch.
    **spring : float or array_like
        The spring's Almen–László arguments (:func:`clutchlab.diaphragm.almen_laszlo_load`):
        ``youngs_modulus`` [Pa], ``poisson_ratio`` [-], ``sheet_thickness``, ``cone_height``,
        ``outer_radius``, ``inner_radius``, ``load_radius_outer``, ``load_radius_inner`` [m].

    Returns
    -------
    numpy.ndarray [N]
        F(λ_B − Δ); NaN where an input is invalid (as in
        :func:`clutchlab.diaphragm.almen_laszlo_load` and :func:`worn_deflection`).

    References
    ----------
    Source paper (000), eq. (10) and Fig. 6 ([1] in the module docstring).
    """
    lam = worn_deflection(deflection_operating, wear)
    with np.errstate(invalid="ignore"):
        load = diaphragm.almen_laszlo_load(np.maximum(lam, 0.0), **spring)
    return np.where(np.isnan(lam), np.nan, load)


def least_clamp_load(wear_allowance, *, deflection_operating, **spring):
    """Least clamp load over the wear travel Δ ∈ [0, Δ_allow].

    Eq. (10) of [1] is a cubic in λ, so its least value on [λ_B − Δ_allow, λ_B] (clipped at 0: an
    unloaded spring) lies at an end or at a stationary point inside (the valley D, where B was
    placed past it; the hump A is a maximum and never the least).

    Parameters
    ----------
    wear_allowance : float or array_like [m]
        Δ_allow, the wear the clutch may take, ≥ 0.
    deflection_operating : float or array_like [m]
        λ_B of the new clutch.
    **spring : float or array_like
        The spring's Almen–László arguments (:func:`clutchlab.diaphragm.almen_laszlo_load`):
        ``youngs_modulus`` [Pa], ``poisson_ratio`` [-], ``sheet_thickness``, ``cone_height``,
        ``outer_radius``, ``inner_radius``, ``load_radius_outer``, ``load_radius_inner`` [m].

    Returns
    -------
    numpy.ndarray [N]
        min F over the travel; NaN where an input is invalid (as :func:`worn_clamp_load`).

    References
    ----------
    Source paper (000), eq. (10) and Fig. 6 ([1] in the module docstring).
    """
    worn = worn_clamp_load(wear_allowance, deflection_operating=deflection_operating, **spring)
    new = worn_clamp_load(0.0 * wear_allowance, deflection_operating=deflection_operating, **spring)
    pts = diaphragm.characteristic_points(**spring)
    lam_d = pts["deflection_D"]
    lo = worn_deflection(deflection_operating, wear_allowance)
    with np.errstate(invalid="ignore"):
        inside = (lam_d > lo) & (lam_d < deflection_operating)
        least = np.minimum(new, worn)
        return np.where(inside, np.minimum(least, pts["load_D"]), least)


def wear_per_engagement(slip_work, specific_wear_rate, outer_radius, inner_radius):
    """Closing-up of the plates by the lining wear of one engagement, δ = q_V·W/A.

    The sum over the faces of each face's wear depth, A = π(R₂² − R₁²) one face's area.

    Parameters
    ----------
    slip_work : float or array_like [J]
        Slip (friction) work W of the engagement, ≥ 0.
    specific_wear_rate : float or array_like [m³/J]
        q_V > 0 (:data:`SPECIFIC_WEAR_RATE`).
    outer_radius, inner_radius : float or array_like [m]
        Lining radii R₂ > R₁ > 0.

    Returns
    -------
    numpy.ndarray [m]
        δ; NaN where an input is not finite, of the wrong sign or implausible, or R₂ ≤ R₁.

    References
    ----------
    VDI 2241 Blatt 1 [2] (module docstring): the worn volume proportional to the friction work.
    """
    inputs = dict(
        slip_work=slip_work,
        specific_wear_rate=specific_wear_rate,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
    )
    domain = {**{k: _RULES[k] for k in inputs}, **_ANNULUS}
    return st.nan_screened(_wear_per_engagement, inputs, domain)


def _wear_per_engagement(*, slip_work, specific_wear_rate, outer_radius, inner_radius):
    area = np.pi * (np.square(outer_radius) - np.square(inner_radius))
    return np.asarray(specific_wear_rate) * np.asarray(slip_work) / area


def life_engagements(wear_allowance, wear_new, wear_half, wear_worn):
    """Engagements the wear allowance lasts, N = ∫₀^Δ dx/δ(x), by Simpson's rule.

    Over the wear per engagement δ of the new, the half-worn and the fully worn clutch (the clamp
    load following the wear; module docstring). Constant δ: exactly Δ/δ.

    Parameters
    ----------
    wear_allowance : float or array_like [m]
        Δ, ≥ 0.
    wear_new, wear_half, wear_worn : float or array_like [m]
        δ per engagement at wear 0, Δ/2 and Δ, ≥ 0.

    Returns
    -------
    numpy.ndarray [-]
        N (not rounded); inf where an engagement wears nothing, 0 for no allowance; NaN where an
        input is not finite, negative or implausible.
    """
    inputs = dict(
        wear_allowance=wear_allowance, wear_new=wear_new, wear_half=wear_half, wear_worn=wear_worn
    )
    domain = {"wear_allowance": _RULES["wear_allowance"]} | {
        # (a nanometre an engagement is a long life, not a slip: no lower magnitude)
        k: st.nonnegative_in("m", lo=0.0)
        for k in ("wear_new", "wear_half", "wear_worn")
    }
    return st.nan_screened(_life_engagements, inputs, domain)


def _life_engagements(*, wear_allowance, wear_new, wear_half, wear_worn):
    with np.errstate(divide="ignore"):
        inv = [1.0 / np.asarray(d, dtype=float) for d in (wear_new, wear_half, wear_worn)]
    life = np.asarray(wear_allowance) / 6.0 * (inv[0] + 4.0 * inv[1] + inv[2])
    return np.where(np.asarray(wear_allowance) == 0, 0.0, life)
