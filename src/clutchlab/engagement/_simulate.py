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
from ._docs import fill
from ._domain import DOMAIN_COMPLIANT, DOMAIN_SIMULATE, check_solver_options, check_table
from ._driver import simulate_batch
from ._profile import PROFILES, _check_profile, _invert_profile

EVENT_TIME_TOL = lay.EVENT_TIME_TOL  # s: bracket width at which an event time is final
#: simulate's arguments screened per scenario (DOMAIN_SIMULATE), in the order _simulate gets them
SCREENED = (
    "engine_speed",
    "engine_inertia",
    "engine_torque",
    "driven_inertia",
    "load_torque",
    "peak_capacity",
    "ramp_time",
    "static_ratio",
    "stribeck_speed",
    "driven_speed",
    "aero_coefficient",
    "load_step",
    "load_step_time",
    "hub_fraction",
    "damper_stiffness",
    "damping_ratio",
    "release_ratio",
    "t_end",
    "fade_coefficient",
    "fade_onset",
    "face_temperature_factor",
)
#: simulate's arguments shared by all scenarios (options of the batch)
OPTIONS = (
    "profile",
    "engine_torque_table",
    "friction_table",
    "compliant",
    "rtol",
    "atol",
    "max_step",
    "first_step",
    "max_steps",
    "trace_times",
    "power_history",
    "peaks",
)


