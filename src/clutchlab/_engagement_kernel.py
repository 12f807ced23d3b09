"""Compiled (numba) kernel of :func:`clutchlab.engagement.simulate`: one scenario at a time.

Per scenario: Dormand-Prince 5(4) with Gustafsson's predictive step-size control (as in
radau5.f: it anticipates the error growing towards lock-up; 25-40 % fewer rejections than the PI
control of dopri5.f here), no growth after a rejection, a fresh starting step (HINIT) after every
mode switch, breakpoints (profile end, load step, trace times, end), and the stick/slip/park
state machine whose events are guessed on the step's continuous extension, then placed on the integrator's own solution by one re-integration from
the step's left end and a Newton correction along the local Taylor line (see :func:`_locate`);
a located step must meet the tolerance itself. The physics (forces, events, mode switches) is
documented in :mod:`clutchlab.engagement`; this module only makes it fast:

* no allocation anywhere, so every function is compiled without numba's reference counting
  (``_nrt=False``): the atomic reference-count updates on every call with an array argument
  were half of the run time (a step cost 0.55 µs with them, 0.27 µs without);
* only the moving state components are integrated (4 for a held engine, 5 free, 8 compliant);
* the rigid and the compliant model are compiled as two loops with the flag a constant.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

# parameter columns (one row per scenario)
(WE0, JE, TE, JV, TM0, CMAX, TR, RS, VS, WC0, KA, DTM, TSTEP, PHI, K, ZETA, TEND, HELD, INV_JE, JH, JR,
 CD, KAPPA, TCON) = range(24)
N_PARAM = 24
NTAB = N_PARAM  # engine torque table: count, then speeds, then torques (shared, appended to every row)
# state columns: engine, hub, output speed, damper twist, slip/load/input/damping work
H, WS, WL, WI, E, R, TH, WD = range(8)  # rigid held: the first 4 move; rigid free: 5
N_STATE = 8
N_WORK = 30  # rows of the per-scenario scratch array (see _simulate_one)
# events (falling through zero from > 0)
LOCK, BREAK, UNPARK, PARK, PEAK = range(5)
N_EVENTS = 5
EVENT_TIME_TOL = 1e-13  # s: bracket width at which an event time is final (Illinois method)
# result columns
(LOCKUP_TIME, BREAKAWAY_TIME, CAPACITY_AT_LOCKUP, ACCEL_JUMP, LOCKUP_SPEED, PEAK_SLIP_POWER,
 PEAK_FRICTION_TORQUE, PEAK_JERK, SLIP_WORK, LOAD_WORK, INPUT_WORK, KINETIC_ENERGY_CHANGE, DAMPING_WORK,
 ENERGY_RESIDUAL, N_STEPS, FINAL_LOCKED, HIT_STEP_LIMIT, N_REJECTED, N_LOCATE, N_FALSE_ALARMS, N_EVENT_STEPS) = range(21)
RESULTS = ("lockup_time", "breakaway_time", "capacity_at_lockup", "accel_jump", "lockup_speed", "peak_slip_power",
           "peak_friction_torque", "peak_jerk", "slip_work", "load_work", "input_work", "kinetic_energy_change",
           "damping_work", "energy_residual", "n_steps", "final_locked", "hit_step_limit",
           "n_rejected", "n_locate", "n_false_alarms", "n_event_steps")
TRACES = ("engine_speed", "hub_speed", "output_speed", "friction_torque", "capacity", "slip_work", "jerk")
N_RESULTS, N_TRACES = len(RESULTS), len(TRACES)

# Dormand-Prince 5(4)
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.zeros((7, 6))
for _i, _row in enumerate([[], [1 / 5], [3 / 40, 9 / 40], [44 / 45, -56 / 15, 32 / 9],
                           [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
                           [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
                           [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84]]):
    _A[_i, :len(_row)] = _row
_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0])
_E = _B - np.array([5179 / 57600, 0.0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40])
_EPS = np.finfo(float).eps
_FAC_ACC_MIN = 0.01 ** 0.2  # Gustafsson's controller: accepted errors below 1e-2 count as 1e-2
# DOPRI5 continuous extension of order 4 (Hairer, Norsett & Wanner, dopri5.f)
_D = np.array([-12715105075 / 11282082432, 0.0, 87487479700 / 32700410799, -10690763975 / 1880347072,
               701980252875 / 199316789632, -1453857185 / 822651844, 69997945 / 29380423])


@njit(cache=True, error_model="numpy", _nrt=False)
def _copy(dst, src):
    for i in range(dst.size):
        dst[i] = src[i]


@njit(cache=True, error_model="numpy", _nrt=False)
def _profile(x, prof):
    if prof == 0:
        return x
    if prof == 1:
        return x * x * (3.0 - 2.0 * x)
    return x * x * x * (10.0 + x * (-15.0 + 6.0 * x))


@njit(cache=True, error_model="numpy", _nrt=False)
def _capacity(t, q, prof):
    """C(t) = C_max·max(0, 1 − κ(1 − p(t/t_r))); κ = 1: the profile itself (a zero ramp time is a
    step at t = 0+); κ > 1: the release-bearing travel first closes an air gap (no clamp force
    until the cushion is touched at t_con), then compresses the lining cushion."""
    x = 1.0
    if q[TR] > 0.0:
        x = min(max(t / q[TR], 0.0), 1.0)
    p = _profile(x, prof)
    if q[KAPPA] != 1.0:
        p = max(0.0, 1.0 - q[KAPPA] * (1.0 - p))
    return q[CMAX] * p


@njit(cache=True, error_model="numpy", _nrt=False)
def _capacity_rate(t, q, prof):
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


@njit(cache=True, error_model="numpy", _nrt=False)
def _interp(x, q):
    """np.interp for a scalar (constant beyond the ends) on the engine torque table stored in the
    parameter row after its N_PARAM columns: count, speeds, torques. (The table is not a separate
    array argument: an array argument merely touched in the right-hand side cost ~55 ns a call.)"""
    n = int(q[NTAB])
    x0, y0 = NTAB + 1, NTAB + 1 + n
    if x <= q[x0]:
        return q[y0]
    if x >= q[x0 + n - 1]:
        return q[y0 + n - 1]
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if q[x0 + mid] <= x:
            lo = mid
        else:
            hi = mid
    return q[y0 + lo] + (q[y0 + hi] - q[y0 + lo]) * (x - q[x0 + lo]) / (q[x0 + hi] - q[x0 + lo])


@njit(cache=True, error_model="numpy", _nrt=False)
def _load_static(t, q):
    return q[TM0] + (q[DTM] if t >= q[TSTEP] else 0.0)


@njit(cache=True, error_model="numpy", _nrt=False)
def _forces(t, y, q, locked, parked, s, compliant, prof, dy):
    """Fill dy; return (C, tc, tm, ts, t_need, slip, f, ar)."""
    held = q[HELD] > 0.0
    we, wh = y[E], y[H]
    wr = y[R] if compliant else wh
    C = _capacity(t, q, prof)
    tm = _load_static(t, q) + q[KA] * wr * wr
    te = 0.0
    if not held:
        te = q[TE]
        if q[NTAB] > 0.0:
            te += _interp(we, q)
    slip = we - wh
    f = 1.0
    if math.isfinite(q[VS]):
        u = slip / q[VS]
        uu = u * u
        f = 1.0 + (q[RS] - 1.0) * math.exp(-uu) if uu < 700.0 else 1.0  # (no underflow: libm's slow path)
    ts = 0.0
    if compliant:
        ts = q[K] * y[TH] + q[CD] * (wh - wr)
        jh = q[JH]
        hub_side = ts
    else:
        jh = q[JV]
        hub_side = tm
    tc_slip = s * f * C
    ah_slip = (tc_slip - hub_side) / jh
    if parked and not compliant:
        ah_slip = 0.0
    a_lock = 0.0 if held else (te - hub_side) * q[INV_JE] / (1.0 + jh * q[INV_JE])
    t_need = hub_side + jh * a_lock
    if locked:
        ah, tc, ae = a_lock, t_need, a_lock
    else:
        ah, tc = ah_slip, tc_slip
        ae = 0.0 if held else (te - tc_slip) * q[INV_JE]
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
    return C, tc, tm, ts, t_need, slip, f, ar


@njit(cache=True, error_model="numpy", _nrt=False)
def _slip_torque_rate(t, q, s, prof, dy, C, slip, f):
    """d/dt of the slipping clutch torque s·f(|Δω|)·C(t) by the chain rule [N m/s]."""
    rate = _capacity_rate(t, q, prof)
    dfdv = 0.0
    if math.isfinite(q[VS]):  # f − 1 = (μs/μk − 1)·exp(−(Δω/v_s)²): no second exp
        dfdv = (f - 1.0) * (-2.0 * abs(slip) / q[VS] ** 2)
    sgn = 1.0 if slip > 0 else (-1.0 if slip < 0 else 0.0)
    return s * (f * rate + C * dfdv * sgn * (dy[E] - dy[H]))


@njit(cache=True, error_model="numpy", _nrt=False)
def _jerk(t, y, q, locked, parked, s, compliant, prof, dy, aux):
    """Output-side jerk from the state (chain rule, never by differencing) [rad/s³]."""
    C, tc, tm, ts, t_need, slip, f, ar = aux
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
    return (_slip_torque_rate(t, q, s, prof, dy, C, slip, f) - dtm) / q[JV]


@njit(cache=True, error_model="numpy", _nrt=False)
def _events(t, y, q, locked, parked, s, compliant, prof, dy, aux, g):
    C, tc, tm, ts, t_need, slip, f, ar = aux
    inf = np.inf
    g[LOCK] = inf if locked else s * slip
    g[BREAK] = q[RS] * C - abs(t_need) if locked else inf
    g[UNPARK] = _load_static(t, q) - (ts if compliant else tc) if parked else inf
    g[PARK] = (y[R] if compliant else y[H]) if (not parked and (not locked or compliant)) else inf
    g[PEAK] = inf if locked else (_slip_torque_rate(t, q, s, prof, dy, C, slip, f) * slip + tc * (dy[E] - dy[H]))


@njit(cache=True, error_model="numpy", _nrt=False)
def _n_active(q, compliant):
    """Number of state components that move: H, WS, WL, WI (+ E for a free engine; all 8 compliant)."""
    return N_STATE if compliant else (4 if q[HELD] > 0.0 else 5)


@njit(cache=True, error_model="numpy", _nrt=False)
def _dopri(t, y, h, q, locked, parked, s, compliant, prof, d0, kk, yi, y_new, err):
    """One DOPRI5 step from (t, y) with first stage d0; fills y_new and err (only the moving
    components are integrated; the others are copied)."""
    n = _n_active(q, compliant)
    for m in range(n, N_STATE):
        yi[m] = y_new[m] = y[m]
        err[m] = 0.0
    for m in range(N_STATE):
        kk[0, m] = d0[m]
    for i in range(1, 7):
        for m in range(n):
            acc = y[m]
            for j in range(i):
                acc += h * _A[i, j] * kk[j, m]
            yi[m] = acc
        _forces(t + _C[i] * h, yi, q, locked, parked, s, compliant, prof, kk[i])
    for m in range(n):
        a = y[m]
        e = 0.0
        for j in range(7):
            a += h * _B[j] * kk[j, m]
            e += h * _E[j] * kk[j, m]
        y_new[m] = a
        err[m] = e


@njit(cache=True, error_model="numpy", _nrt=False)
def _err_norm(y0, y1, err, rtol, atol, n):
    """RMS norm of the error estimate over the n moving components, scaled by atol + rtol·|y|."""
    acc = 0.0
    for m in range(n):
        sc = atol + rtol * max(abs(y0[m]), abs(y1[m]))
        acc += (err[m] / sc) ** 2
    return math.sqrt(acc / n)


@njit(cache=True, error_model="numpy", _nrt=False)
def _initial_step(t, y, d, q, locked, parked, s, compliant, prof, rtol, atol, hmax, y1, d1):
    """Starting step size (Hairer, Norsett & Wanner, dopri5.f HINIT): from the sizes of y, f and
    a difference estimate of f' so that the first step's error is about the tolerance; used at
    t = 0 and after every mode switch (the derivatives jump there). HINIT caps the step at 100
    times its probe; where the cap bites, the estimate is repeated once at the capped step."""
    n = _n_active(q, compliant)
    dnf = dny = 0.0
    for m in range(n):
        sk = atol + rtol * abs(y[m])
        dnf += (d[m] / sk) ** 2
        dny += (y[m] / sk) ** 2
    h = 1e-6 if (dnf <= 1e-10 or dny <= 1e-10) else 0.01 * math.sqrt(dny / dnf)
    h = min(h, hmax)
    for _ in range(2):  # HINIT, then once more with the difference taken at the proposed step
        for m in range(N_STATE):
            y1[m] = y[m] + h * d[m]
        _forces(t + h, y1, q, locked, parked, s, compliant, prof, d1)
        der2 = 0.0
        for m in range(n):
            sk = atol + rtol * abs(y[m])
            der2 += ((d1[m] - d[m]) / sk) ** 2
        der12 = max(math.sqrt(der2) / h, math.sqrt(dnf))
        h1 = max(1e-6, h * 1e-3) if der12 <= 1e-15 else (0.01 / der12) ** 0.2
        h_new = min(100.0 * h, h1, hmax)
        if h_new <= h:
            return h_new
        h = h_new
    return h


@njit(cache=True, error_model="numpy", _nrt=False)
def _hermite(y0, d0, y1, d1, h, th, out):
    h00 = 2 * th**3 - 3 * th**2 + 1
    h10 = th**3 - 2 * th**2 + th
    h01 = -2 * th**3 + 3 * th**2
    h11 = th**3 - th**2
    for m in range(N_STATE):
        out[m] = h00 * y0[m] + h10 * h * d0[m] + h01 * y1[m] + h11 * h * d1[m]


@njit(cache=True, error_model="numpy", _nrt=False)
def _dense_coefficients(y0, y1, kk, h, rc):
    """Coefficients of the step's order-4 continuous extension (stages kk of the step from y0)."""
    for m in range(N_STATE):
        ydiff = y1[m] - y0[m]
        bspl = h * kk[0, m] - ydiff
        acc = 0.0
        for j in range(7):
            acc += _D[j] * kk[j, m]
        rc[0, m] = y0[m]
        rc[1, m] = ydiff
        rc[2, m] = bspl
        rc[3, m] = ydiff - h * kk[6, m] - bspl
        rc[4, m] = h * acc


