"""scipy reference solutions of the compliant engagement, for the tests and the benchmark.

:func:`compliant` integrates one scenario of the compliant-driveline engagement (seed 000 eqs. 1-2
with the damper springs between plate hub and output; the model of
:func:`clutchlab.engagement.simulate` with ``compliant=True``, constant or Stribeck μ, held or free
engine with constant torque, clamp profile ramp/cubic/quintic with the release-bearing air gap,
a load step) with
``scipy.integrate.solve_ivp``: one call per mode (slipping or locked, output parked or moving)
with terminal events, restarted with the new mode at each event — the only way to keep
stick-slip exact with solve_ivp (an event function that is zero at the restart fires at once, so a
mode's events are armed only a hair after its start). Slip work is an integrated state; the output
jerk (K·θ' + c·θ'')/J_R comes from the right-hand side (never from differencing); its peak either at
the solver's steps (``jerk_peak="steps"``, as one usually writes it) or on the dense output,
sampled every 1/40 of the oscillation period and refined by a bounded scalar search
(``"dense"``, the reference). The locked phase is followed for ``follow`` seconds past the
window's end (or past lock-up, whichever is later), far beyond the post-lock transient's first
peaks.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

_PROFILES = {
    "ramp": lambda x: x,
    "cubic": lambda x: x * x * (3 - 2 * x),
    "quintic": lambda x: x**3 * (10 + x * (-15 + 6 * x)),
}


def _slip_law(slip, rs, vs, table):
    """μ/μ_k while slipping: the friction table (np.interp of |Δω|), the Stribeck law, or 1."""
    if table is not None:
        return float(np.interp(abs(slip), *table))
    return 1.0 if not np.isfinite(vs) else 1.0 + (rs - 1.0) * math.exp(-((slip / vs) ** 2))


# noqa reason: the scipy reference's event loop, written plainly as a check of the kernel
def compliant(  # noqa: C901
    p,
    *,
    method="DOP853",
    rtol=1e-12,
    atol=None,
    jerk_peak="dense",
    follow=0.3,
    profile="ramp",
    max_step=np.inf,
    power_samples=0,
):
    """One scenario (``p``: the keyword arguments of :func:`clutchlab.engagement.simulate`, scalars)
    by per-mode ``solve_ivp``; returns dict(lockup_time, slip_work, peak_jerk, peak_friction_torque,
    status 'ok'/'never_locked'). With friction fade (``fade_coefficient`` > 0) the face temperature
    is the solver's state model (its kernel modes and quasi-static part, integrated here with the
    mechanics). With ``power_samples`` > 0 also ``flash_peak``: the peak of Duhamel's integral of the
    slip power, sampled on the dense output about ``power_samples`` times a window."""
    we0, je, te = p["engine_speed"], p.get("engine_inertia", np.inf), p.get("engine_torque", 0.0)
    jv, tm, cmax, tr = p["driven_inertia"], p["load_torque"], p["peak_capacity"], p["ramp_time"]
    rs, vs = p.get("static_ratio", 1.0), p.get("stribeck_speed", np.inf)
    phi, k, zeta, t_end = (
        p.get("hub_fraction", 0.5),
        p["damper_stiffness"],
        p["damping_ratio"],
        p["t_end"],
    )
    dtm, t_step = p.get("load_step", 0.0), p.get("load_step_time", np.inf)
    tm0 = tm
    held = not np.isfinite(je)
    jh, jr = phi * jv, (1 - phi) * jv
    c = 2 * zeta * math.sqrt(k * jh * jr / jv)
    prof = _PROFILES[profile]
    atol = rtol if atol is None else atol

    kappa = p.get("release_ratio", 1.0)

    def cap(t):
        x = prof(min(max(t / tr, 0.0), 1.0)) if tr > 0 else 1.0
        return cmax * max(0.0, 1.0 - kappa * (1.0 - x))

    table = p.get("friction_table")

    def mu_f(slip):
        return _slip_law(slip, rs, vs, table)

    beta = p.get("fade_coefficient", 0.0)
    fade = beta > 0.0
    if (
        fade
    ):  # the solver's face-temperature state: its kernel modes (the same model, integrated here)
        from .engagement._fade import SOE_LAMBDA, SOE_M0, SOE_WEIGHT

        kf, on = p["face_temperature_factor"], p.get("fade_onset", 0.0)

    def fade_factor(y, p0):
        """g solving ΔT = K·(Σ w_k·z_k + M0·P0·g), g = 1/(1 + β(ΔT − ΔT_on)⁺) (a quadratic)."""
        if not fade:
            return 1.0
        slow = kf * float(np.dot(SOE_WEIGHT, y[5:]))
        a, cc = kf * SOE_M0 * p0, slow - on
        if cc + a <= 0.0:
            return 1.0
        b = 1.0 - beta * cc
        u = (-b + math.sqrt(b * b + 4.0 * beta * (cc + a))) / (2.0 * beta)
        return 1.0 / (1.0 + beta * u)

    def torque(t, y, s):
        """The slipping clutch torque s·f·g·C."""
        f = mu_f(y[0] - y[1])
        return s * f * fade_factor(y, f * cap(t) * abs(y[0] - y[1])) * cap(t)

    def rhs_factory(locked, parked, s):
        def rhs(t, y):
            we, wh, wr, th = y[:4]
            ts = k * th + c * (wh - wr)
            if locked:
                a = 0.0 if held else (te - ts) / (je + jh)
                dwe = dwh = a
                tc_slip = 0.0
            else:
                tc = torque(t, y, s)
                dwh = (tc - ts) / jh
                dwe = 0.0 if held else (te - tc) / je
                tc_slip = tc * (we - wh)
            dwr = 0.0 if parked else (ts - tm) / jr
            out = [dwe, dwh, dwr, wh - wr, tc_slip]
            if fade:
                out += list(tc_slip - SOE_LAMBDA * y[5:])
            return out

        return rhs

    def needed(t, y, locked):
        ts = k * y[3] + c * (y[1] - y[2])
        return ts if held else (je * ts + jh * te) / (je + jh)

    def jerk(rhs, t, y, parked):
        if parked:
            return 0.0
        d = rhs(t, y)
        return (k * (y[1] - y[2]) + c * (d[1] - d[2])) / jr

    y = np.array([we0, 0.0, 0.0, 0.0, 0.0] + ([0.0] * SOE_LAMBDA.size if fade else []))
    power = []  # (times, slip power) of the slipping pieces, for the face temperature
    t, locked, parked, s = 0.0, False, tm > 0.0, 1.0
    t_lock, peak_jerk, peak_torque = np.nan, 0.0, 0.0
    period = 2 * math.pi / math.sqrt(k * (1 / jh + 1 / jr))
    horizon = t_end
    while t < horizon:
        tm = tm0 + (dtm if t >= t_step else 0.0)  # the load step is a breakpoint
        rhs = rhs_factory(locked, parked, s)
        t_arm = t + 1e-9

        def armed(fn):
            def g(tt, yy):
                return 1.0 if tt < t_arm else fn(tt, yy)  # noqa: B023 (called in this iteration)

            g.terminal, g.direction = True, -1
            return g

        events, kinds = [], []
        if locked:
            events += [armed(lambda tt, yy: rs * cap(tt) - abs(needed(tt, yy, True)))]
            kinds += ["break"]
        else:
            events += [armed(lambda tt, yy: s * (yy[0] - yy[1]))]  # noqa: B023 (called in this iteration)
            kinds += ["lock"]
        if parked:
            events += [armed(lambda tt, yy: tm - (k * yy[3] + c * yy[1]))]  # noqa: B023 (called in this iteration)
            kinds += ["unpark"]
        else:
            events += [armed(lambda tt, yy: yy[2])]
            kinds += ["park"]
        t_b = horizon
        t_con = tr * _invert(prof, 1.0 - 1.0 / kappa) if kappa > 1.0 else 0.0
        for b in (tr, t_step, t_con):
            if b > t:
                t_b = min(t_b, b)  # the profile's corner and the load step: breakpoints
        sol = solve_ivp(
            rhs,
            (t, t_b),
            y,
            method=method,
            rtol=rtol,
            atol=atol,
            events=events,
            dense_output=(jerk_peak == "dense" or bool(power_samples)),
            max_step=max_step,
        )
        t_stop = sol.t[-1]
        y_stop = sol.y[:, -1].copy()
        if power_samples and not locked and t_stop > t:
            ts_ = np.linspace(t, t_stop, max(int(power_samples * (t_stop - t) / t_end), 8) + 1)
            ys_ = sol.sol(ts_) if sol.sol is not None else None
            if ys_ is not None:
                pw = [
                    torque(tt, yy, s) * (yy[0] - yy[1]) for tt, yy in zip(ts_, ys_.T, strict=False)
                ]
                power.append((ts_, np.array(pw)))
        # peaks over this piece
        if jerk_peak == "dense" and not parked:
            n = max(int(40 * (t_stop - t) / period), 8)
            ts_ = np.linspace(t, t_stop, n + 1)
            js = np.array([abs(jerk(rhs, tt, sol.sol(tt), parked)) for tt in ts_])
            i = int(np.argmax(js))
            best = js[i]
            for j in {max(i - 1, 0), i, min(i + 1, n)}:
                lo, hi = ts_[max(j - 1, 0)], ts_[min(j + 1, n)]
                if hi > lo:
                    r = minimize_scalar(
                        lambda tt: -abs(jerk(rhs, tt, sol.sol(tt), parked)),  # noqa: B023 (called in this iteration)
                        bounds=(lo, hi),
                        method="bounded",
                        options={"xatol": 1e-13 * max(1.0, hi)},
                    )
                    best = max(best, -r.fun)
            peak_jerk = max(peak_jerk, best)
        else:
            for tt, yy in zip(sol.t, sol.y.T, strict=False):
                peak_jerk = max(peak_jerk, abs(jerk(rhs, tt, yy, parked)))
        if locked:
            peak_torque = max(
                peak_torque,
                max(abs(needed(tt, yy, True)) for tt, yy in zip(sol.t, sol.y.T, strict=False)),
            )
        else:
            peak_torque = max(peak_torque, cap(t_stop))
        fired = [i for i, te_ in enumerate(sol.t_events) if te_.size]
        t, y = t_stop, y_stop
        if not fired:
            continue
        kind = kinds[fired[0]]
        if kind == "lock":
            w = y[0] if held else (je * y[0] + jh * y[1]) / (je + jh)
            y[0] = y[1] = w
            locked, t_lock = True, t
            horizon = max(t_end, t + follow)
        elif kind == "break":
            s = 1.0 if needed(t, y, True) >= 0 else -1.0
            locked, t_lock = False, np.nan
            horizon = t_end
            if t > t_end:
                break
        elif kind == "unpark":
            parked = False
        else:
            parked = True
            y[2] = 0.0
    ok = locked and t_lock <= t_end
    out = dict(
        lockup_time=t_lock if ok else np.nan,
        slip_work=y[4],
        peak_jerk=peak_jerk,
        peak_friction_torque=peak_torque,
        status="ok" if ok else "never_locked",
    )
    if power_samples:
        out["flash_peak"] = _flash_peak(power, t_lock if ok else t_end)
    return out


def _flash_peak(pieces, t_last):
    """max over t of ∫P(τ)/√(t − τ)dτ of the sampled slip power (linear between samples, every
    segment exactly: the kernel's own formula, at every sample), the power zero after ``t_last``."""
    from .engagement._power import duhamel_peak

    if not pieces:
        return 0.0
    t = np.concatenate([pc[0] for pc in pieces])
    pw = np.concatenate([pc[1] for pc in pieces])
    keep = np.concatenate([[True], np.diff(t) > 0])
    t, pw = t[keep], pw[keep]
    after = np.linspace(t_last, t_last + 0.5 * (t_last - t[0]) + 1e-3, 400)[1:]
    hist = np.vstack([np.concatenate([t, after]), np.concatenate([pw, np.zeros(after.size)])])
    n = hist.shape[1]
    return float(duhamel_peak(np.ascontiguousarray(hist), n, max(1, int(math.sqrt(n / 2.0)))))


def _invert(prof, q):
    """x in [0, 1] with prof(x) = q (monotone profile), by bisection to round-off."""
    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        lo, hi = (mid, hi) if prof(mid) < q else (lo, mid)
    return hi


def rigid_fade(p, *, rtol=1e-12, samples=20001, iterations=40, tol=1e-10):
    """Engagement of the rigid model with a held engine and friction fade (the model of
    :func:`clutchlab.engagement.simulate` with ``fade_coefficient`` > 0; constant μ_k, the Stribeck
    law or a ``friction_table``), independently of its face-temperature state: Picard iteration on
    the face temperature rise ΔT(t). Given ΔT_j(t), ``solve_ivp`` (DOP853) integrates the driven
    speed with μ_k/(1 + β(ΔT_j − ΔT_on)⁺) (the driven side held by its static load until the clutch
    torque exceeds it; terminal event at lock-up); the slip power on ``samples`` equal steps to
    lock-up then gives ΔT_{j+1} = K·∫P(τ)/√(t − τ)dτ exactly for P linear between the samples (the
    kernel's own :func:`duhamel_at`, O(n²)). Stops when the lock-up time changes by less than
    ``tol`` (relative). Returns dict(lockup_time, slip_work, peak_face_rise, times, face_rise,
    iterations)."""
    from .engagement._power import duhamel_at

    we0, jv, tm, cmax, tr = (
        float(p[k])
        for k in ("engine_speed", "driven_inertia", "load_torque", "peak_capacity", "ramp_time")
    )
    rs, vs, table = (
        p.get("static_ratio", 1.0),
        p.get("stribeck_speed", np.inf),
        p.get("friction_table"),
    )
    beta, on, kf, t_end = (
        p["fade_coefficient"],
        p.get("fade_onset", 0.0),
        p["face_temperature_factor"],
        p["t_end"],
    )
    prof = _PROFILES[p.get("profile", "ramp")]

    def cap(t):
        return cmax * (prof(min(max(t / tr, 0.0), 1.0)) if tr > 0 else 1.0)

    def mu_f(slip):
        return _slip_law(slip, rs, vs, table)

    times, rise = np.array([0.0, t_end]), np.zeros(2)
    t_lock_prev = np.nan
    for it in range(1, iterations + 1):  # noqa: B007 (read after the loop)

        def torque(t, wh, times=times, rise=rise):
            g = 1.0 / (1.0 + beta * max(0.0, float(np.interp(t, times, rise)) - on))
            return mu_f(we0 - wh) * g * cap(t)

        def rhs(t, y):
            tc = torque(t, y[0])
            return [0.0 if (y[0] <= 0.0 and tc <= tm) else (tc - tm) / jv, tc * (we0 - y[0])]

        def lock(t, y):
            return we0 - y[0]

        lock.terminal, lock.direction = True, -1
        sol = solve_ivp(
            rhs,
            (0.0, t_end),
            [0.0, 0.0],
            method="DOP853",
            rtol=rtol,
            atol=rtol,
            events=lock,
            dense_output=True,
        )
        t_lock = float(sol.t_events[0][0]) if sol.t_events[0].size else np.nan
        t_stop = t_lock if np.isfinite(t_lock) else t_end
        grid = np.linspace(0.0, t_stop, samples)
        wh = sol.sol(grid)[0]
        hist = np.vstack(
            [grid, np.array([torque(t, w) * (we0 - w) for t, w in zip(grid, wh, strict=False)])]
        )
        hist[1, -1] = 0.0 if np.isfinite(t_lock) else hist[1, -1]
        new_rise = np.array([kf * duhamel_at(hist, k) if k else 0.0 for k in range(samples)])
        # after lock-up the face cools: the same integral of the (ended) power at later times
        after = np.linspace(t_stop, t_end, 200)[1:] if t_stop < t_end else np.zeros(0)
        if after.size:
            ext = np.hstack([hist, np.vstack([after, np.zeros(after.size)])])
            new_rise = np.concatenate(
                [new_rise, [kf * duhamel_at(ext, samples + k) for k in range(after.size)]]
            )
            grid = np.concatenate([grid, after])
        times, rise = grid, new_rise
        if abs(t_lock - t_lock_prev) <= tol * t_lock:
            break
        t_lock_prev = t_lock
    return dict(
        lockup_time=t_lock,
        slip_work=float(sol.y[1, -1]),
        peak_face_rise=float(rise.max()),
        times=times,
        face_rise=rise,
        iterations=it,
    )
