"""Study "engagement": spring design -> clamp force -> capacity -> engagement (source paper 000).

The diaphragm spring's clamp load at its operating point (eq. 10) and the friction capacity
(eqs. 13-14 corrected) set the peak clutch torque; the clamp force rises to it along a profile
over the ramp (engagement) time; the two-inertia engagement (eqs. 1-2) then gives lock-up time,
slip work (eq. 11) and, with the compliant driveline (damper springs between plate hub and
output), the output jerk (eq. 12).

Clamp force through the release-bearing travel: the profile is the bearing's travel; the plate
lifts (1 − p)·(g + c) (air gap g, lining cushion travel c) and the clamp force is the cushion's,
F_B·max(0, 1 − κ(1 − p)) with κ = (g + c)/c (g = 0: the profile itself); the diaphragm curve gives
F_B and the release-bearing force over the travel (``peak_bearing_force``).

Over the clutch's life (:mod:`clutchlab.wear`, docs/wear.md): the clutch is engaged again with
the lining worn by half and by all of ``wear_allowance`` (the clamp load at λ_B − Δ/2 and λ_B − Δ
on the spring's curve, the same model as the first engagement); the lining wear per engagement
q_V·W/A of each gives the life in engagements (Simpson's rule over the three), their heat the
largest engagement rate the cooling allows. A scenario whose first engagement is ok but whose worn
one does not lock has status ``worn_not_locked``.

Model choice (recorded in the ``model_used`` attribute of the result): option ``driveline``
``compliant`` (default: needed for the output jerk of the efficiency-smoothness trade-off) or
``rigid``; a rigid driveline with constant μ, no rotor drag and a held engine uses the closed
form, anything else the event-driven solver of :func:`clutchlab.engagement.simulate`, which solves
the compliant driveline's linear phases (constant μ, no rotor drag, a held engine or one with
constant torque) in closed form and integrates the others with DOPRI5.

Accuracy: the study key ``accuracy`` (relative, default 1e-6) is what lock-up time, slip work and
peak jerk need; the integrated phases then run at rtol = accuracy/10, atol = accuracy/10³
(calibrated against scipy DOP853 at rtol 1e-13 on 40 random Stribeck designs, accuracy 1e-7 to
1e-3: the largest jerk error is 0.41 × the accuracy, lock-up time and slip work errors below
0.01 ×; the compliant model controls the error of the twist rate, of which the jerk is made).
The result records accuracy, rtol and atol. ``end_time`` bounds the search for lock-up; a lock-up
found is followed past it until its metrics are final (status ``truncated`` where an event after
the window would change them).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .. import diaphragm, engagement, friction, heat, wear
from .. import status as st
from ..engagement._fade import SOE_TMAX
from ..published import DIAPHRAGM_CLUTCH
from ..validation import Row, to_dataset
from . import (
    Parameter,
    Relation,
    Study,
    flat_inputs,
    register,
    seed_design,
    units_metadata,
    value_range,
)
from .diaphragm_spring import PARAMETERS as SPRING_PARAMETERS
from .diaphragm_spring import RELATIONS as SPRING_RELATIONS
from .diaphragm_spring import SPRING_SOURCES, spring_geometry

PARAMETERS = SPRING_PARAMETERS + (
    Parameter("ramp_time", "s", "clamp force rise (engagement) time", 0.15, minimum_inclusive=True),
    Parameter("engine_speed", "rad/s", "engine speed at the start of engagement", 570.0),
    Parameter(
        "engine_inertia",
        "kg m^2",
        "engine-side inertia (inf: engine held at its speed)",
        np.inf,
        allow_infinite=True,
    ),
    Parameter("engine_torque", "N m", "engine torque (free engine)", 156.0, minimum=None),
    Parameter("driven_inertia", "kg m^2", "driven-side inertia (plate hub + output)", 0.021),
    Parameter(
        "load_torque",
        "N m",
        "load torque (static while the output is at rest)",
        44.0,
        minimum_inclusive=True,
    ),
    Parameter(
        "aero_coefficient",
        "N m s^2",
        "rotor drag coefficient k in k*omega^2",
        0.0,
        minimum_inclusive=True,
    ),
    Parameter(
        "static_ratio",
        "1",
        "static over kinetic friction coefficient",
        1.0,
        minimum=1.0,
        minimum_inclusive=True,
        maximum=10.0,  # measured pairs: 1 to about 1.5
    ),
    Parameter(
        "stribeck_speed",
        "rad/s",
        "Stribeck slip speed v_s (inf: constant kinetic mu)",
        np.inf,
        allow_infinite=True,
    ),
    Parameter(
        "hub_fraction",
        "1",
        "share of the driven inertia on the plate hub (compliant driveline)",
        0.5,
        maximum=1.0,
        maximum_inclusive=False,
    ),
    Parameter(
        "damper_stiffness", "N m/rad", "damper angular stiffness C_a between hub and output", 4498.0
    ),
    Parameter(
        "damping_ratio",
        "1",
        "damping ratio of the hub-output mode",
        0.05,
        minimum_inclusive=True,
        maximum=100.0,  # (1: critical damping; 100 is a damper that no longer springs)
    ),
    Parameter(
        "air_gap",
        "m",
        "pressure-plate travel before the lining cushion is touched (release-bearing model)",
        0.0,
        minimum_inclusive=True,
    ),
    Parameter("cushion_travel", "m", "lining cushion travel at full clamp (assumed)", 0.6e-3),
    Parameter(
        "lever_ratio",
        "1",
        "finger lever ratio: bearing travel over plate lift (assumed)",
        4.0,
        maximum=100.0,  # (diaphragm fingers: 3 to 5)
    ),
    Parameter(
        "end_time",
        "s",
        "end of the window searched for lock-up (a lock-up found is followed to its final metrics)",
        0.5,
    ),
    # heat (clutchlab.heat): masses of paper 000 Table 3; the rest assumed (see heat.engagement_heat)
    Parameter("flywheel_mass", "kg", "flywheel mass (source paper 000, Table 3)", 10.3),
    Parameter("pressure_plate_mass", "kg", "pressure plate mass (source paper 000, Table 3)", 2.5),
    Parameter("driven_plate_mass", "kg", "driven plate mass (source paper 000, Table 3)", 1.9),
    Parameter(
        "intermediate_plate_mass",
        "kg",
        "mass of each intermediate (centre) plate of a multi-plate clutch, friction_faces > 2 "
        "(assumed: the pressure plate's 2.5 kg)",
        2.5,
    ),
    Parameter(
        "heat_transfer_coefficient",
        "W/(m^2*K)",
        "convective heat transfer coefficient between engagements (assumed)",
        40.0,
    ),
    Parameter(
        "cooling_area", "m^2", "cooled area of the hottest part (assumed: both sides and rim)", 0.1
    ),
    Parameter(
        "engagement_interval",
        "s",
        "time between engagements in a row (assumed: a retried start)",
        60.0,
    ),
    Parameter(
        "ambient_temperature",
        "K",
        "air in the clutch housing, and the parts before the first engagement (assumed: 40 C)",
        313.15,
        kind="absolute",
    ),
    Parameter(
        "temperature_limit",
        "K",
        "material limit of the hottest part's bulk temperature (assumed: 250 C, organic linings)",
        523.15,
        kind="absolute",
    ),
    # lining wear per engagement (clutchlab.wear): worn volume = q_V x friction work, VDI 2241
    Parameter(
        "specific_wear_rate",
        "m^3/J",
        "specific wear rate q_V of the lining, worn volume per friction work (assumed: "
        "0.2 cm^3/kWh, a resin-bonded dry lining; VDI 2241)",
        wear.SPECIFIC_WEAR_RATE,
    ),
    # friction fade (off by default): mu_k / (1 + beta (T_face - T_onset)+) while slipping
    Parameter(
        "fade_coefficient",
        "1/K",
        "friction fade beta: kinetic mu divided by 1 + beta*(T_face - "
        "fade_onset_temperature) above the onset (0: no fade)",
        0.0,
        minimum_inclusive=True,
    ),
    Parameter(
        "fade_onset_temperature",
        "K",
        "friction-face temperature at which fade begins (assumed: 200 C, "
        "organic linings; not below ambient_temperature)",
        473.15,
        kind="absolute",
    ),
)

PARAMETER_DEFAULTS = {q.name: q.default for q in PARAMETERS}
ACCURACY = 1e-6  # default relative accuracy of lock-up time, slip work and peak jerk

OPTIONS = {
    "driveline": ("compliant", "rigid"),
    "profile": engagement.PROFILES,
    "capacity_formula": ("corrected", "eq14_as_printed"),
}

OUTPUTS = {
    "clamp_load": ("N", "clamp load at the spring operating point B (eq. 10)"),
    "peak_capacity": ("N m", "kinetic torque capacity at full clamp"),
    "lockup_time": ("s", "lock-up time (last transition to stuck)"),
    "lockup_speed": ("rad/s", "driven (hub) speed at lock-up"),
    "slip_work": ("J", "slip (friction) work, eq. 11"),
    "peak_slip_power": ("W", "peak slip power"),
    "peak_friction_torque": ("N m", "peak transmitted clutch torque"),
    "clamp_force_at_lockup": ("N", "clamp force at lock-up"),
    "accel_jump": ("rad/s^2", "driven (rigid) or hub (compliant) acceleration jump at lock-up"),
    "peak_jerk": (
        "rad/s^3",
        "peak output jerk (compliant: from the model equations; rigid: slip phase only)",
    ),
    "energy_residual": (
        "1",
        "input work - kinetic/elastic energy change - slip, load, damping work, relative",
    ),
    "peak_bearing_force": (
        "N",
        "largest release-bearing force over the release travel (diaphragm curve, eq. 10)",
    ),
    "specific_friction_work": ("J/m^2", "slip work per friction area (all faces)"),
    "peak_specific_friction_power": ("W/m^2", "peak slip power per friction area (all faces)"),
    "heat_flywheel": ("J", "friction heat into the flywheel (effusivity partition)"),
    "heat_pressure_plate": ("J", "friction heat into the pressure plate (effusivity partition)"),
    "heat_driven_plate": (
        "J",
        "friction heat into each driven plate (its linings; friction_faces/2 plates)",
    ),
    "heat_intermediate_plate": (
        "J",
        "friction heat into each intermediate plate (friction_faces/2 - 1 plates; 0 with two "
        "faces)",
    ),
    "bulk_temperature_rise": ("K", "lumped temperature rise of the hottest part in one engagement"),
    "peak_surface_temperature": (
        "K",
        "peak friction-face (flash) temperature of flywheel and pressure plate in one "
        "engagement from ambient (Duhamel's integral of the slip power history)",
    ),
    "engagements_to_limit": (
        "1",
        "engagements in a row until the hottest part's bulk temperature reaches "
        "temperature_limit (inf: never)",
    ),
    "clamp_load_worn": ("N", "clamp load at the full wear allowance (eq. 10 at lambda_B - wear)"),
    "peak_capacity_worn": ("N m", "kinetic torque capacity at the full wear allowance"),
    "lockup_time_worn": ("s", "lock-up time of the last engagement (full wear allowance)"),
    "slip_work_worn": ("J", "slip work of the last engagement (full wear allowance)"),
    "wear_per_engagement": (
        "m",
        "lining wear of the first engagement, all faces together (q_V x slip work / face area)",
    ),
    "wear_per_engagement_worn": (
        "m",
        "lining wear of the last engagement (full wear allowance), all faces together",
    ),
    "life_engagements": (
        "1",
        "engagements until the lining has worn the wear allowance (the clamp load following "
        "the wear; Simpson's rule over the new, half and fully worn engagements)",
    ),
    "max_engagement_rate": (
        "1/s",
        "largest rate of engagements keeping every part's periodic bulk temperature under "
        "temperature_limit, new to fully worn",
    ),
}
# temperature outputs: on the scale or a difference (CF units_metadata, config constraints)
TEMPERATURE_KINDS = {"bulk_temperature_rise": "difference", "peak_surface_temperature": "absolute"}
ON_SCALE = units_metadata("absolute")
HEAT = (
    "specific_friction_work",
    "peak_specific_friction_power",
    "heat_flywheel",
    "heat_pressure_plate",
    "heat_driven_plate",
    "heat_intermediate_plate",
    "bulk_temperature_rise",
    "engagements_to_limit",
)


# the status rule (clutchlab.studies): what a scenario of each status keeps. The spring's statics
# hold wherever the spring is valid; a never_locked scenario (slipping at end_time) keeps what it
# did in the window — slip work up to end_time (PHYSICS.md's hard case), its heat, the largest
# slip power and clutch torque so far, the window's energy balance — and nothing of a lock-up that
# did not happen (lock-up time and speed, clamp force there, acceleration jump), nor a peak jerk
# (the compliant model's largest jerk follows the lock-up) or a count of engagements to the limit
# (an engagement that never ends); truncated (an event after end_time would change them) and
# not_converged: only the statics
_STATICS = ("ok", "never_locked", "not_converged", "truncated", "worn_not_locked")
_WINDOW = ("ok", "never_locked", "worn_not_locked")
# worn_not_locked: the first engagement is ok, the half or fully worn one does not lock: the first
# engagement's numbers stand; the life and the worn engagement's do not
_FIRST = ("ok", "worn_not_locked")
VALID_STATUSES = {
    **{
        k: _STATICS
        for k in (
            "clamp_load",
            "peak_capacity",
            "peak_bearing_force",
            "clamp_load_worn",
            "peak_capacity_worn",
        )
    },
    **{
        k: _FIRST
        for k in (
            "lockup_time",
            "lockup_speed",
            "clamp_force_at_lockup",
            "accel_jump",
            "peak_jerk",
            "engagements_to_limit",
            "wear_per_engagement",
        )
    },
    **{
        k: _WINDOW
        for k in (
            "slip_work",
            "peak_slip_power",
            "peak_friction_torque",
            "energy_residual",
            "specific_friction_work",
            "peak_specific_friction_power",
            "heat_flywheel",
            "heat_pressure_plate",
            "heat_driven_plate",
            "heat_intermediate_plate",
            "bulk_temperature_rise",
            "peak_surface_temperature",
            "hottest_part",
        )
    },
    # ok only (the default of a float output): the last engagement's lock-up time, slip work and
    # wear, the life and the engagement rate; model and solver counts: every status
}


# per-scenario model (variable ``model``): code, and what it is
MODEL = {"closed_form": 0, "rigid_events": 1, "compliant_events": 2}
MODEL_TEXT = {
    "closed_form": "rigid two-inertia, closed form",
    "rigid_events": "rigid two-inertia, DOPRI5 with exact events",
    "compliant_events": "compliant driveline (damper springs): linear phases in closed form, slip "
    "with Stribeck, tabulated or fading friction by exponential collocation, other nonlinear ones "
    "by DOPRI5, exact events",
}
# solver statistics stored per scenario (0 for the closed form): simulate's key -> long_name
SOLVER_STATS = {
    "n_steps": "integrator steps taken (accepted)",
    "n_rejected": "integrator steps rejected",
    "n_locate": "events located (stick, slip, lock-up)",
}


def bearing_force(p, pts, points=41):
    """Release-bearing force over the plate lift x ∈ [0, g + c].

    (F_s(λ_B + x) − F_c(x)) / i, with F_s the Almen–László load (eq. (10) of the source paper
    (000); the plate lifts against the spring, deflecting it further), F_c the cushion force
    F_B·max(0, 1 − x/c) and i the finger lever ratio; 0 when engaged.

    Parameters
    ----------
    p : dict of numpy.ndarray
        The study's parameters as flat arrays of one length [SI]
        (:func:`clutchlab.studies.flat_inputs`).
    pts : dict of numpy.ndarray
        The spring's characteristic points (:func:`clutchlab.diaphragm.characteristic_points`).
    points : int
        Number of points of the lift.

    Returns
    -------
    numpy.ndarray [N]
        Shape (scenarios, points).

    References
    ----------
    Source paper (000), eq. (10).
    """
    lift = (p["air_gap"] + p["cushion_travel"])[:, None] * np.linspace(0.0, 1.0, points)[None, :]
    geom = {k: np.asarray(v)[:, None] for k, v in spring_geometry(p).items()}
    # the spring was screened with its operating point (pts: NaN where its inputs are not
    # admissible); the lift adds a non-negative travel to that deflection, so the curve is
    # evaluated unscreened (screening each of the points cost 5 µs a scenario)
    with np.errstate(invalid="ignore", over="ignore"):
        f_spring = diaphragm._almen_laszlo_load(
            deflection=pts["deflection_B"][:, None] + lift, **geom
        )
    f_spring = np.where(np.isfinite(pts["load_B"])[:, None], f_spring, np.nan)
    f_cushion = pts["load_B"][:, None] * np.maximum(0.0, 1.0 - lift / p["cushion_travel"][:, None])
    return (f_spring - f_cushion) / p["lever_ratio"][:, None]


def capacity(p, options, with_points=False):
    """Clamp load at the spring's operating point, peak kinetic capacity and the spring status.

    Parameters
    ----------
    p : dict of numpy.ndarray
        The study's parameters as flat arrays of one length [SI]
        (:func:`clutchlab.studies.flat_inputs`).
    options : dict
        The study's options, complete (:data:`OPTIONS`: ``capacity_formula`` used here).
    with_points : bool
        Whether to return the characteristic points too.

    Returns
    -------
    force : numpy.ndarray [N]
        Clamp load F_B at the operating point (eq. (10)).
    capacity : numpy.ndarray [N m]
        Peak kinetic capacity (:func:`capacity_of`); 0 where the spring or the lining has no
        geometry.
    spring_bad : numpy.ndarray of bool
        True where the spring's load points are off it or the lining radii are swapped.
    points : dict of numpy.ndarray
        The characteristic points (:func:`clutchlab.diaphragm.characteristic_points`); only with
        ``with_points``.

    References
    ----------
    Source paper (000), eqs. (10) and (13)–(14).
    """
    pts = diaphragm.characteristic_points(
        **spring_geometry(p), operating_point_factor=p["operating_point_factor"]
    )
    force = pts["load_B"]
    cap = capacity_of(force, p, options)
    # a spring whose load points are off it, or swapped lining radii: no geometry, no capacity
    spring_bad = (pts["status"] == st.CODE["invalid_geometry"]) | ~(
        p["lining_inner_radius"] < p["lining_outer_radius"]
    )
    out = force, np.where(spring_bad, 0.0, cap), spring_bad
    return out + (pts,) if with_points else out


def capacity_of(force, p, options):
    """Peak kinetic capacity at the clamp load ``force``.

    Eqs. (13)–(14) of the source paper (000) corrected (:func:`clutchlab.friction.torque_capacity`),
    or eq. (14) as printed per the option ``capacity_formula``.

    Parameters
    ----------
    force : numpy.ndarray [N]
        Clamp load.
    p : dict of numpy.ndarray
        The study's parameters as flat arrays of one length [SI]
        (:func:`clutchlab.studies.flat_inputs`).
    options : dict
        The study's options, complete (:data:`OPTIONS`: ``capacity_formula`` used here).

    Returns
    -------
    numpy.ndarray [N m]
        The capacity; NaN where the friction model refuses an input.

    References
    ----------
    Source paper (000), eqs. (13)–(14) (erratum: :func:`clutchlab.friction.torque_capacity`).
    """
    if options["capacity_formula"] == "eq14_as_printed":
        cap = friction.torque_capacity_eq14_as_printed(
            force,
            p["friction_coefficient"],
            p["stack_mass"],
            p["lining_outer_radius"],
            p["lining_inner_radius"],
        )
    else:
        cap = friction.torque_capacity(
            force,
            p["friction_coefficient"],
            p["lining_outer_radius"],
            p["lining_inner_radius"],
            faces=p["friction_faces"],
            stack_mass=p["stack_mass"],
        )
    return cap


def _status(solver_status, spring_bad, cap, hot, life):
    """The scenario's status: invalid_geometry where the spring or the lining has no geometry;
    invalid_input where the spring or friction inputs give no capacity (NaN) or, where the
    engagement itself is ok, where the heat or wear model refuses its inputs (masses, cooling,
    interval, temperature margin, face count, wear rate and allowance: their outputs would be NaN
    under ok); worn_not_locked where the first engagement is ok but the half or fully worn one
    does not lock (``life["worn_status"]``); else the solver's."""
    code = np.where(spring_bad, st.CODE["invalid_geometry"], solver_status)
    code = np.where(~spring_bad & ~np.isfinite(cap), st.CODE["invalid_input"], code)
    heat_refused = (code == st.CODE["ok"]) & (hot["status"] != st.CODE["ok"])
    code = np.where(heat_refused, hot["status"], code)
    ok = code == st.CODE["ok"]
    code = np.where(ok & life["wear_refused"], st.CODE["invalid_input"], code)
    ok = code == st.CODE["ok"]
    code = np.where(ok & life["worn_not_locked"], st.CODE["worn_not_locked"], code)
    return code.astype(st.DTYPE)