@njit(cache=True, error_model="numpy", _nrt=False)
def _dense(rc, th, out):
    """The state at the fraction ``th`` of the step (continuous extension)."""
    for m in range(N_STATE):
        out[m] = _dense_component(rc, th, m)


@njit(cache=True, error_model="numpy", _nrt=False)
def _dense_component(rc, th, m):
    u = 1.0 - th
    return rc[0, m] + th * (rc[1, m] + u * (rc[2, m] + th * (rc[3, m] + u * rc[4, m])))


@njit(cache=True, error_model="numpy", _nrt=False)
def _g_state(kind, t, yv, q, locked, parked, s, compliant, prof, dm, gm):
    """Event function ``kind`` at the state (t, yv); dm gets f there, gm every event function."""
    aux = _forces(t, yv, q, locked, parked, s, compliant, prof, dm)
    _events(t, yv, q, locked, parked, s, compliant, prof, dm, aux, gm)
    return gm[kind]


@njit(cache=True, error_model="numpy", _nrt=False)
def _g_dense(kind, t, tau, h, rc, q, locked, parked, s, compliant, prof, dm, gm, yb):
    """Event function ``kind`` on the step's continuous extension at t + tau. LOCK (slip) and
    PARK (output speed) are linear in the state: no force evaluation for them."""
    th = tau / h
    if kind == LOCK:
        return s * (_dense_component(rc, th, E) - _dense_component(rc, th, H))
    if kind == PARK:
        return _dense_component(rc, th, R if compliant else H)
    _dense(rc, th, yb)
    return _g_state(kind, t + tau, yb, q, locked, parked, s, compliant, prof, dm, gm)


