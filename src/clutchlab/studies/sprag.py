"""Study "sprag": sprag clutch statics under a given or an impact torque (source paper 002).

Per scenario (no ODE): gripping angles V, W from the deflection fixed point (eq. 6 reconstructed),
Hertz contact stresses (eq. 7), shaft von Mises stresses (eq. 8), margins against the allowables and
a status. The torque is either a factor of the design (option ``torque_source: given``) or the peak
T(t₀) of the impact model (eqs. 1-5) over the impact parameters (``impact_peak``). The impact-torque
trace and the peak-torque trends of the source paper (002), Fig. 4, around the nominal impact
parameters are stored on their own dimensions for the report.

Option ``compliance``: ``physical`` uses the ``compliance_factor`` parameter (1 = physical
deflections); ``seed002_fit`` replaces it with the factor fitted to Table 2 at 750 N m
(:func:`clutchlab.sprag.fit_compliance_factor`, 1.7196 for the seed geometry).

Assumed, not printed in the paper: steel E = 206 GPa, ν = 0.3 for all parts; impact parameters
P₀ = 100 kW, C chosen so that √(P₀C) = 267.5 N m (the rated torque), J so that T₀ = 750 N m at
t₀ = 0.1 s from rest.
"""

from __future__ import annotations

import functools

import numpy as np
import xarray as xr

from .. import sprag as sp
from .. import status as st
from ..published import SPRAG_CLUTCH, SPRAG_TABLE2, SPRAG_TABLE2_SOURCE, SPRAG_TABLE2_UNITS
from . import Parameter, Relation, Study, flat_inputs, register, seed_design

MM = 1e-3
_G = sp.SEED_GEOMETRY
P0, TE, T0, RISE = 100e3, 267.5, 750.0, 0.1
C0 = TE**2 / P0
J0 = float(sp.inertia_for_peak(peak=T0, rise_time=RISE, power=P0, damping=C0))

PARAMETERS = (
    Parameter("torque", "N m", "torque transmitted by the clutch", 750.0),
    Parameter(
        "sprags",
        "1",
        "number of sprags n",
        _G["sprags"],
        minimum=1.0,
        minimum_inclusive=True,
        integer=True,
    ),
    Parameter("sprag_length", "m", "sprag (contact) length l", _G["sprag_length"]),
    Parameter(
        "centre_distance",
        "m",
        "distance Z between the centres of the sprag's arcs",
        _G["centre_distance"],
    ),
    Parameter(
        "sprag_inner_radius", "m", "radius r_i of the sprag's inner arc", _G["sprag_inner_radius"]
    ),
    Parameter(
        "sprag_outer_radius", "m", "radius r_o of the sprag's outer arc", _G["sprag_outer_radius"]
    ),
    Parameter(
        "inner_bore_radius",
        "m",
        "bore radius R_id of the inner shaft",
        _G["inner_bore_radius"],
        minimum_inclusive=True,
    ),
    Parameter("inner_race_radius", "m", "inner race radius R_i", _G["inner_race_radius"]),
    Parameter("outer_race_radius", "m", "outer race radius R_o", _G["outer_race_radius"]),
    Parameter(
        "outer_rim_radius", "m", "outer radius R_od of the outer race", _G["outer_rim_radius"]
    ),
    Parameter("youngs_modulus", "Pa", "Young's modulus of races and sprags (assumed)", 206e9),
    Parameter(
        "poisson_ratio",
        "1",
        "Poisson's ratio of races and sprags (assumed)",
        0.3,
        maximum=0.5,
        maximum_inclusive=False,
    ),
    Parameter(
        "compliance_factor",
        "1",
        "deflection multiplier (1 physical; fitted to Table 2: 1.72)",
        1.0,
        minimum=1e-6,  # (clutchlab.sprag's own lower end: a millionth of the races' deflection)
        minimum_inclusive=True,
        maximum=100.0,  # a hundredfold deflection: no longer the races' steel
    ),
    Parameter(
        "contact_allowable",
        "Pa",
        "allowable Hertz contact stress",
        SPRAG_CLUTCH["contact_allowable"].value * 1e6,
    ),
    Parameter(
        "shaft_allowable",
        "Pa",
        "allowable shaft von Mises stress",
        SPRAG_CLUTCH["shaft_allowable"].value * 1e6,
    ),
    Parameter(
        "gripping_angle_allowable",
        "rad",
        "allowable gripping angle V (pop-out beyond)",
        np.deg2rad(SPRAG_CLUTCH["gripping_angle_allowable"].value),
        maximum=np.pi / 2,
        maximum_inclusive=False,
    ),
    Parameter("impact_power", "W", "constant input power P0 of the starter turbine (assumed)", P0),
    Parameter("output_inertia", "kg m^2", "output-side inertia J_r (assumed)", J0),
    Parameter(
        "impact_damping",
        "N m s^2",
        "output quadratic damping C_t (assumed: sqrt(P0 C) = 267.5 N m)",
        C0,
    ),
    Parameter("initial_speed", "rad/s", "output initial speed w0", 0.0, minimum_inclusive=True),
    Parameter("rise_time", "s", "torque rise time t0 of the impact", RISE),
)

