"""Exact linear phases of the compliant driveline (compiled, numba): one segment from its start to
its first event, in closed form.

A linear phase (:func:`clutchlab.engagement._physics.is_linear`) is solved by
:func:`linear_segment` in stages: the phase's polynomials and its oscillator (:func:`_phase`),
the forms of its events and peaks (:func:`_build_forms`) and their arming (:func:`_arm`), the
search for the first event on a grid of half of π/ω₀ that skips ahead wherever bounds exclude a
root or a new peak (:func:`_search`), and the exact works up to the segment's end
(:func:`_works`). The algebra (polynomials, the free response, forms) is
:mod:`clutchlab.engagement._linear_forms`; its docstring gives the equations (source paper
(000), eqs. 1-2 with the damper springs).

The segment's scratch is two records: :class:`Forms` (the form table and each form's role,
quiet horizon and arming time) and :class:`Polys` (the named polynomial rows).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from . import _linear_forms as lf
from ._layout import (
    BREAK,
    CD,
    CMAX,
    FOLLOW_EVENT,
    FOLLOW_OUT_OF_WORK,
    FOLLOW_SETTLED,
    HELD,
    INV_JE,
    JE,
    JH,
    JR,
    KAPPA,
    LOCK,
    MAX_JERK,
    MAX_POWER,
    MAX_TORQUE,
    NO_EVENT,
    OUT_OF_WORK,
    PARK,
    RS,
    TCON,
    TE,
    TEND,
    TH,
    TR,
    UNPARK,
    WD,
    WI,
    WL,
    WS,
    E,
    H,
    K,
    Mode,
    R,
)
from ._linear_forms import N_FORM, NP, FreeResponse, hh
from ._physics import load_static

JIT = dict(cache=True, error_model="numpy", _nrt=False)
INLINE = dict(JIT, inline="always")

# the role of a form in a segment
OFF, EVENT, PEAK_FORM, PENDING = range(4)  # (pending: an event not yet above its round-off)
# how a form is quiet up to its horizon
NOT_QUIET, QUIET_BOUNDS, QUIET_MONOTONE = range(3)

#: The forms of a segment (scratch shared by all segments): ``table`` the form table
#: (N_FROWS × NP), ``degree`` each row's polynomial degree, per form its ``role`` (OFF, EVENT,
#: PEAK_FORM, PENDING), ``quiet`` (NOT_QUIET, QUIET_BOUNDS, QUIET_MONOTONE) up to
#: ``quiet_until`` [s from the segment's start], ``t_arm`` the time it is armed from [s], ``tmp``
#: a scratch row, and per row its Taylor coefficients ``taylor`` at the time ``taylor_at`` [s]
#: (NaN: none yet; the bounds of a row above degree 2 start from them).
Forms = namedtuple(
    "Forms",
    ["table", "degree", "role", "quiet", "quiet_until", "t_arm", "tmp", "taylor", "taylor_at"],
)

#: The polynomial rows of a segment (NP ascending coefficients in τ): ``C`` the capacity, ``D``
#: the drive of body A, ``F`` the oscillator's forcing, ``XP``/``XPD`` the particular solution
#: and its derivative, ``OM`` the mass-weighted speed, ``WE`` the engine speed while slipping,
#: ``T1``/``T2`` scratch, ``ONE``/``ZERO`` constants, ``tq`` (NP × NP) scratch of
#: :func:`clutchlab.engagement._linear_forms.int_qh`.
Polys = namedtuple(
    "Polys", ["C", "D", "F", "XP", "XPD", "OM", "WE", "T1", "T2", "ONE", "ZERO", "tq"]
)

#: A segment's constants (read-only once built by :func:`_phase`): load and engine torque
#: ``tm``, ``te`` [N m], ``ia`` 1/J_A, the oscillator's mass ``m``, ``km`` = K/m, ``cm`` = c/m,
#: ``osc_on`` (False: held, locked and parked, the twist grows at the engine speed), the speeds
#: ω_A = PA + uA·θ', ω_R = PR + uR·θ' (``PA``, ``PR`` polynomial rows), the twist and its rate at
#: the start ``th0``, ``thd0``, the free response ``fr``.
Phase = namedtuple(
    "Phase",
    ["tm", "te", "ia", "m", "km", "cm", "osc_on", "PA", "PR", "uA", "uR", "th0", "thd0", "fr"],
)


def new_forms():
    """The forms' scratch (allocated once a batch)."""
    return Forms(
        np.zeros((lf.N_FROWS, NP)),
        np.zeros(lf.N_FROWS, np.int64),
        np.zeros(N_FORM, np.int64),
        np.zeros(N_FORM, np.int64),
        np.zeros(N_FORM),
        np.zeros(N_FORM),
        np.zeros(NP),
        np.zeros((lf.N_FROWS, NP)),
        np.zeros(lf.N_FROWS),
    )