def _life(p, pts, options, closed, res) -> dict:
    """The clutch over its wear allowance (:mod:`clutchlab.wear`): the half and fully worn
    engagements (the clamp load at λ_B − Δ/2 and λ_B − Δ on the spring's curve, the same model as
    the first), the wear per engagement of each from its slip work, the life in engagements
    (Simpson's rule over the three), and the largest engagement rate over the three engagements'
    heat; ``worn_not_locked`` where a worn engagement is not ok, ``wear_refused`` where the wear
    model refuses its inputs."""
    spring = spring_geometry(p)
    q, ro, ri = p["specific_wear_rate"], p["lining_outer_radius"], p["lining_inner_radius"]
    per = [wear.wear_per_engagement(res["slip_work"], q, ro, ri)]
    rates = [_heat(p, res["slip_work"], res["peak_slip_power"])["max_engagement_rate"]]
    out = {"worn_not_locked": np.zeros(per[0].shape, dtype=bool)}
    for fraction, tag in ((0.5, "half"), (1.0, "worn")):
        force = wear.worn_clamp_load(
            fraction * p["wear_allowance"], deflection_operating=pts["deflection_B"], **spring
        )
        cap = capacity_of(force, p, options)
        with np.errstate(invalid="ignore"):
            run = _engage(p, np.where(cap >= 0, cap, 0.0), options, closed, worn=True)
        out["worn_not_locked"] |= run["status"] != st.CODE["ok"]
        per.append(wear.wear_per_engagement(run["slip_work"], q, ro, ri))
        rates.append(_heat(p, run["slip_work"], run["peak_slip_power"])["max_engagement_rate"])
        if tag == "worn":
            out.update(clamp_load_worn=force, peak_capacity_worn=cap)
            out.update(lockup_time_worn=run["lockup_time"], slip_work_worn=run["slip_work"])
    out["wear_per_engagement"], out["wear_per_engagement_worn"] = per[0], per[2]
    out["life_engagements"] = wear.life_engagements(p["wear_allowance"], *per)
    out["max_engagement_rate"] = np.minimum(np.minimum(rates[0], rates[1]), rates[2])
    with np.errstate(invalid="ignore"):
        out["wear_refused"] = ~(
            (q > 0) & np.isfinite(p["wear_allowance"]) & (p["wear_allowance"] >= 0)
        ) | ~np.isfinite(per[0])
    return out


