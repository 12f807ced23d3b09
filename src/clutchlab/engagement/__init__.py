"""Clutch engagement of a two-inertia driveline (seed 000 eqs. 1-2, 11, 12), batched.

Engine side (eq. 1) J_e·dω_e/dt = T_e − T_c; driven side (eq. 2) J_v·dω_c/dt = T_c − T_m.
While slipping T_c = sign(Δω)·μ(abs(Δω))/μ_k · C(t) with the kinetic capacity
C(t) = C_max·p(t/t_r) (p a clamp profile: linear ramp, cubic or quintic smooth step, 1 after
t_r); while stuck T_c is whatever keeps both sides together, as long as it stays within the
static capacity (μ_s/μ_k)·C(t). The driven side stays parked at rest while the clutch torque is
below the (static) load torque. An engine with ``engine_inertia = inf`` is held at its speed.

Two solvers, one contract (same inputs, same metrics):

* :func:`closed_form` — constant μ, constant torques, polynomial clamp profile, held or free
  engine: speeds are piecewise polynomials in t, lock-up is a polynomial root (bracketed, to
  machine precision), slip/load/input work are exact Gauss-Legendre integrals.
  ≈ 0.7 µs per scenario at 10⁶ scenarios; it is also the reference for the numerical solver.
* :func:`simulate` — everything else (Stribeck μ, rotor drag k·ω², engine torque table, load
  step, compliant driveline): a Dormand-Prince 5(4) integrator (compiled with numba) with per-scenario step
  sizes, breakpoints at the profile end and load step, and an event-driven stick/slip state
  machine whose events are located on the integrator's own solution (re-integration from the
  step's left end and a Newton correction), i.e. to the integrator's accuracy, not to the step
  size.

References
----------
.. [1] Zhao P. (2026), seed 000, eqs. (1), (2), (11), (12), Figs. 7-11.
.. [2] Otter M., Elmqvist H., Mattsson S.E. (1999), "Hybrid modeling in Modelica based on the
   synchronous data flow principle" (friction state machine of the Modelica Standard Library).
"""

from __future__ import annotations

import numpy as np

from .. import status as st
from . import _kernel as _k

__all__ = [
    "PROFILES",
    "clamp_profile",
    "bearing_travel_clamp",
    "closed_form",
    "simulate",
    "ramp_time_for_lockup",
]

PROFILES = ("ramp", "cubic", "quintic")
# profile p(x) on [0, 1] and its integral P(x) = ∫0^x p, as ascending polynomial coefficients
_P = {
    "ramp": np.array([0.0, 1.0]),
    "cubic": np.array([0.0, 0.0, 3.0, -2.0]),  # ADAMS STEP (cubic)
    "quintic": np.array([0.0, 0.0, 0.0, 10.0, -15.0, 6.0]),  # STEP5-like quintic
}


def _polyval(c, x):
    out = np.zeros_like(x) + c[-1]
    for a in c[-2::-1]:
        out = out * x + a
    return out


def _integral_coeffs(c):
    return np.concatenate([[0.0], c / np.arange(1, len(c) + 1)])


def _check_profile(kind):
    if kind not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {kind!r}")


def clamp_profile(x, kind="ramp"):
    """Clamp (capacity) profile p(x), x = t/t_r, clipped to [0, 1] outside [0, 1] [-].

    Parameters
    ----------
    x : array_like
        Time over ramp time t/t_r [-]; ±inf is before the start or after the end; NaN gives NaN.
    kind : {"ramp", "cubic", "quintic"}
        The profile (ValueError for another).
    """
    _check_profile(kind)
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    return _polyval(_P[kind], x)


def _capacity(t, c_max, t_r, kind):
    """C(t) = C_max·p(t/t_r); a zero ramp time is a step at t = 0+."""
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(t_r > 0, t / np.where(t_r > 0, t_r, 1.0), 1.0)  # a step is applied at t = 0
    return c_max * clamp_profile(x, kind)


def _capacity_rate(t, c_max, t_r, kind):
    """dC/dt (one-sided, from the right at breakpoints)."""
    dp = np.polynomial.polynomial.polyder(_P[kind])
    tr = np.where(t_r > 0, t_r, 1.0)
    x = t / tr
    return np.where(
        (t_r > 0) & (x < 1.0) & (x >= 0.0), c_max * _polyval(dp, np.clip(x, 0, 1)) / tr, 0.0
    )


def bearing_travel_clamp(x, *, air_gap, cushion_travel, kind="ramp"):
    """Clamp force fraction F/F_B of the release-bearing travel model [-] at x = t/t_r.

    The bearing travel follows the profile p(x) from full release (p = 0) to engaged (p = 1);
    the pressure plate lifts by (1 − p)·(g + c) (rigid fingers: travel over lever ratio), g the
    air gap and c the travel of the lining cushion (a linear spring carrying F_B when fully
    compressed, F_B = the diaphragm spring's load at its operating point, eq. 10). The clamp force
    is the cushion force: F/F_B = max(0, 1 − κ(1 − p)), κ = (g + c)/c. The diaphragm curve sets F_B
    and the bearing force (:func:`clutchlab.studies.engagement.bearing_force`), not the shape.

    Parameters
    ----------
    x : array_like
        t/t_r [-] (see :func:`clamp_profile`).
    air_gap : array_like
        g ≥ 0 [m].
    cushion_travel : array_like
        c > 0 [m].
    kind : {"ramp", "cubic", "quintic"}

    Returns
    -------
    numpy.ndarray
        F/F_B [-]; NaN where x is NaN or g, c are not finite, negative (c: not positive) or of
        an implausible magnitude (:mod:`clutchlab.plausible`).
    """
    _check_profile(kind)
    return st.nan_screened(
        _bearing_travel_clamp,
        dict(x=x, air_gap=air_gap, cushion_travel=cushion_travel),
        {
            "x": lambda v: ~np.isnan(v),
            "air_gap": st.nonnegative_in("m"),
            "cushion_travel": st.positive_in("m"),
        },
        extra={"kind": kind},
    )


def _bearing_travel_clamp(*, x, air_gap, cushion_travel, kind):
    kappa = (np.asarray(air_gap, float) + cushion_travel) / cushion_travel
    return np.maximum(0.0, 1.0 - kappa * (1.0 - clamp_profile(x, kind)))


