"""Centrifugal clutch with an overrunning linkage (the source paper (001), eqs. 1-2), and its
release after an engine failure.

z shoes of mass m at centroid radius r are held off a drum of radius R by springs (resultant
F_s) and pulled onto it by the centrifugal force F_r = m·ω_e²·r (the paper prints ω²r without
m: erratum). Each shoe is linked to the engine hub by a plate at pressure angle α. Per shoe,
forward (engine drives, eq. 1): F_p + F_s − F_r − F_l·sinα = 0, F_t = F_l·cosα = f·F_p; reverse
(the rotor back-drives a dead engine, eq. 2): the sign of F_l flips. Hence

    M  = z·f·R·(F_r − F_s)/(1 − f·tanα)      (forward capacity)
    M′ = z·f·R·(F_r − F_s)/(1 + f·tanα)      (reverse capacity)

both zero below the engagement speed ω₀ = √(F_s/(m·r)). f·tanα ≥ 1 makes the forward linkage
self-lock (jam): a design failure, flagged, never a number.

Engine failure at rated speed (closed form): while the clutch holds, engine and rotor turn
together, (J_e + J_r)·ω' = −T_p(ω) − k·ω² with the engine's passive (drag) torque
T_p(ω) = p₀ + p₂·ω² and rotor drag k·ω². The torque the rotor must send back through the clutch
to keep the dead engine turning with it is

    T_need(ω) = (J_r·T_p(ω) − J_e·k·ω²)/(J_e + J_r)

and the clutch lets go (release) at the first ω, going down from rated, where T_need ≥ M′(ω): a
quadratic in ω, solved exactly. The time to get there is the exact integral
t = (J_e + J_r)·∫ dω/(p₀ + (p₂ + k)·ω²). After release the engine slows under T_p − M′ and, as
M′ falls with ω_e², the release reinforces itself; below ω₀ the shoes are off the drum.

References
----------
.. [1] Sun R. (2017), "Design and test of a multi-function clutch for unmanned helicopters", the
   source paper (001), eqs. (1)-(2), Fig. 5 (capacity curves), Figs. 6-8 (speed traces).
"""

from __future__ import annotations

import numpy as np

from . import status as st

__all__ = [
    "centrifugal_force",
    "engagement_speed",
    "capacity",
    "linkage_factor_from_targets",
    "passive_torque",
    "needed_reverse_torque",
    "release_after_failure",
    "engine_failure_trace",
    "startup_trace",
    "design_status",
]


MAX_FRICTION_COEFFICIENT = 2.0  # shoe-drum dry friction is below about 1
MAX_FRICTION_SCATTER = 10.0  # relative rise of f a design must survive


def centrifugal_force(*, shoe_mass, shoe_radius, speed):
    """Centrifugal force F_r = m·ω²·r on one shoe.

    Parameters
    ----------
    shoe_mass : float or array_like [kg]
        Mass m of one shoe.
    shoe_radius : float or array_like [m]
        Centroid radius r of the shoe.
    speed : float or array_like [rad/s]
        Engine (shoe carrier) speed ω ≥ 0.

    Returns
    -------
    numpy.ndarray [N]
        F_r; NaN where m, r ≤ 0, ω < 0, or an input is not finite or plausible
        (:mod:`clutchlab.plausible`).

    Notes
    -----
    Erratum: the source paper (001) prints F_r = ω²r, without the shoe mass.

    References
    ----------
    Source paper (001), text after eq. (2) ([1] in the module docstring).
    """
    inputs = dict(shoe_mass=shoe_mass, shoe_radius=shoe_radius, speed=speed)
    return st.nan_screened(_centrifugal_force, inputs, _domain(inputs))


def _centrifugal_force(*, shoe_mass, shoe_radius, speed):
    return shoe_mass * np.square(speed) * shoe_radius


def engagement_speed(*, shoe_mass, shoe_radius, spring_force):
    """Engagement speed ω₀ = √(F_s/(m·r)), where the centrifugal force equals the spring resultant.

    Parameters
    ----------
    shoe_mass : float or array_like [kg]
        Mass m of one shoe.
    shoe_radius : float or array_like [m]
        Centroid radius r of the shoe.
    spring_force : float or array_like [N]
        Spring resultant F_s ≥ 0 per shoe.

    Returns
    -------
    numpy.ndarray [rad/s]
        ω₀ (≈ 2545 rpm for the source paper's design); NaN where m, r ≤ 0, F_s < 0, or an input
        is not finite or plausible.

    References
    ----------
    Source paper (001), eqs. (1)–(2) with F_p = 0 ([1] in the module docstring).
    """
    inputs = dict(shoe_mass=shoe_mass, shoe_radius=shoe_radius, spring_force=spring_force)
    return st.nan_screened(_engagement_speed, inputs, _domain(inputs))


def _engagement_speed(*, shoe_mass, shoe_radius, spring_force):
    return np.sqrt(spring_force / (shoe_mass * shoe_radius))