OPTIONS = {"compliance": ("physical", "seed002_fit"), "torque_source": ("given", "impact_peak")}


def _inside(inner, outer, what):
    return Relation(
        (inner, outer),
        ("max", "min"),
        lambda **v: v[inner] < v[outer],
        f"the radii are in order ({what}: {inner} < {outer})",
    )


# the races' radii in order from the bore out (eqs. 6-8 assume them); whether a sprag spans the
# races (0 < R_i + r_i - (R_o - r_o) < Z) is a question of its design: a status per scenario
RELATIONS = (
    _inside("inner_bore_radius", "inner_race_radius", "the inner shaft's bore inside its race"),
    _inside("inner_race_radius", "outer_race_radius", "the inner race inside the outer race"),
    _inside("outer_race_radius", "outer_rim_radius", "the outer race inside its rim"),
)

_GEOMETRY = tuple(sp.SEED_GEOMETRY) + ("youngs_modulus", "poisson_ratio")
_IMPACT = ("impact_power", "output_inertia", "impact_damping", "initial_speed")

OUTPUTS = {
    "torque_applied": ("N m", "torque on the clutch (given, or the impact peak T(t0))"),
    "gripping_angle": ("rad", "gripping angle V at the inner contact (eq. 6, with deflection)"),
    "gripping_angle_outer": ("rad", "gripping angle W at the outer contact"),
    "central_angle": ("rad", "angle psi between the contact radii (V = W + psi)"),
    "contact_stress_inner": ("Pa", "Hertz contact stress sprag / inner race (eq. 7)"),
    "contact_stress_outer": ("Pa", "Hertz contact stress sprag / outer race (eq. 7)"),
    "vm_stress_inner": ("Pa", "maximum von Mises stress of the inner shaft (eq. 8)"),
    "vm_stress_outer": ("Pa", "maximum von Mises stress of the outer race (eq. 8)"),
}
CHECKS = ("contact_inner", "contact_outer", "vm_inner", "vm_outer", "gripping_angle")
# the status rule (clutchlab.studies): a design above an allowable (above_allowable, pop_out_risk)
# has exact angles, stresses and margins — the margin says by how much it fails; a sprag that does
# not span the races, rolls over or whose fixed point did not converge has none; the torque applied
# and the compliance used are what they are, but for a refused input (invalid_input,
# invalid_geometry: no number at all); the pass flags (integers) say 0 where not passed
_CHECKED = ("ok", "above_allowable", "pop_out_risk")
_GIVEN = _CHECKED + ("roll_over", "not_converged")
VALID_STATUSES = {
    **{k: _CHECKED for k in OUTPUTS if k != "torque_applied"},
    **{f"margin_{c}": _CHECKED for c in CHECKS},
    "torque_applied": _GIVEN,
    "compliance_factor_used": _GIVEN,
}


