"""Compiled (numba) kernel of :func:`clutchlab.engagement.simulate`: one scenario at a time.

Per scenario: Dormand-Prince 5(4) with Gustafsson's predictive step-size control (as in
radau5.f: it anticipates the error growing towards lock-up; 25-40 % fewer rejections than the PI
control of dopri5.f here), no growth after a rejection, a fresh starting step (HINIT) after every
mode switch, breakpoints (profile end, load step, trace times, end), and the stick/slip/park
state machine whose events are guessed on the step's continuous extension, then placed on the
integrator's own solution by one re-integration from
the step's left end and a Newton correction along the local Taylor line (see :func:`_locate`);
a located step must meet the tolerance itself. The physics (forces, events, mode switches) is
documented in :mod:`clutchlab.engagement`; this module only makes it fast:

* no allocation anywhere, so every function is compiled without numba's reference counting
  (``_nrt=False``): the atomic reference-count updates on every call with an array argument
  were half of the run time (a step cost 0.55 µs with them, 0.27 µs without);
* only the moving state components are integrated (4 for a held engine, 5 free, 8 compliant; with
  fade, while slipping, the 15 modes of the friction face's temperature too);
* the rigid and the compliant model are compiled as two loops with the flag a constant.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import _linear_forms as _lp

# parameter columns (one row per scenario)
(
    WE0,
    JE,
    TE,
    JV,
    TM0,
    CMAX,
    TR,
    RS,
    VS,
    WC0,
    KA,
    DTM,
    TSTEP,
    PHI,
    K,
    ZETA,
    TEND,
    HELD,
    INV_JE,
    JH,
    JR,
    CD,
    KAPPA,
    TCON,
    FADE,
    FADE_ON,
    FACE_K,
    FTAB,
) = range(28)
N_PARAM = 28
NTAB = (
    N_PARAM  # engine torque table: count, then speeds, then torques (shared, appended to every row)
)
# FTAB: column of the friction table (0: none) after it, laid out alike: count, slip speeds, μ/μ_k
# state columns: engine, hub, output speed, damper twist, slip/load/input/damping work
H, WS, WL, WI, E, R, TH, WD = range(8)  # rigid held: the first 4 move; rigid free: 5
N_MECH = 8
# friction-face temperature as a state (only with fade, q[FADE] > 0; issue 20 item 4): Duhamel's
# integral I(t) = ∫ P(τ)/√(t − τ) dτ of the slip power with the kernel split as
# 1/√s = erf(√(λ_c s))/√s + erfc(√(λ_c s))/√s. The smooth first part is a sum of exponentials
# Σ w_k e^{−λ_k s} (clutchlab.heat.kernel_modes: non-negative least squares on s ∈ [0, 10 s]
# weighted by √s, λ_k geometric with ratio 2.5 from 4λ_c down to 0.01/s, zero weights dropped:
# 15 modes; max error 3.0e-4/√s), so
# I_slow = Σ w_k z_k with states z_k' = P − λ_k z_k; the second part lives on s ≲ 1/λ_c and is
# taken quasi-statically, ∫ erfc(√(λ_c s))/√s · P(t − s) ds ≈ M0·P(t), M0 = 2/√(π λ_c) (error
# ≈ M1·P', M1 = 2/(3√π λ_c^{3/2}) = 1.5e-6 s^1.5). λ_c = 4000/s: I within 7e-5 of its peak for a
# seed-like slip power (1000/s: 6e-4), and the stiffest mode (6 552/s) within DOPRI5's stability
# for steps up to 0.5 ms. Checked against a Picard iteration with the exact kernel in
# tests/test_fade.py.
SOE_LAMBDA = np.array(
    [
        6551.82794011116,
        2682.9030848013267,
        1098.619961975734,
        449.87306015227944,
        184.21818031306321,
        75.43536380322267,
        30.889970264900256,
        12.64911064067352,
        5.179674782070132,
        2.121021122366016,
        0.8685353406927243,
        0.3556558820077846,
        0.14563725905021752,
        0.059636891435401344,
        0.01,
    ]
)
SOE_WEIGHT = np.array(
    [
        1.0530600051732957,
        23.723283392222843,
        16.97838879544467,
        10.605038794078247,
        6.868111310665909,
        4.362443640753169,
        2.805304573335715,
        1.7886805840332438,
        1.1483443174771812,
        0.7317541220924253,
        0.47246489841591777,
        0.29325528400612916,
        0.20871327506035586,
        0.11227925977551365,
        0.21804431165750585,
    ]
)
SOE_CUT = 4000.0  # λ_c [1/s]
SOE_M0 = 2.0 / math.sqrt(math.pi * SOE_CUT)
SOE_TMAX = 10.0  # [s]: the longest window the fit covers
NZ = SOE_LAMBDA.size
Z0 = N_MECH
N_STATE = N_MECH + NZ
N_WORK = 31  # rows of the per-scenario scratch array (see _simulate_one)
# events (falling through zero from > 0)
LOCK, BREAK, UNPARK, PARK, PEAK = range(5)
N_EVENTS = 5
OUT_OF_WORK = -2  # a linear segment that ran out of its work budget (not an event)
FOLLOW_SETTLED, FOLLOW_EVENT, FOLLOW_OUT_OF_WORK = range(3)
EVENT_TIME_TOL = 1e-13  # s: bracket width at which an event time is final (Illinois method)
# result columns
(
    LOCKUP_TIME,
    BREAKAWAY_TIME,
    CAPACITY_AT_LOCKUP,
    ACCEL_JUMP,
    LOCKUP_SPEED,
    PEAK_SLIP_POWER,
    PEAK_FRICTION_TORQUE,
    PEAK_JERK,
    SLIP_WORK,
    LOAD_WORK,
    INPUT_WORK,
    KINETIC_ENERGY_CHANGE,
    DAMPING_WORK,
    ENERGY_RESIDUAL,
    N_STEPS,
    FINAL_LOCKED,
    HIT_STEP_LIMIT,
    N_REJECTED,
    N_LOCATE,
    N_FALSE_ALARMS,
    N_EVENT_STEPS,
    TRUNCATED,
    N_LINEAR,
    FLASH_PEAK,
    N_POWER_SAMPLES,
) = range(25)
RESULTS = (
    "lockup_time",
    "breakaway_time",
    "capacity_at_lockup",
    "accel_jump",
    "lockup_speed",
    "peak_slip_power",
    "peak_friction_torque",
    "peak_jerk",
    "slip_work",
    "load_work",
    "input_work",
    "kinetic_energy_change",
    "damping_work",
    "energy_residual",
    "n_steps",
    "final_locked",
    "hit_step_limit",
    "n_rejected",
    "n_locate",
    "n_false_alarms",
    "n_event_steps",
    "truncated",
    "n_linear",
    "flash_peak",
    "n_power_samples",
)
# the slip power history (issue 20; only when asked for: with_hist): sampled while slipping every
# ramp time / POWER_SAMPLES_PER_RAMP
# (a ramp shorter than window / 48, or a step: every window / 48²) and at every step end and event,
# at most POWER_SAMPLES_MAX samples a scenario; its Duhamel
# integral's peak, max over t of ∫ P(τ)/√(t − τ) dτ [W s^0.5] (P linear between samples, each segment
# integrated exactly), is the result FLASH_PEAK (NaN if the history overflowed). A slip that ends early in
# the ramp would get few samples (second order: 18 samples gave 5e-3): within a slip phase the spacing is
# also at most (time slipped by the segment's end) / POWER_SAMPLES_PER_SLIP, but not below the ramp
# spacing / POWER_SAMPLES_DENSER (at most POWER_SAMPLES_PER_SLIP · POWER_SAMPLES_DENSER more samples a slip phase)
POWER_SAMPLES_PER_RAMP = 48
POWER_SAMPLES_PER_SLIP = 64
POWER_SAMPLES_DENSER = 8
POWER_SAMPLES_MAX = 4096
TRACES = (
    "engine_speed",
    "hub_speed",
    "output_speed",
    "friction_torque",
    "capacity",
    "slip_work",
    "jerk",
    "face_temperature_rise",
)
N_RESULTS, N_TRACES = len(RESULTS), len(TRACES)

# Dormand-Prince 5(4)
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.zeros((7, 6))
for _i, _row in enumerate(
    [
        [],
        [1 / 5],
        [3 / 40, 9 / 40],
        [44 / 45, -56 / 15, 32 / 9],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
        [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ]
):
    _A[_i, : len(_row)] = _row
_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0])
_E = _B - np.array(
    [5179 / 57600, 0.0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40]
)
_EPS = np.finfo(float).eps
_FAC_ACC_MIN = 0.01**0.2  # Gustafsson's controller: accepted errors below 1e-2 count as 1e-2
# DOPRI5 continuous extension of order 4 (Hairer, Norsett & Wanner, dopri5.f)
_D = np.array(
    [
        -12715105075 / 11282082432,
        0.0,
        87487479700 / 32700410799,
        -10690763975 / 1880347072,
        701980252875 / 199316789632,
        -1453857185 / 822651844,
        69997945 / 29380423,
    ]
)


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
def _table(x, q, base):
    """(value, slope) of np.interp for a scalar (constant beyond the ends, slope 0 there) on a table
    stored in the parameter row from column ``base``: count, abscissae, ordinates. (The tables are
    not separate array arguments: an array argument merely touched in the right-hand side cost
    ~55 ns a call.)"""
    n = int(q[base])
    x0, y0 = base + 1, base + 1 + n
    if x <= q[x0]:
        return q[y0], 0.0
    if x >= q[x0 + n - 1]:
        return q[y0 + n - 1], 0.0
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if q[x0 + mid] <= x:
            lo = mid
        else:
            hi = mid
    slope = (q[y0 + hi] - q[y0 + lo]) / (q[x0 + hi] - q[x0 + lo])
    return q[y0 + lo] + slope * (x - q[x0 + lo]), slope


@njit(cache=True, error_model="numpy", _nrt=False)
def _interp(x, q):
    """The engine torque table at speed x [N m]."""
    return _table(x, q, NTAB)[0]


@njit(cache=True, error_model="numpy", _nrt=False)
def _slip_law(slip, q):
    """(f, df/d|Δω|) of the slipping friction law μ(|Δω|)/μ_k: 1 (constant μ_k), the Stribeck law
    1 + (μ_s/μ_k − 1)·exp(−(Δω/v_s)²), or the tabulated μ(|Δω|)/μ_k (linear between its points)."""
    if q[FTAB] > 0.0:
        return _table(abs(slip), q, int(q[FTAB]))
    if math.isfinite(q[VS]):
        u = slip / q[VS]
        uu = u * u
        if uu >= 700.0:  # (no underflow: libm's slow path)
            return 1.0, 0.0
        e = (q[RS] - 1.0) * math.exp(-uu)  # f − 1: the slope needs no second exp
        return 1.0 + e, e * (-2.0 * abs(slip) / q[VS] ** 2)
    return 1.0, 0.0


@njit(cache=True, error_model="numpy", _nrt=False)
def _face_rise(y, q):
    """Friction-face temperature rise [K] from the slow modes alone (the slip power's quasi-static
    part M0·P is added by :func:`_fade`)."""
    acc = 0.0
    for k in range(NZ):
        acc += SOE_WEIGHT[k] * y[Z0 + k]
    return q[FACE_K] * acc


@njit(cache=True, error_model="numpy", _nrt=False)
def _fade(rise_slow, p0, q):
    """(fade factor g, face temperature rise ΔT) that solve ΔT = ΔT_slow + K·M0·P0·g(ΔT) with
    g = 1/(1 + β·(ΔT − ΔT_on)⁺) (β = q[FADE], ΔT_on = q[FADE_ON], K = q[FACE_K]; P0 ≥ 0 the
    slip power at g = 1): in closed form, a quadratic in u = ΔT − ΔT_on."""
    a = q[FACE_K] * SOE_M0 * p0
    c = rise_slow - q[FADE_ON]
    if c + a <= 0.0:
        return 1.0, rise_slow + a
    beta = q[FADE]
    b = 1.0 - beta * c
    root = math.sqrt(b * b + 4.0 * beta * (c + a))
    u = 2.0 * (c + a) / (b + root) if b >= 0.0 else (root - b) / (2.0 * beta)
    return 1.0 / (1.0 + beta * u), q[FADE_ON] + u


@njit(cache=True, error_model="numpy", _nrt=False)
def _load_static(t, q):
    return q[TM0] + (q[DTM] if t >= q[TSTEP] else 0.0)


@njit(cache=True, error_model="numpy", _nrt=False)
def _forces(t, y, q, locked, parked, s, compliant, prof, dy):
    """Fill dy; return (C, tc, tm, ts, t_need, slip, f, ar, g, df/d|Δω|): f the slip law
    (:func:`_slip_law`), g the fade factor (1 without fade or when locked)."""
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
    f, dfdv = _slip_law(slip, q)
    fade = q[FADE] > 0.0
    gf = 1.0
    if fade and not locked:
        gf, _ = _fade(_face_rise(y, q), s * f * C * slip, q)
    ts = 0.0
    if compliant:
        ts = q[K] * y[TH] + q[CD] * (wh - wr)
        jh = q[JH]
        hub_side = ts
    else:
        jh = q[JV]
        hub_side = tm
    tc_slip = s * f * gf * C
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
    if fade:  # the face temperature's slow modes: z_k' = P − λ_k z_k
        p = 0.0 if locked else tc_slip * slip
        for k in range(NZ):
            dy[Z0 + k] = p - SOE_LAMBDA[k] * y[Z0 + k]
    return C, tc, tm, ts, t_need, slip, f, ar, gf, dfdv


@njit(cache=True, error_model="numpy", _nrt=False)
def _slip_torque_rate(t, q, s, prof, dy, aux):
    """d/dt of the slipping clutch torque X = s·f(|Δω|)·g·C(t) by the chain rule [N m/s]. With
    fade, g' = −β g² ΔT' and ΔT' = K·(Σ w_k z_k' + M0·P'), P' = X·Δω + T_c·Δω': linear in X,
    solved for it."""
    C, tc, slip, f, gf, dfdv = aux[0], aux[1], aux[5], aux[6], aux[8], aux[9]
    rate = _capacity_rate(t, q, prof)
    sgn = 1.0 if slip > 0 else (-1.0 if slip < 0 else 0.0)
    slip_rate = dy[E] - dy[H]
    x0 = s * gf * (f * rate + C * dfdv * sgn * slip_rate)
    if gf < 1.0:
        b = s * f * C * q[FADE] * gf * gf * q[FACE_K]
        s1 = 0.0
        for k in range(NZ):
            s1 += SOE_WEIGHT[k] * dy[Z0 + k]
        return (x0 - b * (s1 + SOE_M0 * tc * slip_rate)) / (1.0 + b * SOE_M0 * slip)
    return x0


@njit(cache=True, error_model="numpy", _nrt=False)
def _jerk(t, y, q, locked, parked, s, compliant, prof, dy, aux):
    """Output-side jerk from the state (chain rule, never by differencing) [rad/s³]."""
    ar = aux[7]
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
    return (_slip_torque_rate(t, q, s, prof, dy, aux) - dtm) / q[JV]


@njit(cache=True, error_model="numpy", _nrt=False)
def _events(t, y, q, locked, parked, s, compliant, prof, dy, aux, g):
    C, tc, ts, t_need, slip = aux[0], aux[1], aux[3], aux[4], aux[5]
    inf = np.inf
    g[LOCK] = inf if locked else s * slip
    g[BREAK] = q[RS] * C - abs(t_need) if locked else inf
    g[UNPARK] = _load_static(t, q) - (ts if compliant else tc) if parked else inf
    g[PARK] = (y[R] if compliant else y[H]) if (not parked and (not locked or compliant)) else inf
    g[PEAK] = (
        inf if locked else (_slip_torque_rate(t, q, s, prof, dy, aux) * slip + tc * (dy[E] - dy[H]))
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def _n_active(q, compliant, locked):
    """Number of state components integrated: H, WS, WL, WI (+ E for a free engine; all 8 compliant;
    with fade while slipping every component, the face temperature's modes too: while locked they
    only decay, exactly, :func:`_decay_modes`)."""
    if q[FADE] > 0.0 and not locked:
        return N_STATE
    return N_MECH if compliant else (4 if q[HELD] > 0.0 else 5)


@njit(cache=True, error_model="numpy", _nrt=False)
def _dopri(t, y, h, q, locked, parked, s, compliant, prof, d0, kk, yi, y_new, err):
    """One DOPRI5 step from (t, y) with first stage d0; fills y_new and err (only the moving
    components are integrated; the others are copied)."""
    n = _n_active(q, compliant, locked)
    for m in range(n, y.size):
        yi[m] = y_new[m] = y[m]
        err[m] = 0.0
    for m in range(y.size):
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
def _err_norm(y0, y1, err, rtol, atol, n, compliant):
    """RMS norm of the error estimate over the n moving components, scaled by atol + rtol·|y|. In
    the compliant model the output speed's entry is the error of the relative speed
    ω_h − ω_r scaled by its own size: the twist rate, and with it the output jerk K·θ' + c·θ'', is
    a small difference of large speeds whose error the output speed's scale would not control."""
    acc = 0.0
    for m in range(n):
        if m == R and compliant:
            e = err[H] - err[R]
            sc = atol + rtol * max(abs(y0[H] - y0[R]), abs(y1[H] - y1[R]))
        else:
            e = err[m]
            sc = atol + rtol * max(abs(y0[m]), abs(y1[m]))
        acc += (e / sc) ** 2
    return math.sqrt(acc / n)


