"""Study "roller": roller-type controllable overrunning clutch (source paper 003).

Per scenario: the statics of eqs. (1)-(4) (computed torque, normal force, Hertz stress, spring
preload, self-locking margin) in closed form, then — only where the wedge can self-lock and the
working mode lets the driving direction lock — the wedging dynamics with stiff Hertz contact
(compiled DOP853/SDIRK4 with exact events): engagement time, backlash (total and its driving/wedge ring
part), peak dynamic contact force and stress against the static value, release time after the
control ring stops. A scenario whose peak dynamic contact stress exceeds 1.5 × the allowable
(``DYNAMIC_STRESS_FACTOR``) gets status ``dynamic_overstress``: the number is kept, but it is far
out (with the paper's contact damping the wedging impact gives 4-10 × the allowable over the
default grid) and such a design is not feasible. The engagement trace of the run's best design
(source paper 003, Fig. 7) is computed after the merge (:mod:`clutchlab.traces`).

Options: ``mode`` (bidirectional_lock, bidirectional_overrun, overrun_forward, overrun_reverse)
with the ``drive_direction`` parameter; ``stress_reading``: ``one_flank`` (z/2 rollers loaded in
either direction, the reading that reproduces the published 2865.5 MPa) or ``all`` (eq. 2 as
printed).

Assumed, not printed in the paper: K₁ + K₂, K₃ split (only the product 2.31 matters), inertias
J_w = 1e-5 and J_o = 1e-2 kg m² of the wedge and driven rings, penetration depth 0.1 mm (ADAMS'
usual value), engagement at 99 % of the driving speed, claw clearance 1 mm, control ring stopped
at 1 ms.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .. import roller as rl
from .. import status as st
from ..contact import hertz_stiffness
from ..published import ROLLER_CLUTCH
from . import Parameter, Relation, Study, flat_inputs, register, seed_design
from .diaphragm_spring import FRICTION_MAX

RPM = rl.RPM
PARAMETERS = (
    Parameter(
        "rollers",
        "1",
        "number of rollers z",
        12.0,
        minimum=2.0,
        minimum_inclusive=True,
        integer=True,
    ),
    Parameter(
        "wedge_angle",
        "rad",
        "wedge angle alpha",
        float(np.deg2rad(11.0)),
        maximum=np.pi / 2,
        maximum_inclusive=False,
    ),
    Parameter("roller_diameter", "m", "roller diameter d", 0.010),
    Parameter("roller_length", "m", "roller length b", 0.015),
    Parameter(
        "friction_coefficient",
        "1",
        "static friction coefficient mu_A (every contact)",
        0.12,
        maximum=FRICTION_MAX,
    ),
    Parameter("contact_radius", "m", "mean effective contact radius R_C", 0.150),
    Parameter("max_torque", "N m", "maximum transmitted torque T_i", 800.0),
    # service factors of drivetrains are 1 to about 3; 20 is past any
    Parameter("service_factor", "1", "K3 (K1 + K2) of eq. 1 (1848 / 800 N m)", 2.31, maximum=20.0),
    Parameter("rated_speed", "rad/s", "rated (driving ring) speed", 2000 * RPM),
    Parameter(
        "spring_force",
        "N",
        "spring preload per roller F_T",
        ROLLER_CLUTCH["spring_preload"].value,
        minimum_inclusive=True,
    ),
    Parameter("youngs_modulus", "Pa", "Young's modulus (GCr15)", 206e9),
    Parameter("poisson_ratio", "1", "Poisson's ratio", 0.3, maximum=0.5, maximum_inclusive=False),
    Parameter("density", "kg/m^3", "roller density", 7850.0),
    Parameter(
        "contact_allowable",
        "Pa",
        "allowable contact stress (lower end of 3041-3247 MPa)",
        ROLLER_CLUTCH["contact_allowable_min"].value * 1e6,
    ),
    Parameter("wedge_inertia", "kg m^2", "wedge ring inertia J_w (assumed)", 1e-5),
    Parameter("driven_inertia", "kg m^2", "driven ring inertia J_o (assumed)", 1e-2),
    Parameter(
        "contact_damping",
        "N s/m",
        "contact damping c_max (2.1e3 N s/mm)",
        2.1e6,
        minimum_inclusive=True,
    ),
    Parameter("penetration_depth", "m", "penetration depth of full damping (assumed)", 1e-4),
    Parameter(
        "sync_tolerance",
        "1",
        "engaged when the driven ring reaches (1 - this) x driving speed",
        0.01,
        maximum=1.0,
        maximum_inclusive=False,
    ),
    Parameter(
        "control_stop_time",
        "s",
        "time the control ring is stopped (release); inf: none",
        1e-3,
        allow_infinite=True,
    ),
    Parameter(
        "claw_clearance",
        "m",
        "free travel of the control-ring claws before they move the rollers (assumed)",
        1e-3,
        minimum_inclusive=True,
    ),
    Parameter("end_time", "s", "end of the simulation", 3e-3),
    Parameter(
        "drive_direction",
        "1",
        "driving direction (+1 forward, -1 reverse)",
        1.0,
        choices=(1.0, -1.0),
    ),
)

OPTIONS = {"mode": rl.MODES, "stress_reading": ("one_flank", "all")}

OUTPUTS = {
    "computed_torque": ("N m", "computed torque T_c = K3 (K1 + K2) T_i (eq. 1)"),
    "normal_force": ("N", "normal force per loaded roller N_A (eq. 2)"),
    "contact_stress": ("Pa", "Hertz contact stress roller / flat at T_c (eq. 3)"),
    "contact_stress_margin": ("1", "contact stress margin: allowable / contact stress - 1"),
    "self_locking_margin": ("1", "self-locking margin: mu / tan(alpha/2) - 1 (self-locks if > 0)"),
    "limit_wedge_angle": ("rad", "largest self-locking wedge angle 2 atan(mu)"),
    "roller_mass": ("kg", "mass of a solid roller"),
    "spring_preload": (
        "N",
        "spring force needed against friction of the roller's centrifugal force (eq. 4)",
    ),
    "spring_margin": ("1", "spring margin: F_T / needed spring force - 1"),
    "engagement_time": ("s", "wedging time: driven ring from rest to the engagement speed"),
    "backlash_angle": ("rad", "total backlash: driving minus driven ring rotation at engagement"),
    "backlash_angle_slip": ("rad", "driving-ring / wedge-ring part of the backlash"),
    "peak_contact_force": ("N", "peak dynamic contact force per loaded roller"),
    "peak_contact_stress": ("Pa", "Hertz stress at the peak dynamic contact force"),
    "dynamic_factor": ("1", "peak dynamic over static (eq. 2) contact force"),
    "release_time": ("s", "from stopping the control ring until the rollers are free"),
}
_DYNAMIC = (
    "engagement_time",
    "backlash_angle",
    "backlash_angle_slip",
    "peak_contact_force",
    "peak_contact_stress",
    "dynamic_factor",
    "release_time",
)

# the status rule (clutchlab.studies): the statics (eqs. 1-4) hold for every design, whether it
# self-locks, overruns in the commanded mode or its static stress is above the allowable; the
# wedging's numbers only for an engagement that happened (ok; above_allowable: the static stress
# check fails, the dynamics are exact; dynamic_overstress: kept and drawn). A wedging that never
# engaged (never_locked: not at the
# engagement speed before the control ring stopped or end_time) has no engagement time, backlash,
# dynamic factor or release of an engaged clutch, and its contact force peak over the window is
# not the peak of an engagement: NaN; not_converged: none
_STATICS = (
    "ok",
    "above_allowable",
    "dynamic_overstress",
    "never_locked",
    "not_converged",
    "not_self_locking",
    "overrunning",
)
VALID_STATUSES = {
    **{k: _STATICS for k in OUTPUTS if k not in _DYNAMIC},
    **{k: ("ok", "above_allowable", "dynamic_overstress") for k in _DYNAMIC},
}


# relations the statics and the wedging dynamics assume for every scenario (refused in a config)
RELATIONS = (
    Relation(
        ("rollers", "roller_diameter", "contact_radius"),
        ("max", "max", "min"),
        lambda rollers, roller_diameter, contact_radius: (
            rollers * roller_diameter < 2 * np.pi * contact_radius
        ),
        "the rollers fit around the contact circle (rollers x roller_diameter < 2 pi "
        "contact_radius)",
    ),
    Relation(
        ("penetration_depth", "roller_diameter"),
        ("max", "min"),
        lambda penetration_depth, roller_diameter: penetration_depth < roller_diameter / 2,
        "the contact's full-damping depth lies within the roller (penetration_depth < "
        "roller_diameter / 2)",
    ),
    Relation(
        ("control_stop_time", "end_time"),
        ("max_finite", "min"),
        lambda control_stop_time, end_time: control_stop_time < end_time,
        "the release is simulated (a finite control_stop_time before end_time; inf: no release)",
    ),
)


def check_config(section):
    """Refuse an odd roller count where the one-flank reading loads z/2 rollers per direction.

    Parameters
    ----------
    section : dict
        The resolved study section (:func:`clutchlab.config.resolve`).

    Returns
    -------
    (str, str) or None
        (config key, problem) of the first combination that cannot be read, or None.
    """
    readings = section.get("option_factors", {}).get(
        "stress_reading", [section["options"]["stress_reading"]]
    )
    if (
        "one_flank" not in readings
    ):  # (a reading drawn per scenario: any scenario may read one flank)
        return None
    key = "roller.parameters.rollers"
    z = section["fixed"].get("rollers")
    values = [z] if z is not None else section["factors"]["rollers"]["values"]
    odd = [v for v in values if v % 2]
    if odd:
        return (
            key,
            f"stress_reading one_flank loads z/2 rollers in each direction, so z must be even "
            f"(got {', '.join(f'{v:g}' for v in odd)}); use option stress_reading: all for an odd count",
        )
    return None


def statics(p, reading):
    """Closed-form statics of the roller clutch, equations (1)–(4) of the source paper (003).

    Parameters
    ----------
    p : dict of numpy.ndarray
        The study's parameters as flat arrays of one length [SI]
        (:func:`clutchlab.studies.flat_inputs`).
    reading : {"one_flank", "all"}
        Which rollers carry the torque (:func:`clutchlab.roller.loaded_rollers`).

    Returns
    -------
    dict of numpy.ndarray
        ``computed_torque`` [N m], ``normal_force`` [N], ``contact_stress`` [Pa],
        ``contact_stress_margin`` [-], ``self_locking_margin`` [-], ``limit_wedge_angle`` [rad],
        ``roller_mass`` [kg], ``spring_preload`` [N], ``spring_margin`` [-], ``loaded`` (the
        loaded rollers) [-] and ``rho`` (the equivalent radius) [m].

    References
    ----------
    Source paper (003), eqs. (1)–(4) and section 1.1.
    """
    tc = p["service_factor"] * p["max_torque"]
    zl = rl.loaded_rollers(p["rollers"], reading)
    na = rl.normal_force(
        tc,
        contact_radius=p["contact_radius"],
        friction_coefficient=p["friction_coefficient"],
        rollers=zl,
    )
    mat = dict(youngs_modulus=p["youngs_modulus"], poisson_ratio=p["poisson_ratio"])
    rho = rl.equivalent_radius(p["roller_diameter"])
    sigma = rl.contact_stress(na, roller_length=p["roller_length"], radius=rho, **mat)
    mass = rl.roller_mass(
        roller_diameter=p["roller_diameter"], roller_length=p["roller_length"], density=p["density"]
    )
    need = rl.spring_preload(
        roller_mass=mass,
        contact_radius=p["contact_radius"],
        friction_coefficient=p["friction_coefficient"],
        speed=p["rated_speed"],
    )
    return dict(
        computed_torque=tc,
        normal_force=na,
        contact_stress=sigma,
        contact_stress_margin=p["contact_allowable"] / sigma - 1.0,
        self_locking_margin=rl.self_locking_margin(
            wedge_angle=p["wedge_angle"], friction_coefficient=p["friction_coefficient"]
        ),
        limit_wedge_angle=rl.limit_wedge_angle(p["friction_coefficient"]),
        roller_mass=mass,
        spring_preload=need,
        spring_margin=p["spring_force"] / need - 1.0,
        loaded=zl,
        rho=rho,
    )


def dynamics_inputs(p, s):
    """Keyword arrays of :func:`clutchlab.roller.simulate` for scenarios ``p`` with statics ``s``.

    Parameters
    ----------
    p : dict of numpy.ndarray
        The study's parameters as flat arrays of one length [SI]
        (:func:`clutchlab.studies.flat_inputs`).
    s : dict of numpy.ndarray
        Their statics (:func:`statics`).

    Returns
    -------
    dict of numpy.ndarray
        The scenario arguments of :func:`clutchlab.roller.simulate` [SI]: the load torque is the
        computed torque, the contact stiffness Hertz's (:func:`clutchlab.contact.hertz_stiffness`).
    """
    return dict(
        driving_speed=p["rated_speed"],
        load_torque=s["computed_torque"],
        wedge_inertia=p["wedge_inertia"],
        driven_inertia=p["driven_inertia"],
        contact_radius=p["contact_radius"],
        rollers_loaded=s["loaded"],
        wedge_angle=p["wedge_angle"],
        friction_coefficient=p["friction_coefficient"],
        spring_force=p["spring_force"],
        stiffness=hertz_stiffness(
            roller_diameter=p["roller_diameter"],
            youngs_modulus=p["youngs_modulus"],
            poisson_ratio=p["poisson_ratio"],
        ),
        damping=p["contact_damping"],
        penetration_depth=p["penetration_depth"],
        control_stop_time=p["control_stop_time"],
        claw_clearance=p["claw_clearance"],
        end_time=p["end_time"],
        sync_tolerance=p["sync_tolerance"],
    )


# a peak dynamic contact stress above this multiple of the allowable is far out (status
# dynamic_overstress): the wedging impact, not the static load, decides the design there, and the
# number depends on the assumed contact damping and inertias
DYNAMIC_STRESS_FACTOR = 1.5
RTOL = 1e-8  # the wedging integrator's relative tolerance (clutchlab.roller.simulate's default)
SOLVER_STATS = {
    "n_steps": "integrator steps taken (accepted)",
    "n_rejected": "integrator steps rejected",
    "n_fev": "right-hand side evaluations",
    "n_newton_fail": "Newton failures (step cut)",
}


# statics every scenario must have numbers for (helpers give NaN where an input is invalid)
_STATICS = (
    "computed_torque",
    "normal_force",
    "contact_stress",
    "self_locking_margin",
    "limit_wedge_angle",
    "roller_mass",
    "spring_preload",
)


def _refused(p, s):
    """Status per scenario where the models refuse it, else ok: invalid_input where a static
    quantity has no number (an input not physical, finite or plausible); invalid_geometry where the
    rollers do not fit around the contact circle (z·d ≥ 2π·R_C) or the penetration depth of full
    damping is not below the roller diameter."""
    code = np.full(p["rollers"].size, st.CODE["ok"], st.DTYPE)
    with np.errstate(invalid="ignore"):
        fits = (p["rollers"] * p["roller_diameter"] < 2.0 * np.pi * p["contact_radius"]) & (
            p["penetration_depth"] < p["roller_diameter"]
        )
    code[~fits] = st.CODE["invalid_geometry"]
    missing = np.zeros(code.shape, bool)
    for k in _STATICS:
        missing |= ~np.isfinite(s[k])
    code[missing] = st.CODE["invalid_input"]
    return code


def compute(inputs, options=None) -> xr.Dataset:
    """Results of a chunk of scenarios of the study "roller".

    Per scenario: statics and, where the clutch can lock, the wedging dynamics.

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
    Source paper (003), eqs. (1)–(4) and section 3.
    """
    options = {k: v[0] for k, v in OPTIONS.items()} | (options or {})
    p = flat_inputs(inputs)
    s = statics(p, options["stress_reading"])
    refused = _refused(p, s)
    n = p["rollers"].size
    code = np.full(n, st.CODE["ok"], st.DTYPE)
    locks = s["self_locking_margin"] > 0.0
    engages = rl.engages(options["mode"], np.sign(p["drive_direction"]))
    run = locks & engages & (refused == st.CODE["ok"])
    dyn = {k: np.full(n, np.nan) for k in _DYNAMIC}
    stats = {k: np.zeros(n, np.int32) for k in SOLVER_STATS}  # 0 where not simulated
    if run.any():
        sim = rl.simulate(
            rtol=RTOL,
            **{k: np.broadcast_to(v, (n,))[run] for k, v in dynamics_inputs(p, s).items()},
        )
        dyn["engagement_time"][run] = sim["engagement_time"]
        dyn["backlash_angle"][run] = sim["backlash"]
        dyn["backlash_angle_slip"][run] = sim["slip_backlash"]
        dyn["peak_contact_force"][run] = sim["peak_contact_force"]
        dyn["release_time"][run] = sim["release_time"]
        code[run] = sim["status"]
        for k in SOLVER_STATS:
            stats[k][run] = sim[k]
    dyn["peak_contact_stress"] = rl.contact_stress(
        dyn["peak_contact_force"],
        roller_length=p["roller_length"],
        radius=s["rho"],
        youngs_modulus=p["youngs_modulus"],
        poisson_ratio=p["poisson_ratio"],
    )
    dyn["dynamic_factor"] = dyn["peak_contact_force"] / s["normal_force"]
    code[(code == st.CODE["ok"]) & (s["contact_stress_margin"] < 0)] = st.CODE["above_allowable"]
    with np.errstate(invalid="ignore"):
        far = dyn["peak_contact_stress"] > DYNAMIC_STRESS_FACTOR * p["contact_allowable"]
    code[(code == st.CODE["ok"]) & far] = st.CODE["dynamic_overstress"]
    code[locks & ~engages] = st.CODE["overrunning"]
    code[~locks] = st.CODE["not_self_locking"]
    code = np.where(refused != st.CODE["ok"], refused, code).astype(st.DTYPE)
    # a scenario a model refuses (here, or the wedging simulation) has no numbers
    bad = np.isin(code, [st.CODE["invalid_input"], st.CODE["invalid_geometry"]])
    values = {**{k: s[k] for k in OUTPUTS if k in s}, **dyn}
    data = {
        k: (
            "run",
            np.where(bad, np.nan, np.asarray(values[k], float)),
            {"units": u, "long_name": ln},
        )
        for k, (u, ln) in OUTPUTS.items()
    }
    data["status"] = (
        "run",
        code,
        st.attrs(
            "not_self_locking: tan(alpha/2) >= mu, never simulated; overrunning: the working mode lets this direction "
            "overrun (no engagement); above_allowable: static contact stress above the allowable; never_locked: "
            "not engaged before the control ring is stopped (control_stop_time) or by end_time; "
            "invalid_geometry: the rollers do not fit around the contact circle (z d >= 2 pi R_C) "
            "or the penetration depth is not below the roller diameter; invalid_input: an input "
            "not physical or implausible; "
            "dynamic_overstress: peak dynamic contact stress above "
            f"{DYNAMIC_STRESS_FACTOR:g} x the allowable (the wedging impact; its value depends on "
            "the assumed contact damping and inertias)"
        ),
    )
    for k, ln in SOLVER_STATS.items():
        data[k] = ("run", stats[k], {"long_name": ln + " (0: not simulated)", "units": "1"})
    ds = xr.Dataset(data)
    ds.attrs.update(
        rtol=RTOL,
        integrator="DOP853 (explicit, order 8); L-stable SDIRK4 where the contact is stiff; "
        "the stick phase before the engagement at rtol, the wedge ring's slip at 10 rtol and the "
        "phase after the engagement at 30 rtol (at most 1e-3)",
    )
    ds.attrs["model_used"] = (
        "statics closed form (eqs. 1-4, reading " + options["stress_reading"] + "); wedging: "
        "reduced 2-ring model, Hertz contact with IMPACT damping, DOP853/SDIRK4 with exact events; "
        "mode " + options["mode"]
    )
    return ds


def seed_trace(inputs, options) -> xr.Dataset:
    """Engagement (and release) trace of one design: the design a run's pages show.

    Like Figs. 7 and 9 of the source paper (003).

    Parameters
    ----------
    inputs : dict
        Parameter name -> value [SI]; the scalars override the defaults
        (:func:`clutchlab.studies.seed_design`).
    options : dict
        The study's options, complete (:data:`OPTIONS`).

    Returns
    -------
    xarray.Dataset
        Ring speeds and the contact force on dimension ``trace_time``, the stick, engagement and
        release times; empty where the wedge cannot self-lock.

    References
    ----------
    Source paper (003), Figs. 7 and 9.
    """
    p = {k: np.atleast_1d(v) for k, v in seed_design(PARAMETERS, inputs).items()}
    s = statics(p, options["stress_reading"])
    if s["self_locking_margin"][0] <= 0.0:
        return xr.Dataset()
    sim = rl.simulate(trace_index=0, max_step=2e-6, **dynamics_inputs(p, s))
    tr = sim["trace"]
    dim = "trace_time"
    coords = {dim: (dim, tr[:, 0], {"units": "s", "long_name": "time (trace of the design shown)"})}
    data = {}
    for j, (name, ln) in enumerate(
        (("driving", "driving ring"), ("wedge", "wedge ring"), ("driven", "driven ring")), start=1
    ):
        data[f"trace_{name}_speed"] = (
            dim,
            tr[:, j],
            {"units": "rad/s", "long_name": f"{ln} speed (design shown)"},
        )
    data["trace_contact_force"] = (
        dim,
        tr[:, 4],
        {"units": "N", "long_name": "contact force per loaded roller (design shown)"},
    )
    for k, name in (
        ("stick_time", "trace_stick_time"),
        ("engagement_time", "trace_engagement_time"),
        ("release_time", "trace_release_time"),
    ):
        data[name] = (
            (),
            float(sim[k][0]),
            {"units": "s", "long_name": name.replace("_", " ") + " (design shown)"},
        )
    data["trace_control_stop_time"] = (
        (),
        float(p["control_stop_time"][0]),
        {"units": "s", "long_name": "control ring stopped at (design shown)"},
    )
    return xr.Dataset(data, coords=coords)


def validation():
    """The source paper (003)'s numbers reproduced by clutchlab, as validation rows.

    :data:`clutchlab.published.ROLLER_CLUTCH`: section 2.2, Table 1 and sections 3.2–3.3.

    Returns
    -------
    xarray.Dataset
        Validation rows on dimension ``row`` (:func:`clutchlab.validation.to_dataset`): each
        published number, clutchlab's value, the relative error and its tolerance, and where the
        number is printed.
    """
    from ..validation import to_dataset

    d = {q.name: np.atleast_1d(q.default) for q in PARAMETERS}
    return to_dataset(
        _statics_rows(d) + _dynamics_rows(d),
        "paper 003: roller-type controllable overrunning clutch",
    )


def _statics_rows(d):
    """Computed torque, normal force, contact stress (both readings), spring and self-locking."""
    from ..validation import Row

    pub = ROLLER_CLUTCH
    one, every = statics(d, "one_flank"), statics(d, "all")
    tc = float(one["computed_torque"][0])
    na12 = rl.normal_force(tc, contact_radius=0.15, friction_coefficient=0.12, rollers=12)
    preload = dict(contact_radius=0.15, friction_coefficient=0.12, speed=2000 * RPM, formula="eq4")
    f_t = pub["spring_preload"].value
    mass_implied = f_t / float(rl.spring_preload(roller_mass=1.0, **preload))
    ft_implied = rl.spring_preload(roller_mass=mass_implied, **preload)
    sigma = pub["contact_stress"]
    return [
        Row.against(
            pub["computed_torque"], tc, 1e-3, "K3 (K1 + K2) = 2.31 (the factors are not printed)"
        ),
        Row.against(pub["normal_force"], na12, 1e-3),
        Row.against(
            sigma,
            float(one["contact_stress"][0]) / 1e6,
            1e-3,
            "clutchlab's reading: symmetric wedges, one flank locks per direction (N = 17111 N)",
            quantity="contact stress sigma_H, one flank loaded (z/2 = 6)",
        ),
        Row.against(
            sigma,
            float(every["contact_stress"][0]) / 1e6,
            1e-3,
            "flat wedge face, rho_v = d/2: a factor sqrt(2) below the published value",
            quantity="contact stress sigma_H, eq. 2 as printed (all 12 loaded)",
        ),
        Row.against(
            pub["spring_preload"],
            ft_implied,
            1e-3,
            f"implied roller mass {mass_implied * 1e3:.3f} g",
            quantity="spring preload F_T (eq. 4 as printed) with the mass it implies",
        ),
        Row.against(
            pub["spring_preload"],
            float(one["spring_preload"][0]),
            1e-3,
            f"solid roller {float(one['roller_mass'][0]) * 1e3:.2f} g: twice the mass "
            f"F_T = 3.7 N implies",
            quantity="spring preload for a solid 10 x 15 mm roller (eq. 4, exact pi)",
        ),
        Row.against(
            pub["self_locking_margin"],
            1.0 + float(one["self_locking_margin"][0]),
            5e-3,
            "published value rounded to 1.25; clutchlab's self_locking_margin is this ratio "
            "minus one",
            quantity="self-locking ratio mu / tan(alpha/2) at 11 deg (self_locking_margin + 1)",
        ),
        Row.against(pub["limit_wedge_angle"], float(np.rad2deg(one["limit_wedge_angle"][0])), 1e-3),
    ]


def _dynamics_rows(d):
    """The ADAMS engagement and release of sections 3.2-3.3: order checks."""
    from ..validation import Row

    pub = ROLLER_CLUTCH
    sim = rl.simulate(**dynamics_inputs(d, statics(d, "one_flank")))
    assumed = (
        "J_w 1e-5, J_o 1e-2 kg m2, c 2.1e3 N s/mm over 0.1 mm, 99 % of 2000 rpm (all but c assumed)"
    )
    return [
        Row.against(
            pub["engagement_time"],
            float(sim["engagement_time"][0]) * 1e3,
            0.5,
            "order check; " + assumed,
        ),
        Row.against(
            pub["backlash"],
            float(np.rad2deg(sim["backlash"][0])),
            0.5,
            "order check; same assumptions",
        ),
        Row.against(
            pub["slip_backlash"],
            float(np.rad2deg(sim["slip_backlash"][0])),
            0.5,
            "not reproduced: the wedge ring starts at rest and needs the wedging force to catch up",
        ),
        Row.against(
            pub["release_time"],
            float(sim["release_time"][0]) * 1e3,
            0.5,
            "not reproduced: here set by the claw clearance (1 mm assumed); the paper's 1.3 ms is "
            "the wedge ring's travel to the reverse wedge, whose geometry is not printed",
        ),
    ]


# where each parameter's default comes from (the reference pages show it)
SOURCES = {
    "rollers": "the source paper (003), Table 1",
    "wedge_angle": "the source paper (003), Table 1: 11 deg",
    "roller_diameter": "the source paper (003), Table 1",
    "roller_length": "the source paper (003), Table 1",
    "friction_coefficient": "the source paper (003), Table 1",
    "contact_radius": "the source paper (003), Table 1",
    "max_torque": "the source paper (003), section 2.2: T_c = 2.31 x 800 N m (eq. 1)",
    "service_factor": "the source paper (003), section 2.2: 1848 / 800 N m (eq. 1)",
    "rated_speed": "the source paper (003), section 3.1.2: the driving ring at 2000 rpm",
    "spring_force": "the source paper (003), Table 1",
    "youngs_modulus": (
        "assumed: GCr15 bearing steel (206 GPa); the source paper (003) names the steel, not "
        "its modulus"
    ),
    "poisson_ratio": "assumed: GCr15 bearing steel (0.3)",
    "density": "assumed: steel (7850 kg/m^3)",
    "contact_allowable": (
        "the source paper (003), section 2.2: 3041-3247 MPa for 10^6 wedging cycles (the lower end)"
    ),
    "wedge_inertia": "assumed: 1e-5 kg m^2; the source paper (003) prints no inertias",
    "driven_inertia": "assumed: 1e-2 kg m^2; the source paper (003) prints no inertias",
    "contact_damping": "the source paper (003), section 3.1.2: 2.1e3 N s/mm",
    "penetration_depth": "assumed: 0.1 mm, ADAMS' usual value for the IMPACT function",
    "sync_tolerance": "assumed: engaged at 99 % of the driving speed",
    "control_stop_time": (
        "assumed: the control ring stopped at 1 ms, after the source paper (003)'s 0.197 ms "
        "engagement (section 3.2)"
    ),
    "claw_clearance": "assumed: 1 mm free travel of the control-ring claws",
    "end_time": (
        "assumed: 3 ms, covering the engagement and the source paper (003)'s 1.3 ms release "
        "(section 3.3)"
    ),
    "drive_direction": (
        "assumed: the forward driving direction (+1) of the source paper (003)'s simulation "
        "(section 3.1.2)"
    ),
}

STUDY = register(
    Study(
        name="roller",
        output="roller/roller.h5",
        description=(
            "Roller-type controllable overrunning clutch:"
            " statics, self-locking, wedging dynamics (source paper 003)"
        ),
        parameters=PARAMETERS,
        compute=compute,
        traces=seed_trace,
        model="statics closed form (eqs. 1-4); wedging dynamics: Hertz contact with IMPACT damping, "
        "compiled DOP853/SDIRK4",
        validation=validation,
        options=OPTIONS,
        outputs={
            "contact_stress": "Pa",
            "engagement_time": "s",
            "self_locking_margin": "1",
            "spring_margin": "1",
            "peak_contact_stress": "Pa",
            "backlash_angle": "rad",
            "release_time": "s",
        },
        # paper 003: fast engagement at low contact stress; self-locking, sigma_H within the 3041 MPa
        # lower end of the allowable range, engaged within 1 ms
        # a robust study's default noise: friction ±20 % (self-locking of the wedge) and the
        # roller's diameter tolerance (±2 µm on 10 mm, a ground roller's grade, assumed)
        noise={
            "friction_coefficient": {"scatter": "±20 %"},
            "roller_diameter": {"scatter": "±0.02 %"},
        },
        conditions=(
            "max_torque",
            "service_factor",
            "rated_speed",
            "driven_inertia",
            "drive_direction",
            "mode",
        ),
        model_options=("stress_reading",),
        objectives=("engagement_time:min", "contact_stress:min"),
        constraints={
            "contact_stress": ("max", ROLLER_CLUTCH["contact_allowable_min"].value * 1e6),
            "self_locking_margin": ("min", 0.0),
            # assumed requirement: engaged within 0.5 ms (2.5x the paper's 0.197 ms); a wedging not
            # engaged when the control ring stops (1 ms in the default study) is never_locked
            "engagement_time": ("max", 0.5e-3),
        },
        check_config=check_config,
        valid_statuses=VALID_STATUSES,
        sources=SOURCES,
        relations=RELATIONS,
    )
)
compute = STUDY.compute  # the status rule applied (clutchlab.studies.apply_valid_statuses)