def tolerances(accuracy):
    """Tolerances of the integrated phases giving ``accuracy`` in lock-up time, slip work and jerk.

    Calibration in the module docstring; checked in the tests (``tests/test_compliant.py``).

    Parameters
    ----------
    accuracy : float
        Relative accuracy of lock-up time, slip work and peak jerk.

    Returns
    -------
    rtol : float
        accuracy/10.
    atol : float
        accuracy/10³.
    """
    return accuracy / 10.0, accuracy / 1e3


def _friction_table(p, options):
    """The config's friction table as simulate's (slip speeds, μ/μ_k), μ_k the (fixed) friction
    coefficient; None without one."""
    table = options.get("friction_table")
    if table is None:
        return None
    mu = np.asarray(p["friction_coefficient"])
    if mu.size and np.any(mu != mu.flat[0]):  # (the config refuses it: a per-scenario reading)
        raise ValueError("a friction_table is read relative to one fixed friction_coefficient")
    return (
        np.asarray(table["slip_speed"]),
        np.asarray(table["friction_coefficient"])
        / float(np.asarray(p["friction_coefficient"]).flat[0]),
    )


def _solver_inputs(p, cap, options):
    """Keyword arguments of :func:`clutchlab.engagement.simulate` shared by the study and its traces."""
    rigid = options["driveline"] == "rigid"
    rtol, atol = tolerances(options["accuracy"])
    return dict(
        engine_speed=p["engine_speed"],
        engine_inertia=p["engine_inertia"],
        engine_torque=p["engine_torque"],
        driven_inertia=p["driven_inertia"],
        load_torque=p["load_torque"],
        peak_capacity=cap,
        ramp_time=p["ramp_time"],
        profile=options["profile"],
        static_ratio=p["static_ratio"],
        t_end=p["end_time"],
        stribeck_speed=p["stribeck_speed"],
        aero_coefficient=p["aero_coefficient"],
        compliant=not rigid,
        hub_fraction=p["hub_fraction"],
        damper_stiffness=p["damper_stiffness"],
        damping_ratio=p["damping_ratio"],
        rtol=rtol,
        atol=atol,
        power_history=True,
        release_ratio=(p["air_gap"] + p["cushion_travel"]) / p["cushion_travel"],
        friction_table=_friction_table(p, options),
        **_fade_inputs(p),
    )