def capacity(
    *,
    speed,
    shoes,
    friction_coefficient,
    pressure_angle,
    shoe_mass,
    shoe_radius,
    drum_radius,
    spring_force,
):
    """Forward and reverse torque capacity of the centrifugal clutch with overrunning linkage.

    M = z·f·R·(F_r − F_s)/(1 − f·tanα) (engine drives), M′ = z·f·R·(F_r − F_s)/(1 + f·tanα) (the
    rotor back-drives a dead engine), F_r = m·ω²·r.

    Parameters
    ----------
    speed : float or array_like [rad/s]
        Engine (shoe carrier) speed ω_e ≥ 0.
    shoes : int or array_like [-]
        Number of shoes z, a whole number in [1, 1000] (3 fits the source paper's springs).
    friction_coefficient : float or array_like [-]
        Shoe–drum friction coefficient f, in (0, 2].
    pressure_angle : float or array_like [rad]
        Linkage pressure angle α, in [0, π/2).
    shoe_mass : float or array_like [kg]
        Mass m of one shoe.
    shoe_radius : float or array_like [m]
        Centroid radius r of a shoe, inside the drum (r < R).
    drum_radius : float or array_like [m]
        Drum radius R.
    spring_force : float or array_like [N]
        Spring resultant F_s ≥ 0 per shoe.

    Returns
    -------
    forward : numpy.ndarray [N m]
        M; zero below the engagement speed; NaN where f·tanα ≥ 1 (jammed forward linkage, see
        :func:`design_status`).
    reverse : numpy.ndarray [N m]
        M′; zero below the engagement speed. Both NaN where an input is not finite or not physical
        (ω, F_s < 0; z not a whole number in [1, 1000]; f outside (0, 2]; α outside [0, π/2); m,
        r, R ≤ 0), of an implausible magnitude (:mod:`clutchlab.plausible`), or where the shoe's
        centroid radius r is not inside the drum (r < R).

    References
    ----------
    Source paper (001), eqs. (1)–(2) ([1] in the module docstring), solved for M and M′; at
    5500 rpm M = 127.84 N·m and M′ = 65 N·m.
    """
    inputs = dict(
        speed=speed,
        shoes=shoes,
        friction_coefficient=friction_coefficient,
        pressure_angle=pressure_angle,
        shoe_mass=shoe_mass,
        shoe_radius=shoe_radius,
        drum_radius=drum_radius,
        spring_force=spring_force,
    )
    return st.nan_screened(_capacity, inputs, {**_domain(inputs), **_GEOMETRY})


def _capacity(
    *,
    speed,
    shoes,
    friction_coefficient,
    pressure_angle,
    shoe_mass,
    shoe_radius,
    drum_radius,
    spring_force,
):
    x = friction_coefficient * np.tan(pressure_angle)
    excess = np.maximum(
        _centrifugal_force(shoe_mass=shoe_mass, shoe_radius=shoe_radius, speed=speed)
        - spring_force,
        0.0,
    )
    base = shoes * friction_coefficient * drum_radius * excess
    with np.errstate(divide="ignore", invalid="ignore"):
        forward = np.where(_jammed(x), np.nan, base / (1.0 - x))
    return forward, base / (1.0 + x)


# f·tanα this close to 1 is jamming within the inputs' rounding: tan(45°) = 1 − 1.1e-16 in floating
# point, and 1/(1 − f·tanα) would otherwise give M ≈ 1e18 N m for f = 1, α = 45°
JAM_TOLERANCE = 1e-9


def _jammed(x):
    return ~(x < 1.0 - JAM_TOLERANCE)


def linkage_factor_from_targets(forward_torque, reverse_torque):
    """Linkage factor f·tanα from the forward and reverse capacity targets (equation 1 over 2).

    M/M′ = (1 + f·tanα)/(1 − f·tanα) ⇒ f·tanα = (M − M′)/(M + M′).

    Parameters
    ----------
    forward_torque : float or array_like [N m]
        Forward capacity target M > 0.
    reverse_torque : float or array_like [N m]
        Reverse capacity target M′, 0 < M′ ≤ M.

    Returns
    -------
    numpy.ndarray [-]
        f·tanα (0.32587 for the source paper's 127.84 and 65 N·m); NaN unless M ≥ M′ > 0, finite
        and plausible (a reverse target above the forward one has no linkage).

    References
    ----------
    Source paper (001), eqs. (1)–(2) divided ([1] in the module docstring).
    """
    inputs = dict(forward_torque=forward_torque, reverse_torque=reverse_torque)
    return st.nan_screened(
        _linkage_factor_from_targets,
        inputs,
        {**_domain(inputs), None: lambda a: a["forward_torque"] >= a["reverse_torque"]},
    )


def _linkage_factor_from_targets(*, forward_torque, reverse_torque):
    return (forward_torque - reverse_torque) / (forward_torque + reverse_torque)