@njit(cache=True, error_model="numpy", _nrt=False)
def _g_true(kind, t, y, d, tau, q, locked, parked, s, compliant, prof, rtol, atol, kk, yi, dm, gm, yout, err):
    """Event function ``kind`` at t + tau by re-integration from (t, y): (g, error norm of that step)."""
    _dopri(t, y, tau, q, locked, parked, s, compliant, prof, d, kk, yi, yout, err)
    return _g_state(kind, t + tau, yout, q, locked, parked, s, compliant, prof, dm, gm), _err_norm(y, yout, err, rtol, atol, _n_active(q, compliant))


@njit(cache=True, error_model="numpy", _nrt=False)
def _line_norm(ya, dm, da, sigma, rtol, atol, n):
    """Error norm of the local Taylor line ya + σ·da at σ: ½|σ|·|f(line) − da| (the y'' term)."""
    acc = 0.0
    for m in range(n):
        sc = atol + rtol * abs(ya[m])
        acc += (0.5 * sigma * (dm[m] - da[m]) / sc) ** 2
    return math.sqrt(acc / n)


@njit(cache=True, error_model="numpy", _nrt=False)
def _g_line(kind, t, ya, da, sigma, q, locked, parked, s, compliant, prof, dm, gm, yb):
    """Event function ``kind`` at t + σ on the local Taylor line ya + σ·da (dm: f there)."""
    for m in range(N_STATE):
        yb[m] = ya[m] + sigma * da[m]
    return _g_state(kind, t + sigma, yb, q, locked, parked, s, compliant, prof, dm, gm)


