"""Roller-type controllable overrunning clutch (the source paper (003)): statics, self-locking and
the wedging dynamics with stiff Hertz contact.

Pure functions of numpy arrays (broadcasting), SI units; the dynamics runs compiled
(:mod:`clutchlab._contact_kernel`) one scenario after another inside one call.

Reduced dynamic model (the source paper (003), section 3.1, Table 2: the ADAMS model's joints). The
driving ring turns at a constant speed ω_d; it drives the wedge ring (inertia J_w) through their
flat interface by Coulomb friction μ·(axial load)·R_C while they slip, and carries it when they
stick; the wedge ring's slopes (wedge angle α) press the loaded rollers onto the flat driven ring
(inertia J_o, load torque T_L). A roller is a two-force member: each contact carries a normal force
N and a tangential force N·tan(α/2), and its compression at each contact is δ = δ₀ + tan(α/2)·u/2
where u = R_C·(θ_w − θ_o) is the tangential travel of the wedge ring over the driven ring (virtual
work; rollers rolling without slip, massless on this time scale). The spring preload F_T holds the
rollers in the wedge at the start: N₀ = F_T / (2·sin(α/2)).

    q' = R_C (ω_d − ω_w)                      (slip at the friction interface; 0 when stuck)
    J_w ω_w' = z R_C (μ − tan(α/2)) N         (0 when stuck: ω_w = ω_d)
    u' = R_C (ω_w − ω_o)
    J_o ω_o' = z R_C tan(α/2) N − T_L         (while the driven ring turns; 0 while it is held)

The load torque T_L is passive (the drag of what the clutch drives): it opposes the driven ring's
motion and, at rest, holds it with up to T_L (Coulomb-like stiction of the load). The driven ring
starts held and stays exactly at rest until the wedge's drive torque z R_C tan(α/2) N reaches T_L
(event), turns forward under the difference after that, and is held again if it comes to rest
(event) — it never turns backwards. (A load acting as an active torque would drive the ring at
rest backwards, to −7.8 rad/s for the seed design, before the wedge takes it up.)

N follows :func:`clutchlab.contact.impact_force` (k·δ^1.5, damping through a cubic step over the
penetration depth, never pulling). Events, located by re-stepping the integrator: the wedge ring
reaching ω_d (stick: it stays stuck because tan(α/2) < μ), the driven ring breaking away from
rest or coming to rest, the driven ring reaching ω_d
(engagement time; total backlash (q + u)/R_C; the driving/wedge part q/R_C frozen at the stick),
the peaks of N, and the release. Release: when the control ring is stopped its claws hold the
rollers, which (after a claw clearance) move toward the wide end of the wedge at the relative speed
R_C·ω_d, opening each contact by tan(α)/2 per unit travel; released when N reaches 0.

Integrator: L-stable SDIRK4 with an analytic Jacobian (:mod:`clutchlab._contact_kernel`): the
contact damping makes the problem stiff (eigenvalues ~ −z·c·(tan(α/2)R_C/2)²/J_o ≈ −10⁷ s⁻¹ for the
seed design).

References
----------
.. [1] Wang P. et al., "Design of a new roller-type control-separated overrunning clutch",
   Sci Sin Tech 2013: the source paper (003), eqs. (1)-(4), Table 1, section 3.
"""

from __future__ import annotations

import numpy as np

from . import _contact_kernel as _k
from . import _contact_systems as _sys
from . import status as st

__all__ = [
    "computed_torque",
    "loaded_rollers",
    "normal_force",
    "equivalent_radius",
    "contact_stress",
    "roller_mass",
    "spring_preload",
    "self_locking_margin",
    "limit_wedge_angle",
    "simulate",
    "parameter_rows",
    "MODES",
    "engages",
    "RPM",
]

RPM = np.pi / 30.0
STEEL_DENSITY = 7850.0
MODES = ("bidirectional_lock", "bidirectional_overrun", "overrun_forward", "overrun_reverse")
READINGS = ("one_flank", "all")
MAX_FRICTION_COEFFICIENT = 2.0
MAX_SERVICE_FACTOR = 100.0  # each of K₁, K₂, K₃ of eq. (1)
MAX_EXPONENT = 10.0  # of the contact law k·δ^e