@njit(cache=True, error_model="numpy", _nrt=False)
def _initial_step(t, y, d, q, locked, parked, s, compliant, prof, rtol, atol, hmax, y1, d1):
    """Starting step size (Hairer, Norsett & Wanner, dopri5.f HINIT): from the sizes of y, f and
    a difference estimate of f' so that the first step's error is about the tolerance; used at
    t = 0 and after every mode switch (the derivatives jump there). HINIT caps the step at 100
    times its probe; where the cap bites, the estimate is repeated once at the capped step."""
    n = _n_active(q, compliant, locked)
    dnf = dny = 0.0
    for m in range(n):
        sk = atol + rtol * abs(y[m])
        dnf += (d[m] / sk) ** 2
        dny += (y[m] / sk) ** 2
    h = 1e-6 if (dnf <= 1e-10 or dny <= 1e-10) else 0.01 * math.sqrt(dny / dnf)
    h = min(h, hmax)
    for _ in range(2):  # HINIT, then once more with the difference taken at the proposed step
        for m in range(y.size):
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
    for m in range(out.size):
        out[m] = h00 * y0[m] + h10 * h * d0[m] + h01 * y1[m] + h11 * h * d1[m]


@njit(cache=True, error_model="numpy", _nrt=False)
def _dense_coefficients(y0, y1, kk, h, rc):
    """Coefficients of the step's order-4 continuous extension (stages kk of the step from y0)."""
    for m in range(y0.size):
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
    for m in range(out.size):
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
def _g_true(
    kind, t, y, d, tau, q, locked, parked, s, compliant, prof, rtol, atol, kk, yi, dm, gm, yout, err
):
    """Event function ``kind`` at t + tau by re-integration from (t, y): (g, error norm of that step)."""
    _dopri(t, y, tau, q, locked, parked, s, compliant, prof, d, kk, yi, yout, err)
    return _g_state(kind, t + tau, yout, q, locked, parked, s, compliant, prof, dm, gm), _err_norm(
        y, yout, err, rtol, atol, _n_active(q, compliant, locked), compliant
    )


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
    n = _n_active(q, compliant, locked)  # (the others do not move along the line)
    for m in range(yb.size):
        yb[m] = ya[m] + sigma * da[m] if m < n else ya[m]
    return _g_state(kind, t + sigma, yb, q, locked, parked, s, compliant, prof, dm, gm)