def _invert_profile(q, kind):
    """x in [0, 1] with p(x) = q (p is monotone), vectorised bisection + Newton to round-off."""
    q = np.clip(q, 0.0, 1.0)
    if kind == "ramp":
        return q
    c, dc = _P[kind], np.polynomial.polynomial.polyder(_P[kind])
    lo, hi = np.zeros_like(q), np.ones_like(q)
    x = q.copy()
    done = np.zeros(q.shape, bool)  # per scenario: a converged x is frozen (batch-independent)
    for _ in range(60):
        f = _polyval(c, x) - q
        lo = np.where(f < 0, x, lo)
        hi = np.where(f >= 0, x, hi)
        d = _polyval(dc, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - f / d
        bad = ~((xn > lo) & (xn < hi))
        xn = np.where(bad, 0.5 * (lo + hi), xn)
        now = np.abs(xn - x) <= 4e-16
        x = np.where(done, x, xn)
        done = done | now
        if done.all():
            break
    return x


# plausible limits of dimensionless inputs (beyond them a value is a slip, never a clutch)
MAX_STATIC_RATIO = 10.0  # μ_s/μ_k (dry friction: 1 to about 1.5)
MAX_DAMPING_RATIO = 100.0  # ζ of the damper springs (a clutch damper: 0.02 to about 1)
MAX_RELEASE_RATIO = 1e4  # κ = (air gap + cushion travel)/cushion travel
MIN_HUB_FRACTION = 1e-6  # share of J_v on the plate hub (and 1 − it on the output)

# admissible per-scenario inputs (anything else: status invalid_input, NaN outputs): sign, finite
# where inf means nothing, and a magnitude within clutchlab.plausible's range of the unit
_DOMAIN = {
    "engine_speed": st.nonnegative_in("rad/s"),
    "engine_inertia": st.positive_or_inf_in("kg m^2"),
    "engine_torque": st.finite_in("N m"),
    "driven_inertia": st.positive_in("kg m^2"),
    "load_torque": st.nonnegative_in("N m"),
    "peak_capacity": st.nonnegative_in("N m"),
    "ramp_time": st.nonnegative_in("s"),
    "static_ratio": st.all_of(st.at_least(1.0), st.plausible("1", hi=MAX_STATIC_RATIO)),
    "driven_speed": st.nonnegative_in("rad/s"),
    "t_end": st.positive_or_inf_in("s"),
    None: lambda a: a["driven_speed"] <= a["engine_speed"],
}


def _simulate_relations(a):
    """Relations between simulate's inputs: ω_c(0) ≤ ω_e(0); the load after a step not negative
    (it is also the static torque that parks the output); fade needs the face temperature
    (factor > 0) and a window its kernel fit covers."""
    return (
        _DOMAIN[None](a)
        & ((a["load_torque"] + a["load_step"] >= 0) | (a["load_step_time"] == np.inf))
        & (
            (a["fade_coefficient"] == 0)
            | ((a["face_temperature_factor"] > 0) & (a["t_end"] <= _k.SOE_TMAX))
        )
    )


_DOMAIN_SIMULATE = {
    **_DOMAIN,
    "t_end": st.positive_in("s"),
    "stribeck_speed": st.positive_or_inf_in("rad/s"),
    "aero_coefficient": st.nonnegative_in("N m s^2"),
    "load_step": st.finite_in("N m"),
    "load_step_time": st.nonnegative_or_inf_in("s"),
    "hub_fraction": st.between(MIN_HUB_FRACTION, 1.0 - MIN_HUB_FRACTION),
    "damper_stiffness": st.positive_or_inf_in("N m/rad"),
    "damping_ratio": st.nonnegative_in("1", hi=MAX_DAMPING_RATIO),
    "release_ratio": st.all_of(st.at_least(1.0), st.plausible("1", hi=MAX_RELEASE_RATIO)),
    "fade_coefficient": st.nonnegative_in("1/K"),
    # a temperature difference [K]: any plausible rise, from a millikelvin
    "fade_onset": st.nonnegative_in("K", lo=1e-3),
    "face_temperature_factor": st.nonnegative_in("K/(W s^0.5)"),
    None: _simulate_relations,
}


def _check_solver_options(rtol, atol, max_step, first_step, max_steps, trace_times):
    """Refuse solver options that cannot be meant (shared by all scenarios: ValueError naming
    the argument)."""
    for name, v in (("rtol", rtol), ("atol", atol)):
        if not (np.isscalar(v) and np.isfinite(v) and 0 < v < 1):
            raise ValueError(f"{name} must be a number in (0, 1), got {v!r}")
    if not (np.isscalar(max_step) and max_step > 0):
        raise ValueError(f"max_step must be > 0 s (inf: no limit), got {max_step!r}")
    if first_step is not None and not (np.isscalar(first_step) and 0 < first_step < np.inf):
        raise ValueError(f"first_step must be None or a finite step > 0 s, got {first_step!r}")
    if not (np.isscalar(max_steps) and 1 <= max_steps <= MAX_WORK and max_steps == int(max_steps)):
        raise ValueError(
            f"max_steps must be a whole number in [1, {MAX_WORK:.0e}], got {max_steps!r}"
        )
    if trace_times is not None and not np.all(np.isfinite(np.asarray(trace_times, float))):
        raise ValueError("trace_times must be finite")


MAX_WORK = 1e9  # the largest work budget a scenario may be given (max_steps)


def closed_form(
    *,
    engine_speed,
    engine_inertia,
    engine_torque,
    driven_inertia,
    load_torque,
    peak_capacity,
    ramp_time,
    profile="ramp",
    static_ratio=1.0,
    driven_speed=0.0,
    t_end=np.inf,
    power_history=False,
):
    """Exact engagement for constant μ, constant torques and a polynomial clamp profile.

    Parameters
    ----------
    engine_speed : array_like
        Initial engine speed ω_e(0) [rad/s].
    engine_inertia : array_like
        J_e [kg m²]; ``inf`` holds the engine at ω_e(0) (as in seed 000's reproduction).
    engine_torque : array_like
        Constant engine torque T_e [N m] (ignored for a held engine).
    driven_inertia : array_like
        J_v [kg m²].
    load_torque : array_like
        Constant load torque T_m ≥ 0 [N m]; also the static torque that keeps a driven side at
        rest parked.
    peak_capacity : array_like
        Kinetic torque capacity at full clamp C_max = z_f·μ_k·F_max·R_eff [N m].
    ramp_time : array_like
        Clamp profile duration t_r [s]; 0 is a step.
    profile : {"ramp", "cubic", "quintic"}
        Clamp profile p.
    static_ratio : array_like
        μ_s/μ_k ≥ 1 (static capacity after lock-up).
    driven_speed : array_like
        Initial driven speed 0 ≤ ω_c(0) ≤ ω_e(0) [rad/s].
    t_end : array_like
        End of the window [s]; a scenario not locked by then is ``never_locked``.

    Returns
    -------
    dict of numpy.ndarray
        ``lockup_time`` [s] (NaN if never locked), ``lockup_speed`` [rad/s], ``slip_work`` (eq. 11),
        ``load_work``, ``input_work``, ``kinetic_energy_change`` [J], ``energy_residual`` [-]
        (relative), ``peak_slip_power`` [W], ``peak_friction_torque`` [N m],
        ``capacity_at_lockup`` [N m], ``accel_jump`` [rad/s²] (driven acceleration after minus
        before lock-up; a rigid model has a Dirac jerk there), ``slip_jerk`` [rad/s³] (driven
        jerk dT_c/dt/J_v at the end of slip, eq. 12), ``status``. Works are over [0, t_lock]
        (or [0, t_end] if never locked). A scenario with an input outside its domain (NaN; J ≤ 0;
        T_m, C_max, t_r or ω_e < 0; μ_s/μ_k < 1; ω_c(0) outside [0, ω_e(0)]) has status
        ``invalid_input`` and NaN outputs; the others are computed as if it were not there.
        With ``power_history``, ``flash_peak`` [W s^0.5] as :func:`simulate` gives it: the peak of
        Duhamel's integral ∫ P(τ)/√(t − τ) dτ of the exact slip power, sampled at
        ``CLOSED_FORM_POWER_SAMPLES`` points on each of its polynomial pieces (parked, moving on
        the profile, after it; P linear between samples, each segment integrated exactly).
    """
    _check_profile(profile)
    return st.screened(
        _closed_form,
        dict(
            engine_speed=engine_speed,
            engine_inertia=engine_inertia,
            engine_torque=engine_torque,
            driven_inertia=driven_inertia,
            load_torque=load_torque,
            peak_capacity=peak_capacity,
            ramp_time=ramp_time,
            static_ratio=static_ratio,
            driven_speed=driven_speed,
            t_end=t_end,
        ),
        _DOMAIN,
        extra={"profile": profile, "power_history": power_history},
    )


def _closed_form(
    *,
    engine_speed,
    engine_inertia,
    engine_torque,
    driven_inertia,
    load_torque,
    peak_capacity,
    ramp_time,
    static_ratio,
    driven_speed,
    t_end,
    profile,
    power_history=False,
):
    arrs = np.broadcast_arrays(
        *(
            np.asarray(v, dtype=float)
            for v in (
                engine_speed,
                engine_inertia,
                engine_torque,
                driven_inertia,
                load_torque,
                peak_capacity,
                ramp_time,
                static_ratio,
                driven_speed,
                t_end,
            )
        )
    )
    shape = arrs[0].shape
    flat = [a.astype(float).ravel() for a in arrs]
    n = flat[0].size
    if n > _BLOCK:  # cache-sized blocks: ~4x faster than whole-array temporaries at 1e6 scenarios
        parts = [
            _closed_form_flat([a[i : i + _BLOCK] for a in flat], profile, power_history)
            for i in range(0, n, _BLOCK)
        ]
        return {k: np.concatenate([p[k] for p in parts]).reshape(shape) for k in parts[0]}
    return {k: v.reshape(shape) for k, v in _closed_form_flat(flat, profile, power_history).items()}


_BLOCK = 8192
CLOSED_FORM_POWER_SAMPLES = 96  # slip power samples on each polynomial piece (flash_peak)


# noqa reason: the closed form's phases in the paper's order, one branch per case
def _closed_form_flat(flat, profile, power_history=False):  # noqa: C901
    we0, je, te, jv, tm, cmax, tr, rs, wc0, tend = flat
    held = ~np.isfinite(je)
    inv_je = np.where(held, 0.0, 1.0 / np.where(held, 1.0, je))
    te = np.where(held, 0.0, te)
    inv_jv = 1.0 / jv
    step = tr <= 0
    trs = np.where(step, 1.0, tr)
    pc, big_p = _P[profile], _integral_coeffs(_P[profile])

    inv_tr = 1.0 / trs
    any_step = bool(step.any())

    def cap_icap(t):
        x = np.minimum(t * inv_tr, 1.0)
        if not any_step:
            if profile == "ramp":  # p = x, P = x²/2 without the general Horner loop; rounded
                # as _polyval rounds it, so that a batch with a step gives the same numbers
                return cmax * x, cmax * (trs * (0.5 * x * x) + np.maximum(t - tr, 0.0))
            return cmax * _polyval(pc, x), cmax * (
                trs * _polyval(big_p, x) + np.maximum(t - tr, 0.0)
            )
        c = cmax * np.where(step, 1.0, _polyval(pc, x))
        ic = cmax * (
            np.where(step, 0.0, trs * _polyval(big_p, x))
            + np.maximum(t - np.where(step, 0.0, tr), 0.0)
        )
        return c, ic

    # phase 1: the driven side is at rest (parked by the static load) while C(t) < T_m. It is parked
    # from t = 0 if it starts at rest; if it starts turning it decelerates and parks at t_p when
    # its speed reaches zero before C reaches T_m (at t0). It moves again from t0 on.
    with np.errstate(divide="ignore", invalid="ignore"):
        q = tm / cmax
    moves = (tm <= 0.0) | (q < 1.0)
    t_m = np.where(
        (tm > 0) & moves & ~step, trs * _invert_profile(np.where(moves, q, 0.0), profile), 0.0
    )
    _, ic_m = cap_icap(t_m)
    wc_at_tm = wc0 + inv_jv * (ic_m - tm * t_m)
    starts_parked = (wc0 <= 0.0) & (tm > 0.0)
    parks_later = (wc0 > 0.0) & (tm > 0.0) & (wc_at_tm < 0.0)
    t_p = np.where(starts_parked, 0.0, np.inf)
    if np.any(parks_later):
        # ω_c = wc0 + (Ic(t) − T_m t)/J_v is decreasing on [0, t_m]: root by bisection + Newton
        def w_moving(t):  # driven speed and its rate before parking
            c, ic = cap_icap(t)
            return wc0 + inv_jv * (ic - tm * t), (c - tm) * inv_jv

        t_p = np.where(
            parks_later,
            _newton_bracketed(w_moving, np.zeros_like(t_m), t_m, 0.5 * t_m, parks_later),
            t_p,
        )
    parked_phase = starts_parked | parks_later
    t0 = np.where(parked_phase, t_m, 0.0)
    moves = moves | ~parked_phase
    _, ic0 = cap_icap(t0)

    all_parked_from_start = bool(
        starts_parked.all()
    )  # the usual case: the driven side starts at rest

    def state(t):
        """(C, Δω, ω_e, ω_c) at t (t ≥ 0), piecewise polynomial."""
        c, ic = cap_icap(t)
        we = we0 + inv_je * (te * t - ic)
        moving = inv_jv * np.where(moves & (t > t0), ic - ic0 - tm * (t - t0), 0.0)
        if all_parked_from_start:
            return c, we - moving, we, moving
        wc = np.where(t < t_p, wc0 + inv_jv * (ic - tm * t), moving)
        wc = np.where(parked_phase, wc, wc0 + inv_jv * (ic - tm * t))
        return c, we - wc, we, wc

    # phase 2: Δω' = A − B·C(t): concave on the ramp, linear after it
    a_coef = te * inv_je + tm * inv_jv
    b_coef = inv_je + inv_jv
    ramp_end = np.where(step, t0, np.maximum(tr, t0))
    s_end = state(ramp_end)[1]
    root_on_ramp = moves & ~step & (tr > t0) & (s_end <= 0.0)
    t_lock = np.full_like(we0, np.inf)
    if profile == "ramp":  # Δω = K + A t − (B a / 2) t² on the moving ramp: quadratic root
        a_r = cmax / trs
        k0 = state(t0)[1] - a_coef * t0 + 0.5 * b_coef * a_r * t0**2
        disc = np.sqrt(np.maximum(a_coef**2 + 2.0 * b_coef * a_r * k0, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r_pos = np.where(
                a_coef >= 0, (a_coef + disc) / (b_coef * a_r), -2.0 * k0 / (a_coef - disc)
            )
        t_lock = np.where(root_on_ramp, np.clip(r_pos, t0, ramp_end), t_lock)
    elif np.any(root_on_ramp):
        with np.errstate(divide="ignore", invalid="ignore"):
            qa = a_coef / (b_coef * cmax)
        t_top = np.where(
            qa >= 1.0, ramp_end, np.maximum(t0, trs * _invert_profile(np.clip(qa, 0, 1), profile))
        )
        lo = np.where(root_on_ramp, np.minimum(t_top, ramp_end), 0.0)
        hi = np.where(root_on_ramp, ramp_end, 1.0)

        def slip_rate(t):
            c, dw, _, _ = state(t)
            return dw, a_coef - b_coef * c

        t_lock = np.where(
            root_on_ramp, _newton_bracketed(slip_rate, lo, hi, hi.copy(), root_on_ramp), t_lock
        )
    rate = b_coef * cmax - a_coef  # −Δω' after the ramp
    after = moves & ~root_on_ramp & (rate > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_lock = np.where(after, ramp_end + np.maximum(s_end, 0.0) / rate, t_lock)
    # initial slip exactly zero: stuck from the start if the static capacity suffices (never sign(0))
    with np.errstate(divide="ignore", invalid="ignore"):
        need0 = np.where(held, tm, (tm + jv * te * inv_je) / (1.0 + jv * inv_je))
    stuck0 = (we0 - wc0 == 0.0) & (
        np.abs(need0) <= rs * cmax * np.where(step, 1.0, _polyval(pc, 0.0))
    )
    t_lock = np.where(stuck0, 0.0, t_lock)
    locked = np.isfinite(t_lock) & (t_lock <= tend)
    t_stop = np.where(locked, t_lock, tend)
    finite_window = np.isfinite(t_stop)
    t_stop = np.where(finite_window, t_stop, 0.0)

    # exact works: Gauss-Legendre with just enough nodes on each polynomial piece
    nodes = {"ramp": 2, "cubic": 4, "quintic": 6}[profile]  # exact: integrands of degree 2n-1
    gx, gw = np.polynomial.legendre.leggauss(nodes)
    knots = list(
        np.sort(
            np.stack(
                [
                    np.zeros_like(t_stop),
                    np.minimum(t_p, t_stop),
                    np.minimum(t0, t_stop),
                    np.minimum(ramp_end, t_stop),
                    t_stop,
                ]
            ),
            axis=0,
        )
    )
    w_slip = w_in = w_load = 0.0
    for a, b in zip(knots[:-1], knots[1:], strict=False):
        half, mid = 0.5 * (b - a), 0.5 * (b + a)
        for xg, wg in zip(gx, gw, strict=False):
            c, dw, we, wc = state(mid + half * xg)
            wt = wg * half
            w_slip = w_slip + wt * c * dw
            w_load = w_load + wt * tm * wc
            w_in = w_in + wt * np.where(held, c * we0, te * we)
    c_lock, _, we_end, wc_end = state(t_stop)
    wc_end = np.where(locked & held, we0, wc_end)  # at lock both sides turn together
    dke = 0.5 * jv * (wc_end**2 - wc0**2) + 0.5 * np.where(held, 0.0, je) * (we_end**2 - we0**2)
    residual = (w_in - dke - w_slip - w_load) / np.maximum(
        np.maximum(np.abs(w_in), np.abs(w_slip)), 1e-300
    )
    peak_power = _peak_power(state, knots, profile, cmax / trs, inv_je, te, we0, a_coef, b_coef, t0)

    acc_before = (c_lock - tm) * inv_jv
    with np.errstate(divide="ignore", invalid="ignore"):
        acc_after = np.where(held, 0.0, (te - tm) * inv_je / (1.0 + jv * inv_je))
    code = np.where(locked, st.CODE["ok"], st.CODE["never_locked"]).astype(st.DTYPE)
    nan = np.where(locked, 1.0, np.nan)
    out = {
        "lockup_time": np.where(locked, t_lock, np.nan),
        "lockup_speed": wc_end * nan,
        "slip_work": w_slip,
        "load_work": w_load,
        "input_work": w_in,
        "kinetic_energy_change": dke,
        "energy_residual": residual,
        "peak_slip_power": peak_power,
        "peak_friction_torque": c_lock,
        "capacity_at_lockup": c_lock * nan,
        "accel_jump": (acc_after - acc_before) * nan,
        "slip_jerk": _slip_jerk(t0, t_p, t_stop, parks_later, cmax, tr, profile) * inv_jv,
        "status": code,
    }
    if power_history:
        # the slip power on each piece between the knots (zero-length pieces give repeated times,
        # which the history skips); 0 from lock-up on
        frac = np.linspace(0.0, 1.0, CLOSED_FORM_POWER_SAMPLES + 1)[:-1]
        times = np.concatenate(
            [
                a[:, None] + (b - a)[:, None] * frac[None, :]
                for a, b in zip(knots[:-1], knots[1:], strict=False)
            ]
            + [t_stop[:, None]],
            axis=1,
        )
        power = np.empty_like(times)
        for j in range(times.shape[1]):
            c, dw, _, _ = state(times[:, j])
            power[:, j] = c * dw
        power[:, -1] = np.where(locked, 0.0, power[:, -1])
        out["flash_peak"] = _k.flash_peaks(times, power)
    for k, v in out.items():
        if k != "status":
            out[k] = np.where(finite_window, v, np.nan)
    return out


def _peak_power(state, knots, profile, a_r, inv_je, te, we0, a_coef, b_coef, t0):
    """max of the slip power C·Δω over [0, t_stop].

    Linear ramp: the power is a cubic on each ramp piece, so its stationary points are quadratic
    roots (evaluated with the end points). Smooth steps: golden-section search (unimodal).
    """
    t_stop = knots[-1]
    cands = list(knots)
    if profile == "ramp":
        with np.errstate(divide="ignore", invalid="ignore"):
            # parked piece: P = a t (ω_e0 + J_e⁻¹(T_e t − a t²/2)) -> P' = a(ω_e0 + 2J_e⁻¹T_e t − 1.5 J_e⁻¹ a t²)
            qa, qb, qc = 1.5 * inv_je * a_r, -2.0 * inv_je * te, -we0
            cands.append(
                np.where(
                    qa > 0, (-qb + np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0))) / (2 * qa), 0.0
                )
            )
            # moving ramp piece: P = a t (K + A t − B a t²/2) -> P' = a(K + 2A t − 1.5 B a t²)
            k0 = state(t0)[1] - a_coef * t0 + 0.5 * b_coef * a_r * t0**2
            qa, qb, qc = 1.5 * b_coef * a_r, -2.0 * a_coef, -k0
            cands.append((-qb + np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0))) / (2 * qa))
            # moving from t = 0 (driven initially turning): same form with K = Δω(0)
            qc = -state(np.zeros_like(t0))[1]
            cands.append((-qb + np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0))) / (2 * qa))
        best = np.zeros_like(t_stop)
        for t in cands:
            t = np.clip(np.nan_to_num(t, nan=0.0), 0.0, t_stop)
            c, dw, _, _ = state(t)
            best = np.maximum(best, c * dw)
        return best
    lo, hi = np.zeros_like(t_stop), t_stop.copy()
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    for _ in range(48):
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        c1, d1, _, _ = state(x1)
        c2, d2, _, _ = state(x2)
        better = c1 * d1 >= c2 * d2
        hi, lo = np.where(better, x2, hi), np.where(better, lo, x1)
    c, dw, _, _ = state(0.5 * (lo + hi))
    best = c * dw
    for t in knots:
        c, dw, _, _ = state(t)
        best = np.maximum(best, c * dw)
    return np.maximum(best, 0.0)