@functools.lru_cache(maxsize=1)
def seed_compliance() -> float:
    """Compliance factor fitted to the source paper (002)'s Table 2.

    V = 5.097° at 750 N·m with the paper's geometry (:func:`clutchlab.sprag.fit_compliance_factor`).

    Returns
    -------
    float [-]
        The factor.
    """
    peak = SPRAG_TABLE2[750.0]
    return float(
        sp.fit_compliance_factor(
            torque=peak.torque, gripping_angle_target=np.deg2rad(peak.gripping_angle)
        )
    )


GRIP_TOL = 1e-12  # rad: clutchlab.sprag.gripping_angle's bracket width at convergence (its default)


def compute(inputs, options=None) -> xr.Dataset:
    """Results of a chunk of scenarios of the study "sprag".

    Per scenario: gripping angles, contact and shaft stresses and margins under a given or impact
    torque.

    Parameters
    ----------
    inputs : dict
        Parameter name -> flat array (one entry per scenario of the chunk) or scalar, in SI units
        (:data:`PARAMETERS`).
    options : dict or None
        The study's options (:data:`OPTIONS`); a missing one takes its first
        choice.

    Returns
    -------
    xarray.Dataset
        One entry per scenario on dimension ``run`` (curves with a further dimension): the outputs
        of the module docstring, each with ``units`` and ``long_name``, and ``status``
        (:mod:`clutchlab.status`). The registered ``compute`` (:func:`clutchlab.studies.get`) also
        applies the status rule (:func:`clutchlab.studies.apply_valid_statuses`).

    References
    ----------
    Source paper (002), eqs. (1)–(8) and Tables 1–2.
    """
    options = {k: v[0] for k, v in OPTIONS.items()} | (options or {})
    p = flat_inputs(inputs)
    c = (
        np.full_like(p["torque"], seed_compliance())
        if options["compliance"] == "seed002_fit"
        else p["compliance_factor"]
    )
    if options["torque_source"] == "impact_peak":
        torque = sp.peak_torque(rise_time=p["rise_time"], **{_k(k): p[k] for k in _IMPACT})
    else:
        torque = p["torque"]
    res = sp.statics(
        torque,
        compliance_factor=c,
        contact_allowable=p["contact_allowable"],
        shaft_allowable=p["shaft_allowable"],
        gripping_angle_allowable=p["gripping_angle_allowable"],
        **{k: p[k] for k in _GEOMETRY},
    )
    res["torque_applied"] = torque
    names = {"gripping_angle": "V", "gripping_angle_outer": "W", "central_angle": "psi"}
    data = {
        k: ("run", res[names.get(k, k)], {"units": u, "long_name": ln})
        for k, (u, ln) in OUTPUTS.items()
    }
    passed = np.ones(torque.shape, bool)
    for name in CHECKS:
        label = name.replace("_", " ")
        data[f"margin_{name}"] = (
            "run",
            res[f"margin_{name}"],
            {"units": "1", "long_name": f"margin of safety {label}: allowable/value - 1"},
        )
        ok = res[f"margin_{name}"] >= 0
        data[f"pass_{name}"] = (
            "run",
            ok.astype(np.int8),
            {"units": "1", "long_name": f"{label} check passed (1) or not (0)"},
        )
        passed &= ok
    data["passes_all"] = (
        "run",
        passed.astype(np.int8),
        {"units": "1", "long_name": "1 if every allowable (contact, shaft, gripping angle) is met"},
    )
    data["compliance_factor_used"] = (
        "run",
        np.broadcast_to(c, torque.shape).copy(),
        {"units": "1", "long_name": "deflection multiplier used (1 physical)"},
    )
    data["status"] = (
        "run",
        res["status"],
        st.attrs(
            "invalid_geometry: the sprag does not span the races; roll_over: loaded races open past the sprag's "
            "reach; pop_out_risk: V above its allowable; above_allowable: a stress above its allowable"
        ),
    )
    data["n_iterations"] = (
        "run",
        np.asarray(res["n_iterations"], np.int32),
        {
            "units": "1",
            "long_name": "fixed-point bracketing steps taken (Illinois regula falsi; 0: not solved)",
        },
    )
    ds = xr.Dataset(data)
    ds.attrs.update(
        fixed_point_tolerance=GRIP_TOL, fixed_point_tolerance_units="rad (final bracket width of V)"
    )
    ds.attrs["model_used"] = (
        f"closed-form statics with deflection fixed point (compliance {options['compliance']}); "
        f"torque {options['torque_source']}"
    )
    return ds