def new_polys():
    """The polynomial rows (allocated once a batch)."""
    return Polys(*(np.zeros(NP) for _ in range(11)), np.zeros((NP, NP)))


@njit(**JIT)
def linear_segment(t, t_b, t_load, y, q, mode, follow, peaks, pk, fm, pl, budget, x_lock=0.0):
    """Advance a linear phase of the compliant model exactly from t to the first event in (t, t_b]
    or to t_b (``t_b`` may be inf with ``follow``). Slipping, the LOCK event fires where the slip
    s·Δω falls to ``x_lock`` [rad/s] (0: lock-up; above 0, the end of a Stribeck law's constant
    part, :func:`clutchlab.engagement._slip_phase.constant_slip`). Returns (time, event kind or NO_EVENT,
    settled, work, free response): y holds the state there (works updated unless ``follow``), pk
    the peaks inside the segment, work the passes of the root search it took (grid intervals and
    skips). With ``follow`` (after the window) the segment ends, settled, once no armed event can
    fire and no peak can grow any more (bounds of the decaying free response); unsettled after
    10⁵ grid intervals. Without ``peaks`` only the slip power's peak is tracked (the friction
    torque's and the output jerk's forms are off). The load is the static load at ``t_load``.
    After ``budget`` passes the segment ends where it is, with kind OUT_OF_WORK (a free response
    far faster than the phase, e.g. a damper spring so stiff that its period is below the time's
    round-off, would take forever)."""
    ph = _phase(t, t_load, y, q, mode, pl)
    _build_forms(ph, q, mode, peaks, pl, fm, x_lock)
    rh, rd, rate = lf.envelope(ph.fr)
    # grid: half of π/ω₀ (ω₀ ≥ ω_d: extrema of the free response are ≥ π/ω₀ apart)
    T = t_b - t
    w0 = math.sqrt(ph.km)
    dg = math.pi / (2.0 * w0) if (ph.osc_on and w0 > 0.0) else (T if math.isfinite(T) else 1.0)
    if math.isfinite(T) and dg >= T:
        dg = T
    period = 2.0 * math.pi / math.sqrt(ph.fr.w2) if ph.fr.w2 > 0.0 else np.inf
    hA, hdA = hh(ph.fr, 0.0)
    _arm(fm, ph.fr, dg, hA, hdA)
    bounds = (rh, rd, rate)
    tau, form_ev, settled, n_pass = _search(
        T, dg, period, hA, hdA, ph.fr, bounds, mode.locked, follow, pk, fm, pl.C, budget
    )
    # the state at the segment's end (and the works up to it)
    hE, hdE = hh(ph.fr, tau)
    th, thd = lf.pv(pl.XP, tau) + hE, lf.pv(pl.XPD, tau) + hdE
    if not follow:
        _works(tau, th, thd, hA, hdA, hE, hdE, y, q, mode, ph, pl)
    y[TH] = th
    y[H] = lf.pv(ph.PA, tau) + ph.uA * thd
    y[R] = lf.pv(ph.PR, tau) + ph.uR * thd
    y[E] = y[H] if mode.locked else lf.pv(pl.WE, tau)
    return t + tau, _event_of_form(form_ev), settled, n_pass, ph.fr


@njit(**INLINE)
def _event_of_form(form):
    """The event a form's root is (NO_EVENT: none; OUT_OF_WORK passed on)."""
    if form == lf.F_LOCK:
        return LOCK
    if form == lf.F_PARK:
        return PARK
    if form == lf.F_UNPARK:
        return UNPARK
    if form == lf.F_BRK_P or form == lf.F_BRK_M:
        return BREAK
    if form == OUT_OF_WORK:
        return OUT_OF_WORK
    return NO_EVENT


# ---- the phase: polynomials and oscillator -----------------------------------------------------