@njit(cache=True, error_model="numpy", _nrt=False)
# noqa reason: numba kernel: event location (guess on the extension, Illinois on re-integration)
def _locate(  # noqa: C901
    kind,
    t,
    y,
    d,
    rc,
    h,
    tau_hi,
    g0,
    q,
    locked,
    parked,
    s,
    compliant,
    prof,
    rtol,
    atol,
    kk,
    yi,
    dm,
    gm,
    ya,
    yb,
    err,
    da,
    interpolant_only=False,
):
    """Time (from t) at which event ``kind`` falls through zero in (0, tau_hi], or inf (false alarm).

    1. Illinois on the event function along the step's order-4 continuous extension (cheap: no
       integration) to the interpolant's root;
    2. one step of the integrator from t to that root (the true solution there);
    3. the secant method along the local Taylor line y(τ + σ) ≈ y(τ) + σ·f(y(τ)) (σ is of the
       size of the interpolation error), accepted when the line's own error ½|σ|·|f(line) − f|
       is below 10 % of the tolerance: the event time then carries the solution's accuracy;
       otherwise a Newton step: re-integrate to τ + σ and repeat;
    4. if that leaves the step (a false alarm, or no usable slope), Illinois on the true function
    by re-integration from t until the bracket
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
        g_a, nv = _g_true(
            kind,
            t,
            y,
            d,
            tau,
            q,
            locked,
            parked,
            s,
            compliant,
            prof,
            rtol,
            atol,
            kk,
            yi,
            dm,
            gm,
            ya,
            err,
        )
        n_re += 1
        if g_a == 0 or nv > 1.0:
            return (
                tau,
                nv,
                n_re,
            )  # on the root, or the step to it fails the tolerance: the caller shortens it
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
        if (
            0.0 < tau + s1 <= tau_hi
            and _line_norm(ya, dm, da, s1, rtol, atol, _n_active(q, compliant, locked)) <= 0.1
        ):
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
        g_hi, n_hi = _g_true(
            kind,
            t,
            y,
            d,
            hi,
            q,
            locked,
            parked,
            s,
            compliant,
            prof,
            rtol,
            atol,
            kk,
            yi,
            dm,
            gm,
            ya,
            err,
        )
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
        g_tau, nv = _g_true(
            kind,
            t,
            y,
            d,
            tau,
            q,
            locked,
            parked,
            s,
            compliant,
            prof,
            rtol,
            atol,
            kk,
            yi,
            dm,
            gm,
            yb,
            err,
        )
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
def _jerk_before(t, y, q, locked, parked, s, compliant, prof, dm, pk):
    """The output jerk's limit from the left at t (the state is continuous there, dC/dt need not
    be); recorded in the running maximum pk[2] and returned."""
    t_l = np.nextafter(t, -np.inf)
    aux = _forces(t_l, y, q, locked, parked, s, compliant, prof, dm)
    jk = _jerk(t_l, y, q, locked, parked, s, compliant, prof, dm, aux)
    pk[2] = max(pk[2], abs(jk))
    return jk


@njit(cache=True, error_model="numpy", _nrt=False)
def _jerk_torque(t, y, q, locked, parked, s, compliant, prof, dm):
    """Output jerk and clutch torque at a state (dm: scratch for the derivatives)."""
    aux = _forces(t, y, q, locked, parked, s, compliant, prof, dm)
    return _jerk(t, y, q, locked, parked, s, compliant, prof, dm, aux), aux[1]


@njit(cache=True, error_model="numpy", _nrt=False)
def _vertex(v0, vm, v1, peak):
    """The parabola through a step's start, middle and end values: the fraction of the step at its
    vertex when that is an interior extremum near the running maximum ``peak``, else −1."""
    a = 2.0 * (v0 - 2.0 * vm + v1)
    b = -3.0 * v0 + 4.0 * vm - v1
    if a == 0.0:
        return -1.0
    th_v = -b / (2.0 * a)
    if not 0.0 < th_v < 1.0 or max(abs(v0 - b * b / (4.0 * a)), abs(vm)) < 0.9 * peak:
        return -1.0
    return th_v


@njit(cache=True, error_model="numpy", _nrt=False)
def _refine_peak(
    slot,
    th_v,
    th_max,
    t,
    h,
    rc,
    q,
    locked,
    parked,
    s,
    compliant,
    prof,
    pk,
    yb,
    dm,
    width=0.25,
    iterations=40,
):
    """A maximum of |jerk| (slot 2) or |clutch torque| (slot 1) inside an integrated step near the
    fraction th_v (:func:`_vertex`), so that a peak does not depend on where the steps fall: golden
    section on the step's continuous extension (order 4: the state to the tolerance) over
    [th_v − width, th_v + width] within [0, th_max] (1: the whole step; less: before an event)."""
    lo, hi = max(0.0, th_v - width), min(th_max, th_v + width)
    gr = 0.5 * (math.sqrt(5.0) - 1.0)
    x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
    f1 = _peak_value(slot, x1, t, h, rc, q, locked, parked, s, compliant, prof, yb, dm)
    f2 = _peak_value(slot, x2, t, h, rc, q, locked, parked, s, compliant, prof, yb, dm)
    for _ in range(iterations):
        if f1 >= f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - gr * (hi - lo)
            f1 = _peak_value(slot, x1, t, h, rc, q, locked, parked, s, compliant, prof, yb, dm)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + gr * (hi - lo)
            f2 = _peak_value(slot, x2, t, h, rc, q, locked, parked, s, compliant, prof, yb, dm)
    pk[slot] = max(pk[slot], f1, f2)


@njit(cache=True, error_model="numpy", _nrt=False)
def _jerk_varies(q):
    """Whether a rigid slip jerk depends on the state (a Stribeck law, a friction table, fade or
    rotor drag): then its maximum may lie inside a step. Without them it is dC/dt/J_v, a function of
    t whose maxima are step nodes (the profile's steepest point and its end are breakpoints)."""
    return q[VS] < np.inf or q[FTAB] > 0.0 or q[FADE] > 0.0 or q[KA] > 0.0


JERK_SCAN_MAX = 32  # samples of the rigid slip jerk in a step, at most (:func:`_scan_jerk`)


@njit(cache=True, error_model="numpy", _nrt=False)
def _scan_value(k, m, frac, t, h, rc, q, locked, parked, s, compliant, prof, yb, dm):
    """|jerk| at the sample k of m of :func:`_scan_jerk` (the last one: its limit from the left,
    for a step that ends where dC/dt jumps)."""
    th = frac * k / m
    _dense(rc, th, yb)
    te = t + th * h
    if k == m:
        te = np.nextafter(te, -np.inf)
    aux = _forces(te, yb, q, locked, parked, s, compliant, prof, dm)
    return abs(_jerk(te, yb, q, locked, parked, s, compliant, prof, dm, aux))


@njit(cache=True, error_model="numpy", _nrt=False)
def _scan_jerk(t, h, frac, slip0, slip1, j0, rc, q, locked, parked, s, compliant, prof, pk, yb, dm):
    """The largest |jerk| of a rigid slipping step [t, t + frac·h] (frac < 1: the part before an
    event): |jerk| sampled on the step's continuous extension (j0: the jerk at t, known), then
    golden section around the vertex of the parabola through the largest sample and its
    neighbours. A Stribeck law's term C·f'(Δω)·Δω'
    peaks within a few v_s of slip, where a step may be longer than the peak is wide: there the
    samples are spaced v_s/4 in slip (at most JERK_SCAN_MAX), elsewhere three."""
    m = 2
    if q[VS] < np.inf:
        near = 4.0 * q[VS]
        lo, hi = min(abs(slip0), abs(slip1)), max(abs(slip0), abs(slip1))
        if lo < near:
            m = max(m, min(JERK_SCAN_MAX, int(math.ceil(4.0 * (min(hi, near) - lo) / q[VS])) + 2))
    # the largest sample, and its two neighbours on each side as they come (no storage)
    best, kb, bm2, bm1, bp1, bp2, p2, p1 = -1.0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for k in range(m + 1):
        v = (
            abs(j0)
            if k == 0
            else _scan_value(k, m, frac, t, h, rc, q, locked, parked, s, compliant, prof, yb, dm)
        )
        if v > best:
            best, kb, bm2, bm1 = v, k, p2, p1
        elif k == kb + 1:
            bp1 = v
        elif k == kb + 2:
            bp2 = v
        p2, p1 = p1, v
    pk[2] = max(pk[2], best)
    if best < 0.9 * pk[2]:
        return
    # the parabola through the largest sample and its neighbours (the three nearest at an end),
    # its vertex (a maximum: concave) also up to half the triple past either end, where the
    # samples of a peak close to a step's end all rise (the golden section keeps to the step)
    if kb == 0:
        a, v0, v1, v2 = 0, best, bp1, bp2
    elif kb == m:
        a, v0, v1, v2 = m - 2, bm2, bm1, best
    else:
        a, v0, v1, v2 = kb - 1, bm1, best, bp1
    curv = 2.0 * (v0 - 2.0 * v1 + v2)
    if curv < 0.0:
        b = -3.0 * v0 + 4.0 * v1 - v2
        th = -b / (2.0 * curv)
        if -0.5 < th < 1.5:
            th_v = min(frac, max(0.0, frac * (a + 2.0 * th) / m))
            _refine_peak(
                2,
                th_v,
                frac,
                t,
                h,
                rc,
                q,
                locked,
                parked,
                s,
                compliant,
                prof,
                pk,
                yb,
                dm,
                frac / m,
                24,
            )


@njit(cache=True, error_model="numpy", _nrt=False)
def _peak_value(slot, th, t, h, rc, q, locked, parked, s, compliant, prof, yb, dm):
    """|jerk| (slot 2) or |clutch torque| (slot 1) at the fraction th of a step (continuous extension)."""
    _dense(rc, th, yb)
    aux = _forces(t + th * h, yb, q, locked, parked, s, compliant, prof, dm)
    if slot == 1:
        return abs(aux[1])
    return abs(_jerk(t + th * h, yb, q, locked, parked, s, compliant, prof, dm, aux))


@njit(cache=True, error_model="numpy", _nrt=False)
def _store_trace(trace, tt, t, y, q, wr_col, aux, jk):
    """Record the state at the trace times equal to t (they are breakpoints: no interpolation); the
    face temperature rise with fade only (the slow modes plus the quasi-static part of the slip
    power, which is 0 when locked: the slip is exactly 0 then)."""
    for i in range(tt.size):
        if tt[i] == t:
            trace[i, 0] = y[E]
            trace[i, 1] = y[H]
            trace[i, 2] = y[wr_col]
            trace[i, 3] = aux[1]
            trace[i, 4] = aux[0]
            trace[i, 5] = y[WS]
            trace[i, 6] = jk
            if q[FADE] > 0.0:
                trace[i, 7] = _face_rise(y, q) + q[FACE_K] * SOE_M0 * aux[1] * aux[5]


# ----------------------------------------------------------------------------------------------
# Exact linear phases of the compliant model (see clutchlab.engagement._linear_forms)
# ----------------------------------------------------------------------------------------------


@njit(cache=True, error_model="numpy", _nrt=False)
def _is_linear(q, locked):
    """Whether the compliant model's phase is linear with polynomial forcing: no rotor drag, a held
    engine or one with constant torque, a finite damper stiffness, and constant μ unless locked (no
    Stribeck law, friction table or fade while slipping; a locked phase with fade is linear too:
    the face temperature's modes then only decay, :func:`_decay_modes`)."""
    return (
        q[KA] == 0.0
        and (q[HELD] > 0.0 or q[NTAB] == 0.0)
        and math.isfinite(q[K])
        and q[K] > 0.0
        and (locked or (not math.isfinite(q[VS]) and q[FTAB] == 0.0 and q[FADE] == 0.0))
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def _decay_modes(y, q, dt):
    """The face temperature's modes over dt without slip power: z_k·exp(−λ_k dt)."""
    if q[FADE] > 0.0:
        for k in range(NZ):
            y[Z0 + k] *= math.exp(-SOE_LAMBDA[k] * dt)


@njit(cache=True, error_model="numpy", _nrt=False)
def _peak_slot(form):
    """Slot of the running maxima (slip power, |friction torque|, |output jerk|) a peak form feeds."""
    return 0 if form == _lp.F_POW else (1 if form == _lp.F_TORQ else 2)


@njit(cache=True, error_model="numpy", _nrt=False)
def _form_bounds(ft, fd, i, lo, hi, rh, rd, rate, osc):
    """(min P, max P, bound of |U·h + W·h'|) of form i over [lo, hi]; hi may be inf (then P beyond
    degree 1 or non-constant U, W give infinite bounds). Constant U, W of an underdamped response:
    the exact envelope of U·h + W·h' = e^(−aτ)·(A·cos ω_dτ + B·sin ω_dτ), √(A² + B²)·e^(−a·lo)."""
    r = 3 * i
    dp, du, dw = int(fd[r]), int(fd[r + 1]), int(fd[r + 2])
    if math.isfinite(hi):
        pmin, pmax = _lp.prange(ft[r], dp, lo, hi, osc[5 + 3 * _lp.N_FORM :])
    else:
        if dp > 1 or du > 0 or dw > 0:
            return -np.inf, np.inf, np.inf
        p0 = _lp.pvd(ft[r], dp, lo)
        slope = ft[r, 1] if dp == 1 else 0.0
        pmin = p0 if slope >= 0.0 else -np.inf
        pmax = p0 if slope <= 0.0 else np.inf
    if du == 0 and dw == 0:
        u, w = ft[r + 1, 0], ft[r + 2, 0]
        a, w2, h0, h1 = osc[0], osc[1], osc[2], osc[3]
        if u == 0.0 and w == 0.0:
            return pmin, pmax, 0.0
        if w2 > 0.0:
            wd = math.sqrt(w2)
            amp = math.hypot(
                u * h0 + w * h1, (u * (h1 + a * h0) - w * (a * h1 + (w2 + a * a) * h0)) / wd
            )
            return pmin, pmax, amp * math.exp(-a * lo)
        um, wm = abs(u), abs(w)
    else:
        u0, u1 = _lp.prange(ft[r + 1], du, lo, hi, osc[5 + 3 * _lp.N_FORM :])
        w0, w1 = _lp.prange(ft[r + 2], dw, lo, hi, osc[5 + 3 * _lp.N_FORM :])
        um, wm = max(abs(u0), abs(u1)), max(abs(w0), abs(w1))
    env = um * rh + wm * rd
    if env > 0.0:
        env *= math.exp(-rate * lo)
    return pmin, pmax, env


@njit(cache=True, error_model="numpy", _nrt=False)
def _arm_pending(ft, fd, armed, tau, h, hd):
    """Arm the pending event forms that are positive at τ."""
    for i in range(_lp.N_FORM):
        if armed[i] == 3.0 and _lp.fvald(ft, fd, i, tau, h, hd) > 0.0:
            armed[i] = 1.0


@njit(cache=True, error_model="numpy", _nrt=False)
def _excluded(ft, fd, i, role, lo, hi, rh, rd, rate, pk, osc):
    """Whether the bounds exclude, on [lo, hi], a root of event form i (role 1) or a value of peak
    form i (role 2) above the running maximum."""
    pmin, pmax, env = _form_bounds(ft, fd, i, lo, hi, rh, rd, rate, osc)
    if role == 1.0:
        return pmin - env > 0.0
    return max(abs(pmin), abs(pmax)) + env <= pk[_peak_slot(i)]


@njit(cache=True, error_model="numpy", _nrt=False)
def _quiet(ft, fd, i, role, lo, hi, rh, rd, rate, pk, osc):
    """How form i is quiet on [lo, hi]: 1 by its bounds, 2 monotone, 0 not quiet."""
    if _excluded(ft, fd, i, role, lo, hi, rh, rd, rate, pk, osc):
        return 1.0
    if _monotone(ft, fd, i, lo, hi, rh, rd, rate, osc):
        return 2.0
    return 0.0


@njit(cache=True, error_model="numpy", _nrt=False)
def _monotone(ft, fd, i, lo, hi, rh, rd, rate, osc):
    """Whether the bounds of form i's derivative keep it of one sign on [lo, hi]."""
    pmin, pmax, env = _form_bounds(ft, fd, i + _lp.N_FORM, lo, hi, rh, rd, rate, osc)
    return pmin - env > 0.0 or pmax + env < 0.0


@njit(cache=True, error_model="numpy", _nrt=False)
# noqa reason: numba kernel: the closed-form linear phases; to be split into named stages
def _linear_segment(  # noqa: C901
    t, t_b, t_load, y, q, locked, parked, s, prof, follow, pk, ft, pw, tq, osc, armed, budget
):
    """Advance a linear phase of the compliant model exactly from t to the first event in (t, t_b]
    or to t_b (``t_b`` may be inf with ``follow``). Returns (time, event kind or −1, settled,
    work): y holds the state there (works updated unless ``follow``), pk the peaks inside the
    segment, work the passes of the root search it took (grid intervals and skips). With
    ``follow`` (after the window) the segment ends, settled, once no armed event can fire and
    no peak can grow any more (bounds of the decaying free response); unsettled after 10⁵ grid
    intervals. The load is the static load at ``t_load``. After ``budget`` passes the segment
    ends where it is, with kind OUT_OF_WORK (a free response far faster than the phase, e.g. a
    damper spring so stiff that its period is below the time's round-off, would take forever)."""
    held = q[HELD] > 0.0
    k, c, jr, jh = q[K], q[CD], q[JR], q[JH]
    tm = _load_static(t_load, q)
    te = 0.0 if held else q[TE]
    C, D, F, XP, XPD, OM, WE = (
        pw[_lp.R_C],
        pw[_lp.R_D],
        pw[_lp.R_F],
        pw[_lp.R_XP],
        pw[_lp.R_XPD],
        pw[_lp.R_OM],
        pw[_lp.R_WE],
    )
    T1, T2, ONE, ZERO = pw[_lp.R_T1], pw[_lp.R_T2], pw[_lp.R_T3], pw[_lp.R_T4]
    _lp._zero(ONE)
    ONE[0] = 1.0
    _lp._zero(ZERO)
    _lp._icap(t, q[TR], q[TCON], q[KAPPA], q[CMAX], prof, C, T1)
    _lp._zero(D)
    if locked:
        ia = 0.0 if held else 1.0 / (q[JE] + jh)
        D[0] = te
    else:
        ia = 1.0 / jh
        for n in range(_lp.NP):
            D[n] = s * C[n]
    th0 = y[TH]
    thd0 = y[H] - (0.0 if parked else y[R])
    osc_on = not (
        parked and ia == 0.0
    )  # held, locked and parked: the twist grows at the engine speed
    ra, rr = 1.0, 0.0
    if parked:
        m = 1.0 / ia if osc_on else np.inf
        for n in range(_lp.NP):
            F[n] = D[n]
    else:
        ra = 1.0 / (1.0 + jr * ia)
        rr = jr * ia * ra
        m = jr * ra
        _lp._axpy(rr, D, ra * tm, ONE, F)
    if osc_on:
        _lp._partic(F, m, c, k, XP)
        km, cm = k / m, c / m
        a = 0.5 * cm
        w2 = km - a * a
    else:
        _lp._zero(XP)
        XP[0], XP[1] = th0, y[E]
        km = cm = a = w2 = 0.0
    _lp._der(XP, XPD)
    h0, h1 = th0 - XP[0], thd0 - XPD[0]
    osc[0], osc[1], osc[2], osc[3], osc[4] = a, w2, h0, h1, t
    # speeds ω_A = PA + uA·θ', ω_R = PR + uR·θ' (PA, PR rows)
    if parked:
        PA, PR, uR = (ZERO if osc_on else OM), ZERO, 0.0
        uA = 1.0 if osc_on else 0.0
        if not osc_on:
            _lp._zero(OM)
            OM[0] = y[E]
    else:
        for n in range(_lp.NP):
            T1[n] = D[n]
        T1[0] -= tm
        _lp._integ(T1, OM)
        for n in range(_lp.NP):
            OM[n] *= ra * ia
        OM[0] += ra * y[H] + rr * y[R]
        PA, PR, uA, uR = OM, OM, rr, -ra
    if not locked:  # engine speed while slipping (held: constant)
        _lp._integ(C, T1)
        _lp._zero(WE)
        WE[0] = y[E]
        if not held:
            for n in range(_lp.NP):
                WE[n] -= q[INV_JE] * s * T1[n]
            WE[1] += q[INV_JE] * te
    # forms
    for i in range(_lp.N_FORM):
        armed[i] = 0.0
    alpha, beta = 1.0 - jh * ia, jh * ia * te  # torque needed to stay locked: α·T_s + β
    # T2 = T_s's polynomial part k·x_p + c·x_p'
    _lp._axpy(k, XP, c, XPD, T2)
    if not locked:
        for n in range(_lp.NP):
            T1[n] = s * (WE[n] - PA[n] - uA * XPD[n])
        _lp._fset(ft, _lp.F_LOCK, T1, -s * uA, -s * uA, ZERO, ONE)
        armed[_lp.F_LOCK] = 1.0
        _lp._mul(C, T1, T1)  # slip power C·s·(ω_e − ω_A)
        for n in range(_lp.NP):
            ft[3 * _lp.F_POW, n] = T1[n]
            ft[3 * _lp.F_POW + 1, n] = 0.0
            ft[3 * _lp.F_POW + 2, n] = -s * uA * C[n]
        armed[_lp.F_POW] = 2.0  # a peak, not an event
    else:
        for form in (_lp.F_BRK_P, _lp.F_BRK_M):
            sign = 1.0 if form == _lp.F_BRK_P else -1.0
            for n in range(_lp.NP):
                T1[n] = q[RS] * C[n] - sign * alpha * T2[n]
            T1[0] -= sign * beta
            _lp._fset(ft, form, T1, -sign * alpha * k, -sign * alpha * c, ONE, ONE)
            armed[form] = 1.0
        _lp._axpy(alpha, T2, 0.0, T2, T1)
        T1[0] += beta
        _lp._fset(ft, _lp.F_TORQ, T1, alpha * k, alpha * c, ONE, ONE)
        armed[_lp.F_TORQ] = 2.0
    if parked:
        _lp._axpy(-1.0, T2, tm, ONE, T1)
        _lp._fset(ft, _lp.F_UNPARK, T1, -k, -c, ONE, ONE)
        armed[_lp.F_UNPARK] = 1.0
    else:
        for n in range(_lp.NP):
            T1[n] = PR[n] + uR * XPD[n]
        _lp._fset(ft, _lp.F_PARK, T1, 0.0, uR, ONE, ONE)
        armed[_lp.F_PARK] = 1.0
        # output jerk T_s'/J_R: T_s in the jerk's derivative slot, differentiated into the jerk slot
        jd = _lp.F_JERK + _lp.N_FORM
        _lp._fset(ft, jd, T2, k, c, ONE, ONE)
        _lp._fder(ft, jd, _lp.F_JERK, km, cm)
        for r in range(3):
            for n in range(_lp.NP):
                ft[3 * _lp.F_JERK + r, n] /= jr
        armed[_lp.F_JERK] = 2.0
    for i in range(_lp.N_FORM):
        if armed[i] > 0.0:
            _lp._fder(ft, i, i + _lp.N_FORM, km, cm)
            _lp._fder(ft, i + _lp.N_FORM, i + 2 * _lp.N_FORM, km, cm)
    fd = armed[_lp.N_FORM :]  # degrees of the form rows
    for i in range(_lp.N_FORM):
        if armed[i] > 0.0:
            for j in (i, i + _lp.N_FORM, i + 2 * _lp.N_FORM):
                for r in range(3 * j, 3 * j + 3):
                    fd[r] = _lp.degree(ft[r])
    rh, rd, rate = _lp.envelope(osc)
    # grid: half of π/ω₀ (ω₀ ≥ ω_d: extrema of the free response are ≥ π/ω₀ apart)
    T = t_b - t
    w0 = math.sqrt(km)
    dg = math.pi / (2.0 * w0) if (osc_on and w0 > 0.0) else (T if math.isfinite(T) else 1.0)
    if math.isfinite(T) and dg >= T:
        dg = T
    period = 2.0 * math.pi / math.sqrt(w2) if w2 > 0.0 else np.inf
    # events armed only where the function starts above zero (as in the integrator). One that starts
    # at zero within round-off (slip just after a break-away, output speed just after unparking)
    # is armed from the first of the times dg·2⁻ᵏ (k = 40 … 0) where it is positive: a restart at
    # an event never fires at once, and a short episode after it is not stepped over. If it is
    # not positive by then, it stays pending and is armed at the first grid point where it is.
    hA, hdA = _lp.hh(0.0, a, w2, h0, h1)
    t_arm = osc[5 + 2 * _lp.N_FORM : 5 + 3 * _lp.N_FORM]
    for i in range(_lp.N_FORM):
        t_arm[i] = 0.0
        if armed[i] == 1.0:
            r = 3 * i
            scale = abs(ft[r, 0]) + abs(ft[r + 1, 0] * hA) + abs(ft[r + 2, 0] * hdA)
            noise = 64.0 * _lp._EPS * scale
            if not _lp.fvald(ft, fd, i, 0.0, hA, hdA) > noise:
                armed[i] = 3.0
                # (above its round-off, not merely > 0: an output speed that starts at zero after
                # unparking with zero acceleration is round-off for a while; armed on a positive
                # round-off value it fired at once, 1e-19 s later, and the restart unparked again:
                # a stiff damper chattered park/unpark forever, or stayed parked for good)
                for kexp in range(40, -1, -1):
                    ta = dg * 2.0 ** (-kexp)
                    hT, hdT = _lp.hh(ta, a, w2, h0, h1)
                    if _lp.fvald(ft, fd, i, ta, hT, hdT) > noise:
                        armed[i], t_arm[i] = 1.0, ta
                        break
    t_lo, n_int, settled = 0.0, 0, False
    mode = osc[
        5 : 5 + _lp.N_FORM
    ]  # per form: how it is quiet up to its horizon (1 bounds, 2 monotone)
    quiet_until = osc[5 + _lp.N_FORM : 5 + 2 * _lp.N_FORM]
    for i in range(_lp.N_FORM):
        mode[i], quiet_until[i] = 0.0, -1.0
    hL, hdL = hA, hdA
    tau_ev, kind_ev = np.inf, -1
    n_pass = 0
    while True:
        n_pass += 1
        if n_pass > budget:  # out of work: end here (the caller reports not_converged)
            t_end = t_lo
            kind_ev = OUT_OF_WORK
            break
        if not math.isfinite(T):
            # after the window: forms that can never fire (events) or grow (peaks) again are disarmed
            n_armed = 0
            for i in range(_lp.N_FORM):
                if armed[i] == 0.0 or armed[i] == 3.0:
                    continue
                if _excluded(ft, fd, i, armed[i], t_lo, T, rh, rd, rate, pk, osc) or (
                    rate <= 0.0 and _lp.degree(ft[3 * i]) == 0 and t_lo > period + dg
                ):  # undamped: a period shows all
                    armed[i] = 0.0
                else:
                    n_armed += 1
            if n_armed == 0:
                t_end = t_lo
                settled = True
                break
        # skip ahead to the earliest quiet horizon of the armed forms: each form's horizon is the
        # longest [t_lo, t_lo + Δ] (Δ doubling from one grid interval) on which its bounds exclude a
        # root (events) or a value above the maximum so far (peaks) — mode 1 — or keep its
        # derivative of one sign, so that only its end value matters — mode 2. A horizon stays
        # valid as t_lo advances (the bounds only tighten, the maxima only grow): recomputed once
        # passed.
        skip_to = T
        for i in range(_lp.N_FORM):
            if armed[i] == 0.0:
                continue
            if armed[i] == 3.0 or t_arm[i] > t_lo:  # pending, or armed inside: step the grid
                skip_to = t_lo
                break
            if quiet_until[i] <= t_lo:
                qu, qm = t_lo, 0.0
                m_i = (
                    _quiet(ft, fd, i, armed[i], t_lo, T, rh, rd, rate, pk, osc)
                    if math.isfinite(T)
                    else 0.0
                )
                if m_i > 0.0:  # quiet to the segment's end (the common case: one try)
                    qu, qm = T, m_i
                else:
                    span = dg
                    while span < 65536.0 * dg:
                        t_s = min(t_lo + span, T)
                        m_i = _quiet(ft, fd, i, armed[i], t_lo, t_s, rh, rd, rate, pk, osc)
                        if m_i == 0.0:
                            break
                        qu, qm = t_s, m_i
                        if t_s >= T:
                            break
                        span *= 4.0
                quiet_until[i], mode[i] = qu, qm
            skip_to = min(skip_to, quiet_until[i])
            if skip_to <= t_lo:
                break
        skip = skip_to - t_lo if skip_to > t_lo and math.isfinite(skip_to) else 0.0
        if skip > 0.0:
            t_s = t_lo + skip
            hS, hdS = _lp.hh(t_s, a, w2, h0, h1)
            for i in range(_lp.N_FORM):  # a monotone event function crosses zero at most once
                if armed[i] == 1.0 and mode[i] == 2.0 and _lp.fvald(ft, fd, i, t_s, hS, hdS) <= 0.0:
                    r = _lp._root(ft, i, t_lo, t_s, osc)
                    if r < tau_ev:
                        tau_ev, kind_ev = r, i
            t_end = min(t_s, tau_ev)
            hE, hdE = (hS, hdS) if t_end == t_s else _lp.hh(t_end, a, w2, h0, h1)
            for i in range(_lp.N_FORM):  # a monotone peak function has its maximum at an end
                if armed[i] == 2.0 and mode[i] == 2.0:
                    pk[_peak_slot(i)] = max(
                        pk[_peak_slot(i)], abs(_lp.fvald(ft, fd, i, t_end, hE, hdE))
                    )
            if not locked:
                pk[1] = max(pk[1], abs(_lp.pv(C, t_end)))
            if kind_ev >= 0:
                break
            _arm_pending(ft, fd, armed, t_s, hS, hdS)
            t_lo = t_s
            if t_lo >= T:
                t_end = T
                break
            hL, hdL = hS, hdS
            continue
        t_hi = t_lo + dg
        if math.isfinite(T) and T - t_hi < 1e-3 * dg:
            t_hi = T
        n_int += 1
        hB, hdB = _lp.hh(t_hi, a, w2, h0, h1)
        # events in (t_lo, t_hi]: the earliest root of the armed functions
        for i in range(_lp.N_FORM):
            if armed[i] != 1.0 or t_arm[i] >= t_hi:
                continue
            lo_i = max(t_lo, t_arm[i])  # (a form armed inside the interval: from its arming time)
            r_hi = np.inf
            if _lp.fvald(ft, fd, i, t_hi, hB, hdB) <= 0.0:
                r_hi = t_hi
            else:
                pmin, _, env = _form_bounds(ft, fd, i, lo_i, t_hi, rh, rd, rate, osc)
                if pmin - env <= 0.0:  # a dip below zero is not excluded: look for a minimum inside
                    hI, hdI = (hL, hdL) if lo_i == t_lo else _lp.hh(lo_i, a, w2, h0, h1)
                    d_lo = _lp.fvald(ft, fd, i + _lp.N_FORM, lo_i, hI, hdI)
                    if d_lo < 0.0 and _lp.fvald(ft, fd, i + _lp.N_FORM, t_hi, hB, hdB) > 0.0:
                        tmin = _lp._extremum(ft, i, lo_i, t_hi, d_lo, osc)
                        hM, hdM = _lp.hh(tmin, a, w2, h0, h1)
                        if _lp.fvald(ft, fd, i, tmin, hM, hdM) <= 0.0:
                            r_hi = tmin
            if r_hi < np.inf:
                r = _lp._root(ft, i, lo_i, r_hi, osc)
                if r < tau_ev:
                    tau_ev, kind_ev = r, i
        t_end = min(t_hi, tau_ev)
        # peaks on (t_lo, t_end]: the end and the extrema inside, where they could exceed the maximum so far
        hE, hdE = (hB, hdB) if t_end == t_hi else _lp.hh(t_end, a, w2, h0, h1)
        for i in range(_lp.N_FORM):
            if armed[i] != 2.0:
                continue
            slot = _peak_slot(i)
            pk[slot] = max(pk[slot], abs(_lp.fvald(ft, fd, i, t_end, hE, hdE)))
            pmin, pmax, env = _form_bounds(ft, fd, i, t_lo, t_end, rh, rd, rate, osc)
            if max(abs(pmin), abs(pmax)) + env <= pk[slot]:
                continue
            d_lo = _lp.fvald(ft, fd, i + _lp.N_FORM, t_lo, hL, hdL)
            d_hi = _lp.fvald(ft, fd, i + _lp.N_FORM, t_end, hE, hdE)
            if (d_lo > 0.0) != (d_hi > 0.0):
                te_ = _lp._extremum(ft, i, t_lo, t_end, d_lo, osc)
                hM, hdM = _lp.hh(te_, a, w2, h0, h1)
                pk[slot] = max(pk[slot], abs(_lp.fvald(ft, fd, i, te_, hM, hdM)))
        if not locked:
            pk[1] = max(pk[1], abs(_lp.pv(C, t_end)))
        if kind_ev >= 0 or (math.isfinite(T) and t_hi >= T):
            break
        _arm_pending(ft, fd, armed, t_hi, hB, hdB)
        t_lo, hL, hdL = t_hi, hB, hdB
        if follow and n_int > 100_000:
            t_end = t_lo
            break
    tau = t_end
    hE, hdE = _lp.hh(tau, a, w2, h0, h1)
    th, thd = _lp.pv(XP, tau) + hE, _lp.pv(XPD, tau) + hdE
    wa, wr = _lp.pv(PA, tau) + uA * thd, _lp.pv(PR, tau) + uR * thd
    if not follow:
        th_a, thd_a = th0, thd0
        _lp._integ(C, T1)
        if held:
            if locked:  # ω_e·∫T_s, ∫θ = ∫x_p + ∫h
                _lp._integ(XP, T2)
                ith = (
                    _lp.pv(T2, tau) + _lp._int_qh(ONE, m, c, k, tau, hA, hdA, hE, hdE, tq)
                    if osc_on
                    else _lp.pv(T2, tau)
                )
                y[WI] += y[E] * (k * ith + c * (th - th_a))
            else:
                y[WI] += y[E] * s * _lp.pv(T1, tau)
        else:
            if locked:
                _lp._integ(PA, T2)
                y[WI] += te * (_lp.pv(T2, tau) + uA * (th - th_a))
            else:
                _lp._integ(WE, T2)
                y[WI] += te * _lp.pv(T2, tau)
        if not parked:
            _lp._integ(PR, T2)
            y[WL] += tm * (_lp.pv(T2, tau) + uR * (th - th_a))
        if not locked:  # ∫C·s(ω_e − ω_A) = ∫C·P_lock − s·uA·([C·h] − ∫C'·h)
            for n in range(_lp.NP):
                T1[n] = s * (WE[n] - PA[n] - uA * XPD[n])
            _lp._mul(C, T1, T1)
            _lp._integ(T1, T2)
            ws = _lp.pv(T2, tau)
            if uA != 0.0:
                _lp._der(C, T1)
                ch = (
                    _lp.pv(C, tau) * hE
                    - C[0] * hA
                    - _lp._int_qh(T1, m, c, k, tau, hA, hdA, hE, hdE, tq)
                )
                ws -= s * uA * ch
            y[WS] += ws
        if osc_on:  # c∫θ'² = [F·θ] − ∫F'·x_p − ∫F'·h − Δ(½mθ'² + ½kθ²)
            _lp._der(F, T1)
            _lp._mul(T1, XP, T2)
            _lp._integ(T2, T2)
            ifth = (
                (_lp.pv(F, tau) * th - F[0] * th_a)
                - _lp.pv(T2, tau)
                - _lp._int_qh(T1, m, c, k, tau, hA, hdA, hE, hdE, tq)
            )
            y[WD] += ifth - (
                0.5 * m * (thd * thd - thd_a * thd_a) + 0.5 * k * (th * th - th_a * th_a)
            )
        else:
            y[WD] += c * y[E] * y[E] * tau
    y[TH] = th
    y[H] = wa
    y[R] = wr
    y[E] = wa if locked else _lp.pv(WE, tau)
    kind = -1
    if kind_ev == _lp.F_LOCK:
        kind = LOCK
    elif kind_ev == _lp.F_PARK:
        kind = PARK
    elif kind_ev == _lp.F_UNPARK:
        kind = UNPARK
    elif kind_ev == _lp.F_BRK_P or kind_ev == _lp.F_BRK_M:
        kind = BREAK
    elif kind_ev == OUT_OF_WORK:
        kind = OUT_OF_WORK
    return t + tau, kind, settled, n_pass


@njit(cache=True, error_model="numpy", _nrt=False)
def _apply_event(kind, t, y, q, locked, parked, s, compliant, prof, d, dm, g, pk, out):
    """Switch the mode at the located event ``kind`` (state y at t): LOCK joins the sides (momentum
    kept), BREAK slips in the direction of the needed torque, (UN)PARK holds or frees the output.
    Records lock-up and break-away; fills d and g at the new mode; returns (locked, parked, s)."""
    held = q[HELD] > 0.0
    wr_col = R if compliant else H
    if kind == UNPARK and not compliant and y[E] == y[H]:
        # no slip to start from (e.g. a held engine at 0 rad/s and a parked driven side): the
        # clutch that now carries the load holds the driven side at the engine's speed — a lock-up,
        # not a start of slip into the wrong direction (negative slip work)
        kind = LOCK
        parked = False
    a_before = _forces(t, y, q, locked, parked, s, compliant, prof, dm)
    if kind == LOCK:
        locked = True
        jh = q[JH] if compliant else q[JV]
        w = y[E] if held else (y[E] + jh * q[INV_JE] * y[H]) / (1.0 + jh * q[INV_JE])
        y[E] = w
        y[H] = w
        if not compliant:
            parked = False
    elif kind == BREAK:
        locked = False
        s = 1.0 if a_before[4] >= 0 else -1.0
    elif kind == UNPARK:
        parked = False
    elif kind == PARK:
        parked = True
        y[wr_col] = 0.0
    acc_before = dm[
        H
    ]  # the hub's (rigid: the driven side's); the output's is continuous (compliant)
    aux = _forces(t, y, q, locked, parked, s, compliant, prof, d)
    if kind == LOCK:
        out[LOCKUP_TIME] = t
        out[LOCKUP_SPEED] = y[H]
        out[CAPACITY_AT_LOCKUP] = aux[0]
        out[ACCEL_JUMP] = d[H] - acc_before
    elif kind == BREAK:
        if math.isnan(out[BREAKAWAY_TIME]):
            out[BREAKAWAY_TIME] = t
        out[LOCKUP_TIME] = np.nan
    _events(t, y, q, locked, parked, s, compliant, prof, d, aux, g)
    _record_peaks(t, y, q, locked, parked, s, compliant, prof, d, aux, pk)
    return locked, parked, s


@njit(cache=True, error_model="numpy", _nrt=False)
def _follow_linear(t, y, q, parked, s, prof, pk, ft, pw, tq, osc, armed, budget):
    """After the window: follow a linear locked phase of the compliant model exactly to t = ∞
    (through the rest of the clamp profile) for its peaks and for any event. Returns (outcome,
    work): outcome FOLLOW_SETTLED when it settles with no event (the metrics are final),
    FOLLOW_EVENT when an event (break-away, park, unpark) would change them or the response does
    not settle, FOLLOW_OUT_OF_WORK when ``budget`` passes of the root search did not decide."""
    used = 0
    while True:
        nb = np.inf
        for b in (q[TR], q[TCON]):
            if t < b < nb:
                nb = b
        t, kind, settled, n = _linear_segment(
            t,
            nb,
            q[TEND],
            y,
            q,
            True,
            parked,
            s,
            prof,
            True,
            pk,
            ft,
            pw,
            tq,
            osc,
            armed,
            budget - used,
        )
        used += n
        if kind == OUT_OF_WORK:
            return FOLLOW_OUT_OF_WORK, used
        if kind >= 0:
            return FOLLOW_EVENT, used
        if nb == np.inf:
            return (FOLLOW_SETTLED if settled else FOLLOW_EVENT), used


@njit(cache=True, error_model="numpy", _nrt=False)
def _hist_add(hist, n, t, p):
    """Append (t, p) to the slip power history (times strictly increasing); returns the new count
    (POWER_SAMPLES_MAX + 1 once it overflowed)."""
    if n > POWER_SAMPLES_MAX:
        return n
    if n > 0 and t <= hist[0, n - 1]:
        return n
    if n == POWER_SAMPLES_MAX:
        return n + 1
    hist[0, n] = t
    hist[1, n] = p
    return n + 1


@njit(cache=True, error_model="numpy", _nrt=False)
def _slip_spacing(dt, t_slip, t1):
    """Spacing of the power samples of a slipping segment ending at t1 of a slip phase begun at t_slip."""
    return min(dt, max((t1 - t_slip) / POWER_SAMPLES_PER_SLIP, dt / POWER_SAMPLES_DENSER))


@njit(cache=True, error_model="numpy", _nrt=False)
def _hist_linear(hist, n, t0, t1, dt, ft, osc):
    """Sample the slip power form of a linear slipping segment on the grid k·dt in (t0, t1) and at t1."""
    k = math.floor(t0 / dt) + 1.0
    while k * dt < t1:
        tau = k * dt - osc[4]
        hv, hd = _lp.hh(tau, osc[0], osc[1], osc[2], osc[3])
        n = _hist_add(hist, n, k * dt, _lp.fval(ft, _lp.F_POW, tau, hv, hd))
        k += 1.0
    tau = t1 - osc[4]
    hv, hd = _lp.hh(tau, osc[0], osc[1], osc[2], osc[3])
    return _hist_add(hist, n, t1, _lp.fval(ft, _lp.F_POW, tau, hv, hd))


@njit(cache=True, error_model="numpy", _nrt=False)
def _hist_step(hist, n, t0, h, t1, dt, y, d, y1, d1, q, locked, parked, s, compliant, prof, ym, dm):
    """Sample the slip power on the grid k·dt in (t0, t1) of a DOPRI5 step [t0, t0 + h] (its cubic
    Hermite interpolant)."""
    k = math.floor(t0 / dt) + 1.0
    while k * dt < t1:
        _hermite(y, d, y1, d1, h, (k * dt - t0) / h, ym)
        aux = _forces(k * dt, ym, q, locked, parked, s, compliant, prof, dm)
        n = _hist_add(hist, n, k * dt, aux[1] * aux[5])
        k += 1.0
    return n


@njit(cache=True, error_model="numpy", _nrt=False)
def duhamel_at(hist, k):
    """∫₀^{t_k} P(τ)/√(t_k − τ) dτ at sample time t_k, P linear between the samples, each segment
    exactly: with u = t_k − τ, σ = √u and slope b on [t_j, t_{j+1}],
    2(P_j + b·u_j)(σ_j − σ_{j+1}) − (2/3)·b·(u_j σ_j − u_{j+1} σ_{j+1}) (one square root per sample;
    the differences lose at most (u/h)^{3/2}·ε: 3e-11 at 4 096 samples)."""
    tk = hist[0, k]
    acc = 0.0
    u0 = tk - hist[0, 0]
    s0 = math.sqrt(u0)
    for j in range(k):
        u1 = tk - hist[0, j + 1]
        s1 = math.sqrt(u1)
        slope = (hist[1, j + 1] - hist[1, j]) / (hist[0, j + 1] - hist[0, j])
        acc += 2.0 * (hist[1, j] + slope * u0) * (s0 - s1) - (2.0 / 3.0) * slope * (
            u0 * s0 - u1 * s1
        )
        u0, s0 = u1, s1
    return acc


@njit(cache=True, error_model="numpy", _nrt=False)
def duhamel_peak(hist, n, stride):
    """max over the sample times of :func:`duhamel_at`: at every ``stride``-th sample (and the last),
    then at every sample within ``stride`` of the best of those (stride 1: every sample; a larger
    stride costs O(n²/stride + n·stride) instead of O(n²)); 0 for fewer than two samples."""
    if n < 2:
        return 0.0
    best, kb = 0.0, 0
    k = stride
    while True:
        k = min(k, n - 1)
        v = duhamel_at(hist, k)
        if v > best:
            best, kb = v, k
        if k == n - 1:
            break
        k += stride
    if stride > 1:
        k0 = kb
        for k in range(max(1, k0 - stride + 1), min(n, k0 + stride)):
            v = duhamel_at(hist, k)
            if v > best:
                best, kb = v, k
    if (
        1 <= kb < n - 1
    ):  # the peak between samples: vertex of the parabola through the best and its neighbours
        ta, tb, tc = hist[0, kb - 1], hist[0, kb], hist[0, kb + 1]
        va, vc = duhamel_at(hist, kb - 1), duhamel_at(hist, kb + 1)
        d1, d2 = (best - va) / (tb - ta), (vc - best) / (tc - tb)
        curv = (d2 - d1) / (tc - ta)  # half the second derivative
        if curv < 0.0:
            slope_b = d1 + curv * (tb - ta)  # derivative of the parabola at tb
            shift = -slope_b / (2.0 * curv)
            if ta - tb < shift < tc - tb:
                best = best - slope_b * slope_b / (4.0 * curv)
    return best


@njit(cache=True, error_model="numpy")
def flash_peaks(times, power):
    """:func:`duhamel_peak` of each row of sampled slip powers (times non-decreasing from 0; a
    repeated time is skipped), e.g. of the closed form's exact slip power."""
    n_s, n = times.shape
    out = np.empty(n_s)
    hist = np.empty((2, n))
    for i in range(n_s):
        m = 0
        for j in range(n):
            m = _hist_add(hist, m, times[i, j], power[i, j]) if m < n else m
        out[i] = duhamel_peak(hist, m, max(1, int(math.sqrt(m / 2.0))))
    return out


@njit(cache=True, error_model="numpy", _nrt=False, inline="always")
# noqa reason: numba kernel: one scenario's driver loop; to be split into named stages
def _simulate_one(  # noqa: C901
    q,
    compliant,
    prof,
    tt,
    rtol,
    atol,
    max_step,
    first_step,
    max_steps,
    out,
    trace,
    work,
    ft,
    pw,
    tq,
    osc,
    armed,
    hist,
    with_hist,
):
    """Integrate one scenario over [0, q[TEND]]; fill ``out`` (RESULTS) and ``trace`` (times × TRACES).
    ``work``: a (N_WORK, N_STATE) scratch array shared by all scenarios (allocating the ~18 small
    arrays per scenario cost more than a short engagement's integration); ``ft``, ``pw``, ``tq``,
    ``osc``, ``armed``: the linear phases' scratch (:func:`_linear_segment`).

    Compliant model: linear phases (:func:`_is_linear`) are advanced exactly, the others by DOPRI5.
    A scenario locked at the window's end is followed until its peaks are final: a linear locked
    phase exactly to t = ∞; a nonlinear one (rotor drag, engine torque table) by DOPRI5 until its
    linearised hub-output oscillation has decayed by 1e-6. An event after the window (break-away,
    park, unpark) sets TRUNCATED: the metrics of the window would not be final."""
    nan, inf = np.nan, np.inf
    held = q[HELD] > 0.0
    for i in range(out.size):
        out[i] = nan
    out[N_REJECTED] = out[N_LOCATE] = out[N_FALSE_ALARMS] = out[N_EVENT_STEPS] = out[TRUNCATED] = (
        0.0
    )
    out[N_LINEAR] = 0.0
    ns = (
        N_STATE if q[FADE] > 0.0 else N_MECH
    )  # state components (the face temperature's modes with fade)
    y, d, d1, dm, y1, ym, err, yi, ya, yb, y_best = (
        work[0, :ns],
        work[1, :ns],
        work[2, :ns],
        work[3, :ns],
        work[4, :ns],
        work[5, :ns],
        work[6, :ns],
        work[7, :ns],
        work[8, :ns],
        work[9, :ns],
        work[10, :ns],
    )
    kk = work[11:18, :ns]
    g, g1, gm, tau_hi = (
        work[18, :N_EVENTS],
        work[19, :N_EVENTS],
        work[20, :N_EVENTS],
        work[21, :N_EVENTS],
    )
    pk = work[22, :3]  # running maxima: slip power, |friction torque|, |output jerk|
    pk[:] = 0.0
    ths = work[23, :5]  # Hermite sample points in a step (fractions of it)
    rc = work[24:29, :ns]  # the step's continuous extension
    da = work[29, :ns]
    y_end = work[
        30, :ns
    ]  # the state at the window's end (the works and energies are over the window)
    y[:] = 0.0
    y[E] = q[WE0]
    y[H] = q[WC0]
    y[R] = q[WC0]
    wr_col = R if compliant else H
    ths[0] = 0.5

    # initial modes, decided from torques (never from sign(0))
    locked = False
    parked = q[WC0] <= 0.0
    s = 1.0
    aux = _forces(0.0, y, q, locked, parked, s, compliant, prof, d)
    drive0 = aux[3] if compliant else aux[6] * aux[8] * aux[0]
    parked = parked and _load_static(0.0, q) > drive0
    if q[WE0] == q[WC0]:
        aux_l = _forces(0.0, y, q, True, False, s, compliant, prof, d)
        if abs(aux_l[4]) <= q[RS] * aux[0]:
            locked = True
            if not compliant:  # (compliant: the lock joins hub and engine; the output stays parked)
                parked = False
            out[LOCKUP_TIME] = 0.0
            out[LOCKUP_SPEED] = q[WC0]
        else:
            s = 1.0 if aux_l[4] >= 0 else -1.0

    t = 0.0
    aux = _forces(t, y, q, locked, parked, s, compliant, prof, d)
    h = (
        first_step
        if first_step > 0
        else _initial_step(
            t,
            y,
            d,
            q,
            locked,
            parked,
            s,
            compliant,
            prof,
            rtol,
            atol,
            min(max_step, q[TEND]),
            y1,
            d1,
        )
    )
    h_acc, fac_acc, last_rejected = 0.0, 1.0, False
    _events(t, y, q, locked, parked, s, compliant, prof, d, aux, g)
    jk = _record_peaks(t, y, q, locked, parked, s, compliant, prof, d, aux, pk)
    _store_trace(trace, tt, t, y, q, wr_col, aux, jk)
    j_left, tc_left = jk, aux[1]  # jerk and clutch torque at the left end of the next step
    # (a step or very short clamp rise: spacing from the window, so that a long slip cannot overflow the history)
    dt_s = max(min(q[TR], q[TEND]), q[TEND] / POWER_SAMPLES_PER_RAMP) / POWER_SAMPLES_PER_RAMP
    n_hist = _hist_add(hist, 0, 0.0, 0.0 if locked else aux[1] * aux[5])
    t_slip = 0.0  # start of the current slip phase (power sample spacing)
    n_steps = 0
    # the work budget (max_steps): integrator steps attempted, mode switches and the linear phases'
    # root-search passes all count, so that no input (a damper spring whose period is below the
    # time's round-off, events that repeat at one instant) can keep a scenario running for ever
    effort = 0
    out_of_work = False
    t_stop, past = q[TEND], False
    # rigid driveline: the clamp profile's steepest point (x = 1/2 of the cubic and quintic steps)
    # is a breakpoint, so that the slip jerk dC/dt/J_v, largest there, is taken at a step node
    # (the cushion touch TCON, where a later steepest point is, is one already)
    t_rate = 0.5 * q[TR] if (prof != 0 and not compliant) else -1.0
    while effort < max_steps:
        if t >= t_stop:
            if past:
                break
            past = True  # the window's end: keep its state, then follow a locked scenario
            _copy(y_end, y)
            if not (locked and compliant):
                break
            if parked and held and y[E] == 0.0 and y[H] == 0.0:
                break  # a held engine at rest, hub locked to it, output parked: nothing moves again
            if _is_linear(q, True):
                outcome, used = _follow_linear(
                    t, y, q, parked, s, prof, pk, ft, pw, tq, osc, armed, max_steps - effort
                )
                effort += used
                if outcome == FOLLOW_OUT_OF_WORK:
                    out_of_work = True
                elif outcome == FOLLOW_EVENT:
                    out[TRUNCATED] = 1.0
                break
            jd = q[JR] / (
                1.0 + q[JR] * (0.0 if held else 1.0 / (q[JE] + q[JH]))
            )  # locked oscillator's mass
            decay = 0.5 * q[CD] / jd
            if not decay > 0.0:
                out[TRUNCATED] = 1.0
                break
            t_stop = max(t, out[LOCKUP_TIME] + math.log(1e6) / decay)
            continue
        nb = t_stop
        for b in (q[TR], q[TSTEP], q[TCON], t_rate):
            if t < b < nb:
                nb = b
        for b in tt:
            if t < b < nb:
                nb = b
        if compliant and _is_linear(q, locked):
            out[N_LINEAR] += 1
            t_new, kind, _, used = _linear_segment(
                t,
                nb,
                t,
                y,
                q,
                locked,
                parked,
                s,
                prof,
                False,
                pk,
                ft,
                pw,
                tq,
                osc,
                armed,
                max_steps - effort,
            )
            effort += used
            _decay_modes(y, q, t_new - t)  # (a linear phase with fade is a locked one)
            if with_hist and not past:
                n_hist = (
                    _hist_add(hist, n_hist, t_new, 0.0)
                    if locked
                    else _hist_linear(
                        hist, n_hist, t, t_new, _slip_spacing(dt_s, t_slip, t_new), ft, osc
                    )
                )
            t = t_new
            if kind == OUT_OF_WORK:
                out_of_work = True
                break
            if kind >= 0:
                effort += 1  # a mode switch (a restart at an event)
                if past:
                    out[TRUNCATED] = 1.0
                    break
                was_locked = locked
                locked, parked, s = _apply_event(
                    kind, t, y, q, locked, parked, s, compliant, prof, d, dm, g, pk, out
                )
                if was_locked and not locked:
                    t_slip = t
                j_left, tc_left = _jerk_torque(t, y, q, locked, parked, s, compliant, prof, dm)
                h = _initial_step(
                    t,
                    y,
                    d,
                    q,
                    locked,
                    parked,
                    s,
                    compliant,
                    prof,
                    rtol,
                    atol,
                    min(max_step, q[TEND]),
                    y1,
                    d1,
                )
                h_acc, fac_acc, last_rejected = 0.0, 1.0, False
            else:
                t = nb
                aux = _forces(t, y, q, locked, parked, s, compliant, prof, d)
                _events(t, y, q, locked, parked, s, compliant, prof, d, aux, g)
                jk = _record_peaks(t, y, q, locked, parked, s, compliant, prof, d, aux, pk)
                _store_trace(trace, tt, t, y, q, wr_col, aux, jk)
                j_left, tc_left = jk, aux[1]
            continue
        h_try = min(h, max_step, nb - t)
        hit = h_try >= nb - t
        _dopri(t, y, h_try, q, locked, parked, s, compliant, prof, d, kk, yi, y1, err)
        norm = _err_norm(y, y1, err, rtol, atol, _n_active(q, compliant, locked), compliant)
        n_steps += 1
        effort += 1
        # step-size control: Gustafsson's predictive controller (as in radau5.f): the smaller of the
        # elementary and the predicted step, factors in [0.2, 10], safety 0.9, no growth after a rejection
        fac11 = norm**0.2 if norm > 1e-6 else 0.0  # (below, growth is capped at 10 anyway)
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
        h_acc, fac_acc, last_rejected = (
            h_try,
            max(_FAC_ACC_MIN, fac11),
            False,
        )  # max(1e-2, err)^(1/5)
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
        jm = tcm = 0.0
        for i in range(n_th):
            th = ths[i]
            _hermite(y, d, y1, d1, h_try, th, ym)
            tm_ = t + th * h_try
            auxm = _forces(tm_, ym, q, locked, parked, s, compliant, prof, dm)
            if i == 0:  # the step's middle: jerk and clutch torque for the peaks inside the step
                jm, tcm = _jerk(tm_, ym, q, locked, parked, s, compliant, prof, dm, auxm), auxm[1]
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
                tau, nv, n_re = _locate(
                    kind,
                    t,
                    y,
                    d,
                    rc,
                    h_try,
                    tau_hi[kind],
                    g[kind],
                    q,
                    locked,
                    parked,
                    s,
                    compliant,
                    prof,
                    rtol,
                    atol,
                    kk,
                    yi,
                    dm,
                    gm,
                    ya,
                    yb,
                    err,
                    da,
                )
                out[N_EVENT_STEPS] += n_re
                if tau == inf:
                    out[N_FALSE_ALARMS] += 1
                if tau < best_tau:
                    best_tau, best_kind, best_norm = tau, kind, nv
                    _copy(y_best, ya)
            if tau_hi[PEAK] < inf:
                # the slip-power maximum: root of its derivative on the interpolant, value from the
                # continuous extension there (valid only before a switching event in the same step)
                tau_p, _, _ = _locate(
                    PEAK,
                    t,
                    y,
                    d,
                    rc,
                    h_try,
                    tau_hi[PEAK],
                    g[PEAK],
                    q,
                    locked,
                    parked,
                    s,
                    compliant,
                    prof,
                    rtol,
                    atol,
                    kk,
                    yi,
                    dm,
                    gm,
                    yb,
                    ya,
                    err,
                    da,
                    True,
                )
                if tau_p < best_tau:
                    aux_p = _forces(t + tau_p, yb, q, locked, parked, s, compliant, prof, dm)
                    pk[0] = max(pk[0], abs(aux_p[1] * aux_p[5]))
            if best_kind >= 0:
                # the located step must meet the tolerance itself; else retry with a shorter step
                if best_norm > 1.0:
                    out[N_REJECTED] += 1
                    h = best_tau / min(5.0, max(best_norm**0.2 / 0.9, 1.0 / 0.9))
                    (h_acc, fac_acc), last_rejected = acc_prev, True
                    continue
                if past:
                    out[TRUNCATED] = 1.0
                    break
                if with_hist and not locked:
                    n_hist = _hist_step(
                        hist,
                        n_hist,
                        t,
                        h_try,
                        t + best_tau,
                        _slip_spacing(dt_s, t_slip, t + best_tau),
                        y,
                        d,
                        y1,
                        d1,
                        q,
                        locked,
                        parked,
                        s,
                        compliant,
                        prof,
                        ym,
                        dm,
                    )
                if not (compliant or locked or parked) and _jerk_varies(q):
                    _scan_jerk(
                        t,
                        h_try,
                        best_tau / h_try,
                        y[E] - y[H],
                        y_best[E] - y_best[H],
                        j_left,
                        rc,
                        q,
                        locked,
                        parked,
                        s,
                        compliant,
                        prof,
                        pk,
                        yb,
                        dm,
                    )
                if locked:
                    _decay_modes(y_best, q, best_tau)
                t = t + best_tau
                _copy(y, y_best)
                # the peaks up to the event, at the state just before it (a lock-up ends the slip at
                # its largest clutch torque when the clamp still rises: a step may end exactly there)
                aux_e = _forces(t, y, q, locked, parked, s, compliant, prof, dm)
                _record_peaks(t, y, q, locked, parked, s, compliant, prof, dm, aux_e, pk)
                if with_hist:
                    n_hist = _hist_add(hist, n_hist, t, 0.0 if locked else aux_e[1] * aux_e[5])
                was_locked = locked
                locked, parked, s = _apply_event(
                    best_kind, t, y, q, locked, parked, s, compliant, prof, d, dm, g, pk, out
                )
                if was_locked and not locked:
                    t_slip = t
                j_left, tc_left = _jerk_torque(t, y, q, locked, parked, s, compliant, prof, dm)
                h = _initial_step(
                    t,
                    y,
                    d,
                    q,
                    locked,
                    parked,
                    s,
                    compliant,
                    prof,
                    rtol,
                    atol,
                    min(max_step, q[TEND]),
                    y1,
                    d1,
                )
                h_acc, fac_acc, last_rejected = 0.0, 1.0, False
                continue
        # no event: take the step as it was, with the peaks inside it (compliant: the output jerk and
        # the clutch torque oscillate; their maxima must not depend on where the steps fall)
        jk = _record_peaks(t_right, y1, q, locked, parked, s, compliant, prof, d1, aux1, pk)
        if not (compliant or locked or parked) and _jerk_varies(q):
            # a rigid slip jerk that depends on the state: the largest inside the step, and its
            # value from the left at a breakpoint (the profile's end, where dC/dt jumps)
            if hit:
                _jerk_before(t_right, y1, q, locked, parked, s, compliant, prof, dm, pk)
            if not fired:
                _dense_coefficients(y, y1, kk, h_try, rc)
            _scan_jerk(
                t,
                h_try,
                1.0,
                y[E] - y[H],
                y1[E] - y1[H],
                j_left,
                rc,
                q,
                locked,
                parked,
                s,
                compliant,
                prof,
                pk,
                yb,
                dm,
            )
        if compliant:
            th_j = _vertex(j_left, jm, jk, pk[2])
            th_t = _vertex(tc_left, tcm, aux1[1], pk[1])
            if th_j > 0.0 or th_t > 0.0:
                if not fired:
                    _dense_coefficients(y, y1, kk, h_try, rc)
                if th_j > 0.0:
                    _refine_peak(
                        2,
                        th_j,
                        1.0,
                        t,
                        h_try,
                        rc,
                        q,
                        locked,
                        parked,
                        s,
                        compliant,
                        prof,
                        pk,
                        yb,
                        dm,
                    )
                if th_t > 0.0:
                    _refine_peak(
                        1,
                        th_t,
                        1.0,
                        t,
                        h_try,
                        rc,
                        q,
                        locked,
                        parked,
                        s,
                        compliant,
                        prof,
                        pk,
                        yb,
                        dm,
                    )
        j_left, tc_left = jk, aux1[1]
        if with_hist and not past:
            if not locked:
                n_hist = _hist_step(
                    hist,
                    n_hist,
                    t,
                    h_try,
                    t_right,
                    _slip_spacing(dt_s, t_slip, t_right),
                    y,
                    d,
                    y1,
                    d1,
                    q,
                    locked,
                    parked,
                    s,
                    compliant,
                    prof,
                    ym,
                    dm,
                )
            n_hist = _hist_add(hist, n_hist, t_right, 0.0 if locked else aux1[1] * aux1[5])
        if locked:
            _decay_modes(y1, q, t_right - t)
        t = t_right
        _copy(y, y1)
        _copy(d, d1)
        _copy(g, g1)
        _store_trace(trace, tt, t, y, q, wr_col, aux1, jk)

    out[PEAK_SLIP_POWER], out[PEAK_FRICTION_TORQUE], out[PEAK_JERK] = pk[0], pk[1], pk[2]
    out[N_POWER_SAMPLES] = n_hist if with_hist else 0.0
    out[FLASH_PEAK] = (
        duhamel_peak(hist, n_hist, max(1, int(math.sqrt(n_hist / 2.0))))
        if with_hist and n_hist <= POWER_SAMPLES_MAX
        else nan
    )
    out[N_STEPS] = n_steps
    out[FINAL_LOCKED] = 1.0 if locked else 0.0
    out[HIT_STEP_LIMIT] = 1.0 if (out_of_work or (effort >= max_steps and t < t_stop)) else 0.0
    if past:
        _copy(y, y_end)
    if not locked:
        out[LOCKUP_TIME] = nan
        out[ACCEL_JUMP] = nan
    wh, wr = y[H], y[wr_col]
    if compliant:
        k_el = q[K] if math.isfinite(q[K]) else 0.0
        dke = (
            0.5 * q[JH] * (wh**2 - q[WC0] ** 2)
            + 0.5 * q[JR] * (wr**2 - q[WC0] ** 2)
            + 0.5 * k_el * y[TH] ** 2
        )
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
def _batch_rigid(
    Q,
    prof,
    tt,
    rtol,
    atol,
    max_step,
    first_step,
    max_steps,
    out,
    trace,
    work,
    ft,
    pw,
    tq,
    osc,
    armed,
    hist,
    with_hist,
):
    for i in range(Q.shape[0]):
        _simulate_one(
            Q[i],
            False,
            prof,
            tt,
            rtol,
            atol,
            max_step,
            first_step,
            max_steps,
            out[i],
            trace[i],
            work,
            ft,
            pw,
            tq,
            osc,
            armed,
            hist,
            with_hist,
        )


@njit(cache=True, error_model="numpy", _nrt=False)
def _batch_compliant(
    Q,
    prof,
    tt,
    rtol,
    atol,
    max_step,
    first_step,
    max_steps,
    out,
    trace,
    work,
    ft,
    pw,
    tq,
    osc,
    armed,
    hist,
    with_hist,
):
    for i in range(Q.shape[0]):
        _simulate_one(
            Q[i],
            True,
            prof,
            tt,
            rtol,
            atol,
            max_step,
            first_step,
            max_steps,
            out[i],
            trace[i],
            work,
            ft,
            pw,
            tq,
            osc,
            armed,
            hist,
            with_hist,
        )


def simulate_batch(
    Q, compliant, prof, tt, rtol, atol, max_step, first_step, max_steps, with_hist=False
):
    """Run every row of the parameter table Q; returns (results, traces). The rigid and the
    compliant model are compiled separately (the constant flag removes their branches: ~25 %)."""
    n = Q.shape[0]
    out = np.empty((n, N_RESULTS))
    trace = np.full((n, tt.size, N_TRACES), np.nan)
    work = np.empty((N_WORK, N_STATE))
    ft = np.zeros((_lp.N_FROWS, _lp.NP))
    pw = np.zeros((_lp.N_PROWS, _lp.NP))
    tq = np.zeros((_lp.NP, _lp.NP))
    osc = np.zeros(
        5 + 3 * _lp.N_FORM + _lp.NP
    )  # free response, quiet modes and horizons, arming times, scratch
    armed = np.zeros(_lp.N_FORM + _lp.N_FROWS)  # flags, then the form rows' degrees
    hist = np.empty((2, POWER_SAMPLES_MAX))  # the slip power history of one scenario (issue 20)
    run = _batch_compliant if compliant else _batch_rigid
    run(
        Q,
        prof,
        tt,
        rtol,
        atol,
        max_step,
        first_step,
        max_steps,
        out,
        trace,
        work,
        ft,
        pw,
        tq,
        osc,
        armed,
        hist,
        bool(with_hist),
    )
    return out, trace