@njit(cache=True, error_model="numpy", _nrt=False)
def _locate(kind, t, y, d, rc, h, tau_hi, g0, q, locked, parked, s, compliant, prof, rtol, atol, kk,
            yi, dm, gm, ya, yb, err, da, interpolant_only=False):
    """Time (from t) at which event ``kind`` falls through zero in (0, tau_hi], or inf (false alarm).

    1. Illinois on the event function along the step's order-4 continuous extension (cheap: no
       integration) to the interpolant's root;
    2. one step of the integrator from t to that root (the true solution there);
    3. the secant method along the local Taylor line y(τ + σ) ≈ y(τ) + σ·f(y(τ)) (σ is of the
       size of the interpolation error), accepted when the line's own error ½|σ|·|f(line) − f|
       is below 10 % of the tolerance: the event time then carries the solution's accuracy;
       otherwise a Newton step: re-integrate to τ + σ and repeat;
    4. if that leaves the step (a false alarm, or no usable slope), Illinois on the true function by re-integration from t until the bracket
       is narrower than max(EVENT_TIME_TOL, 0.01·rtol·h).
    Returns (tau, error norm of the re-integrated step to tau, number of re-integrations); ``ya``
    holds the state at t + tau.
    With ``interpolant_only`` (events that only record a value, e.g. a maximum, whose value is
    insensitive to the time to second order) step 1 only; ``ya`` is the continuous extension there.
    """
    inf = np.inf
    # 1. on the interpolant
    lo, hi, g_lo, side = 0.0, tau_hi, g0, 0.0
    g_hi = _g_dense(kind, t, hi, h, rc, q, locked, parked, s, compliant, prof, dm, gm, yb)
    for _ in range(60):
        if hi - lo <= (1e-6 if interpolant_only else 1e-12) * tau_hi or g_hi == 0 or not g_hi <= 0:
            break
        tau = hi - g_hi * (hi - lo) / (g_hi - g_lo)
        if not (lo < tau < hi):
            tau = 0.5 * (lo + hi)
        g_tau = _g_dense(kind, t, tau, h, rc, q, locked, parked, s, compliant, prof, dm, gm, yb)
        if g_tau > 0:
            if side > 0:
                g_hi *= 0.5
            lo, g_lo, side = tau, g_tau, 1.0
        else:
            if side < 0:
                g_lo *= 0.5
            hi, g_hi, side = tau, g_tau, -1.0
    slope = (g_hi - g_lo) / (hi - lo) if hi > lo else 0.0
    if g_hi == 0:
        guess = hi
    elif slope < 0 and lo < hi - g_hi / slope < hi:
        guess = hi - g_hi / slope
    else:
        guess = 0.5 * (lo + hi)
    if interpolant_only:
        _dense(rc, guess / h, ya)
        return guess, 0.0, 0
    # 2. the true function (re-integration to tau), corrected along the local Taylor line (3.)
    tau, n_re, tau_p, g_p = guess, 0, -1.0, 0.0
    for _ in range(8):
        g_a, nv = _g_true(kind, t, y, d, tau, q, locked, parked, s, compliant, prof, rtol, atol, kk, yi, dm, gm,
                          ya, err)
        n_re += 1
        if g_a == 0 or nv > 1.0:
            return tau, nv, n_re  # on the root, or the step to it fails the tolerance: the caller shortens it
        tau_a = tau
        _copy(da, dm)
        ta = t + tau
        if not slope < 0:
            break
        s0, G0, s1 = 0.0, g_a, -g_a / slope
        for _ in range(6):  # 3. secant along y(tau + σ) ≈ ya + σ·f(ya): no integration
            G1 = _g_line(kind, ta, ya, da, s1, q, locked, parked, s, compliant, prof, dm, gm, yb)
            if G1 == 0 or G1 == G0:
                break
            s0, G0, s1 = s1, G1, s1 - G1 * (s1 - s0) / (G1 - G0)
            if abs(s1 - s0) <= 4 * _EPS * ta:
                break
        if not math.isfinite(s1):
            break
        _g_line(kind, ta, ya, da, s1, q, locked, parked, s, compliant, prof, dm, gm, yb)
        if 0.0 < tau + s1 <= tau_hi and _line_norm(ya, dm, da, s1, rtol, atol, _n_active(q, compliant)) <= 0.1:
            _copy(ya, yb)
            return tau + s1, nv, n_re
        # not accepted (a long step: the line and the step map part): secant on the true function
        # once two of its values are known, else the line's root
        tau_n = tau + s1
        if tau_p >= 0.0 and g_a != g_p:
            tau_n = tau - g_a * (tau - tau_p) / (g_a - g_p)
        if not 0.0 < tau_n <= tau_hi:
            break
        tau_p, g_p, tau = tau, g_a, tau_n
    guess = tau_a
    # 4. fallback: Illinois on the true function, bracket (lo, hi) with g(lo) > 0 >= g(hi)
    if g_a > 0:
        lo, g_lo, hi, hi_known = guess, g_a, tau_hi, False
    else:
        lo, g_lo, hi, g_hi, hi_known, n_hi = 0.0, g0, guess, g_a, True, nv
    if not hi_known:
        g_hi, n_hi = _g_true(kind, t, y, d, hi, q, locked, parked, s, compliant, prof, rtol, atol, kk, yi,
                             dm, gm, ya, err)
        n_re += 1
        if g_hi > 0:
            return inf, 0.0, n_re  # false alarm (the interpolant dipped, the solution does not)
    side = 0.0
    for _ in range(100):
        if hi - lo <= max(EVENT_TIME_TOL, 0.01 * rtol * h) + 4 * _EPS * (t + hi) or g_hi == 0:
            break
        tau = hi - g_hi * (hi - lo) / (g_hi - g_lo)
        if not (lo < tau < hi):
            tau = 0.5 * (lo + hi)
        g_tau, nv = _g_true(kind, t, y, d, tau, q, locked, parked, s, compliant, prof, rtol, atol, kk, yi,
                            dm, gm, yb, err)
        n_re += 1
        if g_tau > 0:
            if side > 0:
                g_hi *= 0.5  # Illinois: the same end moved twice
            lo, g_lo, side = tau, g_tau, 1.0
        else:
            if side < 0:
                g_lo *= 0.5
            hi, g_hi, side, n_hi = tau, g_tau, -1.0, nv
            _copy(ya, yb)
    return hi, n_hi, n_re