@njit(**INLINE)
def _phase(t, t_load, y, q, mode, pl):
    """The phase starting at (t, y): its capacity C and drive D (body A: the hub, slipping, driven
    by s·C; engine and hub, locked, driven by T_e), the oscillator m·θ'' + c·θ' + K·θ = F and its
    particular solution x_p, the free response h = θ − x_p, the speed polynomials."""
    locked, parked, s = mode.locked, mode.parked, mode.sign
    held = q[HELD] > 0.0
    jr, jh = q[JR], q[JH]
    tm = load_static(t_load, q)
    te = 0.0 if held else q[TE]
    C, D, F = pl.C, pl.D, pl.F
    lf.zero(pl.ONE)
    pl.ONE[0] = 1.0
    lf.zero(pl.ZERO)
    lf.icap(t, q[TR], q[TCON], q[KAPPA], q[CMAX], mode.profile, C, pl.T1)
    lf.zero(D)
    if locked:
        ia = 0.0 if held else 1.0 / (q[JE] + jh)
        D[0] = te
    else:
        ia = 1.0 / jh
        for n in range(NP):
            D[n] = s * C[n]
    th0 = y[TH]
    thd0 = y[H] - (0.0 if parked else y[R])
    osc_on = not (
        parked and ia == 0.0
    )  # held, locked and parked: the twist grows at the engine speed
    ra, rr = 1.0, 0.0
    if parked:  # the oscillator's mass and forcing: body A alone, or A against the output
        m = 1.0 / ia if osc_on else np.inf
        for n in range(NP):
            F[n] = D[n]
    else:
        ra = 1.0 / (1.0 + jr * ia)
        rr = jr * ia * ra
        m = jr * ra
        lf.axpy(rr, D, ra * tm, pl.ONE, F)
    km, cm, a, w2 = _particular(q, y, m, osc_on, pl)
    fr = FreeResponse(a, w2, th0 - pl.XP[0], thd0 - pl.XPD[0], t)
    PA, PR, uA, uR = _speeds(y, q, mode, tm, te, ia, ra, rr, osc_on, pl)
    return Phase(tm, te, ia, m, km, cm, osc_on, PA, PR, uA, uR, th0, thd0, fr)


@njit(**INLINE)
def _particular(q, y, m, osc_on, pl):
    """The particular solution x_p (pl.XP) and its derivative (pl.XPD); returns (K/m, c/m, a, ω_d²)
    (all 0 without an oscillator, where x_p is the twist growing at the engine speed)."""
    XP = pl.XP
    if osc_on:
        k, c = q[K], q[CD]
        lf.partic(pl.F, m, c, k, XP)
        km, cm = k / m, c / m
        a = 0.5 * cm
        w2 = km - a * a
    else:
        lf.zero(XP)
        XP[0], XP[1] = y[TH], y[E]
        km = cm = a = w2 = 0.0
    lf.der(XP, pl.XPD)
    return km, cm, a, w2


@njit(**INLINE)
def _speeds(y, q, mode, tm, te, ia, ra, rr, osc_on, pl):
    """The speeds ω_A = PA + uA·θ', ω_R = PR + uR·θ' (returns PA, PR rows and uA, uR) and, while
    slipping, the engine speed (pl.WE; held: constant)."""
    C, D, OM, WE, T1 = pl.C, pl.D, pl.OM, pl.WE, pl.T1
    if mode.parked:
        PA, PR, uR = (pl.ZERO if osc_on else OM), pl.ZERO, 0.0
        uA = 1.0 if osc_on else 0.0
        if not osc_on:
            lf.zero(OM)
            OM[0] = y[E]
    else:
        for n in range(NP):
            T1[n] = D[n]
        T1[0] -= tm
        lf.integ(T1, OM)
        for n in range(NP):
            OM[n] *= ra * ia
        OM[0] += ra * y[H] + rr * y[R]
        PA, PR, uA, uR = OM, OM, rr, -ra
    if not mode.locked:  # engine speed while slipping (held: constant)
        lf.integ(C, T1)
        lf.zero(WE)
        WE[0] = y[E]
        if not q[HELD] > 0.0:
            for n in range(NP):
                WE[n] -= q[INV_JE] * mode.sign * T1[n]
            WE[1] += q[INV_JE] * te
    return PA, PR, uA, uR


# ---- the forms of the phase's events and peaks -------------------------------------------------


@njit(**INLINE)
def _build_forms(ph, q, mode, peaks, pl, fm, x_lock):
    """The forms (P + U·h + W·h') of the events and peaks that can happen in this phase (without
    ``peaks`` no friction torque or output jerk; the slip's LOCK form zero at s·Δω = x_lock),
    their derivatives and the degrees of their rows."""
    ft, role = fm.table, fm.role
    for i in range(N_FORM):
        role[i] = OFF
    k, c = q[K], q[CD]
    lf.axpy(k, pl.XP, c, pl.XPD, pl.T2)  # T2 = T_s's polynomial part k·x_p + c·x_p'
    if not mode.locked:
        _slip_forms(ph, mode.sign, pl, fm, x_lock)
    else:
        _locked_forms(ph, q, peaks, pl, fm)
    if mode.parked:  # the load's margin over the spring torque
        lf.axpy(-1.0, pl.T2, ph.tm, pl.ONE, pl.T1)
        lf.fset(ft, lf.F_UNPARK, pl.T1, -k, -c, pl.ONE, pl.ONE)
        role[lf.F_UNPARK] = EVENT
    else:  # the output speed; the output jerk T_s'/J_R (T_s differentiated into the jerk's slot)
        for n in range(NP):
            pl.T1[n] = ph.PR[n] + ph.uR * pl.XPD[n]
        lf.fset(ft, lf.F_PARK, pl.T1, 0.0, ph.uR, pl.ONE, pl.ONE)
        role[lf.F_PARK] = EVENT
        if peaks:
            jd = lf.F_JERK + N_FORM
            lf.fset(ft, jd, pl.T2, k, c, pl.ONE, pl.ONE)
            lf.fder(ft, jd, lf.F_JERK, ph.km, ph.cm)
            for r in range(3):
                for n in range(NP):
                    ft[3 * lf.F_JERK + r, n] /= q[JR]
            role[lf.F_JERK] = PEAK_FORM
    _derive_forms(ph, fm)