@fill
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
    peaks=True,
    friction_table=None,
    fade_coefficient=0.0,
    fade_onset=0.0,
    face_temperature_factor=0.0,
):
    """Engagement by a Dormand-Prince 5(4) integrator with exact stick-slip events.

    The model of :func:`closed_form` with any friction law, load and driveline; per-scenario step
    sizes, breakpoints, events (lock, break-away, park, unpark, peak slip power) located to the
    integrator's accuracy, the Modelica stick/slip state machine [2] (:mod:`clutchlab.engagement`).

    Parameters
    ----------
    %(driveline)s
    stribeck_speed : array_like [rad/s]
        v_s of μ(v) = μ_k·[1 + (μ_s/μ_k − 1)·exp(−(v/v_s)²)]; ``inf``: constant μ_k while slipping.
    %(driven_speed)s
    aero_coefficient : array_like [N m s²]
        k_a ≥ 0 of the rotor drag k_a·ω_c² added to the load torque.
    load_step : array_like [N m]
        A load torque step ΔT_m at ``load_step_time`` (e.g. collective pulled after engagement).
    load_step_time : array_like [s]
        t_s of the load step (``inf``: none).
    engine_torque_table : (speeds [rad/s], torques [N m]) or None
        Engine torque versus speed added to ``engine_torque`` (linear; one for all scenarios).
    compliant : bool
        Damper springs between plate hub and output, viscous damping on that mode: a finite output
        jerk; the rigid model as the stiffness grows (an infinite ``damper_stiffness`` is refused
        here, status ``invalid_input``: it is the rigid model, ``compliant=False``).
    hub_fraction : array_like [-]
        Share of J_v on the plate hub, the rest on the output (compliant model).
    damper_stiffness : array_like [N m/rad]
        Torsional stiffness of the damper springs (compliant model; source paper (000) eqs. 4-9).
    damping_ratio : array_like [-]
        ζ of the viscous damping on the hub-output mode (compliant model).
    release_ratio : array_like [-]
        κ ≥ 1 of the release-bearing travel (:func:`bearing_travel_clamp`); 1: the profile itself.
    t_end : array_like [s]
        End of the window (finite, > 0).
    rtol, atol : float
        Relative [-] and absolute (state units) tolerances of the step-size control.
    max_step : float [s]
        Largest step (bounds the node spacing of peak metrics).
    first_step : float or None [s]
        First step; None estimates it (Hairer's HINIT [3], as after every mode switch).
    max_steps : int [-]
        Work budget of a scenario in [1, 1e9] (steps, switches, root passes); when spent, it ends
        ``not_converged`` with NaN metrics.
    trace_times : array_like or None [s]
        Times at which to record the state (breakpoints: no interpolation).
    power_history : bool
        Return ``flash_peak`` (below); the compliant model with constant μ, ramp profile, in
        ``config/million.yaml``'s ranges at the engagement study's tolerances for accuracy 1e-6
        takes about twice as long with it (53 against 28 µs of CPU a scenario).
    peaks : bool
        Track the peak friction torque and output jerk (``False``: both NaN; the exact linear
        phases then search fewer forms and the collocated slipping phases refine the slip power's
        peak only, the other outputs unchanged to round-off).
    friction_table : (slip speeds [rad/s], μ/μ_k [-]) or None
        The slipping friction law μ(abs(Δω))/μ_k as a table (linear, constant beyond the ends;
        the Modelica library's ``mu_pos``; one for all scenarios), replacing the Stribeck law.
    fade_coefficient : array_like [1/K]
        β of friction fade: μ_k/(1 + β·(ΔT − ΔT_on)⁺) while slipping (0: off), ΔT the face's rise,
        K times Duhamel's integral of the slip power (15 modes, :mod:`clutchlab.engagement._fade`:
        ΔT within 4e-5 of its peak). Static friction is not faded. Needs K > 0, t_end ≤ 10 s.
        A scenario whose rise, run without fade, stays below 0.99 of the onset everywhere never
        fades: its fade-free results are returned (within 1e-9 of the fade solver's; not with
        ``trace_times``).
    fade_onset : array_like [K]
        ΔT_on, the face temperature rise at which fade starts.
    face_temperature_factor : array_like [K/(W s^0.5)]
        K, the face's temperature rise per unit of Duhamel's integral.

    Returns
    -------
    dict of numpy.ndarray
        The metrics of :func:`closed_form` over [0, t_end] (``lockup_time`` the last lock-up),
        ``breakaway_time`` [s], ``damping_work`` [J], ``peak_jerk`` [rad/s³] (output side), the
        counts ``n_steps``, ``n_rejected``, ``n_locate``, ``n_false_alarms``, ``n_event_steps``;
        with ``power_history`` ``flash_peak`` [W s^0.5] (max of ∫ P(τ)/√(t − τ) dτ) and
        ``n_power_samples``; with ``trace_times`` a ``trace`` dict of (scenario..., time) arrays:
        engine, hub and output speed [rad/s], friction torque and capacity [N m], slip work [J],
        output jerk [rad/s³], face temperature rise [K].
        %(screening)s

    References
    ----------
    .. [1] Zhao P. (2026), source paper (000), eqs. (1), (2) (the two-inertia driveline),
       (4)-(9) (damper springs), (11) (slip work), (12) (jerk), (13)-(14) (torque capacity).
    .. [2] Otter M., Elmqvist H., Mattsson S.E. (1999), "Hybrid modeling in Modelica based on
       the synchronous data flow principle" (the stick/slip state machine).
    .. [3] Hairer E., Nørsett S.P., Wanner G. (1993), Solving Ordinary Differential Equations I,
       2nd ed., sections II.4-II.5 (DOPRI5, continuous extension, HINIT).
    """
    inputs = dict(locals())  # (first: the arguments only)
    _check_profile(profile)
    if not isinstance(compliant, (bool, np.bool_)):  # ("no" would read as True)
        raise ValueError(f"compliant must be True or False, got {compliant!r}")
    check_solver_options(rtol, atol, max_step, first_step, max_steps, trace_times)
    screened, options = ({k: inputs[k] for k in names} for names in (SCREENED, OPTIONS))
    domain = DOMAIN_COMPLIANT if compliant else DOMAIN_SIMULATE
    return st.screened(_simulate, screened, domain, extra=options)


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
    peaks,
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
    batch = dict(
        compliant=bool(compliant),
        prof=PROFILES.index(profile),
        tt=tt,
        rtol=float(rtol),
        atol=float(atol),
        max_step=float(max_step),
        first_step=float(first_step or 0.0),
        max_steps=int(max_steps),
        peaks=bool(peaks),
    )
    res, trace = _batch_with_fade(Q, batch, bool(power_history))
    out = _outputs(res, shape)
    if trace_times is not None:
        out["trace"] = {
            name: trace[:, :, i].reshape(shape + (tt.size,)) for i, name in enumerate(lay.TRACES)
        }
    return out