def _fade_inputs(p):
    """simulate's fade arguments (zero where fade is off, so that nothing of it is screened there)."""
    on = p["fade_coefficient"] > 0
    with np.errstate(invalid="ignore"):
        factor = heat.face_temperature_rise(
            1.0, p["lining_outer_radius"], p["lining_inner_radius"], p["friction_faces"]
        )
    return dict(
        fade_coefficient=p["fade_coefficient"],
        fade_onset=np.where(on, p["fade_onset_temperature"] - p["ambient_temperature"], 0.0),
        face_temperature_factor=np.where(on, factor, 0.0),
    )


# relations the engagement assumes for every scenario, besides the spring's and the lining's
RELATIONS = SPRING_RELATIONS + (
    Relation(
        ("end_time", "ramp_time"),
        ("min", "max"),
        lambda end_time, ramp_time: end_time > ramp_time,
        "the window searched for lock-up covers the clamp force's rise (end_time > ramp_time; "
        "else never_locked would be the window's, not the design's)",
    ),
    Relation(
        ("temperature_limit", "ambient_temperature"),
        ("min", "max"),
        lambda temperature_limit, ambient_temperature: temperature_limit > ambient_temperature,
        "the material limit lies above the ambient temperature (else engagements_to_limit means "
        "nothing)",
    ),
    Relation(
        ("fade_onset_temperature", "ambient_temperature", "fade_coefficient"),
        ("min", "max", "max"),
        lambda fade_onset_temperature, ambient_temperature, fade_coefficient: (
            fade_coefficient == 0 or fade_onset_temperature >= ambient_temperature
        ),
        "fade begins at or above the ambient temperature (where fade_coefficient > 0)",
    ),
    Relation(
        ("end_time", "fade_coefficient"),
        ("max", "max"),
        lambda end_time, fade_coefficient: fade_coefficient == 0 or end_time <= SOE_TMAX,
        f"with fade the face temperature's kernel covers the window (end_time <= {SOE_TMAX:g} s "
        "where fade_coefficient > 0)",
    ),
)


