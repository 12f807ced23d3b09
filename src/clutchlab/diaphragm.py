"""Diaphragm-spring load–deflection curve (Almen–László) and its characteristic points.

All functions are pure, vectorised over numpy broadcasting and in SI units.

References
----------
.. [1] Zhao P. (2026), "Design and engagement simulation of diaphragm spring clutch for
   unmanned helicopters", the source paper (000), eq. (10) and Fig. 6.
.. [2] Almen J.O., László A. (1936), "The uniform-section disk spring", Trans. ASME 58.
"""

from __future__ import annotations

import numpy as np

from . import status as st

__all__ = [
    "spring_constant",
    "radius_ratio_k",
    "almen_laszlo_load",
    "characteristic_points",
    "geometry_is_valid",
]

SQRT2 = np.sqrt(2.0)


MAX_OPERATING_POINT_FACTOR = 10.0  # λ_B/λ_C (0.8 to 1.0 in [1])

_RADIUS = st.positive_in("m")
_RULES = {
    "youngs_modulus": st.positive_in("Pa"),
    "poisson_ratio": st.between(-1.0, 0.5, lo_open=True, hi_open=True),
    "sheet_thickness": st.positive_in("m"),
    "cone_height": st.positive_in("m"),
    "outer_radius": _RADIUS,
    "inner_radius": _RADIUS,
    "load_radius_outer": _RADIUS,
    "load_radius_inner": _RADIUS,
    "operating_point_factor": st.positive_in("1", lo=1e-3, hi=MAX_OPERATING_POINT_FACTOR),
    "deflection": st.finite_in("m"),
}


def _in_order(a):
    """0 < r ≤ r₁ < R₁ ≤ R: the load points on the spring, inside out (r₁ and R₁ a plausible
    length apart: the lever R₁ − r₁ divides the load)."""
    return (
        (a["inner_radius"] <= a["load_radius_inner"])
        & st.apart(a["load_radius_outer"], a["load_radius_inner"])
        & (a["load_radius_outer"] <= a["outer_radius"])
    )


def _domain(inputs, order=True):
    rules = {k: _RULES[k] for k in inputs}
    if order:
        rules[None] = _in_order
    return rules


def radius_ratio_k(outer_radius, inner_radius, load_radius_outer, load_radius_inner):
    """Lever ratio k = (R − r)/(R₁ − r₁) of the Almen–László load, equation (10) of [1].

    Parameters
    ----------
    outer_radius, inner_radius : float or array_like [m]
        Outer and inner radius R, r of the spring cone.
    load_radius_outer, load_radius_inner : float or array_like [m]
        Pressure-plate load radius R₁ and fulcrum-ring load radius r₁.

    Returns
    -------
    numpy.ndarray [-]
        k; NaN unless 0 < r ≤ r₁ < R₁ ≤ R and every radius is finite and of a plausible magnitude
        (:mod:`clutchlab.plausible`).

    References
    ----------
    Source paper (000), eq. (10) ([1] in the module docstring).
    """
    inputs = dict(
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        load_radius_outer=load_radius_outer,
        load_radius_inner=load_radius_inner,
    )
    return st.nan_screened(_radius_ratio_k, inputs, _domain(inputs))


def _radius_ratio_k(*, outer_radius, inner_radius, load_radius_outer, load_radius_inner):
    return (outer_radius - inner_radius) / (load_radius_outer - load_radius_inner)


def spring_constant(
    *,
    youngs_modulus,
    poisson_ratio,
    sheet_thickness,
    outer_radius,
    inner_radius,
    load_radius_outer,
    load_radius_inner,
):
    """Leading factor c of the Almen–László load, equation (10) of [1].

    F = c·λ·[(H − kλ)(H − kλ/2) + h²] with c = π·E·h / (6(1 − μ²)) · ln(R/r) / (R₁ − r₁)².

    Parameters
    ----------
    youngs_modulus : float or array_like [Pa]
        Young's modulus E of the spring steel.
    poisson_ratio : float or array_like [-]
        Poisson's ratio μ, in (−1, 0.5).
    sheet_thickness : float or array_like [m]
        Sheet thickness h.
    outer_radius, inner_radius : float or array_like [m]
        Outer and inner radius R, r of the spring cone.
    load_radius_outer, load_radius_inner : float or array_like [m]
        Pressure-plate load radius R₁ and fulcrum-ring load radius r₁.

    Returns
    -------
    numpy.ndarray [N/m³]
        c; NaN unless ν ∈ (−1, 0.5), 0 < r ≤ r₁ < R₁ ≤ R and every input is finite, positive and
        plausible (:mod:`clutchlab.plausible`).

    References
    ----------
    Source paper (000), eq. (10) ([1] in the module docstring); Almen and László [2].
    """
    inputs = dict(
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
        sheet_thickness=sheet_thickness,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        load_radius_outer=load_radius_outer,
        load_radius_inner=load_radius_inner,
    )
    return st.nan_screened(_spring_constant, inputs, _domain(inputs))