@njit(cache=True, error_model="numpy", _nrt=False)
def _record_peaks(t, y, q, locked, parked, s, compliant, prof, d, aux, pk):
    """Update the running maxima pk = (slip power, |friction torque|, |output jerk|); return the jerk."""
    jk = _jerk(t, y, q, locked, parked, s, compliant, prof, d, aux)
    if not locked:
        pk[0] = max(pk[0], aux[1] * aux[5])
    pk[1] = max(pk[1], abs(aux[1]))
    pk[2] = max(pk[2], abs(jk))
    return jk


@njit(cache=True, error_model="numpy", _nrt=False)
def _store_trace(trace, tt, t, y, wr_col, aux, jk):
    """Record the state at the trace times equal to t (they are breakpoints: no interpolation)."""
    for i in range(tt.size):
        if tt[i] == t:
            trace[i, 0] = y[E]
            trace[i, 1] = y[H]
            trace[i, 2] = y[wr_col]
            trace[i, 3] = aux[1]
            trace[i, 4] = aux[0]
            trace[i, 5] = y[WS]
            trace[i, 6] = jk


@njit(cache=True, error_model="numpy", _nrt=False, inline="always")
def _simulate_one(q, compliant, prof, tt, rtol, atol, max_step, first_step, max_steps, out, trace, work):
    """Integrate one scenario over [0, q[TEND]]; fill ``out`` (RESULTS) and ``trace`` (times × TRACES).
    ``work``: a (N_WORK, N_STATE) scratch array shared by all scenarios (allocating the ~18 small
    arrays per scenario cost more than a short engagement's integration)."""
    nan, inf = np.nan, np.inf
    held = q[HELD] > 0.0
    for i in range(out.size):
        out[i] = nan
    out[N_REJECTED] = out[N_LOCATE] = out[N_FALSE_ALARMS] = out[N_EVENT_STEPS] = 0.0
    y, d, d1, dm, y1, ym, err, yi, ya, yb, y_best = (work[0], work[1], work[2], work[3], work[4], work[5], work[6],
                                                      work[7], work[8], work[9], work[10])
    kk = work[11:18]
    g, g1, gm, tau_hi = work[18, :N_EVENTS], work[19, :N_EVENTS], work[20, :N_EVENTS], work[21, :N_EVENTS]
    pk = work[22, :3]  # running maxima: slip power, |friction torque|, |output jerk|
    pk[:] = 0.0
    ths = work[23, :5]  # Hermite sample points in a step (fractions of it)
    rc = work[24:29]  # the step's continuous extension
    da = work[29]
    y[:] = 0.0
    y[E] = q[WE0]
    y[H] = q[WC0]
    y[R] = q[WC0]
    wr_col = R if compliant else H
    nst = _n_active(q, compliant)
    ths[0] = 0.5

    # initial modes, decided from torques (never from sign(0))
    locked = False
    parked = q[WC0] <= 0.0
    s = 1.0
    aux = _forces(0.0, y, q, locked, parked, s, compliant, prof, d)
    drive0 = aux[3] if compliant else aux[6] * aux[0]
    parked = parked and _load_static(0.0, q) > drive0
    if q[WE0] == q[WC0]:
        aux_l = _forces(0.0, y, q, True, False, s, compliant, prof, d)
        if abs(aux_l[4]) <= q[RS] * aux[0]:
            locked, parked = True, False
            out[LOCKUP_TIME] = 0.0
            out[LOCKUP_SPEED] = q[WC0]
        else:
            s = 1.0 if aux_l[4] >= 0 else -1.0

    t = 0.0
    aux = _forces(t, y, q, locked, parked, s, compliant, prof, d)
    h = first_step if first_step > 0 else _initial_step(t, y, d, q, locked, parked, s, compliant, prof, rtol,
                                                         atol, min(max_step, q[TEND]), y1, d1)
    h_acc, fac_acc, last_rejected = 0.0, 1.0, False
    _events(t, y, q, locked, parked, s, compliant, prof, d, aux, g)
    jk = _record_peaks(t, y, q, locked, parked, s, compliant, prof, d, aux, pk)
    _store_trace(trace, tt, t, y, wr_col, aux, jk)
    n_steps = 0
    while t < q[TEND] and n_steps < max_steps:
        nb = q[TEND]
        for b in (q[TR], q[TSTEP], q[TCON]):
            if t < b < nb:
                nb = b
        for b in tt:
            if t < b < nb:
                nb = b
        h_try = min(h, max_step, nb - t)
        hit = h_try >= nb - t
        _dopri(t, y, h_try, q, locked, parked, s, compliant, prof, d, kk, yi, y1, err)
        norm = _err_norm(y, y1, err, rtol, atol, nst)
        n_steps += 1
        # step-size control: Gustafsson's predictive controller (as in radau5.f): the smaller of the
        # elementary and the predicted step, factors in [0.2, 10], safety 0.9, no growth after a rejection
        fac11 = norm ** 0.2 if norm > 1e-6 else 0.0  # (below, growth is capped at 10 anyway)
        if norm > 1.0:
            out[N_REJECTED] += 1
            h = h_try / min(5.0, fac11 / 0.9)
            last_rejected = True
            continue
        quot = fac11 / 0.9
        if h_acc > 0.0:
            quot = max(quot, (h_acc / h_try) * fac11 * fac11 / fac_acc / 0.9)
        h = h_try / max(0.1, min(5.0, quot))
        if last_rejected:
            h = min(h, h_try)
        acc_prev = (h_acc, fac_acc)
        h_acc, fac_acc, last_rejected = h_try, max(_FAC_ACC_MIN, fac11), False  # max(1e-2, err)^(1/5)
        t_right = nb if hit else t + h_try
        aux1 = _forces(t_right, y1, q, locked, parked, s, compliant, prof, d1)
        _events(t_right, y1, q, locked, parked, s, compliant, prof, d1, aux1, g1)
        # detection: the event functions at the step end, its middle and, where a LOCK or PARK
        # function could dip below zero and back inside the step (slope turning from falling to
        # rising), at the interior extrema of their cubic Hermite interpolants
        fired = False
        for kind in range(N_EVENTS):
            tau_hi[kind] = h_try if (g[kind] > 0 and g1[kind] <= 0) else inf
            fired = fired or tau_hi[kind] < inf
        n_th = 1
        for kind in (LOCK, PARK):
            if kind == LOCK:
                s0, s1 = s * (d[E] - d[H]), s * (d1[E] - d1[H])
            else:
                s0, s1 = d[wr_col], d1[wr_col]
            if g[kind] > 0 and g1[kind] > 0 and g[kind] < inf and s0 < 0 and s1 > 0:
                a0, a1, m0, m1 = g[kind], g1[kind], h_try * s0, h_try * s1
                qa = 6 * a0 + 3 * m0 - 6 * a1 + 3 * m1
                qb = -6 * a0 - 4 * m0 + 6 * a1 - 2 * m1
                qc = m0
                disc = qb * qb - 4 * qa * qc
                if disc >= 0:  # roots of qa·θ² + qb·θ + qc without cancellation (qa ≈ 0 is common)
                    qq = -0.5 * (qb + math.copysign(math.sqrt(disc), qb))
                    for num, den in ((qq, qa), (qc, qq)):
                        if den != 0 and 0 < num / den < 1:
                            ths[n_th] = num / den
                            n_th += 1
        for i in range(n_th):
            th = ths[i]
            _hermite(y, d, y1, d1, h_try, th, ym)
            tm_ = t + th * h_try
            auxm = _forces(tm_, ym, q, locked, parked, s, compliant, prof, dm)
            _events(tm_, ym, q, locked, parked, s, compliant, prof, dm, auxm, gm)
            for kind in range(N_EVENTS):
                if g[kind] > 0 and gm[kind] <= 0 and th * h_try < tau_hi[kind]:
                    tau_hi[kind] = th * h_try
                    fired = True
        if fired:
            _dense_coefficients(y, y1, kk, h_try, rc)
            # locate every candidate exactly; the earliest wins
            best_tau, best_kind, best_norm = inf, -1, 0.0
            for kind in range(N_EVENTS):
                if tau_hi[kind] == inf:
                    continue
                if kind == PEAK:  # records a value only (below): the step is not cut there
                    continue
                out[N_LOCATE] += 1
                tau, nv, n_re = _locate(kind, t, y, d, rc, h_try, tau_hi[kind], g[kind], q, locked, parked, s,
                                  compliant, prof, rtol, atol, kk, yi, dm, gm, ya, yb, err, da)
                out[N_EVENT_STEPS] += n_re
                if tau == inf:
                    out[N_FALSE_ALARMS] += 1
                if tau < best_tau:
                    best_tau, best_kind, best_norm = tau, kind, nv
                    _copy(y_best, ya)
            if tau_hi[PEAK] < inf:
                # the slip-power maximum: root of its derivative on the interpolant, value from the
                # continuous extension there (valid only before a switching event in the same step)
                tau_p, _, _ = _locate(PEAK, t, y, d, rc, h_try, tau_hi[PEAK], g[PEAK], q, locked, parked, s,
                                   compliant, prof, rtol, atol, kk, yi, dm, gm, yb, ya, err, da, True)
                if tau_p < best_tau:
                    aux_p = _forces(t + tau_p, yb, q, locked, parked, s, compliant, prof, dm)
                    pk[0] = max(pk[0], abs(aux_p[1] * aux_p[5]))
            if best_kind >= 0:
                # the located step must meet the tolerance itself; else retry with a shorter step
                if best_norm > 1.0:
                    out[N_REJECTED] += 1
                    h = best_tau / min(5.0, max(best_norm ** 0.2 / 0.9, 1.0 / 0.9))
                    (h_acc, fac_acc), last_rejected = acc_prev, True
                    continue
                t = t + best_tau
                _copy(y, y_best)
                a_before = _forces(t, y, q, locked, parked, s, compliant, prof, dm)
                if best_kind == LOCK:
                    locked = True
                    jh = q[JH] if compliant else q[JV]
                    w = y[E] if held else (y[E] + jh * q[INV_JE] * y[H]) / (1.0 + jh * q[INV_JE])
                    y[E] = w
                    y[H] = w
                    if not compliant:
                        parked = False
                elif best_kind == BREAK:
                    locked = False
                    s = 1.0 if a_before[4] >= 0 else -1.0
                elif best_kind == UNPARK:
                    parked = False
                elif best_kind == PARK:
                    parked = True
                    y[wr_col] = 0.0
                acc_before = dm[wr_col]
                aux = _forces(t, y, q, locked, parked, s, compliant, prof, d)
                if best_kind == LOCK:
                    out[LOCKUP_TIME] = t
                    out[LOCKUP_SPEED] = y[H]
                    out[CAPACITY_AT_LOCKUP] = aux[0]
                    out[ACCEL_JUMP] = d[wr_col] - acc_before
                elif best_kind == BREAK:
                    if math.isnan(out[BREAKAWAY_TIME]):
                        out[BREAKAWAY_TIME] = t
                    out[LOCKUP_TIME] = nan
                _events(t, y, q, locked, parked, s, compliant, prof, d, aux, g)
                _record_peaks(t, y, q, locked, parked, s, compliant, prof, d, aux, pk)
                h = _initial_step(t, y, d, q, locked, parked, s, compliant, prof, rtol, atol, min(max_step, q[TEND]),
                                  y1, d1)
                h_acc, fac_acc, last_rejected = 0.0, 1.0, False
                continue
        # no event: take the step as it was
        t = t_right
        _copy(y, y1)
        _copy(d, d1)
        _copy(g, g1)
        jk = _record_peaks(t, y, q, locked, parked, s, compliant, prof, d, aux1, pk)
        _store_trace(trace, tt, t, y, wr_col, aux1, jk)

    out[PEAK_SLIP_POWER], out[PEAK_FRICTION_TORQUE], out[PEAK_JERK] = pk[0], pk[1], pk[2]
    out[N_STEPS] = n_steps
    out[FINAL_LOCKED] = 1.0 if locked else 0.0
    out[HIT_STEP_LIMIT] = 1.0 if (n_steps >= max_steps and t < q[TEND]) else 0.0
    if not locked:
        out[LOCKUP_TIME] = nan
        out[ACCEL_JUMP] = nan
    wh, wr = y[H], y[wr_col]
    if compliant:
        k_el = q[K] if math.isfinite(q[K]) else 0.0
        dke = (0.5 * q[JH] * (wh**2 - q[WC0] ** 2) + 0.5 * q[JR] * (wr**2 - q[WC0] ** 2)
               + 0.5 * k_el * y[TH] ** 2)
    else:
        dke = 0.5 * q[JV] * (wh**2 - q[WC0] ** 2)
    if not held:
        dke += 0.5 * q[JE] * (y[E] ** 2 - q[WE0] ** 2)
    w_in, w_s, w_l, w_d = y[WI], y[WS], y[WL], y[WD]
    out[SLIP_WORK] = w_s
    out[LOAD_WORK] = w_l
    out[INPUT_WORK] = w_in
    out[KINETIC_ENERGY_CHANGE] = dke
    out[DAMPING_WORK] = w_d
    out[ENERGY_RESIDUAL] = (w_in - dke - w_s - w_l - w_d) / max(abs(w_in), abs(w_s), 1e-300)