def check_config(section):
    """Refuse a combination of values the study cannot read physically.

    An odd face count (the heat model stacks n/2 driven plates lined on both sides); a friction
    table with a friction coefficient factor or noise or a finite Stribeck speed (a friction table replaces
    the Stribeck law and is read relative to a fixed friction coefficient). The relations between
    parameters are :data:`RELATIONS`.

    Parameters
    ----------
    section : dict
        The resolved study section (:func:`clutchlab.config.resolve`).

    Returns
    -------
    (str, str) or None
        (config key, problem) of the first combination that cannot be read, or None.
    """

    def bounds(name):
        return value_range(section, name)

    faces = (
        [section["fixed"]["friction_faces"]]
        if "friction_faces" in section["fixed"]
        else section["factors"]["friction_faces"].get("values")
    )
    if faces is None or any(f % 2 for f in faces):
        return (
            "engagement.parameters.friction_faces",
            "the heat of the engagement needs an even count (n/2 driven plates lined on both sides "
            "between flywheel, intermediate plates and pressure plate): give it as a value or a "
            f"list of even values, got {faces or section['factors']['friction_faces']}",
        )
    if "friction_table" in section["options"]:
        if "friction_coefficient" in section["factors"]:
            return (
                "engagement.parameters.friction_coefficient",
                "must be fixed with a friction_table (the table's mu is read relative to it: mu_k of the "
                "capacity and of static_ratio)",
            )
        if "friction_coefficient" in (section.get("robust") or {}).get("noise", {}):
            return (
                "engagement.noise.friction_coefficient",
                "cannot scatter with a friction_table (the table's mu is read relative to one fixed "
                "friction_coefficient): scale the table instead, or give the study a noise of its "
                "other parameters",
            )
        if bounds("stribeck_speed")[0] < np.inf:
            return (
                "engagement.parameters.stribeck_speed",
                "a friction_table replaces the Stribeck law: leave stribeck_speed at inf",
            )
    return None


def friction_laws(section: dict) -> list[str]:
    """The friction laws the scenarios of a resolved engagement section slip with, by the names of
    :data:`clutchlab.bench.compliant.VARIANTS` (the report's numerics time the solver on these).

    Parameters
    ----------
    section : dict
        A resolved ``engagement`` section (:func:`clutchlab.config.resolve`).

    Returns
    -------
    list of str
        ``"constant_mu"`` always (the exact phases every model has), then ``"stribeck"`` where a
        scenario has a finite ``stribeck_speed``, ``"table"`` with a ``friction_table``, and
        ``"fade"`` where a scenario has ``fade_coefficient`` > 0.
    """
    laws = ["constant_mu"]
    if "friction_table" in section["options"]:
        laws.append("table")
    elif value_range(section, "stribeck_speed")[0] < np.inf:
        laws.append("stribeck")
    if value_range(section, "fade_coefficient")[1] > 0:
        laws.append("fade")
    return laws


def _heat(p, slip_work, peak_slip_power):
    """clutchlab.heat.engagement_heat of the scenarios (NaN where the slip work is NaN)."""
    return heat.engagement_heat(
        slip_work,
        peak_slip_power,
        p["lining_outer_radius"],
        p["lining_inner_radius"],
        p["friction_faces"],
        temperature_margin=p["temperature_limit"] - p["ambient_temperature"],
        **{
            k: p[k]
            for k in (
                "flywheel_mass",
                "pressure_plate_mass",
                "driven_plate_mass",
                "heat_transfer_coefficient",
                "cooling_area",
                "engagement_interval",
                "intermediate_plate_mass",
            )
        },
    )


# the inputs that decide between the closed form and the event solver of a rigid driveline
_MODEL_INPUTS = (
    "engine_inertia",
    "aero_coefficient",
    "stribeck_speed",
    "air_gap",
    "fade_coefficient",
)


def _closed_form_applies(p, options):
    """Where the cheapest exact model is the closed form: a rigid driveline with
    a held engine, no drag, constant mu (no Stribeck law, friction table or fade) and no air gap."""
    return (
        (options["driveline"] == "rigid")
        & ~np.isfinite(p["engine_inertia"])
        & (p["aero_coefficient"] == 0)
        & ~np.isfinite(p["stribeck_speed"])
        & (p["air_gap"] == 0)
        & (p["fade_coefficient"] == 0)
        & ("friction_table" not in options)
    )


def _model_used(inputs, options) -> str:
    """The ``model_used`` attribute: the models this study's inputs can run, from the options and
    the fixed inputs only (the same text in every chunk, whichever scenarios it holds; the
    per-scenario choice is the variable ``model``)."""
    if options["driveline"] != "rigid":
        laws = _slip_laws(inputs, options)
        if not laws:  # (the text of a run with constant mu says so, not the laws it has not)
            return MODEL_TEXT["compliant_events"].split(", slip with")[0] + (
                ", constant μ, other nonlinear phases by DOPRI5, exact events"
            )
        return MODEL_TEXT["compliant_events"].replace(
            "Stribeck, tabulated or fading", " and ".join(laws)
        )
    given = {k: v for k, v in inputs.items() if k in _MODEL_INPUTS}
    if all(np.ndim(v) == 0 for v in given.values()):
        p = {k: np.atleast_1d(given.get(k, PARAMETER_DEFAULTS[k])) for k in _MODEL_INPUTS}
        closed = bool(_closed_form_applies(p, options)[0])
        return MODEL_TEXT["closed_form" if closed else "rigid_events"]
    return "per scenario (variable model): " + "; ".join(
        MODEL_TEXT[m] for m in ("closed_form", "rigid_events")
    )