def passive_torque(speed, *, rated_passive_torque, rated_speed, static_fraction):
    """Engine drag when back-driven, T_p(ω) = T_pr·[c₀ + (1 − c₀)(ω/ω_r)²].

    The paper gives only T_pr = 65.5 N·m at 5500 rpm (the Fig. 5 curve is not tabulated); the
    shape (friction part c₀, pumping part ∝ ω²) is an assumption.

    Parameters
    ----------
    speed : float or array_like [rad/s]
        Engine speed ω ≥ 0.
    rated_passive_torque : float or array_like [N m]
        Passive torque T_pr ≥ 0 at the rated speed.
    rated_speed : float or array_like [rad/s]
        Rated speed ω_r > 0.
    static_fraction : float or array_like [-]
        c₀ ∈ [0, 1], the share of T_pr that does not depend on speed.

    Returns
    -------
    numpy.ndarray [N m]
        T_p; NaN where an input is not finite, out of range or implausible.

    References
    ----------
    Source paper (001), Fig. 5 and its text ([1] in the module docstring): 65.5 N·m at 5500 rpm.
    """
    inputs = dict(
        speed=speed,
        rated_passive_torque=rated_passive_torque,
        rated_speed=rated_speed,
        static_fraction=static_fraction,
    )
    return st.nan_screened(_passive_torque, inputs, _domain(inputs))


def _passive_torque(*, speed, rated_passive_torque, rated_speed, static_fraction):
    u = np.asarray(speed, dtype=float) / rated_speed
    return rated_passive_torque * (static_fraction + (1.0 - static_fraction) * u * u)


def needed_reverse_torque(speed, *, engine_inertia, rotor_inertia, rotor_drag, p0, p2):
    """Torque the rotor must send back through a held clutch to carry the dead engine.

    T_need(ω) = (J_r·T_p(ω) − J_e·k·ω²)/(J_e + J_r) with T_p = p₀ + p₂·ω² (module docstring).

    Parameters
    ----------
    speed : float or array_like [rad/s]
        Common speed ω ≥ 0 of engine and rotor.
    engine_inertia : float or array_like [kg m²]
        Engine-side inertia J_e > 0 (engine, hub, shoes).
    rotor_inertia : float or array_like [kg m²]
        Rotor-side inertia J_r > 0, referred to the clutch.
    rotor_drag : float or array_like [N m s²]
        Rotor drag coefficient k ≥ 0 of k·ω².
    p0 : float or array_like [N m]
        Constant part p₀ ≥ 0 of the passive engine torque.
    p2 : float or array_like [N m s²]
        Quadratic coefficient p₂ ≥ 0 of the passive engine torque.

    Returns
    -------
    numpy.ndarray [N m]
        T_need; NaN where an input is not so, or not finite or plausible.
    """
    inputs = dict(
        speed=speed,
        engine_inertia=engine_inertia,
        rotor_inertia=rotor_inertia,
        rotor_drag=rotor_drag,
        p0=p0,
        p2=p2,
    )
    return st.nan_screened(_needed_reverse_torque, inputs, _domain(inputs))


def _needed_reverse_torque(*, speed, engine_inertia, rotor_inertia, rotor_drag, p0, p2):
    w2 = np.square(speed)
    return (rotor_inertia * (p0 + p2 * w2) - engine_inertia * rotor_drag * w2) / (
        engine_inertia + rotor_inertia
    )


def _drag_coefficients(rated_speed, rotor_load_torque, rated_passive_torque, static_fraction):
    """Rotor drag k [N m s²] of k·ω² and passive-torque coefficients p₀ [N m], p₂ [N m s²] of
    T_p = p₀ + p₂·ω² (see :func:`passive_torque`)."""
    w2 = np.square(rated_speed)
    return (
        rotor_load_torque / w2,
        rated_passive_torque * static_fraction,
        rated_passive_torque * (1.0 - static_fraction) / w2,
    )


# per-input rules: sign, finite, plausible magnitude (clutchlab.plausible)
_DOMAIN = {
    "speed": st.nonnegative_in("rad/s"),
    "rated_speed": st.positive_in("rad/s"),
    "shoes": st.count(1),
    "friction_coefficient": st.positive_in("1", hi=MAX_FRICTION_COEFFICIENT),
    "pressure_angle": st.between(0.0, np.pi / 2, hi_open=True),
    "shoe_mass": st.positive_in("kg"),
    "shoe_radius": st.positive_in("m"),
    "drum_radius": st.positive_in("m"),
    "spring_force": st.nonnegative_in("N"),
    "rotor_load_torque": st.nonnegative_in("N m"),
    "engine_inertia": st.positive_in("kg m^2"),
    "rotor_inertia": st.positive_in("kg m^2"),
    "rated_passive_torque": st.nonnegative_in("N m"),
    "static_fraction": st.between(0.0, 1.0),
    "friction_scatter": st.nonnegative_in("1", hi=MAX_FRICTION_SCATTER),
    "forward_torque": st.positive_in("N m"),
    "reverse_torque": st.positive_in("N m"),
    "rotor_drag": st.nonnegative_in("N m s^2"),
    "p0": st.nonnegative_in("N m"),
    "p2": st.nonnegative_in("N m s^2"),
}
# the shoe's centroid lies inside the drum it is pulled onto
_GEOMETRY = {None: lambda a: a["shoe_radius"] < a["drum_radius"]}