@njit(cache=True, error_model="numpy", _nrt=False)
def _batch_rigid(Q, prof, tt, rtol, atol, max_step, first_step, max_steps, out, trace, work):
    for i in range(Q.shape[0]):
        _simulate_one(Q[i], False, prof, tt, rtol, atol, max_step, first_step, max_steps, out[i], trace[i], work)


@njit(cache=True, error_model="numpy", _nrt=False)
def _batch_compliant(Q, prof, tt, rtol, atol, max_step, first_step, max_steps, out, trace, work):
    for i in range(Q.shape[0]):
        _simulate_one(Q[i], True, prof, tt, rtol, atol, max_step, first_step, max_steps, out[i], trace[i], work)


def simulate_batch(Q, compliant, prof, tt, rtol, atol, max_step, first_step, max_steps):
    """Run every row of the parameter table Q; returns (results, traces). The rigid and the
    compliant model are compiled separately (the constant flag removes their branches: ~25 %)."""
    n = Q.shape[0]
    out = np.empty((n, N_RESULTS))
    trace = np.full((n, tt.size, N_TRACES), np.nan)
    work = np.empty((N_WORK, N_STATE))
    run = _batch_compliant if compliant else _batch_rigid
    run(Q, prof, tt, rtol, atol, max_step, first_step, max_steps, out, trace, work)
    return out, trace