def _peak_rate(a, b, c_max, t_r, kind):
    """max of dC/dt over [a, b] (p' is constant for the ramp, unimodal with its top at x = 1/2 else)."""
    tr = np.where(t_r > 0, t_r, 1.0)
    xa, xb = np.clip(a / tr, 0, 1), np.clip(b / tr, 0, 1)
    dp = np.polynomial.polynomial.polyder(_P[kind])
    cand = np.maximum(_polyval(dp, xa), _polyval(dp, xb))
    cand = np.where(
        (xa <= 0.5) & (xb >= 0.5), np.maximum(cand, _polyval(dp, np.full_like(xa, 0.5))), cand
    )
    return np.where((t_r > 0) & (xb > xa), c_max * cand / tr, np.where(t_r > 0, 0.0, np.inf))


def _slip_jerk(t0, t_p, t_stop, parks_later, c_max, t_r, kind):
    """max of dC/dt while the driven side moves [N m/s]: from t0 to the stop, and for a driven side
    that first decelerates to rest (it parks at t_p) over [0, t_p] too."""
    rate = _peak_rate(t0, t_stop, c_max, t_r, kind)
    if np.any(parks_later):
        early = _peak_rate(
            np.zeros_like(t0), np.where(parks_later, np.minimum(t_p, t_stop), 0.0), c_max, t_r, kind
        )
        rate = np.where(parks_later, np.maximum(rate, early), rate)
    return rate