@njit(**INLINE)
def _slip_forms(ph, s, pl, fm, x_lock):
    """Slipping: the slip s·(ω_e − ω_A) less x_lock (LOCK) and the slip power C·s·(ω_e − ω_A) (a
    peak)."""
    ft, T1, C = fm.table, pl.T1, pl.C
    for n in range(NP):
        T1[n] = s * (pl.WE[n] - ph.PA[n] - ph.uA * pl.XPD[n])
    lf.fset(ft, lf.F_LOCK, T1, -s * ph.uA, -s * ph.uA, pl.ZERO, pl.ONE)
    ft[3 * lf.F_LOCK, 0] -= x_lock
    fm.role[lf.F_LOCK] = EVENT
    lf.mul(C, T1, T1)  # slip power C·s·(ω_e − ω_A)
    for n in range(NP):
        ft[3 * lf.F_POW, n] = T1[n]
        ft[3 * lf.F_POW + 1, n] = 0.0
        ft[3 * lf.F_POW + 2, n] = -s * ph.uA * C[n]
    fm.role[lf.F_POW] = PEAK_FORM


@njit(**INLINE)
def _locked_forms(ph, q, peaks, pl, fm):
    """Locked: the static capacity's margin over the torque needed to stay locked, α·T_s + β,
    in both directions (BREAK), and with ``peaks`` that torque itself (a peak)."""
    ft, T1, T2 = fm.table, pl.T1, pl.T2
    k, c, jh = q[K], q[CD], q[JH]
    alpha, beta = 1.0 - jh * ph.ia, jh * ph.ia * ph.te  # torque needed to stay locked: α·T_s + β
    for form in (lf.F_BRK_P, lf.F_BRK_M):
        sign = 1.0 if form == lf.F_BRK_P else -1.0
        for n in range(NP):
            T1[n] = q[RS] * pl.C[n] - sign * alpha * T2[n]
        T1[0] -= sign * beta
        lf.fset(ft, form, T1, -sign * alpha * k, -sign * alpha * c, pl.ONE, pl.ONE)
        fm.role[form] = EVENT
    if not peaks:
        return
    lf.axpy(alpha, T2, 0.0, T2, T1)
    T1[0] += beta
    lf.fset(ft, lf.F_TORQ, T1, alpha * k, alpha * c, pl.ONE, pl.ONE)
    fm.role[lf.F_TORQ] = PEAK_FORM


@njit(**INLINE)
def _derive_forms(ph, fm):
    """The first and second derivatives of every active form, and the degrees of their rows."""
    ft, fd, role = fm.table, fm.degree, fm.role
    fm.taylor_at[:] = np.nan
    for i in range(N_FORM):
        if role[i] != OFF:
            lf.fder(ft, i, i + N_FORM, ph.km, ph.cm)
            lf.fder(ft, i + N_FORM, i + 2 * N_FORM, ph.km, ph.cm)
    for i in range(N_FORM):
        if role[i] != OFF:
            for j in (i, i + N_FORM, i + 2 * N_FORM):
                for r in range(3 * j, 3 * j + 3):
                    fd[r] = lf.degree(ft[r])


@njit(**INLINE)
def _arm(fm, fr, dg, hA, hdA):
    """Events are armed only where their function starts above zero (as in the integrator). One
    that starts at zero within round-off (slip just after a break-away, output speed just after
    unparking) is armed from the first of the times dg·2⁻ᵏ (k = 40 … 0) where it is positive: a
    restart at an event never fires at once, and a short episode after it is not stepped over.
    If it is not positive by then, it stays pending and is armed at the first grid point where
    it is."""
    ft, fd, role, t_arm = fm.table, fm.degree, fm.role, fm.t_arm
    for i in range(N_FORM):
        t_arm[i] = 0.0
        if role[i] == EVENT:
            r = 3 * i
            scale = abs(ft[r, 0]) + abs(ft[r + 1, 0] * hA) + abs(ft[r + 2, 0] * hdA)
            noise = 64.0 * lf._EPS * scale
            if not lf.fvald(ft, fd, i, 0.0, hA, hdA) > noise:
                role[i] = PENDING
                # (above its round-off, not merely > 0: an output speed that starts at zero after
                # unparking with zero acceleration is round-off for a while; armed on a positive
                # round-off value it fired at once, 1e-19 s later, and the restart unparked again:
                # a stiff damper chattered park/unpark forever, or stayed parked for good)
                for kexp in range(40, -1, -1):
                    ta = dg * 2.0 ** (-kexp)
                    hT, hdT = hh(fr, ta)
                    if lf.fvald(ft, fd, i, ta, hT, hdT) > noise:
                        role[i], t_arm[i] = EVENT, ta
                        break