def _spring_constant(
    *,
    youngs_modulus,
    poisson_ratio,
    sheet_thickness,
    outer_radius,
    inner_radius,
    load_radius_outer,
    load_radius_inner,
):
    return (
        np.pi
        * youngs_modulus
        * sheet_thickness
        / (6.0 * (1.0 - poisson_ratio**2))
        * np.log(outer_radius / inner_radius)
        / (load_radius_outer - load_radius_inner) ** 2
    )


def almen_laszlo_load(
    deflection,
    *,
    youngs_modulus,
    poisson_ratio,
    sheet_thickness,
    cone_height,
    outer_radius,
    inner_radius,
    load_radius_outer,
    load_radius_inner,
):
    """Load of a diaphragm spring at its pressure-plate load point, equation (10) of [1].

    F(λ) = π·E·h·λ / (6(1 − μ²)) · ln(R/r) / (R₁ − r₁)² · [(H − kλ)(H − kλ/2) + h²] with
    k = (R − r)/(R₁ − r₁).

    Parameters
    ----------
    deflection : float or array_like [m]
        Axial deflection λ at the pressure-plate load radius.
    youngs_modulus : float or array_like [Pa]
        Young's modulus E.
    poisson_ratio : float or array_like [-]
        Poisson's ratio μ.
    sheet_thickness : float or array_like [m]
        Sheet thickness h.
    cone_height : float or array_like [m]
        Inner cone height H.
    outer_radius, inner_radius : float or array_like [m]
        Outer and inner radius R, r of the spring cone.
    load_radius_outer, load_radius_inner : float or array_like [m]
        Pressure-plate load radius R₁ and fulcrum-ring load radius r₁.

    Returns
    -------
    numpy.ndarray [N]
        Load F; NaN where an input is not finite or not physical (E, h, H ≤ 0; ν outside
        (−1, 0.5); radii not 0 < r ≤ r₁ < R₁ ≤ R) or of an implausible magnitude
        (:mod:`clutchlab.plausible`).

    References
    ----------
    Source paper (000), eq. (10) ([1] in the module docstring); Almen and László [2].
    """
    inputs = dict(
        deflection=deflection,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
        sheet_thickness=sheet_thickness,
        cone_height=cone_height,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        load_radius_outer=load_radius_outer,
        load_radius_inner=load_radius_inner,
    )
    return st.nan_screened(_almen_laszlo_load, inputs, _domain(inputs))


def _almen_laszlo_load(
    *,
    deflection,
    youngs_modulus,
    poisson_ratio,
    sheet_thickness,
    cone_height,
    outer_radius,
    inner_radius,
    load_radius_outer,
    load_radius_inner,
):
    c = _spring_constant(
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
        sheet_thickness=sheet_thickness,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        load_radius_outer=load_radius_outer,
        load_radius_inner=load_radius_inner,
    )
    k = _radius_ratio_k(
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        load_radius_outer=load_radius_outer,
        load_radius_inner=load_radius_inner,
    )
    lam = np.asarray(deflection, dtype=float)
    H, h = cone_height, sheet_thickness
    return c * lam * ((H - k * lam) * (H - 0.5 * k * lam) + h**2)


def geometry_is_valid(
    *,
    sheet_thickness,
    cone_height,
    outer_radius,
    inner_radius,
    load_radius_outer,
    load_radius_inner,
):
    """Whether the load points lie on the spring and the lengths are admissible.

    Parameters
    ----------
    sheet_thickness : float or array_like [m]
        Sheet thickness h.
    cone_height : float or array_like [m]
        Inner cone height H.
    outer_radius, inner_radius : float or array_like [m]
        Outer and inner radius R, r of the spring cone.
    load_radius_outer, load_radius_inner : float or array_like [m]
        Pressure-plate load radius R₁ and fulcrum-ring load radius r₁.

    Returns
    -------
    numpy.ndarray of bool
        True where 0 < r ≤ r₁ < R₁ ≤ R and h, H > 0, every length finite and of a plausible
        magnitude (:mod:`clutchlab.plausible`).

    References
    ----------
    Source paper (000), eq. (10) and Fig. 6 ([1] in the module docstring): the radii of the
    load points.
    """
    inputs = dict(
        sheet_thickness=sheet_thickness,
        cone_height=cone_height,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        load_radius_outer=load_radius_outer,
        load_radius_inner=load_radius_inner,
    )
    _, ok = st.admissible(inputs, _domain(inputs))
    return ok


_DOMAIN = {k: v for k, v in _RULES.items() if k != "deflection"}


