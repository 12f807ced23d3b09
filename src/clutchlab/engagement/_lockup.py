"""The closed form's phases: speeds as piecewise polynomials in t, the parked phase and the lock-up root.

Constant μ, constant torques and a polynomial clamp profile p (source paper (000), eqs. 1-2):
while slipping Δω' = A − B·C(t) with A = T_e/J_e + T_m/J_v and B = 1/J_e + 1/J_v, so every speed
is a polynomial in t on each piece of C (parked, on the profile, after it), and lock-up is a
polynomial root, bracketed and found to round-off. Numpy, vectorised over a block of scenarios.
"""

from __future__ import annotations

import numpy as np

from ._profile import _P, _integral_coeffs, _invert_profile, _polyval


class Drive:
    """A block of scenarios of the closed form: its inputs (flat arrays, the order of
    :func:`clutchlab.engagement.closed_form`'s arguments) and, once built, the parked phase
    (:func:`_parking`), so that :meth:`state` gives the speeds at any t."""

    def __init__(self, flat, profile):
        we0, je, te, jv, tm, cmax, tr, rs, wc0, tend = flat
        self.we0, self.je, self.jv, self.tm, self.cmax = we0, je, jv, tm, cmax
        self.tr, self.rs, self.wc0, self.tend, self.profile = tr, rs, wc0, tend, profile
        self.held = held = ~np.isfinite(je)  # a held engine keeps its speed
        self.inv_je = np.where(held, 0.0, 1.0 / np.where(held, 1.0, je))
        self.te = np.where(held, 0.0, te)
        self.inv_jv = 1.0 / jv
        self.step = step = tr <= 0  # a zero ramp time is a step at t = 0+
        self.trs = np.where(step, 1.0, tr)
        self.pc, self.big_p = _P[profile], _integral_coeffs(_P[profile])
        self.inv_tr = 1.0 / self.trs
        self.any_step = bool(step.any())
        _parking(self)

    def capacity(self, t):
        """(C(t), ∫0^t C) [N m, N m s]."""
        cmax, trs, tr, step = self.cmax, self.trs, self.tr, self.step
        x = np.minimum(t * self.inv_tr, 1.0)
        if not self.any_step:
            if self.profile == "ramp":  # p = x, P = x²/2 without the general Horner loop; rounded
                # as _polyval rounds it, so that a batch with a step gives the same numbers
                return cmax * x, cmax * (trs * (0.5 * x * x) + np.maximum(t - tr, 0.0))
            return cmax * _polyval(self.pc, x), cmax * (
                trs * _polyval(self.big_p, x) + np.maximum(t - tr, 0.0)
            )
        c = cmax * np.where(step, 1.0, _polyval(self.pc, x))
        ic = cmax * (
            np.where(step, 0.0, trs * _polyval(self.big_p, x))
            + np.maximum(t - np.where(step, 0.0, tr), 0.0)
        )
        return c, ic

    def state(self, t):
        """(C, Δω, ω_e, ω_c) at t (t ≥ 0), piecewise polynomial [N m, rad/s, rad/s, rad/s]."""
        c, ic = self.capacity(t)
        we = self.we0 + self.inv_je * (self.te * t - ic)
        moving = self.inv_jv * np.where(
            self.moves & (t > self.t0), ic - self.ic0 - self.tm * (t - self.t0), 0.0
        )
        if self.all_parked_from_start:
            return c, we - moving, we, moving
        wc = np.where(t < self.t_p, self.wc0 + self.inv_jv * (ic - self.tm * t), moving)
        wc = np.where(self.parked_phase, wc, self.wc0 + self.inv_jv * (ic - self.tm * t))
        return c, we - wc, we, wc


def _parking(d):
    """Phase 1: the driven side is at rest (parked by the static load) while C(t) < T_m. It is
    parked from t = 0 if it starts at rest; if it starts turning it decelerates and parks at t_p
    when its speed reaches zero before C reaches T_m (at t0). It moves again from t0 on. Sets
    ``t_p``, ``t0``, ``moves``, ``parked_phase``, ``parks_later``, ``ic0`` and
    ``all_parked_from_start`` on ``d``, and a free engine's stall in the parked phase
    (:func:`_stall`)."""
    tm = d.tm
    with np.errstate(divide="ignore", invalid="ignore"):
        q = tm / d.cmax
    moves = (tm <= 0.0) | (q < 1.0)
    t_m = np.where(
        (tm > 0) & moves & ~d.step, d.trs * _invert_profile(np.where(moves, q, 0.0), d.profile), 0.0
    )
    _, ic_m = d.capacity(t_m)
    wc_at_tm = d.wc0 + d.inv_jv * (ic_m - tm * t_m)
    starts_parked = (d.wc0 <= 0.0) & (tm > 0.0)
    parks_later = (d.wc0 > 0.0) & (tm > 0.0) & (wc_at_tm < 0.0)
    t_p = np.where(starts_parked, 0.0, np.inf)
    if np.any(parks_later):
        # ω_c = wc0 + (Ic(t) − T_m t)/J_v is decreasing on [0, t_m]: root by bisection + Newton
        def w_moving(t):  # driven speed and its rate before parking
            c, ic = d.capacity(t)
            return d.wc0 + d.inv_jv * (ic - tm * t), (c - tm) * d.inv_jv

        t_p = np.where(
            parks_later,
            newton_bracketed(w_moving, np.zeros_like(t_m), t_m, 0.5 * t_m, parks_later),
            t_p,
        )
    d.parked_phase = parked_phase = starts_parked | parks_later
    d.parks_later, d.t_p = parks_later, t_p
    d.t0 = np.where(parked_phase, t_m, 0.0)
    d.moves = moves | ~parked_phase
    _, d.ic0 = d.capacity(d.t0)
    # the usual case: the driven side starts at rest
    d.all_parked_from_start = bool(starts_parked.all())
    _stall(d)