@njit(**JIT)
def _arm_pending(fm, tau, h, hd):
    """Arm the pending event forms that are positive at τ."""
    for i in range(N_FORM):
        if fm.role[i] == PENDING and lf.fvald(fm.table, fm.degree, i, tau, h, hd) > 0.0:
            fm.role[i] = EVENT


# ---- bounds of a form over an interval -------------------------------------------------------


@njit(**JIT)
def _peak_slot(form):
    """Slot of the running maxima (slip power, |friction torque|, |output jerk|) a peak form feeds."""
    return MAX_POWER if form == lf.F_POW else (MAX_TORQUE if form == lf.F_TORQ else MAX_JERK)


@njit(**INLINE)
def _row_range(fm, r, deg, lo, hi):
    """Bounds of row r's polynomial on [lo, hi]; above degree 2 from its Taylor coefficients at
    lo, kept for the next bounds from the same lo (the horizon's growing spans)."""
    if deg <= 2:
        return lf.prange(fm.table[r], deg, lo, hi, fm.tmp)
    if fm.taylor_at[r] != lo:
        lf.taylor(fm.table[r], deg, lo, fm.taylor[r])
        fm.taylor_at[r] = lo
    return lf.taylor_range(fm.taylor[r], deg, hi - lo)


@njit(**JIT)
def _form_bounds(fm, i, lo, hi, bounds, fr):
    """(min P, max P, bound of |U·h + W·h'|) of form i over [lo, hi]; hi may be inf (then P beyond
    degree 1 or non-constant U, W give infinite bounds). Constant U, W of an underdamped response:
    the exact envelope of U·h + W·h' = e^(−aτ)·(A·cos ω_dτ + B·sin ω_dτ), √(A² + B²)·e^(−a·lo).
    ``bounds``: the free response's envelope (R_h, R_h', rate)."""
    ft, fd = fm.table, fm.degree
    rh, rd, rate = bounds
    r = 3 * i
    dp, du, dw = int(fd[r]), int(fd[r + 1]), int(fd[r + 2])
    if math.isfinite(hi):
        pmin, pmax = _row_range(fm, r, dp, lo, hi)
    else:
        if dp > 1 or du > 0 or dw > 0:
            return -np.inf, np.inf, np.inf
        p0 = lf.pvd(ft[r], dp, lo)
        slope = ft[r, 1] if dp == 1 else 0.0
        pmin = p0 if slope >= 0.0 else -np.inf
        pmax = p0 if slope <= 0.0 else np.inf
    if du == 0 and dw == 0:
        u, w = ft[r + 1, 0], ft[r + 2, 0]
        a, w2, h0, h1 = fr.a, fr.w2, fr.h0, fr.h1
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
        u0, u1 = _row_range(fm, r + 1, du, lo, hi)
        w0, w1 = _row_range(fm, r + 2, dw, lo, hi)
        um, wm = max(abs(u0), abs(u1)), max(abs(w0), abs(w1))
    env = um * rh + wm * rd
    if env > 0.0:
        env *= math.exp(-rate * lo)
    return pmin, pmax, env


@njit(**JIT)
def _excluded(fm, i, lo, hi, bounds, pk, fr):
    """Whether the bounds exclude, on [lo, hi], a root of event form i or a value of peak form i
    above the running maximum."""
    pmin, pmax, env = _form_bounds(fm, i, lo, hi, bounds, fr)
    if fm.role[i] == EVENT:
        return pmin - env > 0.0
    return max(abs(pmin), abs(pmax)) + env <= pk[_peak_slot(i)]


@njit(**JIT)
def _quiet(fm, i, lo, hi, bounds, pk, fr):
    """How form i is quiet on [lo, hi]: QUIET_BOUNDS by its bounds, QUIET_MONOTONE, or NOT_QUIET."""
    if _excluded(fm, i, lo, hi, bounds, pk, fr):
        return QUIET_BOUNDS
    if _monotone(fm, i, lo, hi, bounds, fr):
        return QUIET_MONOTONE
    return NOT_QUIET


@njit(**JIT)
def _monotone(fm, i, lo, hi, bounds, fr):
    """Whether the bounds of form i's derivative keep it of one sign on [lo, hi]."""
    pmin, pmax, env = _form_bounds(fm, i + N_FORM, lo, hi, bounds, fr)
    return pmin - env > 0.0 or pmax + env < 0.0


# ---- the search for the first event ------------------------------------------------------------