_MU = st.positive_in("1", hi=MAX_FRICTION_COEFFICIENT)
# per-input rules of the helpers (sign, finite, plausible magnitude: clutchlab.plausible)
_RULES = {
    "max_torque": st.nonnegative_in("N m"),
    "k1": st.positive_in("1", hi=MAX_SERVICE_FACTOR),
    "k2": st.positive_in("1", hi=MAX_SERVICE_FACTOR),
    "k3": st.positive_in("1", hi=MAX_SERVICE_FACTOR),
    "torque": st.nonnegative_in("N m"),
    "contact_radius": st.positive_in("m"),
    "friction_coefficient": _MU,
    "rollers": st.count(1),
    "roller_diameter": st.positive_in("m"),
    "counter_diameter": st.positive_or_inf_in("m"),
    "force": st.nonnegative_in("N"),
    "roller_length": st.positive_in("m"),
    "radius": st.positive_in("m"),
    "youngs_modulus": st.positive_in("Pa"),
    "poisson_ratio": st.between(-1.0, 0.5, lo_open=True, hi_open=True),
    "density": st.positive_in("kg/m^3"),
    "roller_mass": st.positive_in("kg"),
    "speed": st.nonnegative_in("rad/s"),
    "wedge_angle": st.between(0.0, np.pi / 2, lo_open=True, hi_open=True),
}


def _domain(inputs, relations=None):
    return {**{k: _RULES[k] for k in inputs}, **(relations or {})}


def computed_torque(max_torque, *, k1=1.0, k2=1.1, k3=1.1):
    """Computed (design) torque T_c = K₃(K₁ + K₂)·T_i, equation (1) of [1].

    The paper prints only T_c = 1848 N·m for T_i = 800 N·m, i.e. K₃(K₁+K₂) = 2.31; the split
    K₁ = 1.0, K₂ = 1.1, K₃ = 1.1 is assumed.

    Parameters
    ----------
    max_torque : float or array_like [N m]
        Maximum working torque T_i ≥ 0.
    k1, k2, k3 : float or array_like [-]
        Service factors K₁, K₂, K₃, each in (0, 100].

    Returns
    -------
    numpy.ndarray [N m]
        T_c; NaN where T_i < 0, a factor is not in (0, 100], or an input is not finite or
        plausible.

    References
    ----------
    Source paper (003), eq. (1) ([1] in the module docstring).
    """
    inputs = dict(max_torque=max_torque, k1=k1, k2=k2, k3=k3)
    return st.nan_screened(_computed_torque, inputs, _domain(inputs))


def _computed_torque(*, max_torque, k1, k2, k3):
    return k3 * (k1 + k2) * np.asarray(max_torque, float)


def loaded_rollers(rollers, reading="one_flank"):
    """Rollers carrying the torque in one direction.

    ``one_flank`` (clutchlab): the wedge ring is symmetric for both directions, and in either
    direction only the rollers on one flank of each wedge lock, z/2 of them — the reading that
    gives the published σ_H = 2865.5 MPa; ``all``: eq. (2) as printed, every roller loaded
    (2026 MPa).

    Parameters
    ----------
    rollers : int or array_like [-]
        Number of rollers z, a whole number in [1, 1000] (even for ``one_flank``).
    reading : {"one_flank", "all"}
        Which rollers are loaded.

    Returns
    -------
    numpy.ndarray [-]
        The loaded rollers; NaN for a count that is not a whole number in [1, 1000] — or, for
        ``one_flank``, not even (z = 13 would load 6.5 rollers) — so every number computed from it
        is NaN (the config refuses such counts).

    Raises
    ------
    ValueError
        For another ``reading``.

    Notes
    -----
    Erratum: with every roller loaded, eqs. (2)–(3) of [1] give 2026 MPa, √2 below the published
    2865.5 MPa; loading one flank (z/2 rollers) accounts for the factor 2.

    References
    ----------
    Source paper (003), eqs. (2)–(3) and Table 1 ([1] in the module docstring).
    """
    if reading not in READINGS:
        raise ValueError(f"reading must be one of {READINGS}, got {reading!r}")
    z = np.asarray(rollers, float)
    with np.errstate(invalid="ignore"):
        whole = st.count(1)(z)
    if reading == "one_flank":
        return np.where(whole & (z % 2 == 0), 0.5 * z, np.nan)
    return np.where(whole, z, np.nan)


