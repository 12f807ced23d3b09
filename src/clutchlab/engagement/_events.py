"""Event detection and location on the integrator's own solution (compiled, numba).

An event is a switching function (:func:`clutchlab.engagement._physics.events`: LOCK, BREAK,
UNPARK, PARK, PEAK) falling through zero from above. :func:`detect` looks for candidates in an
integrated step (its end, its middle and where a LOCK or PARK function could dip below zero and
back); :func:`locate_events` places every candidate with :func:`locate` (guess on the step's
continuous extension, one re-integration to it, Newton along the local Taylor line, Illinois on
re-integrations as the last resort) so that an event time carries the solution's accuracy, not
the step size's.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._dopri import EPS, copy, dense, dense_coefficients, dense_component, err_norm, hermite, step
from ._layout import (
    EVENT_TIME_TOL,
    LOCK,
    MAX_POWER,
    N_EVENT_STEPS,
    N_EVENTS,
    N_FALSE_ALARMS,
    N_LOCATE,
    NO_EVENT,
    PARK,
    PEAK,
    E,
    H,
    R,
)
from ._physics import events, forces, jerk, n_active

JIT = dict(cache=True, error_model="numpy", _nrt=False)
INLINE = dict(JIT, inline="always")


# ---- event functions at a state, on the continuous extension, on the Taylor line ---------------


@njit(**JIT)
def g_state(kind, t, yv, q, mode, dm, gm):
    """Event function ``kind`` at the state (t, yv); dm gets f there, gm every event function."""
    fc = forces(t, yv, q, mode, dm)
    events(t, yv, q, mode, dm, fc, gm)
    return gm[kind]


@njit(**JIT)
def g_dense(kind, t, tau, h, rc, q, mode, dm, gm, yb):
    """Event function ``kind`` on the step's continuous extension at t + tau. LOCK (slip) and
    PARK (output speed) are linear in the state: no force evaluation for them."""
    th = tau / h
    if kind == LOCK:
        return mode.sign * (dense_component(rc, th, E) - dense_component(rc, th, H))
    if kind == PARK:
        return dense_component(rc, th, R if mode.compliant else H)
    dense(rc, th, yb)
    return g_state(kind, t + tau, yb, q, mode, dm, gm)


@njit(**JIT)
def g_true(kind, t, tau, q, mode, rtol, atol, w, yout):
    """Event function ``kind`` at t + tau by re-integration from (t, w.y) into yout: (g, error
    norm of that step)."""
    step(t, w.y, tau, q, mode, w.d, w.kk, w.yi, yout, w.err)
    return g_state(kind, t + tau, yout, q, mode, w.dm, w.gm), err_norm(
        w.y, yout, w.err, rtol, atol, n_active(q, mode), mode.compliant
    )


@njit(**JIT)
def line_norm(ya, dm, da, sigma, rtol, atol, n):
    """Error norm of the local Taylor line ya + σ·da at σ: ½|σ|·|f(line) − da| (the y'' term)."""
    acc = 0.0
    for m in range(n):
        sc = atol + rtol * abs(ya[m])
        acc += (0.5 * sigma * (dm[m] - da[m]) / sc) ** 2
    return math.sqrt(acc / n)


@njit(**JIT)
def g_line(kind, t, ya, da, sigma, q, mode, dm, gm, yb):
    """Event function ``kind`` at t + σ on the local Taylor line ya + σ·da (dm: f there)."""
    n = n_active(q, mode)  # (the others do not move along the line)
    for m in range(yb.size):
        yb[m] = ya[m] + sigma * da[m] if m < n else ya[m]
    return g_state(kind, t + sigma, yb, q, mode, dm, gm)


# ---- location ----------------------------------------------------------------------------------


@njit(**JIT)
def locate(kind, t, h, tau_hi, g0, q, mode, rtol, atol, w, interpolant_only=False):
    """Time (from t) at which event ``kind`` falls through zero in (0, tau_hi], or inf (false alarm),
    in a step of h from (t, w.y) whose stages are w.kk and continuous extension w.rc (g0: the
    function at t).

    1. Illinois on the event function along the step's order-4 continuous extension (cheap: no
       integration) to the interpolant's root;
    2. one step of the integrator from t to that root (the true solution there);
    3. the secant method along the local Taylor line y(τ + σ) ≈ y(τ) + σ·f(y(τ)) (σ is of the
       size of the interpolation error), accepted when the line's own error ½|σ|·|f(line) − f|
       is below 10 % of the tolerance: the event time then carries the solution's accuracy;
       otherwise a Newton step: re-integrate to τ + σ and repeat;
    4. if that leaves the step (a false alarm, or no usable slope), Illinois on the true function
       by re-integration from t until the bracket is narrower than max(EVENT_TIME_TOL, 0.01·rtol·h).

    Returns (tau, error norm of the re-integrated step to tau, number of re-integrations); w.ya
    holds the state at t + tau (w.yb is scratch). With ``interpolant_only`` (events that only
    record a value, e.g. a maximum, whose value is insensitive to the time to second order) step 1
    only; w.ya is the continuous extension there.
    """
    guess, slope = _on_interpolant(kind, t, h, tau_hi, g0, q, mode, w, interpolant_only)
    if interpolant_only:
        dense(w.rc, guess / h, w.ya)
        return guess, 0.0, 0
    done, tau, g_a, nv, n_re = _on_taylor_line(
        kind, t, tau_hi, guess, slope, q, mode, rtol, atol, w
    )
    if done:
        return tau, nv, n_re
    return _illinois(kind, t, h, tau_hi, g0, tau, g_a, nv, n_re, q, mode, rtol, atol, w)


@njit(**INLINE)
def _on_interpolant(kind, t, h, tau_hi, g0, q, mode, w, interpolant_only):
    """Step 1 of :func:`locate`: (guess, slope of the final bracket) of the root on the continuous
    extension (Illinois, bracket to 1e-12·tau_hi; 1e-6 for a value-only event)."""
    lo, hi, g_lo, side = 0.0, tau_hi, g0, 0.0
    g_hi = g_dense(kind, t, hi, h, w.rc, q, mode, w.dm, w.gm, w.yb)
    for _ in range(60):
        if hi - lo <= (1e-6 if interpolant_only else 1e-12) * tau_hi or g_hi == 0 or not g_hi <= 0:
            break
        tau = hi - g_hi * (hi - lo) / (g_hi - g_lo)
        if not (lo < tau < hi):
            tau = 0.5 * (lo + hi)
        g_tau = g_dense(kind, t, tau, h, w.rc, q, mode, w.dm, w.gm, w.yb)
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
    return guess, slope


@njit(**INLINE)
def _on_taylor_line(kind, t, tau_hi, guess, slope, q, mode, rtol, atol, w):
    """Steps 2 and 3 of :func:`locate`: re-integrate to the guess, then the secant along the
    local Taylor line, accepted when the line's error is below 10 % of the tolerance; else a
    Newton (secant) step on the true function and again. Returns (done, tau, g there, error norm,
    re-integrations): done when placed (or on the root, or when the step to it fails the
    tolerance: the caller shortens it); else tau is the last re-integrated time."""
    ya, da, yb = w.ya, w.da, w.yb
    tau, n_re, tau_p, g_p = guess, 0, -1.0, 0.0
    for _ in range(8):
        g_a, nv = g_true(kind, t, tau, q, mode, rtol, atol, w, ya)
        n_re += 1
        if g_a == 0 or nv > 1.0:
            return True, tau, g_a, nv, n_re
        tau_a = tau
        copy(da, w.dm)
        ta = t + tau
        if not slope < 0:
            break
        s1 = _line_root(kind, ta, g_a, slope, q, mode, w)
        if not math.isfinite(s1):
            break
        g_line(kind, ta, ya, da, s1, q, mode, w.dm, w.gm, yb)
        if (
            0.0 < tau + s1 <= tau_hi
            and line_norm(ya, w.dm, da, s1, rtol, atol, n_active(q, mode)) <= 0.1
        ):
            copy(ya, yb)
            return True, tau + s1, g_a, nv, n_re
        # not accepted (a long step: the line and the step map part): secant on the true function
        # once two of its values are known, else the line's root
        tau_n = tau + s1
        if tau_p >= 0.0 and g_a != g_p:
            tau_n = tau - g_a * (tau - tau_p) / (g_a - g_p)
        if not 0.0 < tau_n <= tau_hi:
            break
        tau_p, g_p, tau = tau, g_a, tau_n
    return False, tau_a, g_a, nv, n_re


@njit(**INLINE)
def _line_root(kind, ta, g_a, slope, q, mode, w):
    """The secant along y(ta + σ) ≈ ya + σ·f(ya) (no integration) from σ = −g/slope: its root σ."""
    s0, G0, s1 = 0.0, g_a, -g_a / slope
    for _ in range(6):
        G1 = g_line(kind, ta, w.ya, w.da, s1, q, mode, w.dm, w.gm, w.yb)
        if G1 == 0 or G1 == G0:
            break
        s0, G0, s1 = s1, G1, s1 - G1 * (s1 - s0) / (G1 - G0)
        if abs(s1 - s0) <= 4 * EPS * ta:
            break
    return s1


@njit(**INLINE)
def _illinois(kind, t, h, tau_hi, g0, guess, g_a, nv, n_re, q, mode, rtol, atol, w):
    """Step 4 of :func:`locate`: Illinois on the true function (by re-integration), bracket
    (lo, hi) with g(lo) > 0 >= g(hi), until it is narrower than max(EVENT_TIME_TOL, 0.01·rtol·h);
    inf for a false alarm (the interpolant dipped, the solution does not)."""
    if g_a > 0:
        lo, g_lo, hi, hi_known = guess, g_a, tau_hi, False
    else:
        lo, g_lo, hi, g_hi, hi_known, n_hi = 0.0, g0, guess, g_a, True, nv
    if not hi_known:
        g_hi, n_hi = g_true(kind, t, hi, q, mode, rtol, atol, w, w.ya)
        n_re += 1
        if g_hi > 0:
            return np.inf, 0.0, n_re  # false alarm (the interpolant dipped, the solution does not)
    side = 0.0
    for _ in range(100):
        if hi - lo <= max(EVENT_TIME_TOL, 0.01 * rtol * h) + 4 * EPS * (t + hi) or g_hi == 0:
            break
        tau = hi - g_hi * (hi - lo) / (g_hi - g_lo)
        if not (lo < tau < hi):
            tau = 0.5 * (lo + hi)
        g_tau, nv = g_true(kind, t, tau, q, mode, rtol, atol, w, w.yb)
        n_re += 1
        if g_tau > 0:
            if side > 0:
                g_hi *= 0.5  # Illinois: the same end moved twice
            lo, g_lo, side = tau, g_tau, 1.0
        else:
            if side < 0:
                g_lo *= 0.5
            hi, g_hi, side, n_hi = tau, g_tau, -1.0, nv
            copy(w.ya, w.yb)
    return hi, n_hi, n_re


# ---- detection and location in an integrated step ----------------------------------------------


@njit(**INLINE)
def detect(t, h, q, mode, w, wr_col):
    """Candidates of an integrated step [t, t + h] (w.y, w.d at its left end, w.y1, w.d1 and the
    event functions w.g1 at its right end): the event functions at the step end, its middle and,
    where a LOCK or PARK function could dip below zero and back inside the step (slope turning
    from falling to rising), at the interior extrema of their cubic Hermite interpolants. Sets
    w.tau_hi (a candidate's bracket, inf: none); returns (any candidate, output jerk and clutch
    torque at the step's middle)."""
    g, g1, gm, tau_hi = w.g, w.g1, w.gm, w.tau_hi
    fired = False
    for kind in range(N_EVENTS):
        tau_hi[kind] = h if (g[kind] > 0 and g1[kind] <= 0) else np.inf
        fired = fired or tau_hi[kind] < np.inf
    n_th = _hermite_dips(h, mode.sign, wr_col, w)
    jm = tcm = 0.0
    for i in range(n_th):
        th = w.ths[i]
        hermite(w.y, w.d, w.y1, w.d1, h, th, w.ym)
        tm_ = t + th * h
        fm = forces(tm_, w.ym, q, mode, w.dm)
        if i == 0:  # the step's middle: jerk and clutch torque for the peaks inside the step
            jm, tcm = jerk(tm_, w.ym, q, mode, w.dm, fm), fm.torque
        events(tm_, w.ym, q, mode, w.dm, fm, gm)
        for kind in range(N_EVENTS):
            if g[kind] > 0 and gm[kind] <= 0 and th * h < tau_hi[kind]:
                tau_hi[kind] = th * h
                fired = True
    return fired, jm, tcm


@njit(**INLINE)
def _hermite_dips(h, s, wr_col, w):
    """The sample points of :func:`detect` (fractions of the step into w.ths: the middle, then the
    interior extrema of the cubic Hermite interpolants of LOCK and PARK where they fall, then
    rise); returns their number."""
    g, g1, d, d1, ths = w.g, w.g1, w.d, w.d1, w.ths
    n_th = 1
    for kind in (LOCK, PARK):
        if kind == LOCK:
            s0, s1 = s * (d[E] - d[H]), s * (d1[E] - d1[H])
        else:
            s0, s1 = d[wr_col], d1[wr_col]
        if g[kind] > 0 and g1[kind] > 0 and g[kind] < np.inf and s0 < 0 and s1 > 0:
            a0, a1, m0, m1 = g[kind], g1[kind], h * s0, h * s1
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
    return n_th


@njit(**INLINE)
def locate_events(t, h, q, mode, rtol, atol, w, out):
    """Locate every candidate of the step (w.tau_hi) exactly; the earliest wins (its state into
    w.y_best). The slip power's maximum (PEAK) only records a value: the root of its derivative
    on the interpolant, the value from the continuous extension there (valid only before a
    switching event in the same step); the step is not cut there. Counts locations, false alarms
    and re-integrations in ``out``. Returns (time from t, kind or NO_EVENT, error norm of the
    step to it)."""
    tau_hi = w.tau_hi
    dense_coefficients(w.y, w.y1, w.kk, h, w.rc)
    best_tau, best_kind, best_norm = np.inf, NO_EVENT, 0.0
    for kind in range(N_EVENTS):
        if tau_hi[kind] == np.inf:
            continue
        if kind == PEAK:  # records a value only (below): the step is not cut there
            continue
        out[N_LOCATE] += 1
        tau, nv, n_re = locate(kind, t, h, tau_hi[kind], w.g[kind], q, mode, rtol, atol, w)
        out[N_EVENT_STEPS] += n_re
        if tau == np.inf:
            out[N_FALSE_ALARMS] += 1
        if tau < best_tau:
            best_tau, best_kind, best_norm = tau, kind, nv
            copy(w.y_best, w.ya)
    if tau_hi[PEAK] < np.inf:
        tau_p, _, _ = locate(PEAK, t, h, tau_hi[PEAK], w.g[PEAK], q, mode, rtol, atol, w, True)
        if tau_p < best_tau:
            fp = forces(t + tau_p, w.ya, q, mode, w.dm)
            w.pk[MAX_POWER] = max(w.pk[MAX_POWER], abs(fp.torque * fp.slip))
    return best_tau, best_kind, best_norm