def _domain(names):
    return {k: _DOMAIN[k] for k in names}


def release_after_failure(
    *,
    rated_speed,
    shoes,
    friction_coefficient,
    pressure_angle,
    shoe_mass,
    shoe_radius,
    drum_radius,
    spring_force,
    engine_inertia,
    rotor_inertia,
    rotor_load_torque,
    rated_passive_torque,
    static_fraction,
):
    """Release speed and time after the engine dies at rated speed (closed form, exact).

    The clutch lets go at the first ω, going down from rated, where the needed reverse torque
    (:func:`needed_reverse_torque`) reaches the reverse capacity M′(ω): a quadratic in ω; the time
    to get there is the exact integral of the held run-down (module docstring).

    Parameters
    ----------
    rated_speed : float or array_like [rad/s]
        Speed ω_r at the failure, > 0.
    shoes : int or array_like [-]
        Number of shoes z, a whole number in [1, 1000] (3 fits the source paper's springs).
    friction_coefficient : float or array_like [-]
        Shoe–drum friction coefficient f, in (0, 2].
    pressure_angle : float or array_like [rad]
        Linkage pressure angle α, in [0, π/2).
    shoe_mass : float or array_like [kg]
        Mass m of one shoe.
    shoe_radius : float or array_like [m]
        Centroid radius r of a shoe, inside the drum (r < R).
    drum_radius : float or array_like [m]
        Drum radius R.
    spring_force : float or array_like [N]
        Spring resultant F_s ≥ 0 per shoe.
    engine_inertia : float or array_like [kg m²]
        Engine-side inertia J_e (engine, hub, shoes).
    rotor_inertia : float or array_like [kg m²]
        Rotor-side inertia J_r (rotor and drivetrain, referred to the clutch).
    rotor_load_torque : float or array_like [N m]
        Rotor drag T_L at rated speed; k = T_L/ω_r².
    rated_passive_torque : float or array_like [N m]
        Passive engine torque at rated speed (:func:`passive_torque`).
    static_fraction : float or array_like [-]
        Speed-independent share of the passive torque, in [0, 1] (:func:`passive_torque`).

    Returns
    -------
    dict of numpy.ndarray
        ``release_speed`` [rad/s] (engine = rotor speed when the clutch lets go), ``release_time``
        [s] after the failure (0: at once; inf with a release speed of NaN where nothing drags
        the rotor down: it never lets go), ``released_at_once`` (bool), ``status`` (ok, or
        ``invalid_input`` with NaN where an input is not finite or not physical: a negative
        passive torque or drag, a static fraction outside [0, 1], a count that is not whole, ...,
        or of an implausible magnitude (:mod:`clutchlab.plausible`); ``invalid_geometry`` where
        the shoe's centroid radius is not inside the drum).

    References
    ----------
    Source paper (001), eq. (2) and the release argument after it, Figs. 7–8 ([1] in the module
    docstring).
    """
    inputs = dict(
        rated_speed=rated_speed,
        shoes=shoes,
        friction_coefficient=friction_coefficient,
        pressure_angle=pressure_angle,
        shoe_mass=shoe_mass,
        shoe_radius=shoe_radius,
        drum_radius=drum_radius,
        spring_force=spring_force,
        engine_inertia=engine_inertia,
        rotor_inertia=rotor_inertia,
        rotor_load_torque=rotor_load_torque,
        rated_passive_torque=rated_passive_torque,
        static_fraction=static_fraction,
    )
    return st.screened(_release_after_failure, inputs, _domain(inputs), geometry=_GEOMETRY)


def _release_after_failure(
    *,
    rated_speed,
    shoes,
    friction_coefficient,
    pressure_angle,
    shoe_mass,
    shoe_radius,
    drum_radius,
    spring_force,
    engine_inertia,
    rotor_inertia,
    rotor_load_torque,
    rated_passive_torque,
    static_fraction,
):
    k, p0, p2 = _drag_coefficients(
        rated_speed, rotor_load_torque, rated_passive_torque, static_fraction
    )
    j = engine_inertia + rotor_inertia
    a_rev = (
        shoes
        * friction_coefficient
        * drum_radius
        / (1.0 + friction_coefficient * np.tan(pressure_angle))
    )
    w0 = _engagement_speed(shoe_mass=shoe_mass, shoe_radius=shoe_radius, spring_force=spring_force)
    # g(ω) = T_need(ω) − M′(ω) = c2·ω² + c0 on ω ≥ ω₀ (release where g ≥ 0)
    c2 = (rotor_inertia * p2 - engine_inertia * k) / j - a_rev * shoe_mass * shoe_radius
    c0 = rotor_inertia * p0 / j + a_rev * spring_force
    g_rated = c2 * np.square(rated_speed) + c0
    at_once = g_rated >= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(-c0 / c2)  # c0 > 0: a root in (ω₀, ω_r) needs c2 < 0
    w_rel = np.where(
        at_once, rated_speed, np.where((c2 < 0) & (root > w0), np.minimum(root, rated_speed), w0)
    )
    w_rel = np.minimum(w_rel, rated_speed)
    t_rel = j * _inverse_quadratic_integral(p0, p2 + k, w_rel, rated_speed)
    never = ~at_once & ~np.isfinite(t_rel)  # no drag at all: the rotor never slows to release
    return {
        "release_speed": np.where(never, np.nan, w_rel),
        "release_time": np.where(at_once, 0.0, t_rel),
        "released_at_once": at_once,
        "status": np.full(np.shape(w_rel), st.CODE["ok"], dtype=st.DTYPE),
    }