def normal_force(torque, *, contact_radius, friction_coefficient, rollers):
    """Normal force per roller N_A = T_c / (R_C·μ_A·z), equation (2) of [1].

    The normal force per roller that lets the friction interface carry T_c.

    Parameters
    ----------
    torque : float or array_like [N m]
        Computed torque T_c ≥ 0.
    contact_radius : float or array_like [m]
        Radius R_C of the contacts.
    friction_coefficient : float or array_like [-]
        Friction coefficient μ_A, in (0, 2].
    rollers : int or array_like [-]
        Loaded rollers z (:func:`loaded_rollers`), a whole number in [1, 1000].

    Returns
    -------
    numpy.ndarray [N]
        N_A (8555.6 N for [1]'s design with every roller loaded); NaN where an input is not
        physical, finite or plausible.

    References
    ----------
    Source paper (003), eq. (2) ([1] in the module docstring).
    """
    inputs = dict(
        torque=torque,
        contact_radius=contact_radius,
        friction_coefficient=friction_coefficient,
        rollers=rollers,
    )
    return st.nan_screened(_normal_force, inputs, _domain(inputs))


def _normal_force(*, torque, contact_radius, friction_coefficient, rollers):
    return np.asarray(torque, float) / (contact_radius * friction_coefficient * rollers)


def equivalent_radius(roller_diameter, counter_diameter=np.inf):
    """Equivalent radius ρ_v = 0.5·D_v·d/(D_v − d) of a roller on a concave counter-face.

    d/2 on a flat face (D_v = ∞).

    Parameters
    ----------
    roller_diameter : float or array_like [m]
        Roller diameter d > 0.
    counter_diameter : float or array_like [m]
        Diameter D_v > d of the concave counter-face (inf: flat).

    Returns
    -------
    numpy.ndarray [m]
        ρ_v; NaN unless D_v > d > 0, finite (D_v may be inf) and plausible.

    References
    ----------
    Source paper (003), text after eq. (3) ([1] in the module docstring).
    """
    inputs = dict(roller_diameter=roller_diameter, counter_diameter=counter_diameter)
    return st.nan_screened(
        _equivalent_radius,
        inputs,
        _domain(inputs, {None: lambda a: a["counter_diameter"] > a["roller_diameter"]}),
    )


def _equivalent_radius(*, roller_diameter, counter_diameter):
    d = np.asarray(roller_diameter, float)
    dv = np.asarray(counter_diameter, float)
    return np.where(np.isinf(dv), 0.5 * d, 0.5 * dv * d / np.where(np.isinf(dv), 1.0, dv - d))


def contact_stress(force, *, roller_length, radius, youngs_modulus=206e9, poisson_ratio=0.3):
    """Hertz line-contact stress σ_H = √(N·E / (2π(1−ν²)·b·ρ_v)), equation (3) of [1].

    The paper's 0.418 is 1/√(2π(1−ν²)) for steel (ν = 0.3).

    Parameters
    ----------
    force : float or array_like [N]
        Normal force N ≥ 0 per roller.
    roller_length : float or array_like [m]
        Contact length b > 0.
    radius : float or array_like [m]
        Equivalent radius ρ_v > 0 (:func:`equivalent_radius`).
    youngs_modulus : float or array_like [Pa]
        Young's modulus E.
    poisson_ratio : float or array_like [-]
        Poisson's ratio ν ∈ (−1, 0.5).

    Returns
    -------
    numpy.ndarray [Pa]
        σ_H; NaN where an input is not physical, finite or plausible.

    References
    ----------
    Source paper (003), eq. (3) ([1] in the module docstring); see :func:`loaded_rollers` for the
    factor √2 between the reading as printed and the published stress.
    """
    inputs = dict(
        force=force,
        roller_length=roller_length,
        radius=radius,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
    )
    return st.nan_screened(_contact_stress, inputs, _domain(inputs))


def _contact_stress(*, force, roller_length, radius, youngs_modulus, poisson_ratio):
    return np.sqrt(
        np.asarray(force, float)
        * youngs_modulus
        / (2 * np.pi * (1 - np.square(poisson_ratio)) * roller_length * radius)
    )