@njit(**INLINE)
def _search(T, dg, period, hA, hdA, fr, bounds, locked, follow, pk, fm, C, budget):
    """The first event of the segment [0, T] (T may be inf with ``follow``): grid intervals of dg,
    skipping ahead to the armed forms' quiet horizons. Returns (τ at the end, its form or −1 or
    OUT_OF_WORK, settled, passes); the running maxima pk are updated on the way."""
    quiet, quiet_until = fm.quiet, fm.quiet_until
    for i in range(N_FORM):
        quiet[i], quiet_until[i] = NOT_QUIET, -1.0
    t_lo, n_int, settled, n_pass = 0.0, 0, False, 0
    hL, hdL = hA, hdA
    tau_ev, form_ev = np.inf, -1
    while True:
        n_pass += 1
        if n_pass > budget:  # out of work: end here (the caller reports not_converged)
            return t_lo, OUT_OF_WORK, settled, n_pass
        if not math.isfinite(T) and _settled(fm, t_lo, T, period, dg, bounds, pk, fr):
            return t_lo, form_ev, True, n_pass
        skip_to = _horizon(fm, t_lo, T, dg, bounds, pk, fr)
        skip = skip_to - t_lo if skip_to > t_lo and math.isfinite(skip_to) else 0.0
        if skip > 0.0:  # nothing can happen before t_lo + skip
            t_s = t_lo + skip
            hS, hdS = hh(fr, t_s)
            tau_ev, form_ev = _monotone_roots(fm, fr, t_lo, t_s, hS, hdS, tau_ev, form_ev)
            t_end = min(t_s, tau_ev)
            hE, hdE = (hS, hdS) if t_end == t_s else hh(fr, t_end)
            _monotone_peaks(fm, t_end, hE, hdE, pk)
            if not locked:
                pk[MAX_TORQUE] = max(pk[MAX_TORQUE], abs(lf.pv(C, t_end)))
            if form_ev >= 0:
                return t_end, form_ev, settled, n_pass
            _arm_pending(fm, t_s, hS, hdS)
            t_lo = t_s
            if t_lo >= T:
                return T, form_ev, settled, n_pass
            hL, hdL = hS, hdS
            continue
        # one grid interval (t_lo, t_hi]: its earliest event, then the peaks up to it
        t_hi = t_lo + dg
        if math.isfinite(T) and T - t_hi < 1e-3 * dg:
            t_hi = T
        n_int += 1
        hB, hdB = hh(fr, t_hi)
        tau_ev, form_ev = _interval_roots(
            fm, fr, t_lo, t_hi, hL, hdL, hB, hdB, bounds, tau_ev, form_ev
        )
        t_end = min(t_hi, tau_ev)
        hE, hdE = (hB, hdB) if t_end == t_hi else hh(fr, t_end)
        _interval_peaks(fm, fr, t_lo, t_end, hL, hdL, hE, hdE, bounds, pk)
        if not locked:
            pk[MAX_TORQUE] = max(pk[MAX_TORQUE], abs(lf.pv(C, t_end)))
        if form_ev >= 0 or (math.isfinite(T) and t_hi >= T):
            return t_end, form_ev, settled, n_pass
        _arm_pending(fm, t_hi, hB, hdB)
        t_lo, hL, hdL = t_hi, hB, hdB
        if follow and n_int > 100_000:
            return t_lo, form_ev, settled, n_pass


@njit(**INLINE)
def _settled(fm, t_lo, T, period, dg, bounds, pk, fr):
    """After the window: forms that can never fire (events) or grow (peaks) again are disarmed;
    whether none is left."""
    role = fm.role
    n_armed = 0
    for i in range(N_FORM):
        if role[i] == OFF or role[i] == PENDING:
            continue
        if _excluded(fm, i, t_lo, T, bounds, pk, fr) or (
            bounds[2] <= 0.0 and lf.degree(fm.table[3 * i]) == 0 and t_lo > period + dg
        ):  # undamped: a period shows all
            role[i] = OFF
        else:
            n_armed += 1
    return n_armed == 0