def _inverse_quadratic_integral(a, c, lo, hi):
    """∫_lo^hi dω/(a + c·ω²) for a ≥ 0, c ≥ 0, exact; a term below rounding of the other over
    [lo, hi] is left out (a denormal a, or c = 0: no drag growing with speed)."""
    a, c, lo, hi = (np.asarray(v, dtype=float) for v in (a, c, lo, hi))
    eps = np.finfo(float).eps
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        quadratic = a <= eps * c * lo * lo  # ∫ dω/(c·ω²)
        constant = ~quadratic & (c * hi * hi <= eps * a)  # ∫ dω/a
        both = ~quadratic & ~constant
        ra = np.sqrt(np.where(both, a, 1.0))
        rc = np.sqrt(np.where(both, c, 1.0))
        # atan difference as one atan (no cancellation when lo ≈ hi)
        at = np.arctan2(rc / ra * (hi - lo), 1.0 + c / np.where(both, a, 1.0) * lo * hi) / (ra * rc)
        pure = (hi - lo) / (c * lo * hi)
        flat = (hi - lo) / a
    return np.where(quadratic, pure, np.where(constant, flat, at))


def design_status(
    *,
    rated_speed,
    shoes,
    friction_coefficient,
    pressure_angle,
    shoe_mass,
    shoe_radius,
    drum_radius,
    spring_force,
    rotor_load_torque,
    friction_scatter=0.0,
):
    """Status of a centrifugal-clutch design at rated speed.

    Parameters
    ----------
    rated_speed : float or array_like [rad/s]
        Rated engine speed, > 0.
    shoes : int or array_like [-]
        Number of shoes z, a whole number in [1, 1000] (3 fits the source paper's springs).
    friction_coefficient : float or array_like [-]
        Shoe–drum friction coefficient f, in (0, 2].
    pressure_angle : float or array_like [rad]
        Linkage pressure angle α, in [0, π/2).
    shoe_mass : float or array_like [kg]
        Mass m of one shoe.
    shoe_radius : float or array_like [m]
        Centroid radius r of a shoe, inside the drum (r < R).
    drum_radius : float or array_like [m]
        Drum radius R.
    spring_force : float or array_like [N]
        Spring resultant F_s ≥ 0 per shoe.
    rotor_load_torque : float or array_like [N m]
        Rotor load at rated speed that the forward capacity must carry, ≥ 0.
    friction_scatter : float or array_like [-]
        Relative rise of f the design must survive without jamming, in [0, 10].

    Returns
    -------
    numpy.ndarray of int8
        ``jammed`` where f·tanα ≥ 1 (to within :data:`JAM_TOLERANCE`); ``not_engaged`` where the
        springs beat the centrifugal force at rated speed or the forward capacity there is below
        the rotor load; ``near_jam`` where the design works but a friction coefficient higher by
        the relative ``friction_scatter`` would jam it, (1 + scatter)·f·tanα ≥ 1: its forward
        capacity M ∝ 1/(1 − f·tanα) is near-singular there (exact, but a few percent more
        friction multiplies it); ``invalid_input`` where an input is not finite or not physical or
        of an implausible magnitude (:mod:`clutchlab.plausible`); ``invalid_geometry`` where the
        shoe's centroid radius is not inside the drum; else ``ok`` (codes of
        :mod:`clutchlab.status`).

    References
    ----------
    Source paper (001), eq. (1) ([1] in the module docstring): the forward linkage self-locks
    (jams) as f·tanα → 1.
    """
    inputs = dict(
        rated_speed=rated_speed,
        shoes=shoes,
        friction_coefficient=friction_coefficient,
        pressure_angle=pressure_angle,
        shoe_mass=shoe_mass,
        shoe_radius=shoe_radius,
        drum_radius=drum_radius,
        spring_force=spring_force,
        rotor_load_torque=rotor_load_torque,
        friction_scatter=friction_scatter,
    )
    return st.screened(_design_status, inputs, _domain(inputs), geometry=_GEOMETRY)["status"]