def _newton_bracketed(fun, lo, hi, x, mask):
    """Root of fun on [lo, hi] where fun(lo) > 0 ≥ fun(hi): Newton safeguarded by bisection.

    ``fun(x)`` returns (value, derivative); vectorised, to round-off.
    """
    lo, hi = lo.copy(), hi.copy()
    done = ~mask  # per scenario: a converged x is frozen, so that a scenario's root does not
    # depend on how long the other scenarios of its batch take to converge
    for _ in range(100):
        f, d = fun(x)
        lo = np.where(f > 0, x, lo)
        hi = np.where(f <= 0, x, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - f / d
        bad = ~((xn >= lo) & (xn <= hi)) | ~np.isfinite(xn)
        xn = np.where(bad, 0.5 * (lo + hi), xn)
        now = (np.abs(xn - x) <= 2e-16 * np.abs(x)) | (hi - lo <= 4e-16 * np.abs(hi))
        x = np.where(done, x, xn)
        done = done | now
        if done.all():
            break
    return x


def ramp_time_for_lockup(target_lockup_time, **kwargs):
    """Ramp time t_r that makes :func:`closed_form` lock up at ``target_lockup_time`` [s] (scalar).

    Used to reproduce the paper's "engagement shortened to 0.1 s / extended to 0.2 s" variants.

    Parameters
    ----------
    target_lockup_time : float
        The lock-up time wanted [s].
    **kwargs
        The other (scalar) inputs of :func:`closed_form`.

    Returns
    -------
    float
        t_r [s] in [1e-6 s, 10·target]; NaN where the target is not a plausible time, an input is
        invalid (:func:`closed_form` gives no lock-up time), or no ramp time in that bracket
        reaches the target.
    """
    from scipy.optimize import brentq

    target = float(target_lockup_time)
    if not st.positive_in("s")(np.asarray(target)):
        return np.nan

    def f(tr):
        return float(closed_form(ramp_time=tr, **kwargs)["lockup_time"]) - target

    lo, hi = 1e-6, 10.0 * target
    f_lo, f_hi = f(lo), f(hi)
    if not (np.isfinite(f_lo) and np.isfinite(f_hi) and f_lo * f_hi <= 0):
        return np.nan
    return brentq(f, lo, hi, xtol=1e-15, rtol=1e-15)


# ----------------------------------------------------------------------------------------------
# Numerical solver (event-driven DOPRI5; the per-scenario loop is compiled, see _kernel)
# ----------------------------------------------------------------------------------------------

EVENT_TIME_TOL = _k.EVENT_TIME_TOL


def _check_table(table, name, x_name, y_name, y_positive):
    """(x, y) arrays of a shared table: at least one point, finite, x increasing (≥ 0 for the
    friction table), y > 0 where asked, every value of a plausible magnitude (speeds [rad/s];
    torques [N m], or friction ratios μ/μ_k ≤ MAX_STATIC_RATIO); else ValueError naming it."""
    try:
        tx, ty = (np.asarray(a, dtype=float).ravel() for a in table)
    except (TypeError, ValueError):
        raise ValueError(
            f"{name} must be a pair ({x_name}, {y_name}) of equal-length sequences"
        ) from None
    if (
        tx.size == 0
        or tx.size != ty.size
        or not (np.all(np.isfinite(tx)) and np.all(np.isfinite(ty)))
    ):
        raise ValueError(
            f"{name}: {x_name} and {y_name} must be finite and of equal, non-zero length"
        )
    if np.any(np.diff(tx) <= 0):
        raise ValueError(f"{name}: {x_name} must increase")
    if y_positive and (tx[0] < 0 or np.any(ty <= 0)):
        raise ValueError(f"{name}: {x_name} must be >= 0 and {y_name} > 0")
    y_rule = st.plausible("1", hi=MAX_STATIC_RATIO) if y_positive else st.plausible("N m")
    if not (np.all(st.plausible("rad/s")(tx)) and np.all(y_rule(ty))):
        raise ValueError(f"{name}: {x_name} or {y_name} of an implausible magnitude")
    return tx, ty


def _parameter_table(
    *,
    engine_speed,
    engine_inertia,
    engine_torque,
    driven_inertia,
    load_torque,
    peak_capacity,
    ramp_time,
    profile,
    static_ratio,
    stribeck_speed,
    driven_speed,
    aero_coefficient,
    load_step,
    load_step_time,
    engine_torque_table,
    hub_fraction,
    damper_stiffness,
    damping_ratio,
    release_ratio,
    t_end,
    friction_table=None,
    fade_coefficient=0.0,
    fade_onset=0.0,
    face_temperature_factor=0.0,
):
    """The kernel's parameter table (one row per scenario, columns of :mod:`._kernel`)
    and the scenarios' broadcast shape."""
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {profile!r}")
    vals = {
        _k.WE0: engine_speed,
        _k.JE: engine_inertia,
        _k.TE: engine_torque,
        _k.JV: driven_inertia,
        _k.TM0: load_torque,
        _k.CMAX: peak_capacity,
        _k.TR: ramp_time,
        _k.RS: static_ratio,
        _k.VS: stribeck_speed,
        _k.WC0: driven_speed,
        _k.KA: aero_coefficient,
        _k.DTM: load_step,
        _k.TSTEP: load_step_time,
        _k.PHI: hub_fraction,
        _k.K: damper_stiffness,
        _k.ZETA: damping_ratio,
        _k.TEND: t_end,
        _k.KAPPA: release_ratio,
        _k.FADE: fade_coefficient,
        _k.FADE_ON: fade_onset,
        _k.FACE_K: face_temperature_factor,
    }
    arrs = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in vals.values()))
    shape = arrs[0].shape
    tx = ty = fx = fy = np.zeros(0)
    if engine_torque_table is not None:
        tx, ty = _check_table(
            engine_torque_table, "engine_torque_table", "speeds", "torques", False
        )
    if friction_table is not None:
        fx, fy = _check_table(
            friction_table, "friction_table", "slip speeds", "friction ratios", True
        )
    ftab = _k.N_PARAM + 1 + 2 * tx.size  # the shared tables ride on every row
    Q = np.empty((arrs[0].size, ftab + (1 + 2 * fx.size if fx.size else 0)))
    for col, a in zip(vals, arrs, strict=False):
        Q[:, col] = a.ravel()
    Q[:, _k.NTAB] = tx.size
    Q[:, _k.NTAB + 1 : _k.NTAB + 1 + tx.size] = tx
    Q[:, _k.NTAB + 1 + tx.size : ftab] = ty
    Q[:, _k.FTAB] = ftab if fx.size else 0.0
    if fx.size:
        Q[:, ftab] = fx.size
        Q[:, ftab + 1 : ftab + 1 + fx.size] = fx
        Q[:, ftab + 1 + fx.size :] = fy
    kappa = Q[:, _k.KAPPA]
    with np.errstate(divide="ignore"):  # the cushion is touched (kink of C(t)) where p = 1 − 1/κ
        Q[:, _k.TCON] = np.where(
            kappa > 1.0, Q[:, _k.TR] * _invert_profile(1.0 - 1.0 / kappa, profile), 0.0
        )
    held = ~np.isfinite(Q[:, _k.JE])
    Q[:, _k.HELD] = held
    Q[:, _k.INV_JE] = np.where(held, 0.0, 1.0 / np.where(held, 1.0, Q[:, _k.JE]))
    Q[:, _k.JH] = Q[:, _k.PHI] * Q[:, _k.JV]
    Q[:, _k.JR] = (1.0 - Q[:, _k.PHI]) * Q[:, _k.JV]
    with np.errstate(invalid="ignore"):
        Q[:, _k.CD] = np.where(
            np.isfinite(Q[:, _k.K]),
            2.0 * Q[:, _k.ZETA] * np.sqrt(Q[:, _k.K] * Q[:, _k.JH] * Q[:, _k.JR] / Q[:, _k.JV]),
            0.0,
        )
    return Q, shape