#: Fade is left out of a scenario whose face temperature rise stays below FADE_MARGIN times the
#: onset without it: the rise of the fade model (15 modes) is within 4e-5 of the exact Duhamel
#: integral's peak, the slip power history's peak within 5e-4 of it (layout notes); 1 % covers both
#: twentyfold.
FADE_MARGIN = 0.99


def _batch_with_fade(Q, batch, power_history):
    """(results, traces) of every row of the parameter table Q. A scenario with fade whose face
    temperature rise, computed without fade, stays below FADE_MARGIN times the onset everywhere
    never fades (μ_k is divided by 1 only): its fade-free results are final, and only the others
    are solved with the face temperature as a state (several times as long a scenario). Not
    with traces (they show the face temperature of the fade model), nor where the onset is the
    ambient temperature (every slipping scenario fades). Without ``power_history`` the fade-free
    run first goes without the history too, and only the scenarios :func:`surely_cool` does not
    clear are run again with it (the history costs about as much as the rest of a constant-μ
    engagement)."""
    fade = (Q[:, lay.FADE] > 0.0) & (Q[:, lay.FADE_ON] > 0.0)
    if not fade.any() or batch["tt"].size:
        return simulate_batch(Q, with_hist=power_history, **batch)
    plain = Q[fade].copy()
    plain[:, lay.FADE] = 0.0
    pre, cool = None, np.zeros(plain.shape[0], dtype=bool)
    if not power_history:
        pre, _ = simulate_batch(plain, with_hist=False, **batch)
        cool = surely_cool(plain, pre)
    if not cool.all():
        unsure = ~cool
        with_hist, _ = simulate_batch(plain[unsure], with_hist=True, **batch)
        with np.errstate(invalid="ignore"):
            cool[unsure] = (
                plain[unsure, lay.FACE_K] * with_hist[:, lay.FLASH_PEAK]
                <= FADE_MARGIN * plain[unsure, lay.FADE_ON]
            )
        if not power_history:  # (as the solver leaves them without the history)
            with_hist[:, lay.FLASH_PEAK] = np.nan
            with_hist[:, lay.N_POWER_SAMPLES] = 0.0
        if pre is None:
            pre = with_hist
        else:
            pre[unsure] = with_hist
    rows = np.flatnonzero(fade)
    solve = np.ones(Q.shape[0], dtype=bool)
    solve[rows[cool]] = False
    res, trace = simulate_batch(Q[solve], with_hist=power_history, **batch)
    out = np.empty((Q.shape[0], res.shape[1]))
    out[solve] = res
    out[rows[cool]] = pre[cool]
    return out, np.empty((Q.shape[0], 0, trace.shape[2]))


def surely_cool(Q, res):
    """Rows of the parameter table Q whose fade-free results ``res`` (no slip-power history) prove
    the face cool: the slip power P ≥ 0 is at most its peak P_max and is zero after the last
    lock-up t_L (the window's end if it does not end locked), so Duhamel's integral
    ∫ P(τ)/√(t − τ) dτ is at most 2·P_max·√t_L at any time; below FADE_MARGIN times the onset
    over K, the face never reaches it (NaN results, or a run that spent its work budget before
    the window's end: not proven)."""
    t_last = np.where(np.isfinite(res[:, lay.LOCKUP_TIME]), res[:, lay.LOCKUP_TIME], Q[:, lay.TEND])
    bound = 2.0 * res[:, lay.PEAK_SLIP_POWER] * np.sqrt(t_last)
    with np.errstate(invalid="ignore"):
        cool = Q[:, lay.FACE_K] * bound <= FADE_MARGIN * Q[:, lay.FADE_ON]
    return cool & (res[:, lay.HIT_STEP_LIMIT] == 0.0)


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
