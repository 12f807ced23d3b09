"""scipy reference solutions of the compliant engagement, for the tests and the benchmark.

:func:`compliant` integrates one scenario of the compliant-driveline engagement (seed 000 eqs. 1-2
with the damper springs between plate hub and output; the model of
:func:`clutchlab.engagement.simulate` with ``compliant=True``, constant or Stribeck μ or a μ(slip)
table, friction fade, held or free engine with constant torque, clamp profile ramp/cubic/quintic
with the release-bearing air gap, a load step) with
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


class _Compliant:
    """One scenario of the compliant model: its parameters, clamp capacity and right-hand sides."""

    def __init__(self, p, profile):
        self.we0 = p["engine_speed"]
        self.je, self.te = p.get("engine_inertia", np.inf), p.get("engine_torque", 0.0)
        jv, self.tm0 = p["driven_inertia"], p["load_torque"]
        self.cmax, self.tr = p["peak_capacity"], p["ramp_time"]
        self.rs, self.vs = p.get("static_ratio", 1.0), p.get("stribeck_speed", np.inf)
        phi, self.k, zeta = p.get("hub_fraction", 0.5), p["damper_stiffness"], p["damping_ratio"]
        self.t_end = p["t_end"]
        self.dtm, self.t_step = p.get("load_step", 0.0), p.get("load_step_time", np.inf)
        self.held = not np.isfinite(self.je)
        self.jh, self.jr = phi * jv, (1 - phi) * jv
        self.c = 2 * zeta * math.sqrt(self.k * self.jh * self.jr / jv)
        self.prof = _PROFILES[profile]
        self.kappa = p.get("release_ratio", 1.0)
        self.table = p.get("friction_table")
        # friction fade: the solver's face-temperature state (its kernel modes and quasi-static
        # part, the same model, integrated here with the mechanics)
        self.beta = p.get("fade_coefficient", 0.0)
        self.fade = self.beta > 0.0
        self.kf, self.on = p.get("face_temperature_factor", 0.0), p.get("fade_onset", 0.0)
        self.period = 2 * math.pi / math.sqrt(self.k * (1 / self.jh + 1 / self.jr))
        # the instant the clamp force starts rising after the air gap: a breakpoint
        self.t_con = (
            self.tr * _invert(self.prof, 1.0 - 1.0 / self.kappa) if self.kappa > 1.0 else 0.0
        )

    def cap(self, t):
        x = self.prof(min(max(t / self.tr, 0.0), 1.0)) if self.tr > 0 else 1.0
        return self.cmax * max(0.0, 1.0 - self.kappa * (1.0 - x))

    def initial_state(self):
        """Engine, hub, output speed, twist, slip work (and the fade modes, with fade)."""
        from .engagement._fade import SOE_LAMBDA

        return np.array([self.we0, 0.0, 0.0, 0.0, 0.0] + [0.0] * (SOE_LAMBDA.size * self.fade))

    def fade_factor(self, y, p0):
        """g solving ΔT = K·(Σ w_k·z_k + M0·P0·g), g = 1/(1 + β(ΔT − ΔT_on)⁺) (a quadratic; P0
        the slip power at g = 1)."""
        from .engagement._fade import SOE_M0, SOE_WEIGHT

        if not self.fade:
            return 1.0
        slow = self.kf * float(np.dot(SOE_WEIGHT, y[5:]))
        a, cc, beta = self.kf * SOE_M0 * p0, slow - self.on, self.beta
        if cc + a <= 0.0:
            return 1.0
        b = 1.0 - beta * cc
        u = (-b + math.sqrt(b * b + 4.0 * beta * (cc + a))) / (2.0 * beta)
        return 1.0 / (1.0 + beta * u)

    def torque(self, t, y, s):
        """The slipping clutch torque s·f·g·C [N m]."""
        slip = y[0] - y[1]
        f = _slip_law(slip, self.rs, self.vs, self.table)
        return s * f * self.fade_factor(y, f * self.cap(t) * abs(slip)) * self.cap(t)

    def rhs(self, locked, parked, s, tm):
        """The right-hand side of a mode (stuck or slipping in direction ``s``, output parked or
        moving) under the load torque ``tm``; states engine, hub, output speed, twist, slip work
        (and with fade the face temperature's modes z_k' = P − λ_k·z_k)."""
        from .engagement._fade import SOE_LAMBDA

        k, c, held, je, jh, te = self.k, self.c, self.held, self.je, self.jh, self.te

        def rhs(t, y):
            we, wh, wr, th = y[:4]
            ts = k * th + c * (wh - wr)
            if locked:
                a = 0.0 if held else (te - ts) / (je + jh)
                dwe = dwh = a
                tc_slip = 0.0
            else:
                tc = self.torque(t, y, s)
                dwh = (tc - ts) / jh
                dwe = 0.0 if held else (te - tc) / je
                tc_slip = tc * (we - wh)
            dwr = 0.0 if parked else (ts - tm) / self.jr
            out = [dwe, dwh, dwr, wh - wr, tc_slip]
            if self.fade:
                out += list(tc_slip - SOE_LAMBDA * y[5:])
            return out

        return rhs

    def needed(self, y):
        """The clutch torque that keeps engine and hub stuck together."""
        ts = self.k * y[3] + self.c * (y[1] - y[2])
        return ts if self.held else (self.je * ts + self.jh * self.te) / (self.je + self.jh)

    def jerk(self, rhs, t, y, parked):
        """Output jerk (K·θ' + c·θ'')/J_R from the right-hand side (0 while the output is parked)."""
        if parked:
            return 0.0
        d = rhs(t, y)
        return (self.k * (y[1] - y[2]) + self.c * (d[1] - d[2])) / self.jr


def _mode_events(m, t, locked, parked, s, tm):
    """The terminal events of a mode (armed a hair after its start ``t``: an event function that
    is zero at the restart would fire at once) and their kinds."""
    t_arm = t + 1e-9

    def armed(fn):
        def g(tt, yy):
            return 1.0 if tt < t_arm else fn(tt, yy)

        g.terminal, g.direction = True, -1
        return g

    if locked:
        events = [armed(lambda tt, yy: m.rs * m.cap(tt) - abs(m.needed(yy)))]
        kinds = ["break"]
    else:
        events, kinds = [armed(lambda tt, yy: s * (yy[0] - yy[1]))], ["lock"]
    if parked:
        events.append(armed(lambda tt, yy: tm - (m.k * yy[3] + m.c * yy[1])))
        kinds.append("unpark")
    else:
        events.append(armed(lambda tt, yy: yy[2]))
        kinds.append("park")
    return events, kinds


def _dense_peak_jerk(m, rhs, sol, t, t_stop):
    """The largest |jerk| of a moving output's piece on the dense output: sampled every 1/40 of
    the oscillation period, then refined by a bounded scalar search around the largest sample."""

    def jerk(tt):
        return abs(m.jerk(rhs, tt, sol.sol(tt), False))

    n = max(int(40 * (t_stop - t) / m.period), 8)
    ts_ = np.linspace(t, t_stop, n + 1)
    js = np.array([jerk(tt) for tt in ts_])
    i = int(np.argmax(js))
    best = js[i]
    for j in {max(i - 1, 0), i, min(i + 1, n)}:
        lo, hi = ts_[max(j - 1, 0)], ts_[min(j + 1, n)]
        if hi > lo:
            r = minimize_scalar(
                lambda tt: -jerk(tt),
                bounds=(lo, hi),
                method="bounded",
                options={"xatol": 1e-13 * max(1.0, hi)},
            )
            best = max(best, -r.fun)
    return best


def _piece_peaks(m, rhs, sol, t, locked, parked, jerk_peak):
    """Peak |jerk| and peak friction torque over one solve_ivp piece from ``t``."""
    t_stop = sol.t[-1]
    if jerk_peak == "dense" and not parked:
        peak_jerk = _dense_peak_jerk(m, rhs, sol, t, t_stop)
    else:
        peak_jerk = 0.0
        for tt, yy in zip(sol.t, sol.y.T, strict=False):
            peak_jerk = max(peak_jerk, abs(m.jerk(rhs, tt, yy, parked)))
    if locked:
        peak_torque = max(abs(m.needed(yy)) for yy in sol.y.T)
    else:
        peak_torque = m.cap(t_stop)
    return peak_jerk, peak_torque


def compliant(
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
    """One scenario of the compliant engagement by per-mode ``solve_ivp`` (module docstring).

    With friction fade (``fade_coefficient`` > 0) the face temperature is the solver's state model
    (its kernel modes and quasi-static part, integrated here with the mechanics).

    Parameters
    ----------
    p : dict
        The keyword arguments of :func:`clutchlab.engagement.simulate`, scalars.
    method : str
        The solve_ivp method.
    rtol, atol : float
        Tolerances (``atol`` None: ``rtol``).
    jerk_peak : {"dense", "steps"}
        Where the peak jerk is sought: on the dense output (the reference) or at the steps.
    follow : float
        Time [s] the locked phase is followed past the window's end or lock-up.
    profile : {"ramp", "cubic", "quintic"}
        The clamp profile.
    max_step : float
        Largest step [s] of solve_ivp.
    power_samples : int
        With > 0 also ``flash_peak``: the peak of Duhamel's integral of the slip power, sampled on
        the dense output about ``power_samples`` times a window.

    Returns
    -------
    dict
        ``lockup_time`` [s], ``slip_work`` [J], ``peak_jerk`` [rad/s³], ``peak_friction_torque``
        [N m], ``status`` ("ok" or "never_locked"), with ``power_samples`` ``flash_peak``
        [W s^0.5].
    """
    m = _Compliant(p, profile)
    atol = rtol if atol is None else atol
    y = m.initial_state()
    power = []  # (times, slip power) of the slipping pieces, for the face temperature
    t, locked, parked, s = 0.0, False, m.tm0 > 0.0, 1.0
    t_lock, peak_jerk, peak_torque = np.nan, 0.0, 0.0
    horizon = m.t_end
    while t < horizon:
        tm = m.tm0 + (m.dtm if t >= m.t_step else 0.0)  # the load step is a breakpoint
        rhs = m.rhs(locked, parked, s, tm)
        events, kinds = _mode_events(m, t, locked, parked, s, tm)
        # the profile's corner, the load step and the end of the air gap: breakpoints
        t_b = min([horizon] + [b for b in (m.tr, m.t_step, m.t_con) if b > t])
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
        if power_samples and not locked:
            power.append(_piece_power(m, sol, t, s, power_samples))
        piece_jerk, piece_torque = _piece_peaks(m, rhs, sol, t, locked, parked, jerk_peak)
        peak_jerk, peak_torque = max(peak_jerk, piece_jerk), max(peak_torque, piece_torque)
        fired = [i for i, te_ in enumerate(sol.t_events) if te_.size]
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if not fired:
            continue
        kind = kinds[fired[0]]
        if kind == "lock":
            w = y[0] if m.held else (m.je * y[0] + m.jh * y[1]) / (m.je + m.jh)
            y[0] = y[1] = w
            locked, t_lock = True, t
            horizon = max(m.t_end, t + follow)
        elif kind == "break":
            s = 1.0 if m.needed(y) >= 0 else -1.0
            locked, t_lock = False, np.nan
            horizon = m.t_end
            if t > m.t_end:
                break
        elif kind == "unpark":
            parked = False
        else:
            parked = True
            y[2] = 0.0
    ok = locked and t_lock <= m.t_end
    out = dict(
        lockup_time=t_lock if ok else np.nan,
        slip_work=y[4],
        peak_jerk=peak_jerk,
        peak_friction_torque=peak_torque,
        status="ok" if ok else "never_locked",
    )
    if power_samples:
        out["flash_peak"] = _flash_peak(power, t_lock if ok else m.t_end)
    return out


def _piece_power(m, sol, t, s, power_samples):
    """(times, slip power) of a slipping piece on its dense output, about ``power_samples``
    samples a window (at least 8 a piece)."""
    t_stop = sol.t[-1]
    ts_ = np.linspace(t, t_stop, max(int(power_samples * (t_stop - t) / m.t_end), 8) + 1)
    ys_ = sol.sol(ts_)
    return ts_, np.array(
        [m.torque(tt, yy, s) * (yy[0] - yy[1]) for tt, yy in zip(ts_, ys_.T, strict=True)]
    )


def _flash_peak(pieces, t_last):
    """max over t of ∫P(τ)/√(t − τ)dτ of the sampled slip power (linear between samples, every
    segment exactly: the solver's own formula, at every sample), the power zero after ``t_last``."""
    from .engagement._power import duhamel_peak

    if not pieces:
        return 0.0
    t = np.concatenate([pc[0] for pc in pieces])
    pw = np.concatenate([pc[1] for pc in pieces])
    keep = np.concatenate([[True], np.diff(t) > 0])
    t, pw = t[keep], pw[keep]
    after = np.linspace(t_last, t_last + 0.5 * (t_last - t[0]) + 1e-3, 400)[1:]
    hist = np.zeros((3, t.size + after.size))  # (row 2: the peak search's scratch)
    hist[0] = np.concatenate([t, after])
    hist[1, : t.size] = pw
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
    """Engagement of the rigid model with a held engine and friction fade, by Picard iteration.

    The model of :func:`clutchlab.engagement.simulate` with ``fade_coefficient`` > 0 (constant
    μ_k, the Stribeck law or a ``friction_table``), independently of its face-temperature state:
    Picard iteration on the face temperature rise ΔT(t). Given ΔT_j(t), ``solve_ivp`` (DOP853)
    integrates the driven speed with μ_k/(1 + β(ΔT_j − ΔT_on)⁺) (the driven side held by its
    static load until the clutch torque exceeds it; terminal event at lock-up); the slip power on
    ``samples`` equal steps to lock-up then gives ΔT_{j+1} = K·∫P(τ)/√(t − τ)dτ exactly for P
    linear between the samples (the kernel's own :func:`duhamel_at`, O(n²)).

    Parameters
    ----------
    p : dict
        The keyword arguments of :func:`clutchlab.engagement.simulate`, scalars (``profile``
        among them; default ramp).
    rtol : float
        Tolerance (relative and absolute) of solve_ivp.
    samples : int
        Samples of the slip power up to lock-up.
    iterations : int
        Picard iterations at most.
    tol : float
        Stop when the lock-up time changes by less than ``tol`` (relative).

    Returns
    -------
    dict
        ``lockup_time`` [s], ``slip_work`` [J], ``peak_face_rise`` [K], ``times`` [s] and
        ``face_rise`` [K] (the last ΔT(t)), ``iterations``.
    """
    m = _RigidFade(p)
    times, rise = np.array([0.0, m.t_end]), np.zeros(2)
    t_lock_prev = np.nan
    for it in range(1, iterations + 1):  # noqa: B007 (read after the loop)
        t_lock, sol, times, rise = _fade_pass(m, times, rise, rtol, samples)
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


class _RigidFade:
    """One scenario of the rigid model with a held engine and friction fade."""

    def __init__(self, p):
        self.we0, self.jv, self.tm, self.cmax, self.tr = (
            float(p[k])
            for k in ("engine_speed", "driven_inertia", "load_torque", "peak_capacity", "ramp_time")
        )
        self.rs, self.vs, self.table = (
            p.get("static_ratio", 1.0),
            p.get("stribeck_speed", np.inf),
            p.get("friction_table"),
        )
        self.beta, self.on, self.kf, self.t_end = (
            p["fade_coefficient"],
            p.get("fade_onset", 0.0),
            p["face_temperature_factor"],
            p["t_end"],
        )
        self.prof = _PROFILES[p.get("profile", "ramp")]

    def cap(self, t):
        return self.cmax * (self.prof(min(max(t / self.tr, 0.0), 1.0)) if self.tr > 0 else 1.0)

    def torque(self, t, wh, times, rise):
        """Clutch torque at time ``t``, hub speed ``wh``, with the face rise ``rise`` at ``times``."""
        g = 1.0 / (1.0 + self.beta * max(0.0, float(np.interp(t, times, rise)) - self.on))
        return _slip_law(self.we0 - wh, self.rs, self.vs, self.table) * g * self.cap(t)


def _fade_pass(m, times, rise, rtol, samples):
    """One Picard step: the engagement under the face rise ``rise`` at ``times``, and the face rise
    its slip power gives (after lock-up the face cools: the same integral of the ended power)."""
    from .engagement._power import duhamel_at

    we0, tm, jv, kf, t_end = m.we0, m.tm, m.jv, m.kf, m.t_end

    def rhs(t, y):
        tc = m.torque(t, y[0], times, rise)
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
        [
            grid,
            np.array(
                [m.torque(t, w, times, rise) * (we0 - w) for t, w in zip(grid, wh, strict=False)]
            ),
        ]
    )
    hist[1, -1] = 0.0 if np.isfinite(t_lock) else hist[1, -1]
    new_rise = np.array([kf * duhamel_at(hist, k) if k else 0.0 for k in range(samples)])
    after = np.linspace(t_stop, t_end, 200)[1:] if t_stop < t_end else np.zeros(0)
    if after.size:
        ext = np.hstack([hist, np.vstack([after, np.zeros(after.size)])])
        new_rise = np.concatenate(
            [new_rise, [kf * duhamel_at(ext, samples + k) for k in range(after.size)]]
        )
        grid = np.concatenate([grid, after])
    return t_lock, sol, grid, new_rise
