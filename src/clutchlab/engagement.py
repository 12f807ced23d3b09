"""Clutch engagement of a two-inertia driveline (seed 000 eqs. 1-2, 11, 12), batched.

Engine side (eq. 1) J_e·dω_e/dt = T_e − T_c; driven side (eq. 2) J_v·dω_c/dt = T_c − T_m.
While slipping T_c = sign(Δω)·μ(|Δω|)/μ_k · C(t) with the kinetic capacity
C(t) = C_max·p(t/t_r) (p a clamp profile: linear ramp, cubic or quintic smooth step, 1 after
t_r); while stuck T_c is whatever keeps both sides together, as long as it stays within the
static capacity (μ_s/μ_k)·C(t). The driven side stays parked at rest while the clutch torque is
below the (static) load torque. An engine with ``engine_inertia = inf`` is held at its speed.

Two solvers, one contract (same inputs, same metrics):

* :func:`closed_form` — constant μ, constant torques, polynomial clamp profile, held or free
  engine: speeds are piecewise polynomials in t, lock-up is a polynomial root (bracketed, to
  machine precision), slip/load/input work are exact Gauss-Legendre integrals.
  ≈ 0.5 µs per scenario; it is also the reference for the numerical solver.
* :func:`simulate` — everything else (Stribeck μ, rotor drag k·ω², engine torque table, load
  step, compliant driveline): a batched Dormand-Prince 5(4) integrator with per-scenario step
  sizes, breakpoints at the profile end and load step, and an event-driven stick/slip state
  machine whose events are located by re-integrating from the step's left end (Illinois
  method), i.e. exactly to the integrator's accuracy, not to the step size.

References
----------
.. [1] Zhao P. (2026), seed 000, eqs. (1), (2), (11), (12), Figs. 7-11.
.. [2] Otter M., Elmqvist H., Mattsson S.E. (1999), "Hybrid modeling in Modelica based on the
   synchronous data flow principle" (friction state machine of the Modelica Standard Library).
"""
from __future__ import annotations

import numpy as np

from . import status as st

__all__ = ["PROFILES", "clamp_profile", "closed_form", "simulate", "ramp_time_for_lockup"]

PROFILES = ("ramp", "cubic", "quintic")
# profile p(x) on [0, 1] and its integral P(x) = ∫0^x p, as ascending polynomial coefficients
_P = {
    "ramp": np.array([0.0, 1.0]),
    "cubic": np.array([0.0, 0.0, 3.0, -2.0]),            # ADAMS STEP (cubic)
    "quintic": np.array([0.0, 0.0, 0.0, 10.0, -15.0, 6.0]),  # STEP5-like quintic
}


def _polyval(c, x):
    out = np.zeros_like(x) + c[-1]
    for a in c[-2::-1]:
        out = out * x + a
    return out


def _integral_coeffs(c):
    return np.concatenate([[0.0], c / np.arange(1, len(c) + 1)])


def clamp_profile(x, kind="ramp"):
    """Clamp (capacity) profile p(x), x = t/t_r, clipped to [0, 1] outside [0, 1] [-]."""
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
    return np.where((t_r > 0) & (x < 1.0) & (x >= 0.0), c_max * _polyval(dp, np.clip(x, 0, 1)) / tr, 0.0)