def characteristic_points(
    *,
    youngs_modulus,
    poisson_ratio,
    sheet_thickness,
    cone_height,
    outer_radius,
    inner_radius,
    load_radius_outer,
    load_radius_inner,
    operating_point_factor=0.9,
):
    """Characteristic points A (hump), C (flattening), D (valley), B (operating) of equation (10).

    Closed form: with F = c·λ·[(H − kλ)(H − kλ/2) + h²],
    dF/dλ = c·[(3/2)k²λ² − 3kHλ + H² + h²] vanishes at
    λ_A,D = [H ∓ √((H² − 2h²)/3)] / k, which are real only for H/h > √2. The inflection point
    λ_C = H/k is their midpoint (the paper's λ_C = (λ_A + λ_D)/2) and is the position where the
    spring is pressed flat at the load points; F_C = c·H·h²/k. The operating point of [1] is
    λ_B = factor·λ_C with factor 0.8…1.0.

    Parameters
    ----------
    youngs_modulus : float or array_like [Pa]
        Young's modulus E.
    poisson_ratio : float or array_like [-]
        Poisson's ratio μ.
    sheet_thickness : float or array_like [m]
        Sheet thickness h.
    cone_height : float or array_like [m]
        Inner cone height H.
    outer_radius, inner_radius : float or array_like [m]
        Outer and inner radius R, r of the spring cone.
    load_radius_outer, load_radius_inner : float or array_like [m]
        Pressure-plate load radius R₁ and fulcrum-ring load radius r₁.
    operating_point_factor : float or array_like [-]
        λ_B/λ_C, 0.8…1.0 in [1]; at most 10.

    Returns
    -------
    dict of numpy.ndarray
        ``deflection_A/C/D/B`` [m], ``load_A/C/D/B`` [N] and ``status`` (int8, see
        :mod:`clutchlab.status`): ``monotone_no_hump`` where H/h ≤ √2 (A and D are NaN, B is
        still given since the flat position C exists), ``snap_through`` where the valley load
        F_D ≤ 0 (H/h ≥ 2√2: the spring would not spring back), ``invalid_geometry`` (all NaN)
        where the load points are not on the spring (0 < r ≤ r₁ < R₁ ≤ R) and ``invalid_input``
        (all NaN) where an input is not finite or not physical (E, h, H, radii, operating-point
        factor ≤ 0; ν outside (−1, 0.5)) or of an implausible magnitude
        (:mod:`clutchlab.plausible`; the operating-point factor at most 10).

    References
    ----------
    Source paper (000), eq. (10) and Fig. 6 ([1] in the module docstring): the points A, C, D
    and B, λ_C = (λ_A + λ_D)/2 and λ_B = (0.8…1.0)·λ_C.
    """
    return st.screened(
        _characteristic_points,
        dict(
            youngs_modulus=youngs_modulus,
            poisson_ratio=poisson_ratio,
            sheet_thickness=sheet_thickness,
            cone_height=cone_height,
            outer_radius=outer_radius,
            inner_radius=inner_radius,
            load_radius_outer=load_radius_outer,
            load_radius_inner=load_radius_inner,
            operating_point_factor=operating_point_factor,
        ),
        _DOMAIN,
        geometry={None: _in_order},
    )


def _characteristic_points(
    *,
    youngs_modulus,
    poisson_ratio,
    sheet_thickness,
    cone_height,
    outer_radius,
    inner_radius,
    load_radius_outer,
    load_radius_inner,
    operating_point_factor,
):
    args = dict(
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
        sheet_thickness=sheet_thickness,
        cone_height=cone_height,
        outer_radius=outer_radius,
        inner_radius=inner_radius,
        load_radius_outer=load_radius_outer,
        load_radius_inner=load_radius_inner,
    )
    # (screened: every input admissible, the load points on the spring)
    shape = np.broadcast_shapes(
        *(np.shape(v) for v in args.values()), np.shape(operating_point_factor)
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        H = np.broadcast_to(cone_height, shape).astype(float)
        h = np.broadcast_to(sheet_thickness, shape).astype(float)
        k = np.broadcast_to(
            _radius_ratio_k(
                outer_radius=outer_radius,
                inner_radius=inner_radius,
                load_radius_outer=load_radius_outer,
                load_radius_inner=load_radius_inner,
            ),
            shape,
        )
        disc = (H**2 - 2.0 * h**2) / 3.0
        hump = disc > 0
        root = np.sqrt(np.where(hump, disc, np.nan))
        lam_C = H / k
        lam_A = (H - root) / k
        lam_D = (H + root) / k
        lam_B = np.broadcast_to(operating_point_factor, shape) * lam_C
        out = {
            "deflection_A": lam_A,
            "deflection_C": lam_C,
            "deflection_D": lam_D,
            "deflection_B": lam_B,
        }
        for p in "ACDB":
            out[f"load_{p}"] = _almen_laszlo_load(deflection=out[f"deflection_{p}"], **args)
    code = np.full(shape, st.CODE["ok"], dtype=st.DTYPE)
    code[~hump] = st.CODE["monotone_no_hump"]
    code[hump & ~(out["load_D"] > 0)] = st.CODE["snap_through"]
    out["status"] = code
    return out
