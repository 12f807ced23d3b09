"""The closed-form engagement (constant μ, constant torques, polynomial clamp profile): the driver.

It screens the inputs, cuts the batch into cache-sized blocks and, per block, solves the phases
(:mod:`clutchlab.engagement._lockup`) and the integrals (:mod:`clutchlab.engagement._works`).
"""

from __future__ import annotations

import numpy as np

from .. import status as st
from ._docs import fill
from ._domain import DOMAIN
from ._lockup import Drive, lockup_time
from ._profile import _check_profile
from ._works import flash_peak, knots, peak_power, slip_jerk, works

_BLOCK = 8192  # scenarios a block: ~4x faster than whole-array temporaries at 1e6 scenarios


@fill
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

    Engine side (eq. 1) J_e·dω_e/dt = T_e − T_c, driven side (eq. 2) J_v·dω_c/dt = T_c − T_m; while
    slipping T_c = C(t) = C_max·p(t/t_r), the driven side parked while C < T_m: the speeds are
    piecewise polynomials in t, lock-up a polynomial root (to round-off), the works exact
    Gauss-Legendre sums. Also the reference of :func:`simulate`.

    Parameters
    ----------
    %(driveline)s
    %(driven_speed)s
    t_end : array_like [s]
        End of the window (> 0, may be ``inf``); a scenario not locked by then is
        ``never_locked``.
    power_history : bool
        Also return ``flash_peak`` (below).

    Returns
    -------
    dict of numpy.ndarray
        ``lockup_time`` [s] (NaN if never locked), ``lockup_speed`` [rad/s], ``slip_work`` (eq. 11),
        ``load_work``, ``input_work``, ``kinetic_energy_change`` [J], ``energy_residual`` [-]
        (relative), ``peak_slip_power`` [W], ``peak_friction_torque`` [N m],
        ``capacity_at_lockup`` [N m], ``accel_jump`` [rad/s²] (driven acceleration after minus
        before lock-up; a rigid model has a Dirac jerk there), ``slip_jerk`` [rad/s³] (driven
        jerk dT_c/dt/J_v at the end of slip, eq. 12), ``status``. Works are over [0, t_lock]
        (or [0, t_end] if never locked).
        %(screening)s
        With ``power_history``, ``flash_peak`` [W s^0.5] as :func:`simulate` gives it: the peak of
        Duhamel's integral ∫ P(τ)/√(t − τ) dτ of the exact slip power, sampled at
        ``CLOSED_FORM_POWER_SAMPLES`` points on each of its polynomial pieces (parked, moving on
        the profile, after it; P linear between samples, each segment integrated exactly).

    See Also
    --------
    simulate : Every other friction law, load and driveline, numerically.
    ramp_time_for_lockup : The ramp time of a wanted lock-up time.

    References
    ----------
    .. [1] Zhao P. (2026), source paper (000), eqs. (1), (2) (the two-inertia driveline),
       (11) (slip work), (12) (jerk), (13)-(14) (torque capacity, two friction faces);
       Figs. 7-11.
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
        DOMAIN,
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
    """The screened scenarios, broadcast, in blocks of ``_BLOCK`` (:func:`_closed_form_flat`)."""
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


def _closed_form_flat(flat, profile, power_history=False):
    """One block: phases, lock-up, works, energies and peaks (the metrics of :func:`closed_form`)."""
    d = Drive(flat, profile)
    t_lock, ramp_end, a_coef, b_coef = lockup_time(d)
    locked = np.isfinite(t_lock) & (t_lock <= d.tend)
    t_stop = np.where(locked, t_lock, d.tend)
    finite_window = np.isfinite(t_stop)
    t_stop = np.where(finite_window, t_stop, 0.0)
    pieces = knots(d, ramp_end, t_stop)
    w_slip, w_load, w_in = works(d, pieces)
    # energies at the stop: at lock both sides turn together
    c_lock, _, we_end, wc_end = d.state(t_stop)
    wc_end = np.where(locked & d.held, d.we0, wc_end)
    dke = 0.5 * d.jv * (wc_end**2 - d.wc0**2) + 0.5 * np.where(d.held, 0.0, d.je) * (
        we_end**2 - d.we0**2
    )
    residual = (w_in - dke - w_slip - w_load) / np.maximum(
        np.maximum(np.abs(w_in), np.abs(w_slip)), 1e-300
    )
    peak = peak_power(d, pieces, a_coef, b_coef)
    # the driven side's acceleration before and after lock-up (a stall: at rest before and after)
    stalled = locked & d.stalls
    acc_before = np.where(stalled, 0.0, (c_lock - d.tm) * d.inv_jv)
    with np.errstate(divide="ignore", invalid="ignore"):
        acc_after = np.where(
            d.held | stalled, 0.0, (d.te - d.tm) * d.inv_je / (1.0 + d.jv * d.inv_je)
        )
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
        "peak_slip_power": peak,
        "peak_friction_torque": c_lock,
        "capacity_at_lockup": c_lock * nan,
        "accel_jump": (acc_after - acc_before) * nan,
        "slip_jerk": np.where(stalled, 0.0, slip_jerk(d, t_stop) * d.inv_jv),
        "status": code,
    }
    if power_history:
        out["flash_peak"] = flash_peak(d, pieces, t_stop, locked)
    for k, v in out.items():
        if k != "status":
            out[k] = np.where(finite_window, v, np.nan)
    return out


def ramp_time_for_lockup(target_lockup_time, **kwargs):
    """Ramp time t_r [s] that makes :func:`closed_form` lock up at ``target_lockup_time`` (scalar).

    Used to reproduce the source paper (000)'s "engagement shortened to 0.1 s / extended to
    0.2 s" variants: Brent's method on t_r ↦ t_lock(t_r) − target over [1e-6 s, 10·target].

    Parameters
    ----------
    target_lockup_time : float [s]
        The lock-up time wanted (> 0 and plausible).
    **kwargs
        The other inputs of :func:`closed_form` (scalars; not ``ramp_time``).

    Returns
    -------
    float
        t_r [s] in [1e-6 s, 10·target] (to round-off); NaN where the target is not a plausible
        time, an input is invalid (:func:`closed_form` gives no lock-up time), or no ramp time in
        that bracket reaches the target.

    See Also
    --------
    closed_form : The engagement whose lock-up time is matched.

    References
    ----------
    .. [1] Zhao P. (2026), source paper (000), eqs. (1), (2), (11) and the engagement variants of
       Figs. 7-11 (lock-up shortened to 0.1 s, extended to 0.2 s).
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