def roller_mass(*, roller_diameter, roller_length, density=STEEL_DENSITY):
    """Mass of a solid cylindrical roller (10 x 15 mm steel: 9.25 g).

    Parameters
    ----------
    roller_diameter : float or array_like [m]
        Roller diameter.
    roller_length : float or array_like [m]
        Roller length.
    density : float or array_like [kg/m³]
        Density (steel 7850).

    Returns
    -------
    numpy.ndarray [kg]
        The mass; NaN where an input is not positive, finite and plausible.
    """
    inputs = dict(roller_diameter=roller_diameter, roller_length=roller_length, density=density)
    return st.nan_screened(_roller_mass, inputs, _domain(inputs))


def _roller_mass(*, roller_diameter, roller_length, density):
    return density * np.pi / 4 * np.square(roller_diameter) * roller_length


def spring_preload(*, roller_mass, contact_radius, friction_coefficient, speed, formula="exact"):
    """Spring force holding a roller in the wedge against its centrifugal force, equation (4).

    F_T ≥ μ·m·ω²·R_C (``exact``). The printed form 2R_Cμmn²/(18·10⁴) (R_C in mm, n in rpm;
    ``eq4``) is the same with π² taken as 10 (1.3 % higher): 800·m for the source paper's design,
    so the published 3.7 N implies m = 4.6 g, half the 9.25 g of a solid 10 x 15 mm roller.

    Parameters
    ----------
    roller_mass : float or array_like [kg]
        Roller mass m.
    contact_radius : float or array_like [m]
        Radius R_C of the rollers.
    friction_coefficient : float or array_like [-]
        Friction coefficient μ, in (0, 2].
    speed : float or array_like [rad/s]
        Speed ω ≥ 0.
    formula : {"exact", "eq4"}
        The exact form or the printed one.

    Returns
    -------
    numpy.ndarray [N]
        F_T; NaN where an input is not physical, finite or plausible.

    Raises
    ------
    ValueError
        For another ``formula``.

    References
    ----------
    Source paper (003), eq. (4) ([1] in the module docstring).
    """
    if formula not in ("exact", "eq4"):
        raise ValueError(f"formula must be 'exact' or 'eq4', got {formula!r}")
    inputs = dict(
        roller_mass=roller_mass,
        contact_radius=contact_radius,
        friction_coefficient=friction_coefficient,
        speed=speed,
    )
    return st.nan_screened(_spring_preload, inputs, _domain(inputs), extra={"formula": formula})


def _spring_preload(*, roller_mass, contact_radius, friction_coefficient, speed, formula):
    if formula == "eq4":
        n = np.asarray(speed, float) / RPM
        return (
            2
            * (np.asarray(contact_radius) * 1e3)
            * friction_coefficient
            * roller_mass
            * n**2
            / 18e4
        )
    return friction_coefficient * roller_mass * np.square(speed) * contact_radius


def self_locking_margin(*, wedge_angle, friction_coefficient):
    """Self-locking margin μ/tan(α/2) − 1 of a roller wedge.

    The roller locks without slipping at its contacts only if tan(α/2) < μ, i.e. where the margin
    is > 0. A margin in clutchlab is capacity over demand minus one (here the friction μ a contact
    can carry over the tan(α/2) the wedge asks of it), ≥ 0 where met; 11°, μ 0.12: 0.246 (the
    paper's ratio 1.25).

    Parameters
    ----------
    wedge_angle : float or array_like [rad]
        Wedge angle α, in (0, π/2).
    friction_coefficient : float or array_like [-]
        Friction coefficient μ, in (0, 2].

    Returns
    -------
    numpy.ndarray [-]
        The margin; NaN where an input is out of range.

    References
    ----------
    Source paper (003), section 1.1, step 4 ([1] in the module docstring).
    """
    inputs = dict(wedge_angle=wedge_angle, friction_coefficient=friction_coefficient)
    return st.nan_screened(_self_locking_margin, inputs, _domain(inputs))


def _self_locking_margin(*, wedge_angle, friction_coefficient):
    return (
        np.asarray(friction_coefficient, float) / np.tan(0.5 * np.asarray(wedge_angle, float)) - 1.0
    )


