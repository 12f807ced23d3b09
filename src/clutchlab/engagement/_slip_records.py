"""Events, peaks, works and slip power samples of an accepted collocation step (compiled, numba).

The step's solution is a closed form on the whole step (:mod:`clutchlab.engagement._colloc`):
events (lock-up, break-away of the output, its stop, a friction-table point crossed) are roots of
it, placed by Illinois on the dense solution (no re-integration); the peaks (slip power, clutch
torque, output jerk) are taken at the nodes and refined on the dense solution; the works are the
exact integrals of the interpolated node values (Clenshaw–Curtis) and of the free response.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._colloc import (
    CC_WEIGHTS,
    JIT,
    NN,
    NODES,
    fit,
    free_basis,
    integral,
    poly_eval,
    taylor_at,
)
from ._layout import (
    CD,
    FTAB,
    JH,
    JR,
    LOCK,
    MAX_JERK,
    MAX_POWER,
    MAX_TORQUE,
    PARK,
    UNPARK,
    WD,
    WI,
    WL,
    WS,
    K,
)
from ._power import hist_add
from ._slip_step import dense

KNOT = 100  # an internal event: the slip crosses a friction table point (a step boundary only)
SCAN_PER_PERIOD = 16.0  # samples a period of an event's dense scan
JERK_PER_PERIOD = (
    8.0  # samples a period of the jerk's dense scan (a local maximum brackets its peak)
)
GOLDEN_ITER = (
    24  # golden-section steps: the bracket shrinks to 1e-5 (the peak value's error ~1e-10)
)

# ---- events on the dense solution ---------------------------------------------------------------


@njit(**JIT)
def event_value(ec, kind, v, q, knot, rr, ra):
    """Event function ``kind`` on the step's dense solution at v: LOCK s·Δω, UNPARK T_m − T_s
    (parked), PARK ω_r (moving), KNOT s·Δω − knot (the table segment's lower end), KNOT + 1
    knot − s·Δω (its upper end)."""
    sc = ec.sc[0]
    wm, th, thd, _ = dense(ec, v, q[K])
    parked = sc.parked
    wh = thd if parked else wm + rr * thd
    if kind == LOCK:
        return sc.sign * (sc.we - wh)
    if kind == UNPARK:
        return sc.tm - (q[K] * th + q[CD] * thd)
    if kind == PARK:
        return wm - ra * thd
    a = sc.sign * (sc.we - wh)
    return a - knot if kind == KNOT else knot - a


@njit(**JIT)
def locate(ec, kind, lo, hi, g_lo, q, knot, rr, ra):
    """Root in (lo, hi] of event ``kind`` on the dense solution (g(lo) = g_lo > 0 ≥ g(hi)):
    Illinois to a bracket of 1e-14 of the step; the value where it has crossed (≤ 0)."""
    g_hi = event_value(ec, kind, hi, q, knot, rr, ra)
    side = 0.0
    for _ in range(100):
        if hi - lo <= 2e-14 or g_hi == 0.0:
            break
        v = hi - g_hi * (hi - lo) / (g_hi - g_lo)
        if not (lo < v < hi):
            v = 0.5 * (lo + hi)
        g = event_value(ec, kind, v, q, knot, rr, ra)
        if g > 0.0:
            if side > 0.0:
                g_hi *= 0.5
            lo, g_lo, side = v, g, 1.0
        else:
            if side < 0.0:
                g_lo *= 0.5
            hi, g_hi, side = v, g, -1.0
    return hi


@njit(**JIT)
def node_event_values(ec, kind, i, q, knot, rr, ra):
    """Event function ``kind`` at node i (from the node rows)."""
    sc = ec.sc[0]
    parked = sc.parked
    wh = ec.wh[i]
    if kind == LOCK:
        return sc.sign * (sc.we - wh)
    if kind == UNPARK:
        return sc.tm - (q[K] * ec.th[i] + q[CD] * ec.thd[i])
    if kind == PARK:
        return ec.wm[i] - ra * ec.thd[i] if not parked else 1.0
    a = sc.sign * (sc.we - wh)
    return a - knot if kind == KNOT else knot - a


@njit(**JIT)
def free_amplitudes(ec, v_end):
    """Bounds (R_h, R_h') of |h| and |h'| of the step's free response on [−1, v_end] (its envelope
    √(…)·e^(−aτ) at the start or, growing, at the end)."""
    sc = ec.sc[0]
    a, w2, h0, h1 = sc.a, sc.w2, sc.h0, sc.h1
    w0sq = w2 + a * a
    tau = 0.5 * sc.h * (1.0 + v_end)
    if w2 > 0.0:
        wd = math.sqrt(w2)
        rh = math.hypot(h0, (h1 + a * h0) / wd)
        rd = math.hypot(h1, (a * h1 + w0sq * h0) / wd)
        grow = max(1.0, math.exp(-a * tau))
    else:
        b = math.sqrt(max(-w2, 0.0))
        rh = abs(h0) + abs(h1 + a * h0) * max(tau, 1.0 / max(b, 1e-300))
        rd = abs(h1) + abs(a * h1 + w0sq * h0) * max(tau, 1.0 / max(b, 1e-300))
        grow = max(1.0, math.exp((b - a) * tau))
    return rh * grow, rd * grow


@njit(**JIT)
def scan_count(ec, v_end, per_period):
    """Samples of a dense scan of [−1, v_end]: ``per_period`` a period of the free response, at
    least NN."""
    sc = ec.sc[0]
    tau = 0.5 * sc.h * (1.0 + v_end)
    if sc.w2 <= 0.0:
        return NN
    return max(NN, int(math.ceil(per_period * tau * math.sqrt(sc.w2) / (2.0 * math.pi))) + 1)


@njit(**JIT)
def _event_bound(ec, q, kind, rh, rd, rr, ra):
    """(knot, amplitude) of event ``kind`` in the step: the friction table point it crosses (KNOT,
    KNOT + 1; NaN when the step's segment has no such end, or for the lower end at zero slip:
    reaching zero is lock-up) and the free response's amplitude in its event function."""
    sc = ec.sc[0]
    knot = 0.0
    if kind == KNOT:
        knot = sc.x_lo if (q[FTAB] > 0.0 and 0.0 < sc.x_lo < np.inf) else np.nan
    elif kind == KNOT + 1:
        knot = sc.x_hi if (q[FTAB] > 0.0 and sc.x_hi < np.inf) else np.nan
    if kind == UNPARK:
        return knot, q[K] * rh + q[CD] * rd
    if kind == PARK:
        return knot, ra * rd
    return knot, (1.0 if sc.parked else rr) * rd


@njit(**JIT)
def _near_until(ec, q, kind, knot, amp, rr, ra):
    """Up to where event ``kind`` can fire in the step: the node after the last node within twice
    the free response's amplitude of zero (its polynomial part is smooth between the nodes, so
    it cannot reach zero between two nodes farther away); −2 where it cannot fire at all (not
    positive at its start — a mode begun at its own event has it zero — or no node near)."""
    if not node_event_values(ec, kind, 0, q, knot, rr, ra) > 0.0:
        return -2.0
    last = -1
    for i in range(NN):
        if node_event_values(ec, kind, i, q, knot, rr, ra) <= 2.0 * amp * 1.05 + 1e-300:
            last = i
    return NODES[min(last + 1, NN - 1)] if last >= 0 else -2.0


@njit(**JIT)
def first_event(ec, q, kinds_mask, rr, ra):
    """The earliest event in the step: (kind, v) or (−1, 1.0). kinds_mask bits: LOCK, UNPARK, PARK;
    with a friction table also the ends of the step's segment (:func:`_event_bound`). An event that
    can fire (:func:`_near_until`) is scanned on the dense solution (16 samples a period, up to
    where it can fire or the earliest event found so far) for its first sign change, then placed
    by Illinois."""
    rh, rd = free_amplitudes(ec, 1.0)
    best_kind, best_v = -1, 1.0
    for kind in (LOCK, UNPARK, PARK, KNOT, KNOT + 1):
        if kind < KNOT and not (kinds_mask >> kind) & 1:
            continue
        knot, amp = _event_bound(ec, q, kind, rh, rd, rr, ra)
        if math.isnan(knot):
            continue
        v_scan = min(best_v, _near_until(ec, q, kind, knot, amp, rr, ra))
        if v_scan < -1.0:
            continue
        # the scan for the first sign change
        m = scan_count(ec, v_scan, SCAN_PER_PERIOD)
        lo, g_lo = -1.0, node_event_values(ec, kind, 0, q, knot, rr, ra)
        for j in range(1, m + 1):
            v = -1.0 + (v_scan + 1.0) * j / m
            g = event_value(ec, kind, v, q, knot, rr, ra)
            if g <= 0.0:
                best_v = locate(ec, kind, lo, v, g_lo, q, knot, rr, ra)
                best_kind = kind
                break
            lo, g_lo = v, g
    return best_kind, best_v


# ---- peaks ------------------------------------------------------------------------------------

PEAK_POWER, PEAK_TORQUE, PEAK_JERK_ = range(3)  # which peak (:func:`_peak_value`)


@njit(**JIT)
def _peak_value(ec, which, v, q):
    """On the step's solution at v: the slip power D·Δω (dense solution, D interpolated), |D| or
    the |output jerk| (K·θ' + c·θ'')/J_r (dense solution; moving output, T_m constant)."""
    if which == PEAK_TORQUE:
        d, _ = poly_eval(ec.ad, NN, v)
        return abs(d)
    sc = ec.sc[0]
    wm, _, thd, thdd = dense(ec, v, q[K])
    if which == PEAK_JERK_:
        return abs((q[K] * thd + q[CD] * thdd) / q[JR])
    wh = thd if sc.parked else wm + q[JR] / (q[JH] + q[JR]) * thd
    d, _ = poly_eval(ec.ad, NN, v)
    return d * (sc.we - wh)


@njit(**JIT)
def _golden(ec, which, lo, hi, q):
    """Largest value of :func:`_peak_value` on [lo, hi] near its maximum (golden section)."""
    gr = 0.5 * (math.sqrt(5.0) - 1.0)
    x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
    f1, f2 = _peak_value(ec, which, x1, q), _peak_value(ec, which, x2, q)
    for _ in range(GOLDEN_ITER):
        if f1 >= f2:  # the maximum in [lo, x2]
            hi, x2, f2 = x2, x1, f1
            x1 = hi - gr * (hi - lo)
            f1 = _peak_value(ec, which, x1, q)
        else:  # in [x1, hi]
            lo, x1, f1 = x1, x2, f2
            x2 = lo + gr * (hi - lo)
            f2 = _peak_value(ec, which, x2, q)
    return max(f1, f2)


@njit(**JIT)
def _at_points(values, n_in, end_value, i):
    """The value at point i of the step's points (the n_in nodes inside, then v_end); −inf outside."""
    if i < 0 or i > n_in:
        return -np.inf
    return values[i] if i < n_in else end_value


@njit(**JIT)
def _outward(ec, which, v, right_end):
    """Whether the slip power (``which`` PEAK_POWER) or |clutch torque| (PEAK_TORQUE) rises out of
    the step at its end v (right_end) or falls from its start: the largest value next to that
    end is the end's own, already recorded (the slope from the node values' interpolant)."""
    if which == PEAK_POWER:
        _, slope = poly_eval(ec.ap, NN, v)
    else:
        d, dd = poly_eval(ec.ad, NN, v)
        slope = dd if d >= 0.0 else -dd
    return slope > 0.0 if right_end else slope < 0.0


@njit(**JIT)
def _refine(ec, which, values, n_in, v_end, end_value, q, best):
    """The running maximum ``best`` refined by golden section between the neighbours of each of the
    step's points (nodes inside, v_end; the step's ends included) that is a local maximum within
    0.9 of it; not at an end the function rises out of (:func:`_outward`: its value is the
    largest there)."""
    for i in range(n_in + 1):
        x = _at_points(values, n_in, end_value, i)
        left = _at_points(values, n_in, end_value, i - 1)
        right = _at_points(values, n_in, end_value, i + 1)
        if x >= left and x >= right and x >= 0.9 * best:
            if (i == 0 or i == n_in) and _outward(ec, which, -1.0 if i == 0 else v_end, i > 0):
                continue
            lo = NODES[max(i - 1, 0)]
            hi = NODES[i + 1] if i + 1 < n_in else v_end
            if hi > lo:
                best = max(best, _golden(ec, which, lo, hi, q))
    return best


@njit(**JIT)
def _jerk_scan(ec, v_end, q, best):
    """The output jerk oscillates with the free response: where the nodes' largest smooth part plus
    the free response's jerk amplitude reaches 0.9 of the running maximum ``best``, a dense scan
    (JERK_PER_PERIOD samples a period) and golden section around its local maxima. Returns the new maximum."""
    sc = ec.sc[0]
    rh, rd = free_amplitudes(ec, v_end)
    k, c, mo, co, jr = q[K], q[CD], sc.mo, sc.co, q[JR]
    a, w2, h0, h1 = sc.a, sc.w2, sc.h0, sc.h1
    amp = (k * rd + c * (abs(co) * rd + k * rh) / mo) / jr
    # the jerk's smooth part (less the free response's) at the nodes inside: its largest value
    # plus the free part's amplitude bounds the step's jerk
    jn = 0.0
    for i in range(NN):
        if NODES[i] >= v_end:
            break
        cf, sf = ec.cf[i], ec.sf[i]
        hv = h0 * cf + (h1 + a * h0) * sf
        hd = h1 * cf - (a * h1 + (w2 + a * a) * h0) * sf
        jf = (k * hd - c * (co * hd + k * hv) / mo) / jr
        thdd = (ec.fo[i] - co * ec.thd[i] - k * ec.th[i]) / mo
        jn = max(jn, abs((k * ec.thd[i] + c * thdd) / jr - jf))
    if jn + amp < 0.9 * best:
        return best
    # the dense scan: a sample that is a local maximum within 0.9 of the maximum (the step's ends
    # included: a peak just after an event or before the step's end) is refined between its
    # neighbours
    sc.n_scan += 1
    m = scan_count(ec, v_end, JERK_PER_PERIOD)
    dv = (v_end + 1.0) / m
    f_pp, f_p = -np.inf, _peak_value(ec, PEAK_JERK_, -1.0, q)
    for j in range(1, m + 2):
        f = _peak_value(ec, PEAK_JERK_, -1.0 + dv * j, q) if j <= m else -np.inf
        best = max(best, f)
        if f_p >= f_pp and f_p >= f and f_p >= 0.9 * best:
            lo, hi = -1.0 + dv * max(j - 2, 0), -1.0 + dv * min(j, m)
            best = max(best, _golden(ec, PEAK_JERK_, lo, hi, q))
        f_pp, f_p = f_p, f
    return best


@njit(**JIT)
def record_peaks(ec, v_end, q, pk, peaks):
    """Peaks of the step on [−1, v_end] (slip power, |clutch torque|, |output jerk| in pk; without
    ``peaks`` the slip power's only): at the nodes and v_end, refined by golden section around the
    points that are local maxima within 0.9 of the running maximum (:func:`_refine`); the jerk by
    :func:`_jerk_scan`."""
    sc = ec.sc[0]
    moving = not sc.parked
    n_in = 0
    for i in range(NN):
        if NODES[i] < v_end:
            n_in = i + 1
    # the values at the nodes inside and at v_end, refined between them
    for i in range(n_in):
        pk[MAX_POWER] = max(pk[MAX_POWER], ec.p[i])
    pe = _peak_value(ec, PEAK_POWER, v_end, q)
    pk[MAX_POWER] = max(pk[MAX_POWER], pe)
    pk[MAX_POWER] = _refine(ec, PEAK_POWER, ec.p, n_in, v_end, pe, q, pk[MAX_POWER])
    if not peaks:
        return
    for i in range(n_in):  # (ec.tmp2: |torque| at the nodes)
        ec.tmp2[i] = abs(ec.d[i])
        pk[MAX_TORQUE] = max(pk[MAX_TORQUE], ec.tmp2[i])
    de = _peak_value(ec, PEAK_TORQUE, v_end, q)
    pk[MAX_TORQUE] = max(pk[MAX_TORQUE], de)
    pk[MAX_TORQUE] = _refine(ec, PEAK_TORQUE, ec.tmp2, n_in, v_end, de, q, pk[MAX_TORQUE])
    if moving:
        pk[MAX_JERK] = max(pk[MAX_JERK], _peak_value(ec, PEAK_JERK_, v_end, q))
        pk[MAX_JERK] = _jerk_scan(ec, v_end, q, pk[MAX_JERK])


# ---- works and slip power samples --------------------------------------------------------------


@njit(**JIT)
def int_qh(ec, coef, v_end, ta, tb):
    """∫₀^τₑ Q·h dτ (τₑ = τ(v_end)) of a polynomial Q (NN power coefficients in v) times the step's
    free response h, exactly: K·∫Q·h = −m[Q·h'] + m[Q'·h] − c[Q·h] + c∫Q'·h − m∫Q''·h over the
    derivatives of Q (m, c, K of the step's oscillator; ta, tb scratch rows)."""
    sc = ec.sc[0]
    h, a, w2, mo, co = sc.h, sc.a, sc.w2, sc.mo, sc.co
    k = mo * (w2 + a * a)
    sv = 2.0 / h
    h0, h1 = sc.h0, sc.h1
    cf, sf = free_basis(0.5 * h * (1.0 + v_end), a, w2)
    he = h0 * cf + (h1 + a * h0) * sf
    hde = h1 * cf - (a * h1 + (w2 + a * a) * h0) * sf
    taylor_at(coef, NN, -1.0, ta)
    taylor_at(coef, NN, v_end, tb)
    i1 = i2 = 0.0
    fact = 1.0
    for j in range(1, NN):
        fact *= j * sv
    # from the highest derivative down: Q^(j) in τ at the ends = sv^j·j!·taylor_j
    for j in range(NN - 1, -1, -1):
        scale_j = fact
        qa, qb = scale_j * ta[j], scale_j * tb[j]
        if j + 1 < NN:
            s1 = scale_j * (j + 1) * sv
            dqa, dqb = s1 * ta[j + 1], s1 * tb[j + 1]
        else:
            dqa = dqb = 0.0
        ij = (
            -mo * (qb * hde - qa * h1)
            + mo * (dqb * he - dqa * h0)
            - co * (qb * he - qa * h0)
            + co * i1
            - mo * i2
        ) / k
        i2, i1 = i1, ij
        if j > 0:
            fact /= j * sv
    return i1, he, hde


@njit(**JIT)
def int_hd2(ec, v_end, he, hde):
    """∫₀^τₑ h'² dτ of the step's free response: from its energy, −Δ(½m·h'² + ½K·h²)/c, or for a
    (nearly) undamped oscillator from e^(−2aτ)·(cos, sin 2ω_dτ)."""
    sc = ec.sc[0]
    h, a, w2, mo, co = sc.h, sc.a, sc.w2, sc.mo, sc.co
    k = mo * (w2 + a * a)
    tau = 0.5 * h * (1.0 + v_end)
    h0, h1 = sc.h0, sc.h1
    if abs(co) * tau > 1e-3 * mo or w2 <= 0.0:
        e0 = 0.5 * mo * h1 * h1 + 0.5 * k * h0 * h0
        e1 = 0.5 * mo * hde * hde + 0.5 * k * he * he
        return -(e1 - e0) / co
    w = math.sqrt(w2)
    pp = h1
    qq = -(a * h1 + (w2 + a * a) * h0) / w
    z = complex(-2.0 * a, 2.0 * w)
    osc = (np.exp(z * tau) - 1.0) / z
    base = tau if a * tau < 1e-8 else (1.0 - math.exp(-2.0 * a * tau)) / (2.0 * a)
    return (
        0.5 * (pp * pp + qq * qq) * base + 0.5 * (pp * pp - qq * qq) * osc.real + pp * qq * osc.imag
    )


@njit(**JIT)
def _smooth_integral(values, v_end, coef):
    """∫_{−1}^{v_end} dv of the interpolant of the node values ``values`` (``coef`` scratch)."""
    if v_end >= 1.0:
        acc = 0.0
        for i in range(NN):
            acc += CC_WEIGHTS[i] * values[i]
        return acc
    fit(values, coef)
    return integral(coef, v_end)


@njit(**JIT)
def works(ec, v_end, q, y):
    """Add the step's works on [−1, v_end] to y: slip ∫D·Δω, input ∫D·ω_e (held engine), load
    ∫T_m·ω_r, damping ∫c·θ'². The clutch torque D as its interpolant; the free response's share
    (θ' = θ'_p + h') exactly: ∫D·h' = [D·h] − ∫D'·h and ∫θ'_p·h' by :func:`int_qh`, ∫h'² by
    :func:`int_hd2`; the smooth rest by the interpolant of its node values. (A short step whose
    particular solution is a long series, ω₀h < HW_TOPDOWN, resolves the oscillation with its
    nodes: its integrands are interpolated whole.)"""
    sc = ec.sc[0]
    half_h = 0.5 * sc.h
    sv = 1.0 / half_h
    we, tm = sc.we, sc.tm
    c = q[CD]
    parked = sc.parked
    jv = q[JH] + q[JR]
    rr = 1.0 if parked else q[JR] / jv
    ra = q[JH] / jv
    exact = int(sc.nxp) == NN
    a, w2, h0, h1 = sc.a, sc.w2, sc.h0, sc.h1
    w0sq = w2 + a * a
    ta, tb, row = ec.ta, ec.tb, ec.tmp
    # input: ∫D·ω_e
    wi = we * _smooth_integral(ec.d, v_end, ec.tmp2)
    # load: T_m·∫(ω_m − ρ_a·θ') = T_m·(∫ω_m − ρ_a·Δθ) (ω_m smooth)
    wl = 0.0
    if not parked:
        th_end = ec.th[NN - 1]
        if v_end < 1.0:
            _, th_end, _, _ = dense(ec, v_end, q[K])
        wl = tm * (_smooth_integral(ec.wm, v_end, ec.tmp2) - ra * (th_end - ec.th[0]) / half_h)
    if not exact:
        for i in range(NN):
            row[i] = ec.p[i]
        ws = _smooth_integral(row, v_end, ec.tmp2)
        for i in range(NN):
            row[i] = c * ec.thd[i] ** 2
        wd = _smooth_integral(row, v_end, ec.tmp2)
    else:
        # θ'_p at the nodes (θ' less its free part), then the smooth integrands
        for i in range(NN):
            hd = h1 * ec.cf[i] - (a * h1 + w0sq * h0) * ec.sf[i]
            row[i] = ec.d[i] * (we - (ec.wh[i] - rr * hd))
            ec.thdp[i] = ec.thd[i] - hd
        ws = _smooth_integral(row, v_end, ec.tmp2)
        # − ρ·∫D·h' dτ = −ρ·([D·h] − ∫D_τ·h dτ)
        for j in range(NN - 1):
            ec.tmp2[j] = sv * (j + 1) * ec.ad[j + 1]
        ec.tmp2[NN - 1] = 0.0
        for j in range(NN):
            row[j] = ec.tmp2[j]
        idh, he, hde = int_qh(ec, row, v_end, ta, tb)
        d0, _ = poly_eval(ec.ad, NN, -1.0)
        d1, _ = poly_eval(ec.ad, NN, v_end)
        ws -= rr * ((d1 * he - d0 * h0) - idh) / half_h
        # c·∫θ'² = c·(∫θ'_p² + 2·∫θ'_p·h' + ∫h'²), ∫θ'_p·h' = [θ'_p·h] − ∫θ''_p·h
        for i in range(NN):
            row[i] = ec.thdp[i] ** 2
        wd = _smooth_integral(row, v_end, ec.tmp2)
        for j in range(NN - 2):
            row[j] = sv * sv * (j + 2) * (j + 1) * ec.xp[j + 2]
        row[NN - 2] = 0.0
        row[NN - 1] = 0.0
        i_pp, _, _ = int_qh(ec, row, v_end, ta, tb)
        _, dxa = poly_eval(ec.xp, NN, -1.0)
        _, dxb = poly_eval(ec.xp, NN, v_end)
        cross = (sv * dxb * he - sv * dxa * h0) - i_pp
        wd = c * (wd + 2.0 * cross / half_h + int_hd2(ec, v_end, he, hde) / half_h)
    y[WS] += half_h * ws
    y[WI] += half_h * wi
    y[WL] += half_h * wl
    y[WD] += half_h * wd


@njit(**JIT)
def history(ec, v_end, hist, n, dt, t0):
    """Slip power samples on the grid k·dt inside the step's [t₀, t₀ + τ(v_end)) and at its end
    (from the interpolant of the node values)."""
    h = ec.sc[0].h
    t1 = t0 + 0.5 * h * (1.0 + v_end)
    kk = math.floor(t0 / dt) + 1.0
    while kk * dt < t1:
        v = 2.0 * (kk * dt - t0) / h - 1.0
        p, _ = poly_eval(ec.ap, NN, v)
        n = hist_add(hist, n, kk * dt, p)
        kk += 1.0
    p, _ = poly_eval(ec.ap, NN, v_end)
    return hist_add(hist, n, t1, p)
