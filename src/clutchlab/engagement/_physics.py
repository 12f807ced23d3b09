"""The model equations of the numerical solver (compiled, numba): forces, jerk, switching functions.

Engine side (eq. 1 of source paper (000)) J_e·ω_e' = T_e − T_c; driven side (eq. 2)
J_v·ω_c' = T_c − T_m, or with the damper springs between the plate hub and the output
J_h·ω_h' = T_c − T_s, J_r·ω_r' = T_s − T_m, T_s = K·θ + c·θ'. While slipping
T_c = s·f(|Δω|)·g·C(t) (s = ±1 the slip direction, f the friction law of
:mod:`clutchlab.engagement._friction`, g the fade factor of :mod:`clutchlab.engagement._fade`,
C(t) the capacity of the clamp profile, eq. 13); while locked T_c is the torque that keeps the
sides together; a parked output stays at rest under its static load. The mode is a
:class:`clutchlab.engagement._layout.Mode`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._fade import face_rise, fade_factor, fade_torque_rate, mode_rates
from ._friction import engine_torque, friction_law
from ._layout import (
    BREAK,
    CD,
    CMAX,
    DTM,
    FACE_K,
    FADE,
    FTAB,
    HELD,
    INV_JE,
    JH,
    JR,
    JV,
    KA,
    KAPPA,
    LOCK,
    N_MECH,
    N_STATE,
    NTAB,
    PARK,
    PEAK,
    RS,
    TCON,
    TE,
    TH,
    TM0,
    TR,
    TSTEP,
    UNPARK,
    VS,
    WD,
    WI,
    WL,
    WS,
    E,
    Forces,
    H,
    K,
    R,
)

JIT = dict(cache=True, error_model="numpy", _nrt=False)


@njit(**JIT)
def profile(x, prof):
    """The clamp profile p(x) on [0, 1]: ramp (0), cubic (1) or quintic (2) smooth step."""
    if prof == 0:
        return x
    if prof == 1:
        return x * x * (3.0 - 2.0 * x)
    return x * x * x * (10.0 + x * (-15.0 + 6.0 * x))


@njit(**JIT)
def capacity(t, q, prof):
    """C(t) = C_max·max(0, 1 − κ(1 − p(t/t_r))); κ = 1: the profile itself (a zero ramp time is a
    step at t = 0+); κ > 1: the release-bearing travel first closes an air gap (no clamp force
    until the cushion is touched at t_con), then compresses the lining cushion."""
    x = 1.0
    if q[TR] > 0.0:
        x = min(max(t / q[TR], 0.0), 1.0)
    p = profile(x, prof)
    if q[KAPPA] != 1.0:
        p = max(0.0, 1.0 - q[KAPPA] * (1.0 - p))
    return q[CMAX] * p


@njit(**JIT)
def capacity_rate(t, q, prof):
    """dC/dt, one-sided from the right at breakpoints."""
    if q[TR] <= 0.0:
        return 0.0
    x = t / q[TR]
    if x < 0.0 or x >= 1.0:
        return 0.0
    if prof == 0:
        dp = 1.0
    elif prof == 1:
        dp = 6.0 * x * (1.0 - x)
    else:
        dp = 30.0 * x * x * (1.0 - x) * (1.0 - x)
    if q[KAPPA] != 1.0:
        dp = q[KAPPA] * dp if t >= q[TCON] else 0.0
    return q[CMAX] * dp / q[TR]


@njit(**JIT)
def load_static(t, q):
    """The static load torque (with its step at t_s) [N m]."""
    return q[TM0] + (q[DTM] if t >= q[TSTEP] else 0.0)


@njit(**JIT)
def forces(t, y, q, mode, dy):
    """Fill dy (the state's derivative) and return the :class:`Forces` at the state (t, y)."""
    locked, parked, s, compliant, prof = mode
    held = q[HELD] > 0.0
    # torques: capacity, load (with rotor drag), engine (constant plus its table), friction law
    we, wh = y[E], y[H]
    wr = y[R] if compliant else wh
    C = capacity(t, q, prof)
    tm = load_static(t, q) + q[KA] * wr * wr
    te = 0.0
    if not held:
        te = q[TE]
        if q[NTAB] > 0.0:
            te += engine_torque(we, q)
    slip = we - wh
    f, dfdv = friction_law(slip, q)
    fade = q[FADE] > 0.0
    gf = 1.0
    if fade and not locked:
        gf, _ = fade_factor(face_rise(y, q), s * f * C * slip, q)
    # the hub's other side: the damper springs (compliant) or the load (rigid)
    ts = 0.0
    if compliant:
        ts = q[K] * y[TH] + q[CD] * (wh - wr)
        jh = q[JH]
        hub_side = ts
    else:
        jh = q[JV]
        hub_side = tm
    # accelerations slipping and locked, and the torque that keeps the locked sides together
    tc_slip = s * f * gf * C
    ah_slip = (tc_slip - hub_side) / jh
    if parked and not compliant:
        ah_slip = 0.0
    a_lock = 0.0 if held else (te - hub_side) * q[INV_JE] / (1.0 + jh * q[INV_JE])
    t_need = hub_side + jh * a_lock
    if locked and parked and not compliant:
        # stalled: the locked sides at rest, the engine's torque (none if it brakes) held by the
        # parked driven side's static load
        a_lock = 0.0
        t_need = max(te, 0.0)
    if locked:
        ah, tc, ae = a_lock, t_need, a_lock
    else:
        ah, tc = ah_slip, tc_slip
        ae = 0.0 if held else (te - tc_slip) * q[INV_JE]
    # the derivatives: speeds, twist, works (and the face temperature's modes with fade)
    dy[E] = ae
    dy[H] = ah
    if compliant:
        ar = 0.0 if parked else (ts - tm) / q[JR]
        dy[R] = ar
        dy[TH] = wh - wr
        dy[WD] = q[CD] * (wh - wr) ** 2
    else:
        ar = ah
        dy[R] = 0.0
        dy[TH] = 0.0
        dy[WD] = 0.0
    dy[WS] = 0.0 if locked else tc_slip * slip
    dy[WL] = 0.0 if parked else tm * wr
    dy[WI] = tc * we if held else te * we
    if fade:  # the face temperature's slow modes: z_k' = P − λ_k z_k
        mode_rates(y, 0.0 if locked else tc_slip * slip, dy)
    return Forces(C, tc, tm, ts, t_need, slip, f, ar, gf, dfdv)


@njit(**JIT)
def slip_torque_rate(t, q, mode, dy, fc):
    """d/dt of the slipping clutch torque X = s·f(|Δω|)·g·C(t) by the chain rule [N m/s] (fc the
    :class:`Forces` and dy the derivative at the state). With fade g changes too
    (:func:`clutchlab.engagement._fade.fade_torque_rate`)."""
    s = mode.sign
    C, slip, f, gf, dfdv = fc.capacity, fc.slip, fc.law, fc.fade, fc.law_slope
    rate = capacity_rate(t, q, mode.profile)
    sgn = 1.0 if slip > 0 else (-1.0 if slip < 0 else 0.0)
    slip_rate = dy[E] - dy[H]
    x0 = s * gf * (f * rate + C * dfdv * sgn * slip_rate)
    if gf < 1.0:
        b = s * f * C * q[FADE] * gf * gf * q[FACE_K]
        return fade_torque_rate(x0, b, slip, fc.torque, slip_rate, dy)
    return x0


@njit(**JIT)
def jerk(t, y, q, mode, dy, fc):
    """Output-side jerk from the state (chain rule, never by differencing) [rad/s³]."""
    locked, parked, s, compliant, prof = mode
    ar = fc.output_accel
    wr = y[R] if compliant else y[H]
    dtm = 2.0 * q[KA] * wr * ar
    if compliant:
        if parked:
            return 0.0
        return (q[K] * (y[H] - wr) + q[CD] * (dy[H] - ar) - dtm) / q[JR]
    if locked:
        return 0.0 if q[HELD] > 0.0 else -dtm * q[INV_JE] / (1.0 + q[JV] * q[INV_JE])
    if parked:
        return 0.0
    return (slip_torque_rate(t, q, mode, dy, fc) - dtm) / q[JV]


@njit(**JIT)
def events(t, y, q, mode, dy, fc, g):
    """The switching functions at the state into g (inf where an event cannot happen): LOCK the
    slip, BREAK the static capacity's margin, UNPARK the load's margin over the driving torque,
    PARK the output speed (of a rigid locked pair too: a free engine's stall), PEAK the slip
    power's rate."""
    locked, parked, s, compliant, prof = mode
    C, tc, ts, t_need, slip = fc.capacity, fc.torque, fc.spring, fc.needed, fc.slip
    inf = np.inf
    g[LOCK] = inf if locked else s * slip
    g[BREAK] = q[RS] * C - abs(t_need) if locked else inf
    g[UNPARK] = load_static(t, q) - (ts if compliant else tc) if parked else inf
    # (a rigid locked pair parks too: a free engine that cannot carry the load stalls)
    can_park = not parked and (not locked or compliant or q[HELD] == 0.0)
    g[PARK] = (y[R] if compliant else y[H]) if can_park else inf
    g[PEAK] = (
        inf if locked else (slip_torque_rate(t, q, mode, dy, fc) * slip + tc * (dy[E] - dy[H]))
    )


@njit(**JIT)
def n_active(q, mode):
    """Number of state components integrated: H, WS, WL, WI (+ E for a free engine; all 8 compliant;
    with fade while slipping every component, the face temperature's modes too: while locked they
    only decay, exactly, :func:`clutchlab.engagement._fade.decay_modes`)."""
    if q[FADE] > 0.0 and not mode.locked:
        return N_STATE
    return N_MECH if mode.compliant else (4 if q[HELD] > 0.0 else 5)


@njit(**JIT)
def jerk_varies(q):
    """Whether a rigid slip jerk depends on the state (a Stribeck law, a friction table, fade or
    rotor drag): then its maximum may lie inside a step. Without them it is dC/dt/J_v, a function of
    t whose maxima are step nodes (the profile's steepest point and its end are breakpoints)."""
    return q[VS] < np.inf or q[FTAB] > 0.0 or q[FADE] > 0.0 or q[KA] > 0.0


@njit(**JIT)
def is_linear(q, locked):
    """Whether the compliant model's phase is linear with polynomial forcing: no rotor drag, a held
    engine or one with constant torque, a finite damper stiffness, and constant μ unless locked (no
    Stribeck law, friction table or fade while slipping; a locked phase with fade is linear too:
    the face temperature's modes then only decay, :func:`clutchlab.engagement._fade.decay_modes`)."""
    return (
        q[KA] == 0.0
        and (q[HELD] > 0.0 or q[NTAB] == 0.0)
        and math.isfinite(q[K])
        and q[K] > 0.0
        and (locked or (not math.isfinite(q[VS]) and q[FTAB] == 0.0 and q[FADE] == 0.0))
    )