def _k(name):
    return {"impact_power": "power", "output_inertia": "inertia", "impact_damping": "damping"}.get(
        name, name
    )


def impact_curves(inputs, options=None) -> xr.Dataset:
    """Impact torque after its peak, and the peak against each impact parameter (source paper 002).

    T(t) after the rise time, and the peak T₀ against P₀, J, C, ω₀ one at a time around the
    nominal impact parameters.

    Parameters
    ----------
    inputs : dict
        Parameter name -> value [SI]; the scalars override the defaults
        (:func:`clutchlab.studies.seed_design`).
    options : dict or None
        Unused (the curves do not depend on the study's options).

    Returns
    -------
    xarray.Dataset
        ``impact_torque`` on ``impact_time``, ``impact_steady_torque``, and
        ``peak_torque_vs_<parameter>`` on a sweep dimension of each parameter [N m].

    References
    ----------
    Source paper (002), eqs. (1)–(5) and Fig. 4.
    """
    nom = seed_design(PARAMETERS, inputs)
    imp = {_k(k): nom[k] for k in _IMPACT}
    t0 = nom["rise_time"]
    te = float(sp.steady_torque(power=imp["power"], damping=imp["damping"]))
    w_ss = imp["power"] / te
    t = t0 + np.linspace(0.0, 3.0, 151) * imp["inertia"] / (2 * imp["damping"])
    coords = {
        "impact_time": (
            "impact_time",
            t,
            {"units": "s", "long_name": "time after the start of the impact"},
        )
    }
    data = {
        "impact_torque": (
            "impact_time",
            sp.impact_torque(t, **imp),
            {
                "units": "N m",
                "long_name": "clutch torque T(t) after the rise time (nominal impact, eqs. 4-5)",
            },
        ),
        "impact_steady_torque": ((), te, {"units": "N m", "long_name": "steady torque sqrt(P0 C)"}),
    }
    sweeps = {
        "impact_power": (np.linspace(0.5, 1.5, 21) * imp["power"], "W"),
        "output_inertia": (np.linspace(0.5, 1.5, 21) * imp["inertia"], "kg m^2"),
        "impact_damping": (np.linspace(0.5, 1.5, 21) * imp["damping"], "N m s^2"),
        "initial_speed": (np.linspace(0.0, 0.8, 21) * w_ss, "rad/s"),
    }
    for name, (values, units) in sweeps.items():
        dim = f"sweep_{name}"
        coords[dim] = (
            dim,
            values,
            {"units": units, "long_name": f"{name.replace('_', ' ')} (sweep, others nominal)"},
        )
        data[f"peak_torque_vs_{name}"] = (
            dim,
            sp.peak_torque(rise_time=t0, **{**imp, _k(name): values}),
            {
                "units": "N m",
                "long_name": f"peak torque T0 = T(t0) against {name.replace('_', ' ')} (Fig. 4)",
            },
        )
    return xr.Dataset(data, coords=coords)