def lockup_time(d):
    """Phase 2: Δω' = A − B·C(t), concave on the ramp, linear after it. Returns (t_lock [s], inf
    where it never locks; the ramp's end [s]; A [rad/s²]; B [1/(kg m²)])."""
    a_coef = d.te * d.inv_je + d.tm * d.inv_jv
    b_coef = d.inv_je + d.inv_jv
    ramp_end = np.where(d.step, d.t0, np.maximum(d.tr, d.t0))
    s_end = d.state(ramp_end)[1]
    root_on_ramp = d.moves & ~d.step & (d.tr > d.t0) & (s_end <= 0.0)
    t_lock = _root_on_profile(d, a_coef, b_coef, ramp_end, root_on_ramp)
    rate = b_coef * d.cmax - a_coef  # −Δω' after the ramp
    after = d.moves & ~root_on_ramp & (rate > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_lock = np.where(after, ramp_end + np.maximum(s_end, 0.0) / rate, t_lock)
    # initial slip exactly zero: stuck from the start if the static capacity suffices (never sign(0))
    with np.errstate(divide="ignore", invalid="ignore"):
        need0 = np.where(d.held, d.tm, (d.tm + d.jv * d.te * d.inv_je) / (1.0 + d.jv * d.inv_je))
    stuck0 = (d.we0 - d.wc0 == 0.0) & (
        np.abs(need0) <= d.rs * d.cmax * np.where(d.step, 1.0, _polyval(d.pc, 0.0))
    )
    # a free engine slowed to rest while the driven side is still parked: a lock-up at zero speed
    t_lock = np.where(d.stalls, d.t_stall, t_lock)
    return np.where(stuck0, 0.0, t_lock), ramp_end, a_coef, b_coef


def _stall(d):
    """A free engine that the clutch slows to rest (C(t) > T_e) while the driven side is parked:
    sets ``t_stall`` [s], the time its speed reaches the parked side's zero (ω_e is concave while
    C rises, linear after: one root), and ``stalls`` where that comes before the driven side
    moves (``t0``)."""
    d.t_stall = np.full_like(d.we0, np.inf)
    d.stalls = np.zeros(d.we0.shape, dtype=bool)
    cand = ~d.held & d.parked_phase & (d.te < d.cmax)
    if not cand.any():
        return

    def engine(t):  # ω_e and its rate
        c, ic = d.capacity(t)
        return d.we0 + d.inv_je * (d.te * t - ic), (d.te - c) * d.inv_je

    lo = np.where(cand, d.t_p, 0.0)
    full = np.maximum(np.where(d.step, 0.0, d.tr), lo)  # the clamp fully applied from here
    w_lo, w_full = engine(lo)[0], engine(full)[0]
    on_profile = cand & (w_lo > 0.0) & (w_full <= 0.0)
    t = np.where(on_profile, newton_bracketed(engine, lo, full, full.copy(), on_profile), np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        after = full + w_full / ((d.cmax - d.te) * d.inv_je)  # linear once C = C_max
    t = np.where(cand & (w_lo > 0.0) & (w_full > 0.0), after, t)
    parked_until = np.where(d.moves, d.t0, np.inf)
    d.stalls = cand & (t < parked_until)
    d.t_stall = np.where(d.stalls, t, np.inf)


def _root_on_profile(d, a_coef, b_coef, ramp_end, root_on_ramp):
    """Lock-up while the clamp profile still rises (where ``root_on_ramp``), else inf: on the
    linear ramp Δω = K + A t − (B a / 2) t² has a quadratic root; on a smooth step Newton's
    method, bracketed from where Δω' turns negative to the ramp's end."""
    t_lock = np.full_like(d.we0, np.inf)
    t0, trs = d.t0, d.trs
    if d.profile == "ramp":  # Δω = K + A t − (B a / 2) t² on the moving ramp: quadratic root
        a_r = d.cmax / trs
        k0 = d.state(t0)[1] - a_coef * t0 + 0.5 * b_coef * a_r * t0**2
        disc = np.sqrt(np.maximum(a_coef**2 + 2.0 * b_coef * a_r * k0, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r_pos = np.where(
                a_coef >= 0, (a_coef + disc) / (b_coef * a_r), -2.0 * k0 / (a_coef - disc)
            )
        return np.where(root_on_ramp, np.clip(r_pos, t0, ramp_end), t_lock)
    if not np.any(root_on_ramp):
        return t_lock
    with np.errstate(divide="ignore", invalid="ignore"):
        qa = a_coef / (b_coef * d.cmax)
    t_top = np.where(
        qa >= 1.0, ramp_end, np.maximum(t0, trs * _invert_profile(np.clip(qa, 0, 1), d.profile))
    )
    lo = np.where(root_on_ramp, np.minimum(t_top, ramp_end), 0.0)
    hi = np.where(root_on_ramp, ramp_end, 1.0)

    def slip_rate(t):
        c, dw, _, _ = d.state(t)
        return dw, a_coef - b_coef * c

    return np.where(
        root_on_ramp, newton_bracketed(slip_rate, lo, hi, hi.copy(), root_on_ramp), t_lock
    )


def newton_bracketed(fun, lo, hi, x, mask):
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