def _design_status(
    *,
    rated_speed,
    shoes,
    friction_coefficient,
    pressure_angle,
    shoe_mass,
    shoe_radius,
    drum_radius,
    spring_force,
    rotor_load_torque,
    friction_scatter,
):
    fwd, _ = _capacity(
        speed=rated_speed,
        shoes=shoes,
        friction_coefficient=friction_coefficient,
        pressure_angle=pressure_angle,
        shoe_mass=shoe_mass,
        shoe_radius=shoe_radius,
        drum_radius=drum_radius,
        spring_force=spring_force,
    )
    weak = (
        _centrifugal_force(shoe_mass=shoe_mass, shoe_radius=shoe_radius, speed=rated_speed)
        <= spring_force
    ) | (fwd < rotor_load_torque)
    x = friction_coefficient * np.tan(pressure_angle)
    code = np.where(
        _jammed(x),
        st.CODE["jammed"],
        np.where(
            weak,
            st.CODE["not_engaged"],
            np.where(_jammed(x * (1.0 + friction_scatter)), st.CODE["near_jam"], st.CODE["ok"]),
        ),
    )
    return {"status": code.astype(st.DTYPE)}


def _params(p):
    """Unpack a scenario dict (scalars) into what the traces need."""
    k, p0, p2 = _drag_coefficients(
        p["rated_speed"], p["rotor_load_torque"], p["rated_passive_torque"], p["static_fraction"]
    )

    def caps(we):
        return _capacity(
            speed=we,
            **{
                n: p[n]
                for n in (
                    "shoes",
                    "friction_coefficient",
                    "pressure_angle",
                    "shoe_mass",
                    "shoe_radius",
                    "drum_radius",
                    "spring_force",
                )
            },
        )

    return k, p0, p2, caps


# what each trace reads of a scenario dict
_TRACE_KEYS = (
    "rated_speed",
    "shoes",
    "friction_coefficient",
    "pressure_angle",
    "shoe_mass",
    "shoe_radius",
    "drum_radius",
    "spring_force",
    "engine_inertia",
    "rotor_inertia",
    "rotor_load_torque",
    "rated_passive_torque",
    "static_fraction",
)
#: right-hand-side evaluations an integration of a trace may spend (the seed traces take 1 200 and
#: 3 400; DOP853 takes 12 a step); beyond, not_converged
TRACE_MAX_EVALUATIONS = 100_000


class _OutOfWork(Exception):
    pass


def _counted(f):
    """``f`` that raises :class:`_OutOfWork` after :data:`TRACE_MAX_EVALUATIONS` calls."""
    calls = [0]

    def g(*args):
        calls[0] += 1
        if calls[0] > TRACE_MAX_EVALUATIONS:
            raise _OutOfWork
        return f(*args)

    return g


def _trace_status(p, extra=None, relations=None):
    """Status code of a trace's scalar scenario ``p`` (plus ``extra`` inputs with their rules):
    invalid_input, invalid_geometry or ok."""
    extra = extra or {}
    missing = [k for k in _TRACE_KEYS if k not in p]
    if missing:
        raise KeyError(f"the scenario lacks {', '.join(missing)}")
    inputs = {k: p[k] for k in _TRACE_KEYS} | {k: v for k, (v, _) in extra.items()}
    rules = _domain(_TRACE_KEYS) | {k: r for k, (_, r) in extra.items()} | (relations or {})
    _, ok = st.admissible(inputs, rules)
    if not ok:
        return st.CODE["invalid_input"]
    _, fits = st.admissible(inputs, _GEOMETRY)
    return st.CODE["ok"] if fits else st.CODE["invalid_geometry"]


def _check_trace_options(t_end, n, rtol, atol):
    if not (np.isscalar(t_end) and st.positive_in("s")(np.asarray(t_end, float))):
        raise ValueError(f"t_end must be a plausible time > 0 s, got {t_end!r}")
    if not (np.isscalar(n) and 2 <= n <= 1e6 and n == int(n)):
        raise ValueError(f"n must be a whole number in [2, 1e6], got {n!r}")
    for name, v in (("rtol", rtol), ("atol", atol)):
        if not (np.isscalar(v) and np.isfinite(v) and 0 < v < 1):
            raise ValueError(f"{name} must be a number in (0, 1), got {v!r}")


def _failed_trace(times, code, scalars):
    nan = np.full(times.size, np.nan)
    return {
        "time": times,
        "engine_speed": nan,
        "rotor_speed": nan.copy(),
        "clutch_torque": nan.copy(),
        **{k: np.nan for k in scalars},
        "status": code,
    }


