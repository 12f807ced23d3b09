"""The numerical engagement solver's driver: screening, the parameter table, the compiled batch.

:func:`simulate` screens the inputs (:mod:`clutchlab.engagement._domain`), lays every scenario out
as one row of the parameter table (:func:`parameter_table`, columns of
:mod:`clutchlab.engagement._layout`), runs the compiled batch
(:func:`clutchlab.engagement._driver.simulate_batch`) and turns its result columns into the
returned metrics and statuses (:func:`_outputs`).
"""

from __future__ import annotations

import numpy as np

from .. import status as st
from . import _layout as lay
from ._domain import DOMAIN_SIMULATE, check_solver_options, check_table
from ._driver import simulate_batch
from ._profile import PROFILES, _check_profile, _invert_profile

EVENT_TIME_TOL = lay.EVENT_TIME_TOL  # s: bracket width at which an event time is final


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

    Parameters
    ----------
    engine_speed, engine_inertia, engine_torque, driven_inertia, load_torque : array_like
        As in :func:`closed_form`: ω_e(0) [rad/s], J_e [kg m²] (``inf``: held), T_e [N m],
        J_v [kg m²], T_m ≥ 0 [N m].
    peak_capacity, ramp_time, profile, static_ratio, driven_speed : array_like
        As in :func:`closed_form`: C_max [N m] (at μ_k), t_r [s], the clamp profile, μ_s/μ_k [-],
        ω_c(0) [rad/s].
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
        :mod:`clutchlab.engagement._fade`; against a Picard iteration with the exact kernel: ΔT within
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
    hub_fraction : array_like
        Share of J_v on the plate hub [-] (compliant model).
    damper_stiffness : array_like
        Torsional stiffness of the damper springs [N m/rad] (compliant model; the source paper
        (000)'s damper, eqs. 4-9: 4498 N m/rad).
    damping_ratio : array_like
        ζ [-] of the viscous damping on the hub-output mode (compliant model).
    t_end : array_like
        End of the window [s] (finite, > 0).
    rtol, atol : float
        Relative [-] and absolute (in the state's units) error tolerances of the step-size
        control.
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

    References
    ----------
    .. [1] Zhao P. (2026), source paper (000), eqs. (1), (2) (the two-inertia driveline),
       (11) (slip work), (12) (jerk), (13) (torque capacity).
    .. [2] Otter M., Elmqvist H., Mattsson S.E. (1999), "Hybrid modeling in Modelica based on
       the synchronous data flow principle" (the stick/slip state machine).
    .. [3] Hairer E., Nørsett S.P., Wanner G. (1993), Solving Ordinary Differential Equations I,
       2nd ed., Springer, section II.5 (DOPRI5, its continuous extension and HINIT) and II.4
       (step-size control).
    """
    _check_profile(profile)
    check_solver_options(rtol, atol, max_step, first_step, max_steps, trace_times)
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
        DOMAIN_SIMULATE,
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
    """The screened scenarios through the compiled batch (:func:`simulate`'s arguments)."""
    Q, shape = parameter_table(
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
    res, trace = simulate_batch(
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
    out = _outputs(res, shape)
    if trace_times is not None:
        out["trace"] = {
            name: trace[:, :, i].reshape(shape + (tt.size,)) for i, name in enumerate(lay.TRACES)
        }
    return out


# metrics an event after the window would change: NaN in a ``truncated`` scenario
_TRUNCATED_NAN = [
    getattr(lay, n.upper())
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
        for n in lay.RESULTS
    ]
)


def _outputs(res, shape):
    """The returned metrics (scenario shape) and statuses from the kernel's result columns: NaN
    where a scenario was truncated (the metrics an event after the window would change) or ran
    out of work (every metric; the solver counts say how far it got)."""
    truncated = res[:, lay.TRUNCATED] > 0
    res[truncated[:, None] & np.isin(np.arange(lay.N_RESULTS), _TRUNCATED_NAN)[None, :]] = np.nan
    # out of work: every metric is partial (the solver counts say how far it got)
    res[(res[:, lay.HIT_STEP_LIMIT] > 0)[:, None] & _METRIC_COLUMNS[None, :]] = np.nan
    out = {
        name: res[:, i].reshape(shape)
        for i, name in enumerate(lay.RESULTS)
        if name not in ("final_locked", "hit_step_limit", "truncated")
    }
    for name in ("n_steps", "n_linear"):
        out[name] = out[name].astype(np.int64)
    code = np.where(
        res[:, lay.HIT_STEP_LIMIT] > 0,
        st.CODE["not_converged"],
        np.where(
            truncated,
            st.CODE["truncated"],
            np.where(res[:, lay.FINAL_LOCKED] > 0, st.CODE["ok"], st.CODE["never_locked"]),
        ),
    )
    out["status"] = code.astype(st.DTYPE).reshape(shape)
    return out


def parameter_table(
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
    """The kernel's parameter table (one row per scenario, columns of
    :mod:`clutchlab.engagement._layout`) and the scenarios' broadcast shape."""
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {profile!r}")
    vals = {
        lay.WE0: engine_speed,
        lay.JE: engine_inertia,
        lay.TE: engine_torque,
        lay.JV: driven_inertia,
        lay.TM0: load_torque,
        lay.CMAX: peak_capacity,
        lay.TR: ramp_time,
        lay.RS: static_ratio,
        lay.VS: stribeck_speed,
        lay.WC0: driven_speed,
        lay.KA: aero_coefficient,
        lay.DTM: load_step,
        lay.TSTEP: load_step_time,
        lay.PHI: hub_fraction,
        lay.K: damper_stiffness,
        lay.ZETA: damping_ratio,
        lay.TEND: t_end,
        lay.KAPPA: release_ratio,
        lay.FADE: fade_coefficient,
        lay.FADE_ON: fade_onset,
        lay.FACE_K: face_temperature_factor,
    }
    arrs = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in vals.values()))
    Q = _table_columns(arrs[0].size, engine_torque_table, friction_table)
    for col, a in zip(vals, arrs, strict=False):
        Q[:, col] = a.ravel()
    _derived_columns(Q, profile)
    return Q, arrs[0].shape


def _table_columns(n, engine_torque_table, friction_table):
    """The table of n rows with the shared tables filled in (they ride on every row): the engine
    torque table from column NTAB (count, speeds, torques), the friction table (if any) after it
    with its column in FTAB (0: none), laid out alike (count, slip speeds, μ/μ_k)."""
    tx = ty = fx = fy = np.zeros(0)
    if engine_torque_table is not None:
        tx, ty = check_table(engine_torque_table, "engine_torque_table", "speeds", "torques", False)
    if friction_table is not None:
        fx, fy = check_table(
            friction_table, "friction_table", "slip speeds", "friction ratios", True
        )
    ftab = lay.N_PARAM + 1 + 2 * tx.size  # the shared tables ride on every row
    Q = np.empty((n, ftab + (1 + 2 * fx.size if fx.size else 0)))
    Q[:, lay.NTAB] = tx.size
    Q[:, lay.NTAB + 1 : lay.NTAB + 1 + tx.size] = tx
    Q[:, lay.NTAB + 1 + tx.size : ftab] = ty
    Q[:, lay.FTAB] = ftab if fx.size else 0.0
    if fx.size:
        Q[:, ftab] = fx.size
        Q[:, ftab + 1 : ftab + 1 + fx.size] = fx
        Q[:, ftab + 1 + fx.size :] = fy
    return Q


def _derived_columns(Q, profile):
    """Columns computed once from the inputs: the cushion's touch time, the held flag, 1/J_e,
    the hub and output inertias and the damper's viscous coefficient."""
    kappa = Q[:, lay.KAPPA]
    with np.errstate(divide="ignore"):  # the cushion is touched (kink of C(t)) where p = 1 − 1/κ
        Q[:, lay.TCON] = np.where(
            kappa > 1.0, Q[:, lay.TR] * _invert_profile(1.0 - 1.0 / kappa, profile), 0.0
        )
    held = ~np.isfinite(Q[:, lay.JE])
    Q[:, lay.HELD] = held
    Q[:, lay.INV_JE] = np.where(held, 0.0, 1.0 / np.where(held, 1.0, Q[:, lay.JE]))
    Q[:, lay.JH] = Q[:, lay.PHI] * Q[:, lay.JV]
    Q[:, lay.JR] = (1.0 - Q[:, lay.PHI]) * Q[:, lay.JV]
    with np.errstate(invalid="ignore"):
        Q[:, lay.CD] = np.where(
            np.isfinite(Q[:, lay.K]),
            2.0
            * Q[:, lay.ZETA]
            * np.sqrt(Q[:, lay.K] * Q[:, lay.JH] * Q[:, lay.JR] / Q[:, lay.JV]),
            0.0,
        )