# metrics an event after the window would change: NaN in a ``truncated`` scenario
_TRUNCATED_NAN = [
    getattr(_k, n.upper())
    for n in (
        "lockup_time",
        "breakaway_time",
        "capacity_at_lockup",
        "accel_jump",
        "lockup_speed",
        "peak_slip_power",
        "peak_friction_torque",
        "peak_jerk",
        "slip_work",
        "flash_peak",
    )
]


# the result columns that are metrics (not solver counts or flags)
_METRIC_COLUMNS = np.array(
    [
        not (n.startswith("n_") or n in ("final_locked", "hit_step_limit", "truncated"))
        for n in _k.RESULTS
    ]
)


def simulate(
    *,
    engine_speed,
    engine_inertia,
    engine_torque,
    driven_inertia,
    load_torque,
    peak_capacity,
    ramp_time,
    profile="ramp",
    static_ratio=1.0,
    stribeck_speed=np.inf,
    driven_speed=0.0,
    aero_coefficient=0.0,
    load_step=0.0,
    load_step_time=np.inf,
    engine_torque_table=None,
    compliant=False,
    hub_fraction=0.5,
    damper_stiffness=np.inf,
    damping_ratio=0.0,
    release_ratio=1.0,
    t_end=0.5,
    rtol=1e-10,
    atol=1e-10,
    max_step=np.inf,
    first_step=None,
    max_steps=200000,
    trace_times=None,
    power_history=False,
    friction_table=None,
    fade_coefficient=0.0,
    fade_onset=0.0,
    face_temperature_factor=0.0,
):
    """Engagement by a Dormand-Prince 5(4) integrator with exact stick-slip events.

    Every scenario has its own step sizes; steps end on breakpoints (profile end, load step, trace
    times, end). Events — LOCK (slip reaches zero), BREAK (the torque needed to stay stuck exceeds
    the static capacity μ_s/μ_k·C), UNPARK / PARK (a driven side held by its static load starts or
    stops), PEAK (maximum slip power) — are detected at the step end, the step middle and the
    interior extrema of the cubic Hermite interpolant of the LOCK and PARK functions (so a sign
    change and back inside one step is not missed), then located: root on the step's order-4
    continuous extension, one re-integration from the step's left end to it, then Newton
    (secant) along the local Taylor line y + σ·f(y), accepted when the line's own error is
    below 10 % of the tolerance (else re-integrate to the corrected time and repeat; Illinois
    with re-integration, bracket ≤ max(``EVENT_TIME_TOL``, 0.01·rtol·h), as the last resort); a
    located step must itself meet the tolerance (PEAK only records a value: its time and value
    from the continuous extension, and the step is not cut there). A state that locks stays
    stuck until BREAK: no chatter (hysteresis of the Modelica friction state machine [2]). The
    loop over scenarios is compiled with numba; a fresh starting step (Hairer's HINIT) is
    estimated at t = 0 and after every mode switch.

    Parameters are those of :func:`closed_form` plus:

    stribeck_speed : array_like
        v_s [rad/s] of μ(v) = μ_k·[1 + (μ_s/μ_k − 1)·exp(−(v/v_s)²)]; ``inf`` gives constant μ_k
        while slipping (μ_s then applies only to sticking).
    aero_coefficient : array_like
        k_a [N m s²] of the rotor drag k_a·ω_c² added to the load torque.
    load_step, load_step_time : array_like
        A load torque step ΔT_m [N m] at t_s [s] (e.g. collective pulled after engagement).
    engine_torque_table : (speeds [rad/s], torques [N m]) or None
        Engine torque versus speed (linear interpolation, constant beyond the ends), added to
        ``engine_torque`` (shared by all scenarios).
    friction_table : (slip speeds [rad/s], μ/μ_k [-]) or None
        The slipping friction law as a table (measured data, as the Modelica library's ``mu_pos``):
        μ(abs(Δω))/μ_k, linear between the points, constant beyond the ends; it replaces the Stribeck
        law (``stribeck_speed`` is then ignored). ``peak_capacity`` is the capacity at μ_k;
        sticking still holds up to ``static_ratio``·C. Shared by all scenarios.
    fade_coefficient, fade_onset, face_temperature_factor : array_like
        Friction fade (off with β = 0, the default): while slipping, μ_k is divided by
        1 + β·(ΔT − ΔT_on)⁺, ΔT the friction face's temperature rise over its start temperature
        [K], β ``fade_coefficient`` [1/K], ΔT_on ``fade_onset`` [K]; ΔT = K·I with I Duhamel's
        integral of the slip power (the face as a semi-infinite body, :mod:`clutchlab.heat`) and K
        ``face_temperature_factor`` [K/(W s^0.5)] (:func:`clutchlab.heat.face_temperature_rise` of
        1 W s^0.5). The face temperature becomes a state: the smooth part of the kernel
        1/√(t − τ) as 15 exponential modes, its singular part quasi-static (see
        :mod:`._kernel`; against a Picard iteration with the exact kernel: ΔT within
        4e-5 of its peak while slipping, lock-up time within 6e-6, slip work 5e-7). Static friction
        is not faded. Needs K > 0 and t_end ≤ 10 s (the fit's span). Costs: with fade every
        slipping phase is integrated with the 15 modes, steps ≤ 0.5 ms (the stiffest mode): about
        0.7 ms a scenario of the compliant model instead of 27 µs.
    release_ratio : array_like
        κ [-] of the release-bearing travel model (:func:`bearing_travel_clamp`): the profile is the
        bearing travel and the capacity C_max·max(0, 1 − κ(1 − p)); 1 (default) is the profile
        itself, κ > 1 adds the air gap before the lining cushion is touched.
    compliant : bool
        Insert the damper springs between plate hub and output: hub inertia
        ``hub_fraction``·J_v, output inertia (1 − ``hub_fraction``)·J_v, stiffness
        ``damper_stiffness`` [N m/rad] and viscous damping of the given ``damping_ratio`` on the
        hub-output mode. Gives a finite output jerk; as the stiffness grows it tends to the rigid
        model.
    rtol, atol : float
        Error tolerances of the step-size control.
    max_step : float
        Largest step [s] (bounds the node spacing of peak metrics).
    first_step : float or None
        First step [s]; None estimates it from the tolerance (as after every mode switch).
    max_steps : int
        Work budget of one scenario (a whole number in [1, 1e9]): integrator steps attempted, mode
        switches and the passes of the exact linear phases' root search all count; a scenario
        that spends it ends ``not_converged`` with NaN metrics (its solver counts kept).
    trace_times : array_like or None
        Times [s] at which to record the state (they become breakpoints, so no interpolation).
    power_history : bool
        Keep each scenario's slip power history while it slips and return the peak of its
        Duhamel integral (``flash_peak``, for the friction-face temperature; the engagement study
        asks for it). Off by default: it costs about 8 µs a scenario on the compliant model's
        ramp designs (12 → 20 µs) and doubles the rigid integrator's time at loose tolerance.

    Returns
    -------
    dict of numpy.ndarray
        The metrics of :func:`closed_form` over [0, t_end] (``lockup_time`` is the last
        lock-up; NaN if slipping at t_end), plus ``breakaway_time`` (first re-slip after a
        lock-up), ``damping_work`` [J], ``peak_jerk`` [rad/s³] (output side, from the model
        equations at every step node and event and inside the steps: the compliant model's
        peaks on each step's continuous extension; the rigid model's steepest point of a smooth
        clamp profile, t_r/2, as a breakpoint, and with a Stribeck law, friction table, fade or
        rotor drag each slipping step scanned and refined on its continuous extension; the
        Dirac jerk of a rigid lock-up is reported as ``accel_jump``), solver counts
        ``n_steps`` (attempted), ``n_rejected``, ``n_locate`` (event locations),
        ``n_false_alarms`` (candidates the solution did not confirm),
        ``n_event_steps`` (re-integrations spent locating events: one per event when the first
        correction is accepted); with ``power_history``, ``flash_peak`` [W s^0.5]: max over t of
        Duhamel's integral ∫ P(τ)/√(t − τ) dτ of the slip power history (sampled while slipping
        every ramp time / 48 and at least 64 times a slip phase, at every step end and event; see
        :func:`clutchlab.heat.face_temperature_rise`; NaN without) and ``n_power_samples``, and, with
        ``trace_times``, a ``trace`` dict of arrays (scenario..., time): engine, hub and output
        speed [rad/s], friction torque and capacity [N m], slip work [J], output jerk [rad/s³],
        with fade the friction face's temperature rise [K] (NaN without).
        Inputs are screened as in :func:`closed_form` (plus v_s, J-split, stiffness > 0, ζ, k_a ≥ 0,
        κ ≥ 1, a finite t_end > 0): a bad scenario has status ``invalid_input`` and NaN outputs.
    """
    _check_profile(profile)
    _check_solver_options(rtol, atol, max_step, first_step, max_steps, trace_times)
    return st.screened(
        _simulate,
        dict(
            engine_speed=engine_speed,
            engine_inertia=engine_inertia,
            engine_torque=engine_torque,
            driven_inertia=driven_inertia,
            load_torque=load_torque,
            peak_capacity=peak_capacity,
            ramp_time=ramp_time,
            static_ratio=static_ratio,
            stribeck_speed=stribeck_speed,
            driven_speed=driven_speed,
            aero_coefficient=aero_coefficient,
            load_step=load_step,
            load_step_time=load_step_time,
            hub_fraction=hub_fraction,
            damper_stiffness=damper_stiffness,
            damping_ratio=damping_ratio,
            release_ratio=release_ratio,
            t_end=t_end,
            fade_coefficient=fade_coefficient,
            fade_onset=fade_onset,
            face_temperature_factor=face_temperature_factor,
        ),
        _DOMAIN_SIMULATE,
        extra=dict(
            profile=profile,
            engine_torque_table=engine_torque_table,
            friction_table=friction_table,
            compliant=compliant,
            rtol=rtol,
            atol=atol,
            max_step=max_step,
            first_step=first_step,
            max_steps=max_steps,
            trace_times=trace_times,
            power_history=power_history,
        ),
    )