def _invert_profile(q, kind):
    """x in [0, 1] with p(x) = q (p is monotone), vectorised bisection + Newton to round-off."""
    q = np.clip(q, 0.0, 1.0)
    if kind == "ramp":
        return q
    c, dc = _P[kind], np.polynomial.polynomial.polyder(_P[kind])
    lo, hi = np.zeros_like(q), np.ones_like(q)
    x = q.copy()
    for _ in range(60):
        f = _polyval(c, x) - q
        lo = np.where(f < 0, x, lo)
        hi = np.where(f >= 0, x, hi)
        d = _polyval(dc, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - f / d
        bad = ~((xn > lo) & (xn < hi))
        xn = np.where(bad, 0.5 * (lo + hi), xn)
        if np.all(np.abs(xn - x) <= 4e-16):
            x = xn
            break
        x = xn
    return x


def closed_form(*, engine_speed, engine_inertia, engine_torque, driven_inertia, load_torque, peak_capacity,
                ramp_time, profile="ramp", static_ratio=1.0, driven_speed=0.0, t_end=np.inf):
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
        (or [0, t_end] if never locked).
    """
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {profile!r}")
    arrs = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (
        engine_speed, engine_inertia, engine_torque, driven_inertia, load_torque, peak_capacity, ramp_time,
        static_ratio, driven_speed, t_end)))
    shape = arrs[0].shape
    flat = [a.astype(float).ravel() for a in arrs]
    n = flat[0].size
    if n > _BLOCK:  # cache-sized blocks: ~4x faster than whole-array temporaries at 1e6 scenarios
        parts = [_closed_form_flat([a[i:i + _BLOCK] for a in flat], profile) for i in range(0, n, _BLOCK)]
        return {k: np.concatenate([p[k] for p in parts]).reshape(shape) for k in parts[0]}
    return {k: v.reshape(shape) for k, v in _closed_form_flat(flat, profile).items()}


_BLOCK = 8192


def _closed_form_flat(flat, profile):
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
            return cmax * _polyval(pc, x), cmax * (trs * _polyval(big_p, x) + np.maximum(t - tr, 0.0))
        c = cmax * np.where(step, 1.0, _polyval(pc, x))
        ic = cmax * (np.where(step, 0.0, trs * _polyval(big_p, x)) + np.maximum(t - np.where(step, 0.0, tr), 0.0))
        return c, ic

    # phase 1: the driven side is at rest (parked by the static load) while C(t) < T_m. It is parked
    # from t = 0 if it starts at rest; if it starts turning it decelerates and parks at t_p when
    # its speed reaches zero before C reaches T_m (at t0). It moves again from t0 on.
    with np.errstate(divide="ignore", invalid="ignore"):
        q = tm / cmax
    moves = (tm <= 0.0) | (q < 1.0)
    t_m = np.where((tm > 0) & moves & ~step, trs * _invert_profile(np.where(moves, q, 0.0), profile), 0.0)
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

        t_p = np.where(parks_later, _newton_bracketed(w_moving, np.zeros_like(t_m), t_m, 0.5 * t_m, parks_later), t_p)
    parked_phase = starts_parked | parks_later
    t0 = np.where(parked_phase, t_m, 0.0)
    moves = moves | ~parked_phase
    _, ic0 = cap_icap(t0)

    def state(t):
        """(C, Δω, ω_e, ω_c) at t (t ≥ 0), piecewise polynomial."""
        c, ic = cap_icap(t)
        we = we0 + inv_je * (te * t - ic)
        wc = np.where(t < t_p, wc0 + inv_jv * (ic - tm * t),
                      inv_jv * np.where(moves & (t > t0), ic - ic0 - tm * (t - t0), 0.0))
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
            r_pos = np.where(a_coef >= 0, (a_coef + disc) / (b_coef * a_r), -2.0 * k0 / (a_coef - disc))
        t_lock = np.where(root_on_ramp, np.clip(r_pos, t0, ramp_end), t_lock)
    elif np.any(root_on_ramp):
        with np.errstate(divide="ignore", invalid="ignore"):
            qa = a_coef / (b_coef * cmax)
        t_top = np.where(qa >= 1.0, ramp_end, np.maximum(t0, trs * _invert_profile(np.clip(qa, 0, 1), profile)))
        lo = np.where(root_on_ramp, np.minimum(t_top, ramp_end), 0.0)
        hi = np.where(root_on_ramp, ramp_end, 1.0)
        def slip_rate(t):
            c, dw, _, _ = state(t)
            return dw, a_coef - b_coef * c

        t_lock = np.where(root_on_ramp, _newton_bracketed(slip_rate, lo, hi, hi.copy(), root_on_ramp), t_lock)
    rate = b_coef * cmax - a_coef  # −Δω' after the ramp
    after = moves & ~root_on_ramp & (rate > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_lock = np.where(after, ramp_end + np.maximum(s_end, 0.0) / rate, t_lock)
    # initial slip exactly zero: stuck from the start if the static capacity suffices (never sign(0))
    with np.errstate(divide="ignore", invalid="ignore"):
        need0 = np.where(held, tm, (tm + jv * te * inv_je) / (1.0 + jv * inv_je))
    stuck0 = (we0 - wc0 == 0.0) & (np.abs(need0) <= rs * cmax * np.where(step, 1.0, _polyval(pc, 0.0)))
    t_lock = np.where(stuck0, 0.0, t_lock)
    locked = np.isfinite(t_lock) & (t_lock <= tend)
    t_stop = np.where(locked, t_lock, tend)
    finite_window = np.isfinite(t_stop)
    t_stop = np.where(finite_window, t_stop, 0.0)

    # exact works: Gauss-Legendre with just enough nodes on each polynomial piece
    nodes = {"ramp": 2, "cubic": 4, "quintic": 6}[profile]  # exact: integrands of degree 2n-1
    gx, gw = np.polynomial.legendre.leggauss(nodes)
    knots = list(np.sort(np.stack([np.zeros_like(t_stop), np.minimum(t_p, t_stop), np.minimum(t0, t_stop),
                                   np.minimum(ramp_end, t_stop), t_stop]), axis=0))
    w_slip = w_in = w_load = 0.0
    for a, b in zip(knots[:-1], knots[1:]):
        half, mid = 0.5 * (b - a), 0.5 * (b + a)
        for xg, wg in zip(gx, gw):
            c, dw, we, wc = state(mid + half * xg)
            wt = wg * half
            w_slip = w_slip + wt * c * dw
            w_load = w_load + wt * tm * wc
            w_in = w_in + wt * np.where(held, c * we0, te * we)
    c_lock, _, we_end, wc_end = state(t_stop)
    wc_end = np.where(locked & held, we0, wc_end)  # at lock both sides turn together
    dke = 0.5 * jv * (wc_end**2 - wc0**2) + 0.5 * np.where(held, 0.0, je) * (we_end**2 - we0**2)
    residual = (w_in - dke - w_slip - w_load) / np.maximum(np.maximum(np.abs(w_in), np.abs(w_slip)), 1e-300)
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
        "slip_jerk": _peak_rate(t0, t_stop, cmax, tr, profile) * inv_jv,
        "status": code,
    }
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
            cands.append(np.where(qa > 0, (-qb + np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0))) / (2 * qa), 0.0))
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
    cand = np.where((xa <= 0.5) & (xb >= 0.5), np.maximum(cand, _polyval(dp, np.full_like(xa, 0.5))), cand)
    return np.where((t_r > 0) & (xb > xa), c_max * cand / tr, np.where(t_r > 0, 0.0, np.inf))


def _newton_bracketed(fun, lo, hi, x, mask):
    """Root of fun on [lo, hi] where fun(lo) > 0 ≥ fun(hi): Newton safeguarded by bisection.

    ``fun(x)`` returns (value, derivative); vectorised, to round-off.
    """
    lo, hi = lo.copy(), hi.copy()
    for _ in range(100):
        f, d = fun(x)
        lo = np.where(f > 0, x, lo)
        hi = np.where(f <= 0, x, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - f / d
        bad = ~((xn >= lo) & (xn <= hi)) | ~np.isfinite(xn)
        xn = np.where(bad, 0.5 * (lo + hi), xn)
        done = (np.abs(xn - x) <= 2e-16 * np.abs(x)) | (hi - lo <= 4e-16 * np.abs(hi)) | ~mask
        x = xn
        if np.all(done):
            break
    return x


def ramp_time_for_lockup(target_lockup_time, **kwargs):
    """Ramp time t_r that makes :func:`closed_form` lock up at ``target_lockup_time`` [s] (scalar).

    Used to reproduce the paper's "engagement shortened to 0.1 s / extended to 0.2 s" variants.
    """
    from scipy.optimize import brentq

    def f(tr):
        return float(closed_form(ramp_time=tr, **kwargs)["lockup_time"]) - target_lockup_time

    return brentq(f, 1e-6, 10.0 * target_lockup_time, xtol=1e-15, rtol=1e-15)


# ----------------------------------------------------------------------------------------------
# Batched numerical solver
# ----------------------------------------------------------------------------------------------

# Dormand-Prince 5(4) tableau
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = [
    [],
    [1 / 5],
    [3 / 40, 9 / 40],
    [44 / 45, -56 / 15, 32 / 9],
    [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
    [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
    [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
]
_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0])
_E = _B - np.array([5179 / 57600, 0.0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40])

LOCK, BREAK, UNPARK, PARK, PEAK = range(5)
EVENT_TIME_TOL = 1e-13  # s: bracket width at which an event time is final (Illinois method)
_N_EVENTS = 5  # PEAK (slip power maximum) switches no mode: it locates the peak exactly


class _Model:
    """Right-hand side, events and mode switches of the rigid or compliant driveline."""

    def __init__(self, compliant: bool, profile: str, engine_table):
        self.compliant = compliant
        self.profile = profile
        self.table = engine_table
        # state columns
        if compliant:
            self.E, self.H, self.R, self.TH, self.WS, self.WL, self.WI, self.WD = range(8)
            self.n_state = 8
        else:
            self.E, self.H, self.WS, self.WL, self.WI = range(5)
            self.R = self.H
            self.n_state = 5
        self.dyn = [self.E, self.H] + ([self.R, self.TH] if compliant else [])

    def capacity(self, t, P):
        return _capacity(t, P["cmax"], P["tr"], self.profile)

    def friction_factor(self, slip, P):
        with np.errstate(over="ignore", invalid="ignore"):
            ex = np.where(np.isfinite(P["vs"]), np.exp(-(slip / P["vs"]) ** 2), 0.0)
        return 1.0 + (P["rs"] - 1.0) * ex

    def load_static(self, t, P):
        return P["tm0"] + np.where(t >= P["tstep"], P["dtm"], 0.0)

    def engine_torque(self, we, P):
        if self.table is None:
            return P["te"]
        return P["te"] + np.interp(we, self.table[0], self.table[1])

    def forces(self, t, y, P, M):
        """Derivatives and auxiliary quantities for the current modes M = (locked, parked, s)."""
        locked, parked, s = M
        held = P["held"]
        we, wh, wr = y[:, self.E], y[:, self.H], y[:, self.R]
        C = self.capacity(t, P)
        tm = self.load_static(t, P) + P["ka"] * wr * wr
        te = np.where(held, 0.0, self.engine_torque(we, P))
        slip = we - wh
        f = self.friction_factor(np.abs(slip), P)
        dy = np.zeros_like(y)
        # torque resisting the hub: damper spring (compliant) or the load itself (rigid)
        if self.compliant:
            ts = P["k"] * y[:, self.TH] + P["c"] * (wh - wr)
            jh, hub_side = P["jh"], ts
        else:
            ts, jh, hub_side = None, P["jv"], tm
        # slipping clutch (a rigid driven side parked by the static load does not move)
        tc_slip = s * f * C
        ah_slip = (tc_slip - hub_side) / jh
        if not self.compliant:
            ah_slip = np.where(parked, 0.0, ah_slip)
        # locked clutch: engine and hub (rigid: whole driven side) move together
        with np.errstate(invalid="ignore", divide="ignore"):
            a_lock = np.where(held, 0.0, (te - hub_side) * P["inv_je"] / (1.0 + jh * P["inv_je"]))
        t_need = hub_side + jh * a_lock
        ah = np.where(locked, a_lock, ah_slip)
        tc = np.where(locked, t_need, tc_slip)
        ae = np.where(locked, a_lock, np.where(held, 0.0, (te - tc_slip) * P["inv_je"]))
        dy[:, self.E] = ae
        dy[:, self.H] = ah
        if self.compliant:
            ar = np.where(parked, 0.0, (ts - tm) / P["jr"])
            dy[:, self.R] = ar
            dy[:, self.TH] = wh - wr
            dy[:, self.WD] = P["c"] * (wh - wr) ** 2
        else:
            ar = ah
        dy[:, self.WS] = np.where(locked, 0.0, tc_slip * slip)
        dy[:, self.WL] = np.where(parked, 0.0, tm * wr)
        dy[:, self.WI] = np.where(held, tc * we, te * we)
        return dy, {"C": C, "tc": tc, "tm": tm, "ts": ts, "t_need": t_need, "slip": slip, "f": f, "ar": ar,
                    "ah": ah, "ae": ae}

    def jerk(self, t, y, P, M, dy, aux):
        """Output-side jerk from the state (chain rule, never by differencing): rad/s³."""
        locked, parked, s = M
        wr = y[:, self.R]
        dtm = 2.0 * P["ka"] * wr * aux["ar"]
        if self.compliant:
            dts = P["k"] * (y[:, self.H] - wr) + P["c"] * (dy[:, self.H] - aux["ar"])
            return np.where(parked, 0.0, (dts - dtm) / P["jr"])
        dtc = self.slip_torque_rate(t, P, M, dy, aux)
        j_slip = np.where(parked, 0.0, (dtc - dtm) / P["jv"])
        j_lock = np.where(P["held"], 0.0, -dtm * P["inv_je"] / (1.0 + P["jv"] * P["inv_je"]))
        return np.where(locked, j_lock, j_slip)

    def slip_torque_rate(self, t, P, M, dy, aux):
        """d/dt of the slipping clutch torque s·f(|Δω|)·C(t) (chain rule) [N m/s]."""
        rate = _capacity_rate(t, P["cmax"], P["tr"], self.profile)
        slip = aux["slip"]
        with np.errstate(over="ignore", invalid="ignore"):
            ex = np.where(np.isfinite(P["vs"]), np.exp(-(slip / P["vs"]) ** 2), 0.0)
            dfdv = np.where(np.isfinite(P["vs"]), (P["rs"] - 1.0) * ex * (-2.0 * np.abs(slip) / P["vs"] ** 2), 0.0)
        dabs = np.sign(slip) * (dy[:, self.E] - dy[:, self.H])
        return M[2] * (aux["f"] * rate + aux["C"] * dfdv * dabs)

    def events(self, t, y, P, M, dy, aux):
        """Event functions (falling through zero from strictly positive); +inf where not armed."""
        locked, parked, s = M
        g = np.full((y.shape[0], _N_EVENTS), np.inf)
        g[:, LOCK] = np.where(~locked, s * aux["slip"], np.inf)
        g[:, BREAK] = np.where(locked, P["rs"] * aux["C"] - np.abs(aux["t_need"]), np.inf)
        drive = aux["ts"] if self.compliant else aux["tc"]
        g[:, UNPARK] = np.where(parked, self.load_static(t, P) - drive, np.inf)
        g[:, PARK] = np.where(~parked & (~locked | self.compliant), y[:, self.R], np.inf)
        dpower = (self.slip_torque_rate(t, P, M, dy, aux) * aux["slip"]
                  + aux["tc"] * (dy[:, self.E] - dy[:, self.H]))
        g[:, PEAK] = np.where(~locked, dpower, np.inf)
        return g

    def may_dip(self, g0, g1, d0, d1, M):
        """Rows where the LOCK or PARK function is positive at both ends of a step but its slope turns
        from falling to rising inside it (a dip below zero could hide there)."""
        out = np.zeros(g0.shape[0], bool)
        for kind, s0, s1 in ((LOCK, M[2] * (d0[:, self.E] - d0[:, self.H]), M[2] * (d1[:, self.E] - d1[:, self.H])),
                             (PARK, d0[:, self.R], d1[:, self.R])):
            out |= (g0[:, kind] > 0) & (g1[:, kind] > 0) & np.isfinite(g0[:, kind]) & (s0 < 0) & (s1 > 0)
        return out

    def extrema(self, g0, g1, d0, d1, h, M):
        """Interior extrema θ in (0, 1) of the cubic Hermite interpolants of the LOCK and PARK event
        functions over a step (their derivatives are known from the state derivatives); where an
        event function dips below zero and back inside one step, it does so around these points."""
        out = []
        for kind, slope0, slope1 in (
                (LOCK, M[2] * (d0[:, self.E] - d0[:, self.H]), M[2] * (d1[:, self.E] - d1[:, self.H])),
                (PARK, d0[:, self.R], d1[:, self.R])):
            a0, a1 = g0[:, kind], g1[:, kind]
            fin = np.isfinite(a0) & np.isfinite(a1)
            a0, a1 = np.where(fin, a0, 0.0), np.where(fin, a1, 0.0)
            m0, m1 = h * slope0, h * slope1
            qa = 6 * a0 + 3 * m0 - 6 * a1 + 3 * m1
            qb = -6 * a0 - 4 * m0 + 6 * a1 - 2 * m1
            qc = m0
            with np.errstate(invalid="ignore", divide="ignore"):
                disc = np.sqrt(qb**2 - 4 * qa * qc)
                for r in ((-qb + disc) / (2 * qa), (-qb - disc) / (2 * qa), -qc / qb):
                    out.append(np.where(fin & np.isfinite(r) & (r > 0) & (r < 1), r, 0.5))
        return out

    def switch(self, kind, t, y, P, M):
        """Apply the mode change of event ``kind`` in place (y projected onto the new mode)."""
        locked, parked, s = M
        if kind == LOCK:
            locked[:] = True
            je_inv = P["inv_je"]
            jh = P["jh"] if self.compliant else P["jv"]
            w = np.where(P["held"], y[:, self.E], (y[:, self.E] + jh * je_inv * y[:, self.H]) / (1 + jh * je_inv))
            y[:, self.E] = w
            y[:, self.H] = w
            if not self.compliant:
                parked[:] = False
        elif kind == BREAK:
            _, aux = self.forces(t, y, P, M)
            locked[:] = False
            s[:] = np.where(aux["t_need"] >= 0, 1.0, -1.0)
        elif kind == PEAK:
            pass
        elif kind == UNPARK:
            parked[:] = False
        elif kind == PARK:
            parked[:] = True
            y[:, self.R] = 0.0


def _dopri_step(model, t, y, h, P, M, k1=None):
    k = [] if k1 is None else [k1]
    for i in range(len(k), 7):
        yi = y.copy()
        for j, a in enumerate(_A[i]):
            if a:
                yi += (h * a)[:, None] * k[j]
        k.append(model.forces(t + _C[i] * h, yi, P, M)[0])
    y_new = y.copy()
    err = np.zeros_like(y)
    for j in range(7):
        if _B[j]:
            y_new += (h * _B[j])[:, None] * k[j]
        err += (h * _E[j])[:, None] * k[j]
    return y_new, err, k[6]


def _sub(P, idx):
    return {k: v[idx] for k, v in P.items()}


def simulate(*, engine_speed, engine_inertia, engine_torque, driven_inertia, load_torque, peak_capacity,
             ramp_time, profile="ramp", static_ratio=1.0, stribeck_speed=np.inf, driven_speed=0.0,
             aero_coefficient=0.0, load_step=0.0, load_step_time=np.inf, engine_torque_table=None,
             compliant=False, hub_fraction=0.5, damper_stiffness=np.inf, damping_ratio=0.0,
             t_end=0.5, rtol=1e-10, atol=1e-10, max_step=np.inf, first_step=1e-5, max_steps=200000,
             trace_times=None):
    """Engagement by a batched Dormand-Prince 5(4) integrator with exact stick-slip events.

    Parameters are those of :func:`closed_form` plus:

    stribeck_speed : array_like
        v_s [rad/s] of μ(v) = μ_k·[1 + (μ_s/μ_k − 1)·exp(−(v/v_s)²)]; ``inf`` gives constant μ_k
        while slipping (μ_s then applies only to sticking).
    aero_coefficient : array_like
        k_a [N m s²] of the rotor drag k_a·ω_c² added to the load torque.
    load_step, load_step_time : array_like
        A load torque step ΔT_m [N m] at t_s [s] (e.g. collective pulled after engagement).
    engine_torque_table : (speeds [rad/s], torques [N m]) or None
        Engine torque versus speed, added to ``engine_torque`` (shared by all scenarios).
    compliant : bool
        Insert the damper springs between plate hub and output: hub inertia
        ``hub_fraction``·J_v, output inertia (1 − ``hub_fraction``)·J_v, stiffness
        ``damper_stiffness`` [N m/rad] and viscous damping of the given ``damping_ratio`` on the
        hub-output mode. Gives a finite output jerk; as the stiffness grows it tends to the rigid
        model.
    rtol, atol : float
        Error tolerances of the step-size control.
    max_step : float
        Largest step [s] (bounds the node spacing of peak metrics and traces).
    trace_times : array_like or None
        Times [s] at which to record the state (they become breakpoints, so no interpolation).

    Returns
    -------
    dict of numpy.ndarray
        The metrics of :func:`closed_form` over [0, t_end] (``lockup_time`` is the last
        lock-up; NaN if slipping at t_end), plus ``breakaway_time`` (first re-slip after a
        lock-up), ``peak_jerk`` [rad/s³] (output side, from the model equations at every step
        node and event; the Dirac jerk of a rigid lock-up is reported as ``accel_jump``),
        ``n_steps`` and, with ``trace_times``, a ``trace`` dict of arrays (scenario, time).
    """
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {profile!r}")
    names = ["we0", "je", "te", "jv", "tm0", "cmax", "tr", "rs", "vs", "wc0", "ka", "dtm", "tstep", "phi", "k",
             "zeta", "tend"]
    vals = [engine_speed, engine_inertia, engine_torque, driven_inertia, load_torque, peak_capacity, ramp_time,
            static_ratio, stribeck_speed, driven_speed, aero_coefficient, load_step, load_step_time, hub_fraction,
            damper_stiffness, damping_ratio, t_end]
    arrs = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in vals))
    shape = arrs[0].shape
    P = {k: a.ravel().copy() for k, a in zip(names, arrs)}
    n = P["we0"].size
    P["held"] = ~np.isfinite(P["je"])
    P["inv_je"] = np.where(P["held"], 0.0, 1.0 / np.where(P["held"], 1.0, P["je"]))
    model = _Model(bool(compliant), profile, engine_torque_table)
    P["jh"] = P["phi"] * P["jv"]
    P["jr"] = (1.0 - P["phi"]) * P["jv"]
    with np.errstate(invalid="ignore"):
        P["c"] = np.where(np.isfinite(P["k"]), 2.0 * P["zeta"] * np.sqrt(P["k"] * P["jh"] * P["jr"] / P["jv"]), 0.0)

    y = np.zeros((n, model.n_state))
    y[:, model.E] = P["we0"]
    y[:, model.H] = P["wc0"]
    if compliant:
        y[:, model.R] = P["wc0"]
    # initial modes: decided from torques, never from sign(0)
    locked = np.zeros(n, bool)
    parked = P["wc0"] <= 0.0
    s = np.ones(n)
    M = (locked, parked, s)
    _, aux = model.forces(np.zeros(n), y, P, M)
    C0 = aux["C"]
    parked &= model.load_static(np.zeros(n), P) > (aux["ts"] if compliant else aux["f"] * C0)
    zero_slip = P["we0"] == P["wc0"]
    if np.any(zero_slip):
        Mt = (np.ones(n, bool), np.zeros(n, bool), s)
        _, aux_l = model.forces(np.zeros(n), y, P, Mt)
        stick = zero_slip & (np.abs(aux_l["t_need"]) <= P["rs"] * C0)
        locked |= stick
        parked &= ~stick
        initially_stuck = stick
        s[:] = np.where(zero_slip & ~stick, np.where(aux_l["t_need"] >= 0, 1.0, -1.0), s)

    # breakpoints: profile end, load step, trace times, end
    bps = [P["tr"], P["tstep"], P["tend"]]
    tt = None if trace_times is None else np.asarray(trace_times, dtype=float)
    if tt is not None:
        bps += [np.full(n, v) for v in tt]
    BP = np.stack(bps, axis=1)

    res = {k: np.full(n, np.nan) for k in ("lockup_time", "breakaway_time", "capacity_at_lockup",
                                           "accel_jump", "lockup_speed")}
    peaks = {k: np.zeros(n) for k in ("peak_slip_power", "peak_friction_torque", "peak_jerk")}
    res_events = {**res, "peak_slip_power": peaks["peak_slip_power"]}  # same arrays, for the event handler
    if np.any(zero_slip):
        res["lockup_time"][initially_stuck] = 0.0
        res["lockup_speed"][initially_stuck] = P["wc0"][initially_stuck]
    n_steps = np.zeros(n, np.int64)
    code = np.full(n, st.CODE["ok"], dtype=st.DTYPE)
    if tt is not None:
        trace = {k: np.full((n, tt.size), np.nan) for k in ("engine_speed", "hub_speed", "output_speed",
                                                            "friction_torque", "capacity", "slip_work", "jerk")}
        trace_idx = {float(v): i for i, v in enumerate(tt)}

    t = np.zeros(n)
    h = np.minimum(np.full(n, first_step), P["tend"])
    idx = np.arange(n)  # positions of the active scenarios
    yA, PA, MA, tA, hA = y, P, M, t, h
    dA, aux = model.forces(tA, yA, PA, MA)
    gA = model.events(tA, yA, PA, MA, dA, aux)

    def record(ids, tt_, yy, PP, MM, dy, ax):
        jerk = model.jerk(tt_, yy, PP, MM, dy, ax)
        power = np.where(MM[0], 0.0, ax["tc"] * ax["slip"])
        peaks["peak_slip_power"][ids] = np.maximum(peaks["peak_slip_power"][ids], power)
        peaks["peak_friction_torque"][ids] = np.maximum(peaks["peak_friction_torque"][ids], np.abs(ax["tc"]))
        peaks["peak_jerk"][ids] = np.maximum(peaks["peak_jerk"][ids], np.abs(jerk))

    record(idx, tA, yA, PA, MA, dA, aux)
    while idx.size:
        nb = np.min(np.where(BP[idx] > tA[:, None], BP[idx], np.inf), axis=1)
        h_try = np.minimum(np.minimum(hA, max_step), nb - tA)
        hit = h_try >= nb - tA
        y_new, err, _ = _dopri_step(model, tA, yA, h_try, PA, MA, k1=dA)
        scale = atol + rtol * np.maximum(np.abs(yA), np.abs(y_new))
        norm = np.sqrt(np.mean((err / scale) ** 2, axis=1))
        ok = norm <= 1.0
        n_steps[idx] += 1
        with np.errstate(divide="ignore"):
            fac = np.clip(0.9 * norm ** -0.2, 0.2, 5.0)
        hA = np.where(ok, h_try * fac, h_try * np.minimum(fac, 0.9))
        acc = np.flatnonzero(ok)
        if acc.size:
            Pa, Ma = _sub(PA, acc), tuple(m[acc] for m in MA)
            ha, ta, y0, y1 = h_try[acc], tA[acc], yA[acc], y_new[acc]
            t_right = np.where(hit[acc], nb[acc], ta + ha)
            d1, aux_r = model.forces(t_right, y1, Pa, Ma)
            g_right = model.events(t_right, y1, Pa, Ma, d1, aux_r)
            # detection: the event functions at 3 interior points of a cubic Hermite interpolant,
            # so that a sign change and back within one step is not missed (location is exact:
            # re-integration in _handle_events, which also rejects false alarms)
            d0 = dA[acc]
            g0 = gA[acc]
            tau_hi = np.where((g0 > 0) & (g_right <= 0), ha[:, None], np.inf)
            samples = [(np.arange(acc.size), np.full(acc.size, 0.5))]
            dip = model.may_dip(g0, g_right, d0, d1, Ma)
            if dip.any():
                r = np.flatnonzero(dip)
                samples += [(r, th) for th in model.extrema(g0[r], g_right[r], d0[r], d1[r], ha[r],
                                                            tuple(m[r] for m in Ma))]
            for r, th in samples:
                th = th[:, None]
                hr = ha[r][:, None]
                ym = ((2 * th**3 - 3 * th**2 + 1) * y0[r] + (th**3 - 2 * th**2 + th) * hr * d0[r]
                      + (-2 * th**3 + 3 * th**2) * y1[r] + (th**3 - th**2) * hr * d1[r])
                tm_ = ta[r] + th[:, 0] * ha[r]
                Pr, Mr = (Pa, Ma) if r.size == acc.size else (_sub(Pa, r), tuple(m[r] for m in Ma))
                dm, auxm = model.forces(tm_, ym, Pr, Mr)
                gm = model.events(tm_, ym, Pr, Mr, dm, auxm)
                tau_hi[r] = np.where((g0[r] > 0) & (gm <= 0), np.minimum(tau_hi[r], th * hr), tau_hi[r])
            any_f = np.isfinite(tau_hi).any(axis=1)
            adv = ~any_f
            if np.any(any_f):
                fired_rows = np.flatnonzero(any_f)
                handled, retry_h = _handle_events(model, acc[fired_rows], tau_hi[fired_rows], tA, yA, gA, dA, PA,
                                                  MA, res_events, idx, record, (rtol, atol))
                retry = np.isfinite(retry_h)
                hA[acc[fired_rows[retry]]] = retry_h[retry]  # located step too long: shorter step, again
                adv[fired_rows[~handled & ~retry]] = True  # false alarms: take the step as it was
            sel = acc[adv]
            tA[sel] = t_right[adv]
            yA[sel] = y1[adv]
            gA[sel] = g_right[adv]
            dA[sel] = d1[adv]
            record(idx[sel], t_right[adv], y1[adv], _sub(Pa, np.flatnonzero(adv)),
                   tuple(m[adv] for m in Ma), d1[adv], {k: (v[adv] if v is not None else None)
                                                        for k, v in aux_r.items()})
            if tt is not None:
                for j in sel:
                    key = float(tA[j])
                    if key in trace_idx:
                        gi, ti = idx[j], trace_idx[key]
                        Pj, Mj = _sub(PA, [j]), tuple(m[[j]] for m in MA)
                        dy, ax = model.forces(tA[[j]], yA[[j]], Pj, Mj)
                        trace["engine_speed"][gi, ti] = yA[j, model.E]
                        trace["hub_speed"][gi, ti] = yA[j, model.H]
                        trace["output_speed"][gi, ti] = yA[j, model.R]
                        trace["friction_torque"][gi, ti] = ax["tc"][0]
                        trace["capacity"][gi, ti] = ax["C"][0]
                        trace["slip_work"][gi, ti] = yA[j, model.WS]
                        trace["jerk"][gi, ti] = model.jerk(tA[[j]], yA[[j]], Pj, Mj, dy, ax)[0]
        done = (tA >= PA["tend"]) | (n_steps[idx] >= max_steps)
        if done.any():
            d = np.flatnonzero(done)
            gi = idx[d]
            y[gi], t[gi] = yA[d], tA[d]
            for m_all, m_act in zip(M, MA):
                m_all[gi] = m_act[d]
            code[gi[n_steps[gi] >= max_steps]] = st.CODE["not_converged"]
            keep = np.flatnonzero(~done)
            idx, yA, tA, hA, gA, dA = idx[keep], yA[keep], tA[keep], hA[keep], gA[keep], dA[keep]
            PA = _sub(PA, keep)
            MA = tuple(m[keep] for m in MA)

    locked, parked, s = M
    code[(code == st.CODE["ok"]) & ~locked] = st.CODE["never_locked"]
    res["lockup_time"] = np.where(locked, res["lockup_time"], np.nan)
    res["accel_jump"] = np.where(locked, res["accel_jump"], np.nan)
    w_e, w_h, w_r = y[:, model.E], y[:, model.H], y[:, model.R]
    dke = 0.5 * P["jv"] * (w_h**2 - P["wc0"] ** 2) if not compliant else (
        0.5 * P["jh"] * (w_h**2 - P["wc0"] ** 2) + 0.5 * P["jr"] * (w_r**2 - P["wc0"] ** 2)
        + 0.5 * np.where(np.isfinite(P["k"]), P["k"], 0.0) * y[:, model.TH] ** 2)
    dke = dke + 0.5 * np.where(P["held"], 0.0, P["je"]) * (w_e**2 - P["we0"] ** 2)
    w_d = y[:, model.WD] if compliant else 0.0
    w_in, w_s, w_l = y[:, model.WI], y[:, model.WS], y[:, model.WL]
    out = {
        **res,
        "slip_work": w_s, "load_work": w_l, "input_work": w_in, "kinetic_energy_change": dke,
        "damping_work": w_d + np.zeros(n),
        "energy_residual": (w_in - dke - w_s - w_l - w_d) / np.maximum(np.maximum(np.abs(w_in), np.abs(w_s)), 1e-300),
        **peaks,
        "n_steps": n_steps,
        "status": code,
    }
    out = {k: v.reshape(shape) for k, v in out.items()}
    if tt is not None:
        out["trace"] = {k: v.reshape(shape + (tt.size,)) for k, v in trace.items()}
    return out


def _handle_events(model, ev, tau_hi, tA, yA, gA, dA, PA, MA, res, idx, record, tol):
    """Locate events of the active scenarios ``ev`` by re-integration from the step's left end.

    ``tau_hi[:, kind]`` is a step length at which event ``kind`` appeared to have happened (inf
    if not). The root is bracketed in (0, tau_hi] with the true event function and found by the
    Illinois method; the earliest event of a scenario is applied. Returns a boolean array: True
    where an event was applied, False for a false alarm (no true sign change).
    """
    Pe, Me = _sub(PA, ev), tuple(m[ev].copy() for m in MA)
    t0, y0, g0, d0 = tA[ev], yA[ev], gA[ev], dA[ev]
    best_tau = np.full(ev.size, np.inf)
    best_kind = np.full(ev.size, -1)
    best_y = y0.copy()
    eps = np.finfo(float).eps
    for kind in range(_N_EVENTS):
        rows = np.flatnonzero(np.isfinite(tau_hi[:, kind]))
        if not rows.size:
            continue
        Pk, Mk = _sub(Pe, rows), tuple(m[rows] for m in Me)
        tk, yk, dk = t0[rows], y0[rows], d0[rows]
        hi = tau_hi[rows, kind].copy()
        y_hi, _, _ = _dopri_step(model, tk, yk, hi, Pk, Mk, k1=dk)
        dd, ax = model.forces(tk + hi, y_hi, Pk, Mk)
        g_hi = model.events(tk + hi, y_hi, Pk, Mk, dd, ax)[:, kind]
        real = g_hi <= 0
        rows, hi, g_hi, y_hi = rows[real], hi[real], g_hi[real], y_hi[real]
        if not rows.size:
            continue
        Pk, Mk = _sub(Pe, rows), tuple(m[rows] for m in Me)
        tk, yk, dk = t0[rows], y0[rows], d0[rows]
        lo, g_lo = np.zeros(rows.size), g0[rows, kind].copy()
        side = np.zeros(rows.size)
        live = np.ones(rows.size, bool)
        for _ in range(100):
            r = np.flatnonzero(live)
            with np.errstate(invalid="ignore", divide="ignore"):
                tau = hi[r] - g_hi[r] * (hi[r] - lo[r]) / (g_hi[r] - g_lo[r])
            mid = 0.5 * (lo[r] + hi[r])
            tau = np.where(np.isfinite(tau) & (tau > lo[r]) & (tau < hi[r]), tau, mid)
            Pr, Mr = _sub(Pk, r), tuple(m[r] for m in Mk)
            y_tau, _, _ = _dopri_step(model, tk[r], yk[r], tau, Pr, Mr, k1=dk[r])
            dd, ax = model.forces(tk[r] + tau, y_tau, Pr, Mr)
            g_tau = model.events(tk[r] + tau, y_tau, Pr, Mr, dd, ax)[:, kind]
            pos = g_tau > 0
            stale_hi = pos & (side[r] > 0)
            stale_lo = ~pos & (side[r] < 0)
            lo[r], g_lo[r] = np.where(pos, tau, lo[r]), np.where(pos, g_tau, np.where(stale_lo, 0.5 * g_lo[r], g_lo[r]))
            hi[r], g_hi[r] = np.where(pos, hi[r], tau), np.where(pos, np.where(stale_hi, 0.5 * g_hi[r], g_hi[r]), g_tau)
            y_hi[r] = np.where(pos[:, None], y_hi[r], y_tau)
            side[r] = np.where(pos, 1.0, -1.0)
            live[r] = ~((hi[r] - lo[r] <= EVENT_TIME_TOL + 4 * eps * (tk[r] + hi[r])) | (g_hi[r] == 0))
            if not live.any():
                break
        better = hi < best_tau[rows]
        rb = rows[better]
        best_tau[rb], best_kind[rb], best_y[rb] = hi[better], kind, y_hi[better]
    applied = best_kind >= 0
    # the located step must itself meet the tolerance; otherwise retry with a shorter step
    retry_h = np.full(ev.size, np.nan)
    rows = np.flatnonzero(applied)
    if rows.size:
        Pk, Mk = _sub(Pe, rows), tuple(m[rows] for m in Me)
        y_v, err_v, _ = _dopri_step(model, t0[rows], y0[rows], best_tau[rows], Pk, Mk, k1=d0[rows])
        norm = np.sqrt(np.mean((err_v / (tol[1] + tol[0] * np.maximum(np.abs(y0[rows]), np.abs(y_v)))) ** 2, axis=1))
        bad = norm > 1.0
        with np.errstate(divide="ignore"):
            retry_h[rows[bad]] = best_tau[rows[bad]] * np.clip(0.9 * norm[bad] ** -0.2, 0.1, 0.9)
        applied[rows[bad]] = False
        best_kind[rows[bad]] = -1
    t_ev = t0 + np.where(applied, best_tau, 0.0)
    for kind in range(_N_EVENTS):
        rows = np.flatnonzero(best_kind == kind)
        if not rows.size:
            continue
        Pk, Mk = _sub(Pe, rows), tuple(m[rows].copy() for m in Me)
        yk = best_y[rows]
        tk = t_ev[rows]
        a_before = model.forces(tk, yk, Pk, Mk)[0][:, model.R]
        model.switch(kind, tk, yk, Pk, Mk)
        dyk, auxk = model.forces(tk, yk, Pk, Mk)
        gi = idx[ev[rows]]
        if kind == LOCK:
            res["lockup_time"][gi] = tk
            res["lockup_speed"][gi] = yk[:, model.H]
            res["capacity_at_lockup"][gi] = auxk["C"]
            res["accel_jump"][gi] = dyk[:, model.R] - a_before
        elif kind == PEAK:
            res["peak_slip_power"][gi] = np.maximum(res["peak_slip_power"][gi], np.abs(auxk["tc"] * auxk["slip"]))
        elif kind == BREAK:
            res["breakaway_time"][gi] = np.where(np.isnan(res["breakaway_time"][gi]), tk, res["breakaway_time"][gi])
            res["lockup_time"][gi] = np.nan
        for m_act, m_new in zip(MA, Mk):
            m_act[ev[rows]] = m_new
        best_y[rows] = yk
        gA[ev[rows]] = model.events(tk, yk, Pk, Mk, dyk, auxk)
        dA[ev[rows]] = dyk
        record(gi, tk, yk, Pk, Mk, dyk, auxk)
    tA[ev[applied]] = t_ev[applied]
    yA[ev[applied]] = best_y[applied]
    return applied, retry_h