@njit(**INLINE)
def _horizon(fm, t_lo, T, dg, bounds, pk, fr):
    """Skip ahead to the earliest quiet horizon of the armed forms: each form's horizon is the
    longest [t_lo, t_lo + Δ] (Δ doubling from one grid interval) on which its bounds exclude a
    root (events) or a value above the maximum so far (peaks) — QUIET_BOUNDS — or keep its
    derivative of one sign, so that only its end value matters — QUIET_MONOTONE. A horizon stays
    valid as t_lo advances (the bounds only tighten, the maxima only grow): recomputed once
    passed. Returns the time to skip to (≤ t_lo: step the grid)."""
    role, quiet, quiet_until = fm.role, fm.quiet, fm.quiet_until
    skip_to = T
    for i in range(N_FORM):
        if role[i] == OFF:
            continue
        if role[i] == PENDING or fm.t_arm[i] > t_lo:  # pending, or armed inside: step the grid
            return t_lo
        if quiet_until[i] <= t_lo:
            qu, qm = t_lo, NOT_QUIET
            m_i = _quiet(fm, i, t_lo, T, bounds, pk, fr) if math.isfinite(T) else NOT_QUIET
            if m_i != NOT_QUIET:  # quiet to the segment's end (the common case: one try)
                qu, qm = T, m_i
            else:
                span = dg
                while span < 65536.0 * dg:
                    t_s = min(t_lo + span, T)
                    m_i = _quiet(fm, i, t_lo, t_s, bounds, pk, fr)
                    if m_i == NOT_QUIET:
                        break
                    qu, qm = t_s, m_i
                    if t_s >= T:
                        break
                    span *= 4.0
            quiet_until[i], quiet[i] = qu, qm
        skip_to = min(skip_to, quiet_until[i])
        if skip_to <= t_lo:
            return skip_to
    return skip_to


@njit(**INLINE)
def _monotone_roots(fm, fr, t_lo, t_s, hS, hdS, tau_ev, form_ev):
    """A skip to t_s: a monotone event function crosses zero at most once, so its root is there
    if it is not positive at t_s. Returns the earliest (τ, form) so far."""
    for i in range(N_FORM):
        if (
            fm.role[i] == EVENT
            and fm.quiet[i] == QUIET_MONOTONE
            and lf.fvald(fm.table, fm.degree, i, t_s, hS, hdS) <= 0.0
        ):
            r = lf.root(fm.table, i, t_lo, t_s, fr)
            if r < tau_ev:
                tau_ev, form_ev = r, i
    return tau_ev, form_ev


@njit(**INLINE)
def _monotone_peaks(fm, t_end, hE, hdE, pk):
    """A skip: a monotone peak function has its maximum at an end."""
    for i in range(N_FORM):
        if fm.role[i] == PEAK_FORM and fm.quiet[i] == QUIET_MONOTONE:
            pk[_peak_slot(i)] = max(
                pk[_peak_slot(i)], abs(lf.fvald(fm.table, fm.degree, i, t_end, hE, hdE))
            )


@njit(**INLINE)
def _interval_roots(fm, fr, t_lo, t_hi, hL, hdL, hB, hdB, bounds, tau_ev, form_ev):
    """Events in (t_lo, t_hi]: the earliest root of the armed functions, a sign change at t_hi or
    a dip below zero inside (a minimum where the bounds do not exclude it). Returns (τ, form)."""
    ft, fd = fm.table, fm.degree
    for i in range(N_FORM):
        if fm.role[i] != EVENT or fm.t_arm[i] >= t_hi:
            continue
        lo_i = max(t_lo, fm.t_arm[i])  # (a form armed inside the interval: from its arming time)
        r_hi = np.inf
        if lf.fvald(ft, fd, i, t_hi, hB, hdB) <= 0.0:
            r_hi = t_hi
        else:
            pmin, _, env = _form_bounds(fm, i, lo_i, t_hi, bounds, fr)
            if pmin - env <= 0.0:  # a dip below zero is not excluded: look for a minimum inside
                hI, hdI = (hL, hdL) if lo_i == t_lo else hh(fr, lo_i)
                d_lo = lf.fvald(ft, fd, i + N_FORM, lo_i, hI, hdI)
                if d_lo < 0.0 and lf.fvald(ft, fd, i + N_FORM, t_hi, hB, hdB) > 0.0:
                    tmin = lf.extremum(ft, i, lo_i, t_hi, d_lo, fr)
                    hM, hdM = hh(fr, tmin)
                    if lf.fvald(ft, fd, i, tmin, hM, hdM) <= 0.0:
                        r_hi = tmin
        if r_hi < np.inf:
            r = lf.root(ft, i, lo_i, r_hi, fr)
            if r < tau_ev:
                tau_ev, form_ev = r, i
    return tau_ev, form_ev


@njit(**INLINE)
def _interval_peaks(fm, fr, t_lo, t_end, hL, hdL, hE, hdE, bounds, pk):
    """Peaks on (t_lo, t_end]: the end and the extrema inside, where they could exceed the
    maximum so far."""
    ft, fd = fm.table, fm.degree
    for i in range(N_FORM):
        if fm.role[i] != PEAK_FORM:
            continue
        slot = _peak_slot(i)
        pk[slot] = max(pk[slot], abs(lf.fvald(ft, fd, i, t_end, hE, hdE)))
        pmin, pmax, env = _form_bounds(fm, i, t_lo, t_end, bounds, fr)
        if max(abs(pmin), abs(pmax)) + env <= pk[slot]:
            continue
        d_lo = lf.fvald(ft, fd, i + N_FORM, t_lo, hL, hdL)
        d_hi = lf.fvald(ft, fd, i + N_FORM, t_end, hE, hdE)
        if (d_lo > 0.0) != (d_hi > 0.0):
            te_ = lf.extremum(ft, i, t_lo, t_end, d_lo, fr)
            hM, hdM = hh(fr, te_)
            pk[slot] = max(pk[slot], abs(lf.fvald(ft, fd, i, te_, hM, hdM)))