def engine_failure_trace(p, *, t_end=3.0, n=301, rtol=1e-10, atol=1e-10):
    """Speeds after an engine failure at rated speed for one scenario.

    Held phase (one inertia) until the release event T_need = M′, then engine and rotor apart:
    J_e·ω_e' = −T_p(ω_e) + M′(ω_e), J_r·ω_r' = −k·ω_r² − M′(ω_e); the engine stops at 0.
    Integrated with scipy's DOP853 with the release located as an event (a check of the closed
    form :func:`release_after_failure`).

    Parameters
    ----------
    p : dict
        The scalar parameters of :func:`release_after_failure` (SI units as there).
    t_end : float [s]
        End of the trace, a plausible time > 0.
    n : int
        Number of output points, in [2, 1e6].
    rtol, atol : float
        Tolerances of the integration, in (0, 1).

    Returns
    -------
    dict
        ``time`` [s], ``engine_speed``, ``rotor_speed`` [rad/s], ``clutch_torque`` [N m]
        (positive forward), ``release_time`` [s] (inf: still held at ``t_end``),
        ``release_speed`` [rad/s] (NaN then), ``status``: ok;
        invalid_input / invalid_geometry (NaN) where ``p`` fails the screening of
        :func:`release_after_failure`; not_converged (NaN) where the integration spends more than
        :data:`TRACE_MAX_EVALUATIONS` evaluations.

    Raises
    ------
    ValueError
        If ``t_end``, ``n``, ``rtol`` or ``atol`` is out of range.
    KeyError
        If ``p`` lacks a parameter.

    References
    ----------
    Source paper (001), Fig. 8 ([1] in the module docstring): speeds after an engine failure with
    the overrunning clutch.
    """
    _check_trace_options(t_end, n, rtol, atol)
    times = np.linspace(0.0, t_end, int(n))
    code = _trace_status(p)
    if code == st.CODE["ok"]:
        try:
            return _engine_failure_trace(p, times, rtol, atol)
        except _OutOfWork:
            code = st.CODE["not_converged"]
    return _failed_trace(times, code, ("release_time", "release_speed"))


def _engine_failure_trace(p, times, rtol, atol):
    from scipy.integrate import solve_ivp

    t_end, n = float(times[-1]), times.size
    k, p0, p2, caps = _params(p)
    je, jr = p["engine_inertia"], p["rotor_inertia"]

    def need_minus_cap(w):
        return (
            _needed_reverse_torque(
                speed=w, engine_inertia=je, rotor_inertia=jr, rotor_drag=k, p0=p0, p2=p2
            )
            - caps(w)[1]
        )

    w_r = p["rated_speed"]
    if need_minus_cap(w_r) >= 0:
        t_rel, w_rel = 0.0, w_r
    else:
        ev = lambda t, y: need_minus_cap(y[0])  # noqa: E731
        ev.terminal, ev.direction = True, 1
        sol = solve_ivp(
            _counted(lambda t, y: [-(p0 + (p2 + k) * y[0] ** 2) / (je + jr)]),
            (0.0, t_end),
            [w_r],
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=ev,
            dense_output=True,
        )
        t_rel = float(sol.t_events[0][0]) if sol.t_events[0].size else np.inf
        w_rel = float(sol.y_events[0][0][0]) if sol.t_events[0].size else np.nan
    we = np.full(n, np.nan)
    wr = np.full(n, np.nan)
    tc = np.full(n, np.nan)
    held = times <= t_rel
    if np.any(held) and t_rel > 0:
        yy = sol.sol(times[held])[0]
        we[held] = wr[held] = yy
        tc[held] = -_needed_reverse_torque(
            speed=yy, engine_inertia=je, rotor_inertia=jr, rotor_drag=k, p0=p0, p2=p2
        )
    elif t_rel == 0.0:  # released at once: both at rated speed at t = 0, slipping from there
        we[0] = wr[0] = w_r
        tc[0] = -caps(w_r)[1]
    if np.isfinite(t_rel):

        def free(t, y):
            e = max(y[0], 0.0)
            m_rev = caps(e)[1]
            de = (-(p0 + p2 * e * e) + m_rev) / je if y[0] > 0 else 0.0
            return [de, (-k * y[1] ** 2 - m_rev) / jr]

        stop = lambda t, y: y[0]  # noqa: E731
        stop.terminal, stop.direction = True, -1
        after = times[times > t_rel]
        s2 = solve_ivp(
            _counted(free),
            (t_rel, t_end),
            [w_rel, w_rel],
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=stop,
            dense_output=True,
        )
        t_stop = s2.t[-1]
        moving = after <= t_stop
        sel = np.flatnonzero(times > t_rel)
        if np.any(moving):
            yy = s2.sol(after[moving])
            we[sel[moving]], wr[sel[moving]] = yy[0], yy[1]
        if np.any(~moving):  # engine at rest: the rotor runs down free
            # (the stop at once: no step, no dense output)
            w_stop = s2.sol(t_stop)[1] if s2.t.size > 1 else s2.y[1, -1]
            tt = after[~moving] - t_stop
            we[sel[~moving]] = 0.0
            wr[sel[~moving]] = w_stop / (1.0 + k * w_stop * tt / jr)
        tc[sel] = -caps(np.maximum(we[sel], 0.0))[1]
    return {
        "time": times,
        "engine_speed": we,
        "rotor_speed": wr,
        "clutch_torque": tc,
        "release_time": t_rel,
        "release_speed": w_rel,
        "status": st.CODE["ok"],
    }