#: The Table 2 quantities: (field of :class:`clutchlab.published.SpragTheory`, row label).
TABLE2_LABELS = {
    "gripping_angle": "gripping angle V",
    "contact_stress_inner": "contact stress inner",
    "contact_stress_outer": "contact stress outer",
    "vm_stress_inner": "shaft von Mises inner",
    "vm_stress_outer": "shaft von Mises outer",
}


def validation():
    """The source paper (002)'s Table 2 (theory column) reproduced three ways, as validation rows.

    :data:`clutchlab.published.SPRAG_TABLE2`, fed with the published V, with physical deflection
    (compliance 1), and with the compliance factor fitted at 750 N·m.

    Returns
    -------
    xarray.Dataset
        Validation rows on dimension ``row`` (:func:`clutchlab.validation.to_dataset`): each
        published number, clutchlab's value, the relative error and its tolerance, and where the
        number is printed.
    """
    from ..validation import to_dataset

    rows = _fed_published_angle_rows()
    fit = seed_compliance()
    rows += _statics_rows(1.0, "physical deflection", 0.15)
    rows += _statics_rows(fit, f"compliance fitted at 750 N m ({fit:.4f})", 0.01)
    return to_dataset(rows, "paper 002: sprag clutch statics (Table 2)")


def _table2_row(pub, field, computed, tag, tolerance, note=""):
    """The validation row of the Table 2 number ``field`` of ``pub`` (a SpragTheory)."""
    from ..validation import Row

    return Row(
        "002",
        f"{TABLE2_LABELS[field]} at {pub.torque:g} N m, {tag}",
        SPRAG_TABLE2_SOURCE,
        getattr(pub, field),
        float(computed),
        SPRAG_TABLE2_UNITS[field],
        tolerance,
        note,
    )


def _fed_published_angle_rows():
    """Eqs. 7-8 on the rest radii with V from the table."""
    rows = []
    for t, pub in SPRAG_TABLE2.items():
        v = np.deg2rad(pub.gripping_angle)
        w = np.arcsin(_G["inner_race_radius"] * np.sin(v) / _G["outer_race_radius"])
        ci, co = sp.contact_stress(t, V=v, W=w, **_G, **sp.STEEL)
        vm = sp.shaft_stress(t, V=v, W=w, **_G)
        computed = dict(
            contact_stress_inner=ci,
            contact_stress_outer=co,
            vm_stress_inner=vm["inner"],
            vm_stress_outer=vm["outer"],
        )
        for field, value in computed.items():
            note = "eqs. 7-8 on rest radii with V from the table"
            rows.append(_table2_row(pub, field, value / 1e6, "fed the published V", 0.03, note))
    return rows


def _statics_rows(compliance, tag, tolerance):
    """Every Table 2 number from the statics with the deflection multiplied by ``compliance``."""
    rows = []
    for t, pub in SPRAG_TABLE2.items():
        r = sp.statics(t, compliance_factor=compliance)
        computed = dict(
            gripping_angle=np.rad2deg(r["V"]),
            contact_stress_inner=r["contact_stress_inner"] / 1e6,
            contact_stress_outer=r["contact_stress_outer"] / 1e6,
            vm_stress_inner=r["vm_stress_inner"] / 1e6,
            vm_stress_outer=r["vm_stress_outer"] / 1e6,
        )
        for field in TABLE2_LABELS:
            note, tol = "", tolerance
            if field == "gripping_angle" and compliance == 1.0:
                note = "Lame races + Palmgren contact approach, E 206 GPa: V low, stresses high"
            elif field == "gripping_angle":
                note = "the fit target" if t == 750.0 else "prediction; tolerance 0.05 deg"
                tol = 1e-9 if t == 750.0 else 0.05 / pub.gripping_angle
            rows.append(_table2_row(pub, field, computed[field], tag, tol, note))
    return rows