# ---- the works over the segment ----------------------------------------------------------------


@njit(**INLINE)
def _works(tau, th, thd, hA, hdA, hE, hdE, y, q, mode, ph, pl):
    """Add the exact works over [0, τ] to y: input, load, slip and damping work (integrals of
    polynomials, and of Q·h by :func:`clutchlab.engagement._linear_forms.int_qh`)."""
    locked, parked, s = mode.locked, mode.parked, mode.sign
    held = q[HELD] > 0.0
    k, c, m, tm, te = q[K], q[CD], ph.m, ph.tm, ph.te
    C, T1, T2, tq = pl.C, pl.T1, pl.T2, pl.tq
    th_a, thd_a = ph.th0, ph.thd0
    lf.integ(C, T1)
    if held:  # input work: ω_e·∫T_c (locked: ∫T_s, ∫θ = ∫x_p + ∫h), or T_e·∫ω_e
        if locked:
            lf.integ(pl.XP, T2)
            ith = (
                lf.pv(T2, tau) + lf.int_qh(pl.ONE, m, c, k, tau, hA, hdA, hE, hdE, tq)
                if ph.osc_on
                else lf.pv(T2, tau)
            )
            y[WI] += y[E] * (k * ith + c * (th - th_a))
        else:
            y[WI] += y[E] * s * lf.pv(T1, tau)
    else:
        if locked:
            lf.integ(ph.PA, T2)
            y[WI] += te * (lf.pv(T2, tau) + ph.uA * (th - th_a))
        else:
            lf.integ(pl.WE, T2)
            y[WI] += te * lf.pv(T2, tau)
    if not parked:  # load work T_m·∫ω_R
        lf.integ(ph.PR, T2)
        y[WL] += tm * (lf.pv(T2, tau) + ph.uR * (th - th_a))
    if not locked:  # ∫C·s(ω_e − ω_A) = ∫C·P_lock − s·uA·([C·h] − ∫C'·h)
        for n in range(NP):
            T1[n] = s * (pl.WE[n] - ph.PA[n] - ph.uA * pl.XPD[n])
        lf.mul(C, T1, T1)
        lf.integ(T1, T2)
        ws = lf.pv(T2, tau)
        if ph.uA != 0.0:
            lf.der(C, T1)
            ch = lf.pv(C, tau) * hE - C[0] * hA - lf.int_qh(T1, m, c, k, tau, hA, hdA, hE, hdE, tq)
            ws -= s * ph.uA * ch
        y[WS] += ws
    if ph.osc_on:  # c∫θ'² = [F·θ] − ∫F'·x_p − ∫F'·h − Δ(½mθ'² + ½kθ²)
        lf.der(pl.F, T1)
        lf.mul(T1, pl.XP, T2)
        lf.integ(T2, T2)
        ifth = (
            (lf.pv(pl.F, tau) * th - pl.F[0] * th_a)
            - lf.pv(T2, tau)
            - lf.int_qh(T1, m, c, k, tau, hA, hdA, hE, hdE, tq)
        )
        y[WD] += ifth - (0.5 * m * (thd * thd - thd_a * thd_a) + 0.5 * k * (th * th - th_a * th_a))
    else:
        y[WD] += c * y[E] * y[E] * tau


# ---- after the window --------------------------------------------------------------------------


@njit(**JIT)
def follow_linear(t, y, q, mode, peaks, pk, fm, pl, budget):
    """After the window: follow a linear locked phase of the compliant model exactly to t = ∞
    (through the rest of the clamp profile) for its peaks and for any event. Returns (outcome,
    work): outcome FOLLOW_SETTLED when it settles with no event (the metrics are final),
    FOLLOW_EVENT when an event (break-away, park, unpark) would change them or the response does
    not settle, FOLLOW_OUT_OF_WORK when ``budget`` passes of the root search did not decide."""
    used = 0
    locked = Mode(True, mode.parked, mode.sign, True, mode.profile)
    while True:
        nb = np.inf
        for b in (q[TR], q[TCON]):
            if t < b < nb:
                nb = b
        t, kind, settled, n, _ = linear_segment(
            t, nb, q[TEND], y, q, locked, True, peaks, pk, fm, pl, budget - used
        )
        used += n
        if kind == OUT_OF_WORK:
            return FOLLOW_OUT_OF_WORK, used
        if kind >= 0:
            return FOLLOW_EVENT, used
        if nb == np.inf:
            return (FOLLOW_SETTLED if settled else FOLLOW_EVENT), used
