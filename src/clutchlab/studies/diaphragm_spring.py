"""Study "diaphragm_spring": Almen–László statics, clamp load, torque capacity (source paper 000).

Inputs are the spring geometry (thickness h, cone-height ratio H/h, radius ratio R/r and the
load-point offsets), the release-bearing operating point factor λ_B/λ_C, and the lining and
friction data. Outputs: characteristic points A/C/D/B of eq. (10), clamp load at B, torque
capacity (eqs. 13–14 corrected), reserve factor and the load–deflection curve of each spring;
over the wear allowance (the operating point worn from λ_B to λ_B − Δ on the spring's curve,
:mod:`clutchlab.wear`) the clamp load, capacity and reserve factor half and fully worn and the
least over the wear.

Model: closed form (eq. 10 is a cubic in λ; its stationary points are roots of a quadratic).
No solver is involved.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .. import diaphragm, driven_plate, friction, wear
from .. import status as st
from ..published import DIAPHRAGM_CLUTCH
from ..validation import Row, to_dataset
from . import Parameter, Relation, Study, flat_inputs, register

MM = 1e-3
# the largest friction coefficient of any dry or wet clutch pair (sintered metal, carbon: about 1;
# above 2 a value is a slip, e.g. a percentage given as a number)
FRICTION_MAX = 2.0
# geometric ratios of a diaphragm spring (H/h, R/r): 10 is far past any spring
RATIO_MAX = 10.0

PARAMETERS = (
    Parameter("youngs_modulus", "Pa", "Young's modulus of the spring steel", 206e9),
    Parameter(
        "poisson_ratio",
        "1",
        "Poisson's ratio of the spring steel",
        0.3,
        maximum=0.5,
        maximum_inclusive=False,
    ),
    Parameter("sheet_thickness", "m", "diaphragm sheet thickness h", 2.334 * MM),
    # H/h: a hump for H/h > sqrt(2), snap-through from 2 sqrt(2); 10 is far past any spring
    Parameter(
        "cone_height_ratio",
        "1",
        "inner cone height over sheet thickness H/h",
        3.5 / 2.334,
        maximum=RATIO_MAX,
    ),
    Parameter("outer_radius", "m", "outer radius R of the spring cone", 110 * MM),
    Parameter(
        "radius_ratio",
        "1",
        "outer over inner radius of the spring cone R/r",
        110 / 85,
        minimum=1.0,
        maximum=RATIO_MAX,
    ),
    Parameter(
        "load_radius_outer_offset",
        "m",
        "R - R1: pressure-plate load point inside the outer edge",
        2 * MM,
        minimum_inclusive=True,
    ),
    Parameter(
        "load_radius_inner_offset",
        "m",
        "r1 - r: fulcrum-ring load point outside the inner edge",
        1 * MM,
        minimum_inclusive=True,
    ),
    Parameter(
        "operating_point_factor",
        "1",
        "operating point B over flat point C, lambda_B/lambda_C",
        0.9,
        minimum=1e-3,  # (clutchlab.diaphragm's own lower end: below it no operating point)
        minimum_inclusive=True,
        maximum=2.0,
    ),
    Parameter(
        "friction_coefficient", "1", "lining friction coefficient mu", 0.4, maximum=FRICTION_MAX
    ),
    Parameter("lining_outer_radius", "m", "lining outer radius R2", 112.5 * MM),
    Parameter("lining_inner_radius", "m", "lining inner radius R1 (lining)", 75 * MM),
    Parameter("friction_faces", "1", "number of friction faces", 2.0, integer=True),
    Parameter(
        "stack_mass",
        "kg",
        "driven plate + pressure plate + spring mass whose weight adds to the "
        "clamp load (vertical shaft); 0 for a horizontal shaft",
        0.0,
        minimum_inclusive=True,
    ),
    Parameter("max_engine_torque", "N m", "engine maximum torque T_emax", 173.0),
    # the lining wear the clutch must take (all faces together): the pressure plate follows it and
    # the operating point moves from B towards A on the spring's curve (clutchlab.wear)
    Parameter(
        "wear_allowance",
        "m",
        "lining wear allowance, all friction faces together (assumed: 1.5 mm)",
        1.5 * MM,
        minimum_inclusive=True,
        maximum=20 * MM,  # (a dry lining is 3 to 5 mm thick per face)
    ),
)

OPTIONS = {"friction_radius": ("uniform_pressure", "uniform_wear")}

# relations the statics assume for every scenario (clutchlab.diaphragm.geometry_is_valid, the
# lining annulus of clutchlab.friction): refused in a config, naming the parameters
RELATIONS = (
    Relation(
        ("load_radius_inner_offset", "load_radius_outer_offset", "outer_radius", "radius_ratio"),
        ("max", "max", "min", "min"),
        lambda load_radius_inner_offset, load_radius_outer_offset, outer_radius, radius_ratio: (
            outer_radius / radius_ratio + load_radius_inner_offset
            < outer_radius - load_radius_outer_offset
        ),
        "the load points lie on the spring in order (fulcrum r1 = R/(R/r) + (r1 - r) inside the "
        "pressure-plate point R1 = R - (R - R1))",
    ),
    Relation(
        ("sheet_thickness", "outer_radius", "radius_ratio"),
        ("max", "min", "min"),
        lambda sheet_thickness, outer_radius, radius_ratio: (
            sheet_thickness < outer_radius - outer_radius / radius_ratio
        ),
        "the spring is a thin annular plate (sheet_thickness below the annulus width R - R/(R/r); "
        "a bare 2.3 is 2.3 m: write '2.3 mm')",
    ),
    Relation(
        ("lining_inner_radius", "lining_outer_radius"),
        ("max", "min"),
        lambda lining_inner_radius, lining_outer_radius: lining_inner_radius < lining_outer_radius,
        "the lining is an annulus (lining_inner_radius < lining_outer_radius)",
    ),
)

CURVE_POINTS = np.linspace(0.0, 2.0, 81)


def _attrs(long_name, units, **extra):
    return {"long_name": long_name, "units": units, **extra}


def spring_geometry(p) -> dict:
    """Almen–László arguments from the study parameters (h, H/h, R, R/r and load-point offsets).

    Parameters
    ----------
    p : dict of numpy.ndarray
        The study's parameters as flat arrays of one length [SI]
        (:func:`clutchlab.studies.flat_inputs`).

    Returns
    -------
    dict of numpy.ndarray
        The keyword arguments of :func:`clutchlab.diaphragm.almen_laszlo_load` but the
        deflection: ``youngs_modulus`` [Pa], ``poisson_ratio`` [-], ``sheet_thickness``,
        ``cone_height``, ``outer_radius``, ``inner_radius``, ``load_radius_outer``,
        ``load_radius_inner`` [m].
    """
    h, R = p["sheet_thickness"], p["outer_radius"]
    r = R / p["radius_ratio"]
    return dict(
        youngs_modulus=p["youngs_modulus"],
        poisson_ratio=p["poisson_ratio"],
        sheet_thickness=h,
        cone_height=p["cone_height_ratio"] * h,
        outer_radius=R,
        inner_radius=r,
        load_radius_outer=R - p["load_radius_outer_offset"],
        load_radius_inner=r + p["load_radius_inner_offset"],
    )


def _capacity_status(code, capacity, reserve, p, worn):
    """The spring's status, and where the spring has numbers (ok, monotone_no_hump, snap_through)
    but the capacity or reserve factor has none: ``invalid_geometry`` for swapped lining radii,
    ``invalid_input`` for inputs the friction model refuses (μ, faces, stack mass, engine torque
    out of range) — never a NaN under a status that promises numbers."""
    numbers = np.isin(code, [st.CODE[k] for k in ("ok", "monotone_no_hump", "snap_through")])
    lining_bad = ~(p["lining_inner_radius"] < p["lining_outer_radius"])
    missing = ~np.isfinite(capacity) | ~np.isfinite(reserve)
    for v in worn.values():  # (the wear allowance refused: no end-of-wear numbers)
        missing |= np.isnan(v)
    code = np.where(numbers & lining_bad, st.CODE["invalid_geometry"], code)
    code = np.where(numbers & ~lining_bad & missing, st.CODE["invalid_input"], code)
    return code.astype(st.DTYPE)


def _capacity(clamp_load, p, assumption):
    """Torque capacity [N m] of clamp load ``clamp_load`` [N] with the lining of flat parameter
    arrays ``p`` (eqs. 13-14 corrected, :func:`clutchlab.friction.torque_capacity`)."""
    return friction.torque_capacity(
        clamp_load,
        p["friction_coefficient"],
        p["lining_outer_radius"],
        p["lining_inner_radius"],
        faces=p["friction_faces"],
        assumption=assumption,
        stack_mass=p["stack_mass"],
    )


def wear_states(p, spring, pts, assumption="uniform_pressure") -> dict:
    """Clamp load, torque capacity and reserve factor of the half-worn and the fully worn clutch.

    The operating point at λ_B − Δ/2 and λ_B − Δ on the spring's curve, Δ = ``wear_allowance``
    (:func:`clutchlab.wear.worn_clamp_load`), and the least over the whole wear travel
    (:func:`clutchlab.wear.least_clamp_load`).

    Parameters
    ----------
    p : dict of numpy.ndarray
        The study's parameters as flat arrays of one length [SI]
        (:func:`clutchlab.studies.flat_inputs`).
    spring : dict of numpy.ndarray
        The spring's Almen–László arguments (:func:`spring_geometry`).
    pts : dict of numpy.ndarray
        Its characteristic points (:func:`clutchlab.diaphragm.characteristic_points`).
    assumption : {"uniform_pressure", "uniform_wear"}
        Pressure distribution of the friction radius (:func:`clutchlab.friction.effective_radius`).

    Returns
    -------
    dict of numpy.ndarray
        ``clamp_load_*`` [N], ``torque_capacity_*`` [N m] and ``reserve_factor_*`` [-] for
        ``half``, ``worn`` and ``least``, and ``deflection_worn`` [m] (≤ 0: the spring is unloaded)
        (:data:`WEAR_OUTPUTS`).

    References
    ----------
    Source paper (000), eq. (10) and eqs. (13)–(14) corrected (:mod:`clutchlab.friction`).
    """
    out = {}
    lam_b = pts["deflection_B"]
    loads = {
        "half": wear.worn_clamp_load(
            0.5 * p["wear_allowance"], deflection_operating=lam_b, **spring
        ),
        "worn": wear.worn_clamp_load(p["wear_allowance"], deflection_operating=lam_b, **spring),
        "least": wear.least_clamp_load(p["wear_allowance"], deflection_operating=lam_b, **spring),
    }
    for state, load in loads.items():
        cap = _capacity(load, p, assumption)
        out[f"clamp_load_{state}"] = load
        out[f"torque_capacity_{state}"] = cap
        out[f"reserve_factor_{state}"] = friction.reserve_factor(cap, p["max_engine_torque"])
    out["deflection_worn"] = wear.worn_deflection(lam_b, p["wear_allowance"])
    return out


WEAR_OUTPUTS = {
    "clamp_load_half": ("N", "clamp load at half the wear allowance"),
    "clamp_load_worn": ("N", "clamp load at the full wear allowance (end of wear)"),
    "clamp_load_least": ("N", "least clamp load over the wear travel"),
    "torque_capacity_half": ("N m", "torque capacity at half the wear allowance"),
    "torque_capacity_worn": ("N m", "torque capacity at the full wear allowance (end of wear)"),
    "torque_capacity_least": ("N m", "least torque capacity over the wear travel"),
    "reserve_factor_half": ("1", "reserve factor at half the wear allowance"),
    "reserve_factor_worn": ("1", "reserve factor at the full wear allowance (end of wear)"),
    "reserve_factor_least": ("1", "least reserve factor over the wear travel"),
    "deflection_worn": (
        "m",
        "spring deflection at the full wear allowance, lambda_B - wear (<= 0: spring unloaded)",
    ),
}


def compute(inputs, options=None) -> xr.Dataset:
    """Results of a chunk of scenarios of the study "diaphragm_spring".

    Per scenario: the spring's characteristic points, clamp load, capacity and reserve, new and
    worn.

    Parameters
    ----------
    inputs : dict
        Parameter name -> flat array (one entry per scenario of the chunk) or scalar, in SI units
        (:data:`PARAMETERS`).
    options : dict or None
        The study's options (:data:`OPTIONS`: ``friction_radius``); missing: uniform pressure.

    Returns
    -------
    xarray.Dataset
        One entry per scenario on dimension ``run`` (curves with a further dimension): the outputs
        of the module docstring, each with ``units`` and ``long_name``, and ``status``
        (:mod:`clutchlab.status`). The registered ``compute`` (:func:`clutchlab.studies.get`) also
        applies the status rule (:func:`clutchlab.studies.apply_valid_statuses`).

    References
    ----------
    Source paper (000), eqs. (10) and (13)–(14) corrected.
    """
    options = options or {}
    assumption = options.get("friction_radius", "uniform_pressure")
    p = flat_inputs(inputs)
    spring = spring_geometry(p)
    ds = xr.Dataset(
        _variables(_statics(p, spring, assumption), spring, assumption),
        coords={
            "deflection_ratio": (
                "deflection_ratio",
                CURVE_POINTS,
                _attrs("deflection over flat-point deflection, lambda/lambda_C", "1"),
            )
        },
    )
    return ds


def _statics(p, spring, assumption) -> dict:
    """The spring's characteristic points, capacity, reserve, worn states and curve of flat
    parameter arrays ``p``, and the status; NaN where a model refuses the scenario."""
    pts = diaphragm.characteristic_points(
        **spring, operating_point_factor=p["operating_point_factor"]
    )
    code = pts["status"]
    capacity = _capacity(pts["load_B"], p, assumption)
    reserve = friction.reserve_factor(capacity, p["max_engine_torque"])
    worn = wear_states(p, spring, pts, assumption)
    code = _capacity_status(code, capacity, reserve, p, worn)

    lam_curve = pts["deflection_C"][:, None] * CURVE_POINTS[None, :]
    load_curve = diaphragm.almen_laszlo_load(
        lam_curve, **{k: v[:, None] for k, v in spring.items()}
    )

    # a scenario a model refuses has no numbers (the spring's too: one result, one status)
    refused = np.isin(code, [st.CODE["invalid_input"], st.CODE["invalid_geometry"]])
    pts = {k: (np.where(refused, np.nan, v) if k != "status" else v) for k, v in pts.items()}
    capacity, reserve = np.where(refused, np.nan, capacity), np.where(refused, np.nan, reserve)
    worn = {k: np.where(refused, np.nan, v) for k, v in worn.items()}
    lam_curve = np.where(refused[:, None], np.nan, lam_curve)
    load_curve = np.where(refused[:, None], np.nan, load_curve)
    return dict(
        pts=pts,
        capacity=capacity,
        reserve=reserve,
        worn=worn,
        code=code,
        lam_curve=lam_curve,
        load_curve=load_curve,
    )


def _variables(res, spring, assumption) -> dict:
    """The result's variables on ``run`` from :func:`_statics`'s ``res``."""
    pts, worn = res["pts"], res["worn"]
    capacity, reserve, code = res["capacity"], res["reserve"], res["code"]
    lam_curve, load_curve = res["lam_curve"], res["load_curve"]
    r = spring["inner_radius"]
    run = "run"
    data = {
        "clamp_load": (run, pts["load_B"], _attrs("clamp load at operating point B (eq. 10)", "N")),
        "deflection_operating": (
            run,
            pts["deflection_B"],
            _attrs("spring deflection at operating point B", "m"),
        ),
        "load_peak": (run, pts["load_A"], _attrs("local maximum load A", "N")),
        "deflection_peak": (run, pts["deflection_A"], _attrs("deflection at local maximum A", "m")),
        "load_flat": (run, pts["load_C"], _attrs("load at flattening point C", "N")),
        "deflection_flat": (
            run,
            pts["deflection_C"],
            _attrs("deflection at flattening point C (spring flat)", "m"),
        ),
        "load_valley": (run, pts["load_D"], _attrs("local minimum load D", "N")),
        "deflection_valley": (
            run,
            pts["deflection_D"],
            _attrs("deflection at local minimum D", "m"),
        ),
        "cone_height": (run, spring["cone_height"], _attrs("inner cone height H", "m")),
        "inner_radius": (run, r, _attrs("inner radius r of the spring cone", "m")),
        "torque_capacity": (
            run,
            capacity,
            _attrs(f"friction torque capacity at B ({assumption.replace('_', ' ')})", "N m"),
        ),
        "reserve_factor": (
            run,
            reserve,
            _attrs("reserve factor: capacity over engine maximum torque", "1"),
        ),
        "curve_deflection": (
            (run, "deflection_ratio"),
            lam_curve,
            _attrs("spring deflection on the curve", "m"),
        ),
        "curve_load": (
            (run, "deflection_ratio"),
            load_curve,
            _attrs("spring load on the curve (eq. 10)", "N"),
        ),
        **{k: (run, worn[k], _attrs(ln, u)) for k, (u, ln) in WEAR_OUTPUTS.items()},
        "status": (
            run,
            code,
            st.attrs(
                "invalid_geometry: load points off the spring or lining R1 >= R2; "
                "monotone_no_hump: H/h <= sqrt(2); snap_through: valley load <= 0"
            ),
        ),
    }
    return data


# the status rule (clutchlab.studies): a spring without a hump (H/h <= sqrt(2)) has no A and no D
# but its flat point C, operating point B and curve; a snap-through spring (valley load <= 0) is a
# design that fails the check, its points exact (like a stress above its allowable); load points
# off the spring, a lining R1 >= R2 or an input the models refuse: nothing
_SPRING = ("ok", "monotone_no_hump", "snap_through")
VALID_STATUSES = {
    **{
        k: _SPRING
        for k in (
            "clamp_load",
            "deflection_operating",
            "load_flat",
            "deflection_flat",
            "torque_capacity",
            "reserve_factor",
            "curve_deflection",
            "curve_load",
            *WEAR_OUTPUTS,
        )
    },
    **{
        k: ("ok", "snap_through")
        for k in ("load_peak", "deflection_peak", "load_valley", "deflection_valley")
    },
    "cone_height": _SPRING,
    "inner_radius": _SPRING,
}


# --- seed-000 validation rows (statics) ------------------------------------------------------

T_EMAX = 173.0  # N m, Table 1
#: τ and G of the damper springs are not printed in paper 000; 65Mn values assumed here.
DAMPER_ALLOWABLE_SHEAR = 400e6  # Pa
DAMPER_SHEAR_MODULUS = 79e9  # Pa
LINING_RO, LINING_RI = 112.5 * MM, 75 * MM  # lining radii, Table 2: D = 225 mm, d = 150 mm


def seed_spring() -> dict:
    """An Almen–László parameter set that gives F_B = 2500 N at λ_B = 0.9·λ_C.

    The source paper (000) prints no spring dimensions; this is one set (of many) consistent with
    its 2500 N: E = 206 GPa, ν = 0.3, h = 2.334 mm, H = 3.50 mm, R/r/R₁/r₁ = 110/85/108/86 mm.

    Returns
    -------
    dict
        The keyword arguments of :func:`clutchlab.diaphragm.almen_laszlo_load` but the
        deflection [SI].
    """
    return dict(
        youngs_modulus=206e9,
        poisson_ratio=0.3,
        sheet_thickness=2.334 * MM,
        cone_height=3.5 * MM,
        outer_radius=110 * MM,
        inner_radius=85 * MM,
        load_radius_outer=108 * MM,
        load_radius_inner=86 * MM,
    )


def validation() -> xr.Dataset:
    """The source paper (000)'s statics numbers reproduced, as validation rows (its engagement's
    are the engagement study's: :func:`clutchlab.studies.engagement.validation`).

    :data:`clutchlab.published.DIAPHRAGM_CLUTCH`.

    Returns
    -------
    xarray.Dataset
        Validation rows on dimension ``row`` (:func:`clutchlab.validation.to_dataset`): each
        published number, clutchlab's value, the relative error and its tolerance, and where the
        number is printed.
    """
    return to_dataset(_statics_rows(), "paper 000: diaphragm spring, damper, spline, capacity")


def _statics_rows() -> list[Row]:
    """Lining and damper rows (Tables 1-2, eqs. 3-9), then the spline, capacity and clamp load."""
    pub = DIAPHRAGM_CLUTCH
    Tj = driven_plate.damper_design_torque(T_EMAX)
    p_total = driven_plate.damper_total_force(Tj, 52 * MM)
    c_a = driven_plate.damper_angular_stiffness(Tj)
    rate = driven_plate.damper_spring_rate(c_a, 52 * MM, 4)
    d1 = driven_plate.damper_wire_diameter(
        driven_plate.damper_spring_force(p_total, 4), 15 * MM, DAMPER_ALLOWABLE_SHEAR
    )
    coils = driven_plate.damper_coil_count(DAMPER_SHEAR_MODULUS, d1, 15 * MM, rate)
    return [
        Row.against(
            pub["lining_constant"], friction.lining_coefficient(T_EMAX, 2 * LINING_RO), 1e-3
        ),
        Row.against(
            pub["damper_total_force"],
            p_total,
            1e-3,
            "R1 = 52 mm inferred (not printed); Table 2 calls it 'single spring' (erratum)",
        ),
        Row.against(pub["damper_angular_stiffness"], c_a, 1e-3),
        Row.against(
            pub["damper_spring_rate"],
            rate,
            1e-3,
            "printed as 416 'N/m': the value is in N/mm (erratum)",
        ),
        Row.against(
            pub["damper_coils"],
            coils,
            0.05,
            "tau = 400 MPa, G = 79 GPa assumed (not printed); eq. 6 with cube root (erratum)",
        ),
    ] + _spline_capacity_rows()


def _spline_capacity_rows() -> list[Row]:
    """Spline (section 3.2.2), capacity (eqs. 13-14) and clamp-load (eq. 10, Fig. 7) rows."""
    pub = DIAPHRAGM_CLUTCH
    spline = dict(
        teeth=10, outer_diameter=35 * MM, inner_diameter=28 * MM, tooth_width=4 * MM, length=35 * MM
    )
    bearing, _ = driven_plate.spline_stresses(T_EMAX, **spline)
    _, shear = driven_plate.spline_stresses(driven_plate.damper_design_torque(T_EMAX), **spline)
    ro, ri = LINING_RO, LINING_RI
    pts = diaphragm.characteristic_points(**seed_spring(), operating_point_factor=0.9)
    return [
        Row.against(pub["spline_bearing_stress"], bearing, 0.01),
        Row.against(
            pub["spline_shear_stress"],
            shear,
            0.05,
            "reached only with 2 T_emax = T_j = 346 N m (load not stated in the paper)",
        ),
        Row.against(
            pub["capacity_eq14_as_printed"],
            friction.torque_capacity_eq14_as_printed(2500.0, 0.4, 4.757, ro, ri),
            1e-3,
            "the paper's formula: one face, mu on the weight only; physically wrong (erratum)",
        ),
        Row.against(pub["capacity_two_faces"], friction.torque_capacity(2500.0, 0.4, ro, ri), 1e-3),
        Row.against(
            pub["capacity_two_faces_stack_weight"],
            friction.torque_capacity(2500.0, 0.4, ro, ri, stack_mass=4.757),
            1e-3,
            "Fig. 11's 250-256 N m is above the 225 N m ceiling at mu = 0.4, F = 2500 N",
        ),
        Row.against(
            pub["clamp_load"],
            pts["load_B"],
            5e-3,
            "spring dimensions not printed: E 206 GPa, nu 0.3, R/r/R1/r1 110/85/108/86 mm, "
            "h 2.334, H 3.50 mm",
        ),
    ]


# where each parameter's default comes from (the reference pages show it)
SPRING_SOURCES = {
    "youngs_modulus": (
        "assumed: spring steel (206 GPa); the source paper (000) prints no spring material"
    ),
    "poisson_ratio": (
        "assumed: spring steel (0.3); the source paper (000) prints no spring material"
    ),
    "sheet_thickness": (
        "assumed: the source paper (000) prints no spring dimensions; one spring that gives "
        "its clamp load F_B = 2500 N at lambda_B = 0.9 lambda_C (section 5.1, eq. 10)"
    ),
    "cone_height_ratio": (
        "assumed: H = 3.50 mm over h = 2.334 mm, a spring that gives the source paper (000)'s"
        " F_B = 2500 N (section 5.1, eq. 10)"
    ),
    "outer_radius": (
        "assumed: R = 110 mm, a spring that gives the source paper (000)'s F_B = 2500 N "
        "(section 5.1, eq. 10)"
    ),
    "radius_ratio": (
        "assumed: R/r = 110/85 mm, a spring that gives the source paper (000)'s F_B = 2500 N "
        "(section 5.1, eq. 10)"
    ),
    "load_radius_outer_offset": (
        "assumed: R1 = 108 mm, a spring that gives the source paper (000)'s F_B = 2500 N "
        "(section 5.1, eq. 10)"
    ),
    "load_radius_inner_offset": (
        "assumed: r1 = 86 mm, a spring that gives the source paper (000)'s F_B = 2500 N "
        "(section 5.1, eq. 10)"
    ),
    "operating_point_factor": (
        "the source paper (000), eq. (10) text: lambda_B = (0.8 to 1.0) lambda_C; 0.9 the middle"
    ),
    "friction_coefficient": "the source paper (000), Table 4",
    "lining_outer_radius": "the source paper (000), Table 2 (D = 225 mm)",
    "lining_inner_radius": "the source paper (000), Table 2 (d = 150 mm)",
    "friction_faces": (
        "the source paper (000), eqs. (13)-(14) corrected: a single-plate clutch has two faces"
    ),
    "stack_mass": (
        "assumed: a horizontal shaft (0); the source paper (000)'s eq. (14) adds the stack "
        "weight of a vertical one (Table 3 masses)"
    ),
    "max_engine_torque": "the source paper (000), Table 1",
    "wear_allowance": (
        "assumed: 1.5 mm of lining over all faces, of the order of a dry clutch's usable rivet "
        "depth; the source paper (000) places B at 0.8-1.0 lambda_C for the wear travel"
    ),
}

STUDY = register(
    Study(
        name="diaphragm_spring",
        output="diaphragm_spring/diaphragm_spring.h5",
        description=(
            "Diaphragm-spring statics:"
            " Almen-Laszlo curve, clamp load, torque capacity (source paper 000)"
        ),
        parameters=PARAMETERS,
        compute=compute,
        model="closed form: Almen-Laszlo eq. (10) with analytic stationary points; capacity eqs. (13)-(14) corrected",
        validation=validation,
        outputs={
            "clamp_load": "N",
            "reserve_factor": "1",
            "torque_capacity": "N m",
            "load_peak": "N",
            "load_valley": "N",
            "deflection_operating": "m",
            "clamp_load_worn": "N",
            "torque_capacity_worn": "N m",
            "reserve_factor_worn": "1",
            "reserve_factor_least": "1",
        },
        # torque reserve against the peak release force the bearing must overcome (load at the hump A;
        # the clamp load itself is proportional to the reserve, no trade-off); paper 000 takes beta >= 1.2
        # the lining's state (new: uniform pressure; worn in: uniform wear) is a condition of its life
        # a robust study's default noise: the spring's sheet-thickness and cone-height
        # tolerances on the clamp load (±1.5 % and ±2 %, spring-steel strip and forming, assumed)
        noise={
            "sheet_thickness": {"scatter": "±1.5 %"},
            "cone_height_ratio": {"scatter": "±2 %"},
        },
        conditions=("max_engine_torque", "stack_mass", "friction_radius"),
        objectives=("reserve_factor:max", "load_peak:min"),
        # ... new and at the end of the wear allowance (the spring's operating point worn towards A)
        constraints={"reserve_factor": ("min", 1.2), "reserve_factor_worn": ("min", 1.2)},
        options=OPTIONS,
        valid_statuses=VALID_STATUSES,
        sources=SPRING_SOURCES,
        relations=RELATIONS,
    )
)
compute = STUDY.compute  # the status rule applied (clutchlab.studies.apply_valid_statuses)
