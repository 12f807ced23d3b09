"""Study "diaphragm_spring": Almen–László statics, clamp load and torque capacity (seed 000).

Inputs are the spring geometry (thickness h, cone-height ratio H/h, radius ratio R/r and the
load-point offsets), the release-bearing operating point factor λ_B/λ_C, and the lining and
friction data. Outputs: characteristic points A/C/D/B of eq. (10), clamp load at B, torque
capacity (eqs. 13–14 corrected), reserve factor and the load–deflection curve of each spring.

Model: closed form (eq. 10 is a cubic in λ; its stationary points are roots of a quadratic).
No solver is involved.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .. import diaphragm, driven_plate, engagement, friction
from .. import status as st
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
    """Almen-Laszlo arguments from the study parameters (h, H/h, R, R/r and load-point offsets)."""
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


def compute(inputs, options=None) -> xr.Dataset:
    """Compute the statics of a chunk of scenarios (see module docstring)."""
    options = options or {}
    assumption = options.get("friction_radius", "uniform_pressure")
    p = flat_inputs(inputs)
    spring = spring_geometry(p)
    r = spring["inner_radius"]
    pts = diaphragm.characteristic_points(
        **spring, operating_point_factor=p["operating_point_factor"]
    )
    code = pts["status"]
    capacity = friction.torque_capacity(
        pts["load_B"],
        p["friction_coefficient"],
        p["lining_outer_radius"],
        p["lining_inner_radius"],
        faces=p["friction_faces"],
        assumption=assumption,
        stack_mass=p["stack_mass"],
    )
    lining_bad = ~(p["lining_inner_radius"] < p["lining_outer_radius"])
    capacity = np.where(lining_bad, np.nan, capacity)
    code = np.where(lining_bad & (code == st.CODE["ok"]), st.CODE["invalid_geometry"], code).astype(
        st.DTYPE
    )

    lam_curve = pts["deflection_C"][:, None] * CURVE_POINTS[None, :]
    load_curve = diaphragm.almen_laszlo_load(
        lam_curve, **{k: v[:, None] for k, v in spring.items()}
    )

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
            friction.reserve_factor(capacity, p["max_engine_torque"]),
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
        "status": (
            run,
            code,
            st.attrs(
                "invalid_geometry: load points off the spring or lining R1 >= R2; "
                "monotone_no_hump: H/h <= sqrt(2); snap_through: valley load <= 0"
            ),
        ),
    }
    ds = xr.Dataset(
        data,
        coords={
            "deflection_ratio": (
                "deflection_ratio",
                CURVE_POINTS,
                _attrs("deflection over flat-point deflection, lambda/lambda_C", "1"),
            )
        },
    )
    return ds


# --- seed-000 validation rows (statics) ------------------------------------------------------

SEED = "000"
T_EMAX = 173.0  # N m, Table 1
#: τ and G of the damper springs are not printed in seed 000; 65Mn values assumed here.
DAMPER_ALLOWABLE_SHEAR = 400e6  # Pa
DAMPER_SHEAR_MODULUS = 79e9  # Pa


def seed_spring() -> dict:
    """The Almen–László parameter set of PHYSICS.md that gives F_B = 2500 N at λ_B = 0.9·λ_C.

    Seed 000 prints no spring dimensions; this is one set (of many) consistent with its 2500 N.
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
    """Seed-000 statics numbers reproduced by clutchlab, as validation rows."""
    pts = diaphragm.characteristic_points(**seed_spring(), operating_point_factor=0.9)
    Tj = driven_plate.damper_design_torque(T_EMAX)
    p_total = driven_plate.damper_total_force(Tj, 52 * MM)
    c_a = driven_plate.damper_angular_stiffness(Tj)
    rate = driven_plate.damper_spring_rate(c_a, 52 * MM, 4)
    d1 = driven_plate.damper_wire_diameter(
        driven_plate.damper_spring_force(p_total, 4), 15 * MM, DAMPER_ALLOWABLE_SHEAR
    )
    coils = driven_plate.damper_coil_count(DAMPER_SHEAR_MODULUS, d1, 15 * MM, rate)
    spline = dict(
        teeth=10, outer_diameter=35 * MM, inner_diameter=28 * MM, tooth_width=4 * MM, length=35 * MM
    )
    bearing, _ = driven_plate.spline_stresses(T_EMAX, **spline)
    _, shear = driven_plate.spline_stresses(Tj, **spline)
    ro, ri = 112.5 * MM, 75 * MM
    rows = [
        Row(
            SEED,
            "lining design constant A (eq. 3, D = 225 mm)",
            "Table 1-2, eq. (3)",
            34.17,
            float(friction.lining_coefficient(T_EMAX, 2 * ro)),
            "1",
            1e-3,
        ),
        Row(
            SEED,
            "damper total spring force P_total (eq. 4)",
            "Table 2",
            6654.0,
            float(p_total),
            "N",
            1e-3,
            "R1 = 52 mm inferred (not printed); Table 2 calls it 'single spring' (erratum)",
        ),
        Row(
            SEED,
            "damper angular stiffness C_a (eq. 7)",
            "Table 2",
            4498.0,
            float(c_a),
            "N m rad-1",
            1e-3,
        ),
        Row(
            SEED,
            "damper spring rate C (eq. 8)",
            "Table 2",
            415.9e3,
            float(rate),
            "N m-1",
            1e-3,
            "printed as 416 'N/m': the value is in N/mm (erratum)",
        ),
        Row(
            SEED,
            "damper coil count i (eqs. 6, 9)",
            "Table 2",
            6.0,
            float(coils),
            "1",
            0.05,
            "tau = 400 MPa, G = 79 GPa assumed (not printed); eq. 6 with cube root (erratum)",
        ),
        Row(
            SEED,
            "spline bearing stress at T_emax",
            "section 3.2.2",
            8.9e6,
            float(bearing),
            "Pa",
            0.01,
        ),
        Row(
            SEED,
            "spline shear stress",
            "section 3.2.2",
            15e6,
            float(shear),
            "Pa",
            0.05,
            "reached only with 2 T_emax = T_j = 346 N m (load not stated in the paper)",
        ),
        Row(
            SEED,
            "friction torque, eq. (14) as printed",
            "eq. (14), Fig. 11",
            239.3,
            float(friction.torque_capacity_eq14_as_printed(2500.0, 0.4, 4.757, ro, ri)),
            "N m",
            1e-3,
            "the paper's formula: one face, mu on the weight only; physically wrong (erratum)",
        ),
        Row(
            SEED,
            "capacity, 2 faces, uniform pressure, F = 2500 N",
            "eqs. (13)-(14) corrected",
            190.0,
            float(friction.torque_capacity(2500.0, 0.4, ro, ri)),
            "N m",
            1e-3,
        ),
        Row(
            SEED,
            "capacity as above + 4.757 kg stack weight",
            "eqs. (13)-(14) corrected",
            193.5,
            float(friction.torque_capacity(2500.0, 0.4, ro, ri, stack_mass=4.757)),
            "N m",
            1e-3,
            "Fig. 11's 250-256 N m is above the 225 N m ceiling at mu = 0.4, F = 2500 N",
        ),
        Row(
            SEED,
            "clamp load F_B at lambda_B = 0.9 lambda_C (eq. 10)",
            "section 5.1, Fig. 7",
            2500.0,
            float(pts["load_B"]),
            "N",
            5e-3,
            "spring dimensions not printed: E 206 GPa, nu 0.3, R/r/R1/r1 110/85/108/86 mm, h 2.334, H 3.50 mm",
        ),
    ]
    # engagement (eqs. 1-2, 11): engine held at 570 rad/s, capacity ramped 0 -> 239.3 N m (eq. 14 as
    # printed) over 0.15 s, load 44 N m, driven inertia 0.021 kg m² (inferred, not printed)
    seed_eng = dict(
        engine_speed=570.0,
        engine_inertia=np.inf,
        engine_torque=156.0,
        driven_inertia=0.021,
        load_torque=44.0,
        peak_capacity=239.3,
    )
    r = engagement.closed_form(**seed_eng, ramp_time=0.15)
    assumption = "engine held at 570 rad/s, J_v = 0.021 kg m2 inferred, linear ramp to 239.3 N m (eq. 14 as printed)"
    rows += [
        Row(
            SEED,
            "engagement: lock-up time",
            "section 5.2, Fig. 8",
            0.150,
            float(r["lockup_time"]),
            "s",
            0.01,
            assumption,
        ),
        Row(
            SEED,
            "engagement: driven speed at lock-up",
            "section 5.2, Fig. 8",
            570.0,
            float(r["lockup_speed"]),
            "rad s-1",
            1e-3,
        ),
        Row(
            SEED,
            "engagement: slip work (eq. 11)",
            "section 5.3, Fig. 9",
            5800.0,
            float(r["slip_work"]),
            "J",
            0.02,
        ),
    ]
    return to_dataset(rows, "seed 000: diaphragm spring, damper, spline, capacity, engagement")


STUDY = register(
    Study(
        name="diaphragm_spring",
        output="diaphragm/spring.h5",
        description="Diaphragm-spring statics: Almen-Laszlo curve, clamp load, torque capacity (seed 000)",
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
        },
        # torque reserve against the peak release force the bearing must overcome (load at the hump A;
        # the clamp load itself is proportional to the reserve, no trade-off); seed 000 takes beta >= 1.2
        # the lining's state (new: uniform pressure; worn in: uniform wear) is a condition of its life
        conditions=("max_engine_torque", "stack_mass", "friction_radius"),
        objectives=("reserve_factor:max", "load_peak:min"),
        constraints={"reserve_factor": ("min", 1.2)},
        options=OPTIONS,
        relations=RELATIONS,
    )
)