def _slip_laws(inputs, options) -> list[str]:
    """The nonlinear friction laws the inputs can slip with: by a fixed input's value, a varying
    one's law always (the same in every chunk, whichever values it holds)."""

    def may(name, uses):
        v = inputs.get(name, PARAMETER_DEFAULTS[name])
        return np.ndim(v) > 0 or bool(uses(float(v)))

    laws = ["tabulated"] if "friction_table" in options else []
    if may("stribeck_speed", np.isfinite):
        laws.append("Stribeck")
    if may("fade_coefficient", lambda b: b != 0):
        laws.append("fading")
    return laws


def compute(inputs, options=None) -> xr.Dataset:
    """Results of a chunk of scenarios of the study "engagement".

    Per scenario: clamp load, capacity, lock-up, slip work, jerk, heat and wear (module docstring).

    Parameters
    ----------
    inputs : dict
        Parameter name -> flat array (one entry per scenario of the chunk) or scalar, in SI units
        (:data:`PARAMETERS`).
    options : dict or None
        The study's options (:data:`OPTIONS`, ``accuracy``, ``friction_table``); a missing one takes
        its first choice (``accuracy``: :data:`ACCURACY`).

    Returns
    -------
    xarray.Dataset
        One entry per scenario on dimension ``run`` (curves with a further dimension): the outputs
        of the module docstring, each with ``units`` and ``long_name``, and ``status``
        (:mod:`clutchlab.status`). The registered ``compute`` (:func:`clutchlab.studies.get`) also
        applies the status rule (:func:`clutchlab.studies.apply_valid_statuses`).

    References
    ----------
    Source paper (000), eqs. (1)–(2) (engagement), (10) (spring), (11) (slip work), (12) (jerk),
    (13)–(14) corrected (capacity).
    """
    options = {k: v[0] for k, v in OPTIONS.items()} | {"accuracy": ACCURACY} | (options or {})
    p = flat_inputs(inputs)
    force, cap, spring_bad, pts = capacity(p, options, with_points=True)
    rigid = options["driveline"] == "rigid"
    closed = _closed_form_applies(p, options)
    model = np.where(
        closed, MODEL["closed_form"], MODEL["rigid_events" if rigid else "compliant_events"]
    )
    res = _engage(p, cap, options, closed)
    with np.errstate(invalid="ignore", divide="ignore"):
        res["clamp_force_at_lockup"] = np.where(
            cap > 0, res["capacity_at_lockup"] / cap * force, np.nan
        )
    res["clamp_load"], res["peak_capacity"] = force, cap
    with np.errstate(invalid="ignore"):
        res["peak_bearing_force"] = np.max(bearing_force(p, pts), axis=1)
    hot = _heat(p, res["slip_work"], res["peak_slip_power"])
    res.update({k: hot[k] for k in HEAT})
    # the friction face's peak (flash) temperature from the slip power history (the event solver's
    # samples, or the closed form's exact slip power sampled on its pieces)
    flash = np.where(hot["status"] != 0, np.nan, res.get("flash_peak", np.full(model.size, np.nan)))
    res["peak_surface_temperature"] = p["ambient_temperature"] + heat.face_temperature_rise(
        flash, p["lining_outer_radius"], p["lining_inner_radius"], p["friction_faces"]
    )
    life = _life(p, pts, options, closed, res)
    res.update(life)
    code = _status(res["status"], spring_bad, cap, hot, life)
    return _dataset(res, code, hot, model, inputs, options)


def _engage(p, cap, options, closed, worn=False) -> dict:
    """One engagement of every scenario at the peak capacity ``cap`` [N m]: the closed form where
    ``closed``, the event solver elsewhere (the outputs of :data:`OUTPUTS` they give, the solver's
    status, capacity at lock-up, the solver statistics and, unless ``worn``, the flash integral's
    peak). A ``worn`` engagement needs only its status, lock-up time, slip work and peak slip
    power: without the slip-power history the compliant solver takes about half the time, and
    without the friction torque's and jerk's peaks (NaN) the exact phases search fewer forms; the
    other outputs are unchanged to round-off."""
    kw = _solver_inputs(p, cap, options) | {"power_history": not worn, "peaks": not worn}
    res = {}
    for mask, closed_form in ((closed, True), (~closed, False)):
        if not mask.any() and (
            mask.size or closed_form
        ):  # (an empty chunk runs the solver on nothing)
            continue
        sub = {
            k: (v[mask] if isinstance(v, np.ndarray) and v.shape == mask.shape else v)
            for k, v in kw.items()
        }
        if closed_form:
            part = engagement.closed_form(
                **{
                    k: sub[k]
                    for k in (
                        "engine_speed",
                        "engine_inertia",
                        "engine_torque",
                        "driven_inertia",
                        "load_torque",
                        "peak_capacity",
                        "ramp_time",
                        "profile",
                        "static_ratio",
                        "t_end",
                    )
                },
                power_history=not worn,
            )
            part["peak_jerk"] = part.pop("slip_jerk")
        else:
            part = engagement.simulate(**sub)
        for k in (*OUTPUTS, "status", "capacity_at_lockup", "flash_peak", *SOLVER_STATS):
            if k in part:
                res.setdefault(k, np.zeros(mask.size, dtype=np.asarray(part[k]).dtype))[mask] = (
                    part[k]
                )
    return res


def _dataset(res, code, hot, model, inputs, options) -> xr.Dataset:
    """The study's result Dataset of the computed outputs ``res`` and status ``code``."""
    refused = np.isin(code, [st.CODE["invalid_geometry"], st.CODE["invalid_input"]])
    data = {
        k: (
            "run",
            np.where(refused, np.nan, res[k]),
            {"units": u, "long_name": ln, **units_metadata(TEMPERATURE_KINDS.get(k))},
        )
        for k, (u, ln) in OUTPUTS.items()
    }
    data["hottest_part"] = (
        "run",
        hot["hottest_part"],
        {
            "long_name": "part with the largest bulk temperature rise",
            "units": "1",
            "flag_values": np.arange(-1, len(heat.PARTS), dtype=np.int8),
            "flag_meanings": " ".join(("none",) + heat.PARTS),  # none: no valid heat (-1)
        },
    )
    data["model"] = (
        "run",
        model.astype(np.int8),
        {
            "long_name": "model that computed the scenario (the cheapest exact one for its inputs)",
            "units": "1",
            "flag_values": np.array(sorted(MODEL.values()), np.int8),
            "flag_meanings": " ".join(MODEL),
        },
    )
    for k, ln in SOLVER_STATS.items():
        data[k] = (
            "run",
            res.get(k, np.zeros(model.size)).astype(np.int32),
            {"long_name": ln, "units": "1"},
        )
    data["status"] = (
        "run",
        code,
        st.attrs(
            "invalid_geometry: spring load points off the spring, or lining radii "
            "swapped; invalid_input: an input not physical or implausible; "
            "never_locked: slipping at end_time; not_converged: work limit; "
            "truncated: an event after end_time (break-away, the output "
            "stopping) would change the metrics: raise end_time"
        ),
    )
    ds = xr.Dataset(data)
    ds.attrs["model_used"] = _model_used(inputs, options)
    rtol, atol = tolerances(options["accuracy"])
    ds.attrs.update(accuracy=options["accuracy"], rtol=rtol, atol=atol)
    return ds