def startup_trace(p, *, idle_speed, startup_time, t_end=None, n=301, rtol=1e-10, atol=1e-10):
    """Start-up of one scenario: the rotor picked up by the forward capacity as the engine runs up.

    Engine speed ramped from idle to rated over ``startup_time``; the rotor (drag k·ω²) slips while
    J_r·ω_r' = M(ω_e) − k·ω_r² keeps ω_r < ω_e, then turns with the engine. DOP853 with the lock-up
    as an event.

    Parameters
    ----------
    p : dict
        The scalar parameters of :func:`release_after_failure` (SI units as there).
    idle_speed : float [rad/s]
        Engine speed at the start, ≥ 0 and below the rated speed.
    startup_time : float [s]
        Duration of the engine's ramp from idle to rated, a plausible time > 0.
    t_end : float or None [s]
        End of the trace (default 1.5·``startup_time``).
    n : int
        Number of output points, in [2, 1e6].
    rtol, atol : float
        Tolerances of the integration, in (0, 1).

    Returns
    -------
    dict
        ``time`` [s], ``engine_speed``, ``rotor_speed`` [rad/s], ``clutch_torque`` [N m],
        ``lockup_time`` [s] (inf: not locked by ``t_end``), ``lockup_speed`` [rad/s], ``status``:
        ok; invalid_input / invalid_geometry (NaN) where ``p`` fails the screening of
        :func:`release_after_failure`, the idle speed is not ≥ 0 and below the rated speed, or the
        start-up time is not a plausible time > 0; not_converged (NaN) beyond
        :data:`TRACE_MAX_EVALUATIONS` evaluations.

    Raises
    ------
    ValueError
        If ``t_end``, ``n``, ``rtol`` or ``atol`` is out of range.
    KeyError
        If ``p`` lacks a parameter.

    References
    ----------
    Source paper (001), Fig. 6 ([1] in the module docstring): speeds of a normal run.
    """
    extra = {
        "idle_speed": (idle_speed, _DOMAIN["speed"]),
        "startup_time": (startup_time, st.positive_in("s")),
    }
    below = {None: lambda a: a["idle_speed"] < a["rated_speed"]}
    code = _trace_status(p, extra, below)
    if t_end is None:  # (1 s for a start-up time that is no time: its trace is NaN anyway)
        t_end = 1.5 * startup_time if code == st.CODE["ok"] else 1.0
    _check_trace_options(t_end, n, rtol, atol)
    times = np.linspace(0.0, t_end, int(n))
    if code == st.CODE["ok"]:
        try:
            return _startup_trace(p, idle_speed, startup_time, times, rtol, atol)
        except _OutOfWork:
            code = st.CODE["not_converged"]
    return _failed_trace(times, code, ("lockup_time", "lockup_speed"))


def _startup_trace(p, idle_speed, startup_time, times, rtol, atol):
    from scipy.integrate import solve_ivp

    k, _, _, caps = _params(p)
    jr, w_r = p["rotor_inertia"], p["rated_speed"]
    t_end = float(times[-1])
    rate = (w_r - idle_speed) / startup_time

    def w_e(t):
        return np.minimum(idle_speed + rate * t, w_r)

    @_counted
    def rhs(t, y):
        return [(caps(w_e(t))[0] - k * y[0] ** 2) / jr]

    lock = lambda t, y: w_e(t) - y[0]  # noqa: E731
    lock.terminal, lock.direction = True, -1
    sol = solve_ivp(
        rhs,
        (0.0, startup_time),
        [0.0],
        method="DOP853",
        rtol=rtol,
        atol=atol,
        events=lock,
        dense_output=True,
        max_step=startup_time / 200,
    )
    if not sol.t_events[0].size:
        s2 = solve_ivp(
            rhs,
            (startup_time, t_end),
            sol.y[:, -1],
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=lock,
            dense_output=True,
        )
        t_lock = float(s2.t_events[0][0]) if s2.t_events[0].size else np.inf
    else:
        s2, t_lock = None, float(sol.t_events[0][0])
    we = w_e(times)
    wr = np.where(times >= t_lock, we, np.nan)
    slip = times < t_lock
    first = slip & (times <= startup_time)
    wr[first] = sol.sol(times[first])[0]
    if s2 is not None:
        second = slip & (times > startup_time)
        wr[second] = s2.sol(times[second])[0]
    tc = np.where(slip, caps(we)[0], jr * np.where(times < startup_time, rate, 0.0) + k * we**2)
    return {
        "time": times,
        "engine_speed": we,
        "rotor_speed": wr,
        "clutch_torque": tc,
        "lockup_time": t_lock,
        "lockup_speed": float(w_e(t_lock)) if np.isfinite(t_lock) else np.nan,
        "status": st.CODE["ok"],
    }