def _simulate(
    *,
    profile,
    engine_torque_table,
    friction_table,
    compliant,
    rtol,
    atol,
    max_step,
    first_step,
    max_steps,
    trace_times,
    power_history,
    **scenario,
):
    Q, shape = _parameter_table(
        profile=profile,
        engine_torque_table=engine_torque_table,
        friction_table=friction_table,
        **scenario,
    )
    tt = (
        np.zeros(0)
        if trace_times is None
        else np.ascontiguousarray(trace_times, dtype=float).ravel()
    )
    res, trace = _k.simulate_batch(
        Q,
        bool(compliant),
        PROFILES.index(profile),
        tt,
        float(rtol),
        float(atol),
        float(max_step),
        float(first_step or 0.0),
        int(max_steps),
        bool(power_history),
    )
    truncated = res[:, _k.TRUNCATED] > 0
    res[truncated[:, None] & np.isin(np.arange(_k.N_RESULTS), _TRUNCATED_NAN)[None, :]] = np.nan
    # out of work: every metric is partial (the solver counts say how far it got)
    res[(res[:, _k.HIT_STEP_LIMIT] > 0)[:, None] & _METRIC_COLUMNS[None, :]] = np.nan
    out = {
        name: res[:, i].reshape(shape)
        for i, name in enumerate(_k.RESULTS)
        if name not in ("final_locked", "hit_step_limit", "truncated")
    }
    for name in ("n_steps", "n_linear"):
        out[name] = out[name].astype(np.int64)
    code = np.where(
        res[:, _k.HIT_STEP_LIMIT] > 0,
        st.CODE["not_converged"],
        np.where(
            truncated,
            st.CODE["truncated"],
            np.where(res[:, _k.FINAL_LOCKED] > 0, st.CODE["ok"], st.CODE["never_locked"]),
        ),
    )
    out["status"] = code.astype(st.DTYPE).reshape(shape)
    if trace_times is not None:
        out["trace"] = {
            name: trace[:, :, i].reshape(shape + (tt.size,)) for i, name in enumerate(_k.TRACES)
        }
    return out