TRACE_POINTS = 401
SEQUENCE_ENGAGEMENTS = 30  # engagements in a row drawn for the design shown


def seed_traces(inputs, options) -> xr.Dataset:
    """Time traces of one design: the design a run's pages show (:mod:`clutchlab.traces`).

    The equivalents of Figs. 7–11 of the source paper (000): clamp force, speeds, slip work,
    friction torque, jerk.

    Parameters
    ----------
    inputs : dict
        Parameter name -> value [SI]; the scalars override the defaults
        (:func:`clutchlab.studies.seed_design`).
    options : dict
        The study's options, complete (:data:`OPTIONS`, ``accuracy``).

    Returns
    -------
    xarray.Dataset
        The traces on dimension ``trace_time``; empty where the design has no capacity.

    References
    ----------
    Source paper (000), Figs. 7–11.
    """
    p = {k: np.atleast_1d(v) for k, v in seed_design(PARAMETERS, inputs).items()}
    force, cap, bad = capacity(p, options)
    if bad[0] or not cap[0] > 0:
        return xr.Dataset()
    times = np.linspace(0.0, float(p["end_time"][0]), TRACE_POINTS)
    res = engagement.simulate(**_solver_inputs(p, cap, options), trace_times=times)
    tr = {k: v[0] for k, v in res["trace"].items()}
    dim = "trace_time"
    meta = {
        "engine_speed": ("rad/s", "engine speed"),
        "hub_speed": ("rad/s", "driven plate (hub) speed"),
        "output_speed": ("rad/s", "output speed (after the damper springs)"),
        "friction_torque": ("N m", "transmitted clutch torque"),
        "slip_work": ("J", "slip work so far (eq. 11)"),
        "jerk": ("rad/s^3", "output jerk (eq. 12)"),
    }
    data = {
        f"trace_{k}": (dim, tr[k], {"units": u, "long_name": f"{ln} (design shown)"})
        for k, (u, ln) in meta.items()
    }
    data["trace_clamp_force"] = (
        dim,
        tr["capacity"] / cap[0] * force[0],
        {
            "units": "N",
            "long_name": "clamp force (design shown; its rise follows the ramp profile)",
        },
    )
    data["trace_lockup_time"] = (
        (),
        float(res["lockup_time"][0]),
        {"units": "s", "long_name": "lock-up time (design shown)"},
    )
    data.update(_trace_temperatures(p, times, tr, dim))
    return xr.Dataset(
        data,
        coords={
            dim: (dim, times, {"units": "s", "long_name": "time (traces of the design shown)"})
        },
    )


def _trace_temperatures(p, times, tr, dim) -> dict:
    """The design's heat history (clutchlab.heat): slip power P = T_c·(ω_e − ω_h); the pressure
    plate's friction-face (flash) temperature, ambient + Duhamel's integral of its heat flux
    q = γ·P/A (γ its effusivity share at the face, A the friction area of all faces; the solver's
    own trace, not a second run); its bulk temperature, ambient + its share of the slip work so far
    over m c."""
    power = np.nan_to_num(tr["friction_torque"] * (tr["engine_speed"] - tr["hub_speed"]))
    area = float(
        heat.lining_area(p["lining_outer_radius"][0], p["lining_inner_radius"][0])
        * p["friction_faces"][0]
    )
    e_fw, e_pp, e_lining = heat.part_effusivities()
    faces = float(p["friction_faces"][0])
    gamma = e_pp / (e_pp + e_lining)
    ambient = float(p["ambient_temperature"][0])
    surface = ambient + heat.duhamel_surface_temperature(times, gamma * power / area, e_pp)
    bulk = ambient + gamma / faces * np.nan_to_num(tr["slip_work"]) / (
        float(p["pressure_plate_mass"][0]) * heat.MATERIALS["cast_iron"]["specific_heat"]
    )
    where = "(design shown; pressure plate)"
    # engagements in a row, engagement_interval apart, the hottest part cooling between them
    hot = _heat(
        {k: v[:1] for k, v in p.items()},
        np.nan_to_num(tr["slip_work"][-1:]),
        np.array([power.max()]),
    )
    part = heat.PARTS[int(hot["hottest_part"][0])]
    capacity = (
        float(p[f"{part}_mass"][0]) * heat.MATERIALS[heat.BULK_MATERIAL[part]]["specific_heat"]
    )
    tau = capacity / float(p["heat_transfer_coefficient"][0] * p["cooling_area"][0])
    seq = ambient + heat.sequence_temperatures(
        hot["bulk_temperature_rise"][0],
        float(p["engagement_interval"][0]),
        tau,
        SEQUENCE_ENGAGEMENTS,
    )
    return {
        "trace_sequence_temperature": (
            "engagement_number",
            seq,
            {
                "units": "K",
                **ON_SCALE,
                "long_name": f"bulk temperature of the {part.replace('_', ' ')} just after each engagement "
                "in a row (design shown)",
            },
        ),
        "engagement_number": (
            "engagement_number",
            np.arange(1, SEQUENCE_ENGAGEMENTS + 1),
            {"units": "1", "long_name": "engagement in a row (engagement_interval apart)"},
        ),
        "trace_slip_power": (dim, power, {"units": "W", "long_name": "slip power (design shown)"}),
        "trace_surface_temperature": (
            dim,
            surface,
            {"units": "K", **ON_SCALE, "long_name": f"friction-face temperature {where}"},
        ),
        "trace_bulk_temperature": (
            dim,
            bulk,
            {"units": "K", **ON_SCALE, "long_name": f"bulk temperature {where}"},
        ),
        "trace_peak_surface_temperature": (
            (),
            float(surface.max()),
            {"units": "K", **ON_SCALE, "long_name": f"peak friction-face temperature {where}"},
        ),
    }