def limit_wedge_angle(friction_coefficient):
    """Largest self-locking wedge angle 2·atan(μ) (13.69° for μ = 0.12).

    Parameters
    ----------
    friction_coefficient : float or array_like [-]
        Friction coefficient μ, in (0, 2].

    Returns
    -------
    numpy.ndarray [rad]
        The angle; NaN unless μ is in (0, 2].

    References
    ----------
    Source paper (003), section 1.1, step 4 ([1] in the module docstring): tan(α/2) < μ.
    """
    inputs = dict(friction_coefficient=friction_coefficient)
    return st.nan_screened(
        lambda friction_coefficient: 2.0 * np.arctan(friction_coefficient),
        inputs,
        _domain(inputs),
    )


def engages(mode, direction=1):
    """Whether a working mode lets the clutch lock when driven in ``direction``.

    Bidirectional lock locks both ways; bidirectional overrun neither; one-way overrun forward
    locks only in reverse, and vice versa (the control ring holds the rollers out of the wedges of
    the overrunning direction).

    Parameters
    ----------
    mode : str
        One of :data:`MODES`.
    direction : int or array_like [-]
        +1 forward, −1 reverse; any other value (NaN, 0, 0.5) never locks.

    Returns
    -------
    numpy.ndarray of bool
        True where the clutch locks.

    Raises
    ------
    ValueError
        For an unknown ``mode``.

    References
    ----------
    Source paper (003), section 1 ([1] in the module docstring): the four working modes.
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    d = np.asarray(direction, dtype=float)
    valid = (d == 1.0) | (d == -1.0)
    if mode == "bidirectional_lock":
        return valid
    if mode == "bidirectional_overrun":
        return np.zeros(d.shape, bool)
    return valid & ((d < 0) if mode == "overrun_forward" else (d > 0))


_DOMAIN = {
    "driving_speed": st.positive_in("rad/s"),
    "load_torque": st.nonnegative_in("N m"),
    "wedge_inertia": st.positive_in("kg m^2"),
    "driven_inertia": st.positive_in("kg m^2"),
    "contact_radius": st.positive_in("m"),
    "rollers_loaded": st.count(1),
    "wedge_angle": st.between(0.0, np.pi / 2, lo_open=True, hi_open=True),
    "friction_coefficient": _MU,
    "spring_force": st.nonnegative_in("N"),
    "stiffness": st.positive_in("N/m^1.5"),
    "exponent": st.all_of(st.at_least(1.0), st.plausible("1", hi=MAX_EXPONENT)),
    "damping": st.nonnegative_in("N s/m"),
    "penetration_depth": st.positive_in("m"),
    "control_stop_time": st.nonnegative_or_inf_in("s"),
    "claw_clearance": st.nonnegative_in("m"),
    "end_time": st.positive_in("s"),
    "sync_tolerance": st.between(0.0, 1.0, hi_open=True),
    "max_step": st.positive_or_inf_in("s"),
}

#: parameter_rows' inputs in the order of its columns' unpacking (and of the screening)
_ROW_INPUTS = (
    "driving_speed",
    "load_torque",
    "wedge_inertia",
    "driven_inertia",
    "contact_radius",
    "rollers_loaded",
    "wedge_angle",
    "friction_coefficient",
    "spring_force",
    "stiffness",
    "exponent",
    "damping",
    "penetration_depth",
    "control_stop_time",
    "claw_clearance",
    "end_time",
    "max_step",
    "sync_tolerance",
)


def parameter_rows(
    *,
    driving_speed,
    load_torque,
    wedge_inertia,
    driven_inertia,
    contact_radius,
    rollers_loaded,
    wedge_angle,
    friction_coefficient,
    spring_force,
    stiffness,
    exponent=1.5,
    damping=2.1e6,
    penetration_depth=1e-4,
    control_stop_time=np.inf,
    claw_clearance=0.0,
    end_time=2e-3,
    sync_tolerance=0.01,
    max_step=np.inf,
):
    """The compiled kernel's parameter rows (one per scenario, broadcast) and their shape.

    A scenario with an input :func:`simulate` refuses has a row of NaN.

    Parameters
    ----------
    driving_speed : float or array_like [rad/s]
        Constant speed ω_d > 0 of the driving ring (2000 rpm in [1]).
    load_torque : float or array_like [N m]
        Passive load torque T_L ≥ 0: opposes the driven ring's motion, holds it at rest up to T_L.
    wedge_inertia, driven_inertia : float or array_like [kg m²]
        Inertias J_w of the wedge ring and J_o of the driven ring.
    contact_radius : float or array_like [m]
        Radius R_C of the rollers' contacts.
    rollers_loaded : int or array_like [-]
        Loaded rollers z (:func:`loaded_rollers`), a whole number in [1, 1000].
    wedge_angle : float or array_like [rad]
        Wedge angle α, in (0, π/2).
    friction_coefficient : float or array_like [-]
        Friction coefficient μ, in (0, 2].
    spring_force : float or array_like [N]
        Spring preload F_T ≥ 0 per roller.
    stiffness : float or array_like [N/m^exponent]
        Contact stiffness k of k·δ^e (:func:`clutchlab.contact.hertz_stiffness`).
    exponent : float or array_like [-]
        Exponent e of the contact law, in [1, 10] (1.5: Hertz).
    damping : float or array_like [N s/m]
        Contact damping c_max ≥ 0 (2.1e6: the 2.1e3 N·s/mm of [1]).
    penetration_depth : float or array_like [m]
        Depth d_max > 0 over which the damping rises to c_max.
    control_stop_time : float or array_like [s]
        Time at which the control ring stops (inf: no release).
    claw_clearance : float or array_like [m]
        Travel of the control ring's claws before they hold the rollers.
    end_time : float or array_like [s]
        End of the simulation.
    sync_tolerance : float or array_like [-]
        Engaged when the driven ring first reaches (1 − tolerance)·ω_d, in [0, 1).
    max_step : float or array_like [s]
        Largest integrator step (inf: no limit).

    Returns
    -------
    rows : numpy.ndarray
        (scenarios, :data:`clutchlab._contact_kernel.N_PARAM`) parameter rows.
    shape : tuple of int
        The broadcast shape of the inputs.
    """
    inputs = dict(locals())  # (first: the arguments only)
    args = np.broadcast_arrays(*(np.asarray(inputs[name], float) for name in _ROW_INPUTS))
    (wd, tl, jw, jo, rc, z, alpha, mu, ft, k, e, c, dmax, trel, clr, tend, hmax, eps) = (
        a.ravel() for a in args
    )
    P = np.zeros((wd.size, _sys.N_PARAM))
    with np.errstate(divide="ignore", invalid="ignore"):  # rows of invalid inputs are not simulated
        n0 = ft / (2.0 * np.sin(0.5 * alpha))  # preload normal force of the spring-held roller
        cols = {
            _sys.WD: wd,
            _sys.TL: tl,
            _sys.JW: jw,
            _sys.JO: jo,
            _sys.RC: rc,
            _sys.Z: z,
            _sys.TH: np.tan(0.5 * alpha),
            _sys.TA: np.tan(alpha),
            _sys.MU: mu,
            _sys.K: k,
            _sys.EXP: e,
            _sys.CD: c,
            _sys.DMAX: dmax,
            _sys.D0: (n0 / k) ** (1.0 / e),
            _sys.TREL: trel,
            _sys.CLR: clr,
            _sys.TEND: tend,
            _sys.HMAX: hmax,
            _sys.WSYNC: (1.0 - eps) * wd,
            _sys.TCLAW: trel + clr / (rc * wd),
        }
    for col, v in cols.items():
        P[:, col] = v
    _, ok = st.admissible(dict(zip(_ROW_INPUTS, args, strict=True)), _DOMAIN)
    P[~ok.ravel()] = np.nan
    return P, args[0].shape


def _check_options(rtol, max_steps, trace_points):
    if not (np.isscalar(rtol) and np.isfinite(rtol) and 0 < rtol < 1):
        raise ValueError(f"rtol must be a number in (0, 1), got {rtol!r}")
    if not (np.isscalar(max_steps) and 1 <= max_steps <= 1e9 and max_steps == int(max_steps)):
        raise ValueError(f"max_steps must be a whole number in [1, 1e9], got {max_steps!r}")
    if not (np.isscalar(trace_points) and 0 <= trace_points <= 1e7):
        raise ValueError(f"trace_points must be a number in [0, 1e7], got {trace_points!r}")


def simulate(*, rtol=1e-8, max_steps=200_000, trace_index=None, trace_points=20_000, **scenario):
    """Wedging (and release) of the roller clutch for a batch of scenarios (broadcast arrays).

    Parameters
    ----------
    rtol : float
        Integrator tolerance, in (0, 1): of the stick phase before the engagement, which sets the
        engagement time (the most sensitive output); the wedge ring's slip is integrated at 10
        times it and the phase after the engagement at 30 times it, up to 1e-3
        (:data:`clutchlab._contact_kernel.SLIP_RTOL_FACTOR`, ``ENGAGED_RTOL_FACTOR``,
        ``LOOSEST_RTOL``), which keeps the other outputs' errors below the engagement time's.
    max_steps : int
        Step attempts a scenario may spend, a whole number in [1, 1e9].
    trace_index : int or None
        The scenario whose trace is returned.
    trace_points : int
        Points of the trace, in [0, 1e7].
    **scenario : float or array_like
        The arguments of :func:`parameter_rows`, broadcast together, in SI units: driving_speed
        [rad/s], load_torque [N m], wedge_inertia and driven_inertia [kg m²], contact_radius [m],
        rollers_loaded [-], wedge_angle [rad], friction_coefficient [-], spring_force [N],
        stiffness [N/m^exponent], exponent [-] (1.5), damping [N s/m] (2.1e6), penetration_depth
        [m] (1e-4), control_stop_time [s] (inf: no release), claw_clearance [m] (0), end_time [s]
        (2e-3), sync_tolerance [-] (0.01: engaged when the driven ring first reaches 99 % of the
        driving speed), max_step [s].

    Returns
    -------
    dict of numpy.ndarray
        ``engagement_time`` [s], ``backlash`` [rad] (driving minus driven ring rotation at
        engagement), ``slip_backlash`` [rad] (its driving/wedge ring part), ``stick_time`` [s],
        ``peak_contact_force`` [N] (per roller, peaks located exactly), ``release_time`` [s] after
        the control ring stops, ``final_contact_force`` [N], ``n_steps``, ``n_fev``, ``status``
        (ok; never_locked; not_converged: ``max_steps`` step attempts (accepted, rejected or
        failed) spent; not_self_locking: tan(α/2) ≥ μ, not simulated; invalid_input: an input not
        finite, not physical (a roller count that is not a whole number in [1, 1000], ...) or of
        an implausible magnitude (:mod:`clutchlab.plausible`), not simulated, NaN); and ``trace``
        (columns t, ω_d, ω_w, ω_o, N) of scenario ``trace_index``.

    Raises
    ------
    ValueError
        If ``rtol``, ``max_steps`` or ``trace_points`` is out of range.

    References
    ----------
    Source paper (003), section 3 and Table 2 ([1] in the module docstring): the ADAMS model
    reduced as in the module docstring; published wedging time 0.197 ms, backlash 1.12°, release
    time 1.3 ms.
    """
    _check_options(rtol, max_steps, trace_points)
    P, shape = parameter_rows(**scenario)
    _, ok = st.admissible(scenario, {k: _DOMAIN[k] for k in scenario})
    ok = np.broadcast_to(ok, shape).ravel()
    th, mu = P[:, _sys.TH], P[:, _sys.MU]
    locks = ok & (th < mu)
    idx = np.flatnonzero(locks)
    row = -1 if trace_index is None else int(np.searchsorted(idx, trace_index))
    if trace_index is not None and (row >= idx.size or idx[row] != trace_index):
        row = -1
    out, trace = _k.simulate_roller(P[idx], float(rtol), int(max_steps), row, int(trace_points))
    full = np.full((P.shape[0], len(_k.RESULTS)), np.nan)
    full[idx] = out
    full[ok & ~locks, _k.STATUS] = st.CODE["not_self_locking"]
    full[~ok, _k.STATUS] = st.CODE["invalid_input"]
    res = {name: full[:, i].reshape(shape) for i, name in enumerate(_k.RESULTS)}
    res["status"] = res["status"].astype(st.DTYPE)
    res["trace"] = trace
    return res