# where each parameter's default comes from (the reference pages show it)
SOURCES = {
    "torque": "the source paper (002), Table 2: peak torque 750 N m",
    "sprags": "the source paper (002), Table 1",
    "sprag_length": "the source paper (002), Table 1",
    "centre_distance": "the source paper (002), Table 1",
    "sprag_inner_radius": "the source paper (002), Table 1",
    "sprag_outer_radius": "the source paper (002), Table 1",
    "inner_bore_radius": "the source paper (002), Table 1",
    "inner_race_radius": "the source paper (002), Table 1",
    "outer_race_radius": "the source paper (002), Table 1",
    "outer_rim_radius": "the source paper (002), Table 1",
    "youngs_modulus": "assumed: bearing steel (206 GPa); the source paper (002) prints no modulus",
    "poisson_ratio": "assumed: steel (0.3); the source paper (002) prints none",
    "compliance_factor": (
        "model choice: 1 is the physical deflection; the fit to the source paper (002)'s "
        "Table 2 at 750 N m (1.72) is option compliance: seed002_fit"
    ),
    "contact_allowable": "the source paper (002), Table 2 (allowable)",
    "shaft_allowable": "the source paper (002), Table 2 (allowable)",
    "gripping_angle_allowable": "the source paper (002), Table 2 (allowable), section 2.2",
    "impact_power": "assumed: 100 kW starter turbine; the source paper (002) prints no power",
    "output_inertia": (
        "assumed: chosen so that the impact torque reaches 750 N m at t0 = 0.1 s from rest "
        "(the source paper (002), eqs. 1-5, Table 2)"
    ),
    "impact_damping": (
        "assumed: chosen so that sqrt(P0 C) equals the rated 267.5 N m (the source paper "
        "(002), eqs. 1-5)"
    ),
    "initial_speed": "assumed: the output starts from rest",
    "rise_time": (
        "assumed: 0.1 s, the finite rise time the source paper (002)'s impact model needs "
        "(T(0) is infinite from rest)"
    ),
}

STUDY = register(
    Study(
        name="sprag",
        output="sprag/sprag.h5",
        description=(
            "Sprag clutch:"
            " gripping angle with deflection, contact and shaft stresses, impact torque (source paper 002)"
        ),
        parameters=PARAMETERS,
        compute=compute,
        traces=impact_curves,
        model=(
            "closed-form statics (eqs. 6-8) with a vectorised deflection fixed point; impact torque "
            "eqs. 1-5 closed form"
        ),
        validation=validation,
        outputs={
            "margin_contact_inner": "1",
            "margin_contact_outer": "1",
            "margin_vm_inner": "1",
            "margin_vm_outer": "1",
            "margin_gripping_angle": "1",
            "gripping_angle": "rad",
            "contact_stress_inner": "Pa",
        },
        # paper 002 Table 2: every allowable met (margins >= 0); the largest contact and grip margins
        # a robust study's default noise: manufacturing tolerances of the sprag geometry
        # (±0.1 % of the arc radii and the centre distance, about ±10 µm: ground sprags, assumed)
        noise={
            "sprag_inner_radius": {"scatter": "±0.1 %"},
            "sprag_outer_radius": {"scatter": "±0.1 %"},
            "centre_distance": {"scatter": "±0.1 %"},
        },
        conditions=(
            "torque",
            "impact_power",
            "output_inertia",
            "impact_damping",
            "initial_speed",
            "rise_time",
        ),
        model_options=("compliance", "torque_source"),
        objectives=("margin_contact_inner:max", "margin_gripping_angle:max"),
        constraints={
            f"margin_{c}": ("min", 0.0)
            for c in ("contact_inner", "contact_outer", "vm_inner", "vm_outer", "gripping_angle")
        },
        options=OPTIONS,
        valid_statuses=VALID_STATUSES,
        sources=SOURCES,
        relations=RELATIONS,
    )
)
compute = STUDY.compute  # the status rule applied (clutchlab.studies.apply_valid_statuses)