# where each parameter's default comes from (the reference pages show it)
SOURCES = SPRING_SOURCES | {
    "specific_wear_rate": (
        "assumed: 0.2 cm^3/kWh, of the order VDI 2241 gives for organic dry linings (not checked "
        "against its table); replace it with the lining maker's value"
    ),
    "ramp_time": "the source paper (000), section 5.1, Fig. 7: the clamp load rises in 0.15 s",
    "engine_speed": "the source paper (000), section 5.2, Fig. 8: 570 rad/s at lock-up",
    "engine_inertia": (
        "assumed: engine held at its speed (inf), what reproduces the source paper (000)'s "
        "Fig. 8 (a free engine with 156 > 44 N m would keep accelerating)"
    ),
    "engine_torque": "the source paper (000), section 4 (after Table 4): drive torque 156 N m",
    "driven_inertia": (
        "assumed: inferred from the source paper (000)'s lock-up at 0.15 s and slip work "
        "(section 5.2-5.3); the plate's own inertia, not printed"
    ),
    "load_torque": "the source paper (000), section 4 (after Table 4): load torque 44 N m",
    "aero_coefficient": (
        "assumed: no rotor drag (0), as the source paper (000)'s constant load torque"
    ),
    "static_ratio": "assumed: one friction coefficient (1), as the source paper (000)'s Table 4",
    "stribeck_speed": (
        "assumed: constant kinetic friction (inf), as the source paper (000)'s Table 4"
    ),
    "hub_fraction": (
        "assumed: half the driven inertia on the plate hub; the source paper (000) prints no split"
    ),
    "damper_stiffness": "the source paper (000), Table 2, eq. (7): C_a = 13 T_j = 4498 N m/rad",
    "damping_ratio": "assumed: 5 %; the source paper (000) prints no driveline damping",
    "air_gap": (
        "assumed: no free travel (0), the clamp ramp starting at first touch as in the source"
        " paper (000)'s Fig. 7"
    ),
    "cushion_travel": "assumed: 0.6 mm; the source paper (000) prints no cushion",
    "lever_ratio": "assumed: 4; the source paper (000) prints no lever ratio",
    "end_time": (
        "assumed: a 0.5 s window, beyond the source paper (000)'s lock-up at 0.15 s and the "
        "default limit on lock-up time"
    ),
    "flywheel_mass": "the source paper (000), Table 3",
    "pressure_plate_mass": "the source paper (000), Table 3",
    "driven_plate_mass": "the source paper (000), Table 3",
    "intermediate_plate_mass": (
        "assumed: the pressure plate's 2.5 kg (the source paper (000), Table 3); only with "
        "more than two faces"
    ),
    "heat_transfer_coefficient": "assumed: 40 W/(m^2 K), a closed clutch housing",
    "cooling_area": "assumed: 0.1 m^2, both sides and rim of the hottest part",
    "engagement_interval": "assumed: 60 s, a retried start",
    "ambient_temperature": "assumed: 40 degC, air in the clutch housing",
    "temperature_limit": (
        "assumed: 250 degC, the service limit of organic linings (Limpert, Brake Design and "
        "Safety, ch. 3)"
    ),
    "fade_coefficient": (
        "assumed: no fade (0) unless given; the source paper (000) uses a constant friction "
        "coefficient"
    ),
    "fade_onset_temperature": (
        "assumed: 200 degC, organic linings (Limpert, Brake Design and Safety, ch. 3)"
    ),
}


def validation() -> xr.Dataset:
    """The source paper (000)'s engagement numbers reproduced, as validation rows.

    :data:`clutchlab.published.DIAPHRAGM_CLUTCH` (lock-up time, speed at lock-up, slip work).

    Returns
    -------
    xarray.Dataset
        Validation rows on dimension ``row`` (:func:`clutchlab.validation.to_dataset`): each
        published number, clutchlab's value, the relative error and its tolerance, and where the
        number is printed.
    """
    return to_dataset(_engagement_rows(), "paper 000: engagement")


def _engagement_rows() -> list[Row]:
    """Engagement (eqs. 1-2, 11): engine held at 570 rad/s, capacity ramped 0 -> the published
    239.3 N m (eq. 14 as printed) over 0.15 s, load 44 N m, driven inertia 0.021 kg m² (inferred,
    not printed)."""
    pub = DIAPHRAGM_CLUTCH
    r = engagement.closed_form(
        engine_speed=570.0,
        engine_inertia=np.inf,
        engine_torque=156.0,
        driven_inertia=0.021,
        load_torque=44.0,
        peak_capacity=pub["capacity_eq14_as_printed"].value,
        ramp_time=0.15,
    )
    assumption = (
        "engine held at 570 rad/s, J_v = 0.021 kg m2 inferred, linear ramp to 239.3 N m "
        "(eq. 14 as printed)"
    )
    return [
        Row.against(pub["lockup_time"], r["lockup_time"], 0.01, assumption),
        Row.against(pub["lockup_speed"], r["lockup_speed"], 1e-3),
        Row.against(pub["slip_work"], r["slip_work"], 0.02),
    ]


STUDY = register(
    Study(
        name="engagement",
        output="engagement/engagement.h5",
        description=(
            "Diaphragm-spring clutch engagement: lock-up, slip work, jerk (source paper 000)"
        ),
        parameters=PARAMETERS,
        compute=compute,
        traces=seed_traces,
        validation=validation,
        model="chosen by options (see model_used): closed form, or DOPRI5 with exact stick-slip events",
        options=OPTIONS,
        outputs={
            "lockup_time": "s",
            "slip_work": "J",
            "peak_slip_power": "W",
            "peak_friction_torque": "N m",
            "specific_friction_work": "J/m^2",
            "peak_specific_friction_power": "W/m^2",
            "bulk_temperature_rise": ("K", "difference"),
            "peak_surface_temperature": ("K", "absolute"),
            "accel_jump": "rad/s^2",
            "peak_jerk": "rad/s^3",
            "peak_bearing_force": "N",
            "clamp_load": "N",
            # over the clutch's life (clutchlab.wear)
            "clamp_load_worn": "N",
            "peak_capacity_worn": "N m",
            "lockup_time_worn": "s",
            "slip_work_worn": "J",
            "wear_per_engagement": "m",
            "life_engagements": "1",
            "max_engagement_rate": "1/s",
        },
        # paper 000: a cool (little slip work) and smooth (little jerk) engagement, locked within 0.5 s
        conditions=(
            "engine_speed",
            "engine_inertia",
            "engine_torque",
            "driven_inertia",
            "load_torque",
            "aero_coefficient",
        ),
        model_options=("driveline", "capacity_formula"),
        tables={
            "friction_table": (
                ("slip_speed", "rad/s"),
                ("friction_coefficient", "1"),
                "measured kinetic friction coefficient over slip speed (replaces the Stribeck law)",
            )
        },
        # a robust study's default noise: dry friction scatters by about ±20 % with temperature,
        # wear and humidity (the lining's nominal mu is a design choice, its scatter is not)
        noise={"friction_coefficient": {"scatter": "±20 %"}},
        objectives=("slip_work:min", "peak_jerk:min"),
        # ... new and at the end of the wear allowance (less clamp load: a longer engagement)
        constraints={"lockup_time": ("max", 0.5), "lockup_time_worn": ("max", 0.5)},
        accuracy=ACCURACY,
        check_config=check_config,
        valid_statuses=VALID_STATUSES,
        sources=SOURCES,
        relations=RELATIONS,
    )
)
compute = STUDY.compute  # the status rule applied (clutchlab.studies.apply_valid_statuses)
