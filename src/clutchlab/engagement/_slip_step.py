"""One step of the exponential collocation of a slipping phase (compiled, numba): the clutch torque
at the step's nodes iterated to a fixed point, the linear part solved exactly for it.

The method is described in :mod:`clutchlab.engagement._colloc`; the step's arrays and scalars are
its :class:`~clutchlab.engagement._colloc.Colloc` record ``ec`` (scalars ``ec.sc[0]``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._colloc import (
    JIT,
    NN,
    NODES,
    fit,
    free_basis,
    mean_series,
    osc_particular,
    poly_eval,
    poly_nodes,
    tail_error,
)
from ._fade import SOE_LAMBDA, SOE_WEIGHT, face_rise, fade_factor
from ._friction import friction_law
from ._heat_modes import grid_level, level_map, node_decay, weighted_at_nodes
from ._layout import CD, FACE_K, FADE, FTAB, JH, JR, NZ, TH, Z0, E, H, K, R
from ._physics import capacity, load_static

MAXIT = 20  # Picard iterations of a step, at most
ITER_TOL = 0.1  # the iteration stops when D changes by less than ITER_TOL·rtol of its size
EARLY_ITER = 1  # from this iteration on, a step whose torque's interpolation error exceeds …
EARLY_REJECT = 100.0  # … EARLY_REJECT·rtol is rejected without converging


# ---- the linear part: setup and exact solution for given forcing node values ------------------


@njit(**JIT)
def setup(ec, t0, h, gamma, parked, jh, jr, k, c, we, tm, s, q, prof):
    """Node times, the oscillator (mass, damping with γ) and its free-response basis at the nodes,
    the mean mode's β and e^(βv_i). Returns ω₀·h (which particular solution the twist takes)."""
    sc = ec.sc[0]
    jv = jh + jr
    if parked:
        mo = jh
        co = c - gamma
    else:
        mo = jh * jr / jv
        co = c - (jr / jv) ** 2 * gamma
    a = 0.5 * co / mo
    w2 = k / mo - a * a
    sc.h, sc.t0, sc.gamma, sc.a, sc.w2 = h, t0, gamma, a, w2
    sc.mo, sc.co, sc.parked = mo, co, parked
    sc.we, sc.tm, sc.sign = we, tm, s
    beta = 0.0 if parked else 0.5 * gamma * h / jv
    sc.beta = beta
    for i in range(NN):
        tau = 0.5 * h * (1.0 + NODES[i])
        ec.tau[i] = tau
        cf, sf = free_basis(tau, a, w2)
        ec.cf[i] = cf
        ec.sf[i] = sf
        ec.eb[i] = math.exp(beta * NODES[i]) if beta != 0.0 else 1.0
        ec.cap[i] = capacity(t0 + tau, q, prof)
    return math.sqrt(k / mo) * h


@njit(**JIT)
def solve_linear(ec, th0, thd0, wm0, k, hw):
    """The node values of θ, θ' (and ω_m, moving) of the step for the forcing node values in rows
    R_FO (and R_FM): fits them, solves the linear equations exactly (particular solution plus free
    response from the start's θ₀, θ'₀; ω_m = A·e^(βv) + W(v), ω_m(−1) = ω_m₀)."""
    sc = ec.sc[0]
    h, a, w2, mo, co = sc.h, sc.a, sc.w2, sc.mo, sc.co
    sv = 2.0 / h  # d/dτ = sv·d/dv
    fit(ec.fo, ec.ao)
    nxp = osc_particular(ec.ao, mo * sv * sv, co * sv, k, hw, ec.xp)
    sc.nxp = nxp
    x0, dx0 = poly_eval(ec.xp, nxp, -1.0)
    h0 = th0 - x0
    h1 = thd0 - sv * dx0
    sc.h0, sc.h1 = h0, h1
    w0sq = w2 + a * a
    poly_nodes(ec.xp, nxp, ec.th, ec.thd)
    for i in range(NN):
        cf, sf = ec.cf[i], ec.sf[i]
        ec.th[i] = ec.th[i] + h0 * cf + (h1 + a * h0) * sf
        ec.thd[i] = sv * ec.thd[i] + h1 * cf - (a * h1 + w0sq * h0) * sf
    if sc.parked:
        for i in range(NN):
            ec.wm[i] = 0.0
        return
    fit(ec.fm, ec.am)
    beta = sc.beta
    nws = mean_series(ec.am, beta, 0.5 * h, ec.wser)
    sc.nws = nws
    w_lo, _ = poly_eval(ec.wser, nws, -1.0)
    amp = (wm0 - w_lo) * (math.exp(beta) if beta != 0.0 else 1.0)
    sc.amp = amp
    poly_nodes(ec.wser, nws, ec.wm, ec.tmp)
    for i in range(NN):
        ec.wm[i] = amp * ec.eb[i] + ec.wm[i]


@njit(**JIT)
def dense(ec, v, k):
    """(ω_m, θ, θ', θ'') of the step's solution at v ∈ [−1, 1] (ω_m = 0 parked); θ'' from the twist
    equation with the interpolated forcing."""
    sc = ec.sc[0]
    h, a, w2, mo, co = sc.h, sc.a, sc.w2, sc.mo, sc.co
    sv = 2.0 / h
    tau = 0.5 * h * (1.0 + v)
    x, dx = poly_eval(ec.xp, int(sc.nxp), v)
    cf, sf = free_basis(tau, a, w2)
    h0, h1 = sc.h0, sc.h1
    th = x + h0 * cf + (h1 + a * h0) * sf
    thd = sv * dx + h1 * cf - (a * h1 + (w2 + a * a) * h0) * sf
    fo, _ = poly_eval(ec.ao, NN, v)
    thdd = (fo - co * thd - k * th) / mo
    wm = 0.0
    if not sc.parked:
        w, _ = poly_eval(ec.wser, int(sc.nws), v)
        beta = sc.beta
        wm = sc.amp * (math.exp(beta * v) if beta != 0.0 else 1.0) + w
    return wm, th, thd, thdd


@njit(**JIT)
def node_state(ec, i, parked, rr):
    """Hub speed at node i (rr = ρ_r)."""
    if parked:
        return ec.thd[i]
    return ec.wm[i] + rr * ec.thd[i]


@njit(**JIT)
def forcings(ec, jh, jr):
    """The forcing node values (rows R_FO, R_FM) from the clutch torque and the node states:
    moving F_o = ρ_r·D − ρ_r²·γ·θ' + ρ_a·T_m, F_m = (D − γ·ω_m − T_m)/J_v; parked F_o = D − γ·θ'."""
    sc = ec.sc[0]
    gamma, tm = sc.gamma, sc.tm
    if sc.parked:
        for i in range(NN):
            ec.fo[i] = ec.d[i] - gamma * ec.thd[i]
        return
    jv = jh + jr
    rr, ra = jr / jv, jh / jv
    for i in range(NN):
        d = ec.d[i]
        ec.fo[i] = rr * d - rr * rr * gamma * ec.thd[i] + ra * tm
        ec.fm[i] = (d - gamma * ec.wm[i] - tm) / jv


# ---- the friction law at the nodes, the fixed-point map and its mixing ---------------------


@njit(**JIT)
def law(t, slip, q, prof, s, rise_slow, sc, c_t):
    """(D, g, ΔT, df/d|Δω|) of the slipping clutch: D = s·f·g·C(t) with the slip law f
    (:func:`friction_law`; a friction table as the line of the step's segment, sc[S_XLO…S_SLOPE], in
    s·Δω: smooth across the segment's ends and through zero slip, so that a step that reaches a
    table point or lock-up has a smooth forcing up to its event); with fade (q[FADE] > 0) g and the
    face temperature rise ΔT from its slow part ``rise_slow`` (:func:`fade_factor`); c_t = C(t)."""
    if q[FTAB] > 0.0:
        dfdv = sc.slope
        f = sc.f_lo + dfdv * (s * slip - sc.x_lo) if dfdv != 0.0 else sc.f_lo
    else:
        f, dfdv = friction_law(slip, q)
    g, rise = 1.0, 0.0
    if q[FADE] > 0.0:
        g, rise = fade_factor(rise_slow, s * f * c_t * slip, q)
    return s * f * g * c_t, g, rise, dfdv


@njit(**JIT)
def table_segment(q, a, rising, sc):
    """Set the friction table's segment of the step (fields of the step record sc) for s·Δω = a: the one containing
    it, or at a table point the one it moves into (``rising``); none beyond the ends (constant)."""
    base = int(q[FTAB])
    n = int(q[base])
    x0, y0 = base + 1, base + 1 + n
    j = -1  # segment [x_j, x_{j+1}]; -1 below the first point, n - 1 above the last
    for i in range(n):
        xi = q[x0 + i]
        if a > xi or (a == xi and rising):
            j = i
    if j < 0:
        sc.x_lo, sc.x_hi, sc.f_lo, sc.slope = -np.inf, q[x0], q[y0], 0.0
    elif j >= n - 1:
        sc.x_lo, sc.x_hi, sc.f_lo, sc.slope = q[x0 + n - 1], np.inf, q[y0 + n - 1], 0.0
    else:
        xl, xh = q[x0 + j], q[x0 + j + 1]
        sc.x_lo, sc.x_hi, sc.f_lo = xl, xh, q[y0 + j]
        sc.slope = (q[y0 + j + 1] - q[y0 + j]) / (xh - xl)


@njit(**JIT)
def node_torques(ec, q, prof, rr):
    """The law's clutch torque at the nodes' hub speeds (row R_GNEW; R_WH, R_G, R_RISE); returns the
    largest change against the torque the solution was computed with (row R_D; NaN propagates)."""
    sc = ec.sc[0]
    parked = sc.parked
    we, s, t0 = sc.we, sc.sign, sc.t0
    fade = q[FADE] > 0.0
    change = 0.0
    for i in range(NN):
        wh = node_state(ec, i, parked, rr)
        ec.wh[i] = wh
        slow = ec.slow[i] if fade else 0.0
        d, g, rise, _ = law(t0 + ec.tau[i], we - wh, q, prof, s, slow, sc, ec.cap[i])
        ec.gnew[i] = d
        ec.g[i] = g
        ec.rise[i] = rise
        dd = abs(d - ec.d[i])
        if not dd <= change:  # (a NaN propagates)
            change = dd
    return change


@njit(**JIT)
def mix(ec, it):
    """The next torque iterate (row R_D) from the map's value G (R_GNEW): Anderson mixing of depth
    one, x ← G − θ·(G − G_prev) with θ minimising the combined residual (G − x), from the second
    iteration on (Walker & Ni, SIAM J. Numer. Anal. 49, 2011)."""
    num = 0.0
    den = 0.0
    if it > 0:
        for i in range(NN):
            f = ec.gnew[i] - ec.d[i]
            df = f - ec.fprev[i]
            num += df * f
            den += df * df
    theta = num / den if den > 0.0 else 0.0
    for i in range(NN):
        g = ec.gnew[i]
        ec.fprev[i] = g - ec.d[i]
        ec.d[i] = g - theta * (g - ec.gprev[i])
        ec.gprev[i] = g


@njit(**JIT)
def heat_setup(ec, h):
    """Fade: the face temperature's modes over the step h [s]: on the step grid their maps (the
    batch's, built on first use: :func:`clutchlab.engagement._heat_modes.level_map`) and their
    weighted free decay from the start's modes at the nodes (row ``zfree``); off it their decay
    at the nodes for :func:`clutchlab.engagement._heat_modes.weighted_at_nodes`."""
    sc = ec.sc[0]
    level = grid_level(h)
    sc.level = level
    if level < 0:
        node_decay(SOE_LAMBDA, h, NODES, ec.enode)
        return
    if ec.fset[level] == 0.0:
        for k in range(NZ):
            ec.tmp2[k] = 0.0
        scratch = (ec.enode, ec.ta, ec.tb, ec.tmp2, ec.comb, ec.htmp)
        maps = (ec.fmap[level], ec.fdec[level], ec.fend[level])
        level_map(SOE_LAMBDA, SOE_WEIGHT, h, NODES, *scratch, *maps)
        ec.fset[level] = 1.0
    for i in range(NN):
        acc = 0.0
        for k in range(NZ):
            acc += ec.fdec[level, k, i] * ec.modes[k]
        ec.zfree[i] = acc


@njit(**JIT)
def face_rise_nodes(ec, q, rr):
    """Fade: the face temperature's slow part K·Σ w_k·z_k at the nodes (row R_TMP) for the slip
    power of the current iterate (clutch torque R_D times the solution's slip), its modes solved
    exactly for that power's interpolant: on the step grid by the step's maps
    (:func:`heat_setup`), else mode by mode (:mod:`clutchlab._heat_modes`)."""
    sc = ec.sc[0]
    parked = sc.parked
    we = sc.we
    for i in range(NN):
        ec.p[i] = ec.d[i] * (we - node_state(ec, i, parked, rr))
    fit(ec.p, ec.ap)
    level = sc.level
    if level >= 0:
        for i in range(NN):
            acc = ec.zfree[i]
            for j in range(NN):
                acc += ec.fmap[level, i, j] * ec.ap[j]
            ec.slow[i] = q[FACE_K] * acc
        return
    weighted_at_nodes(
        SOE_LAMBDA,
        SOE_WEIGHT,
        ec.modes,
        ec.ap,
        NN,
        sc.h,
        NODES,
        ec.enode,
        ec.slow,
        ec.comb,
        ec.htmp,
    )
    for i in range(NN):
        ec.slow[i] *= q[FACE_K]


# ---- the step: start, first guess, Picard iteration ------------------------------------------


@njit(**JIT)
def start(ec, q, prof, t0, y, parked, s):
    """The step's start: the friction table's segment (the one the slip is in, or moves into by the
    hub's acceleration), the clutch torque D₀ there and γ = ∂D/∂ω_h = −g·C·df/d|Δω| (s·Δω > 0).
    Returns (D₀, γ, the face temperature's slow part)."""
    jh, k, c = q[JH], q[K], q[CD]
    we, wh0 = y[E], y[H]
    thd0 = wh0 - (0.0 if parked else y[R])
    slow0 = face_rise(y, q) if q[FADE] > 0.0 else 0.0
    c0 = capacity(t0, q, prof)
    sc = ec.sc[0]
    if q[FTAB] > 0.0:
        f0, _ = friction_law(we - wh0, q)
        g0 = 1.0
        if q[FADE] > 0.0:
            g0, _ = fade_factor(slow0, s * f0 * c0 * (we - wh0), q)
        dwh = (s * f0 * g0 * c0 - k * y[TH] - c * thd0) / jh
        table_segment(q, s * (we - wh0), -s * dwh > 0.0, sc)
    d0, g0, _, dfdv0 = law(t0, we - wh0, q, prof, s, slow0, sc, c0)
    return d0, -dfdv0 * g0 * c0, slow0


@njit(**JIT)
def _slow_rate(ec, q, p0):
    """Fade: the rate of the face temperature's slow part at the step's start [K/s],
    K·Σ w_k·(P₀ − λ_k·z_k) under the slip power P₀ [W] there (0 without fade)."""
    if not q[FADE] > 0.0:
        return 0.0
    acc = 0.0
    for m in range(NZ):
        acc += SOE_WEIGHT[m] * (p0 - SOE_LAMBDA[m] * ec.modes[m])
    return q[FACE_K] * acc


@njit(**JIT)
def predict(ec, q, d0, slow0, th0, thd0, wm0, parked):
    """First node values: the hub speed along its rate at the start (the mean speed along its own,
    the twist rate taking the rest), D₀, and the face temperature's slow part along its rate at
    the start (fade)."""
    jh, jr, k, c = q[JH], q[JR], q[K], q[CD]
    jv = jh + jr
    sc = ec.sc[0]
    tm = sc.tm
    dwh0 = (d0 - k * th0 - c * thd0) / jh
    dwm0 = 0.0 if parked else (d0 - tm) / jv
    wh0 = thd0 if parked else wm0 + jr / jv * thd0
    dslow0 = _slow_rate(ec, q, d0 * (sc.we - wh0))
    for i in range(NN):
        tau = ec.tau[i]
        if parked:
            ec.thd[i] = thd0 + dwh0 * tau
            ec.wm[i] = 0.0
        else:
            ec.thd[i] = thd0 + (dwh0 - dwm0) * tau * jv / jr
            ec.wm[i] = wm0 + dwm0 * tau
        ec.d[i] = d0
        ec.slow[i] = slow0 + dslow0 * tau


@njit(**JIT)
def step(ec, q, prof, t0, h, y, parked, s, rtol):
    """One step of size h from the state y at t0 (held engine, slipping): Picard iteration (with
    Anderson mixing) to a fixed point of the clutch torque at the nodes. Returns (whether the
    error estimate holds: converged, or far above the tolerance from the second iteration on —
    EARLY_REJECT —; the error estimate relative to the forcing's size); a converged solution is
    then in ec for :func:`dense` and the node rows."""
    # the state at the step's start: twist, its rate and the mean speed
    jh, jr, k, c = q[JH], q[JR], q[K], q[CD]
    jv = jh + jr
    rr = jr / jv
    we, wh0 = y[E], y[H]
    wr0 = 0.0 if parked else y[R]
    th0, thd0 = y[TH], wh0 - wr0
    wm0 = (jh * wh0 + jr * wr0) / jv
    # the torque and its frozen slope γ there, the nodes and the oscillator with γ
    d0, gamma, slow0 = start(ec, q, prof, t0, y, parked, s)
    hw = setup(ec, t0, h, gamma, parked, jh, jr, k, c, we, load_static(t0, q), s, q, prof)
    # with fade the face temperature's modes at the start and over the step
    fade = q[FADE] > 0.0
    if fade:
        for m in range(NZ):
            ec.modes[m] = y[Z0 + m]
        heat_setup(ec, h)
    # the first guess: the hub speed along its start's rate, the law's torque for it
    predict(ec, q, d0, slow0, th0, thd0, wm0, parked)
    node_torques(ec, q, prof, rr)
    for i in range(NN):
        ec.d[i] = ec.gnew[i]
    converged = False
    scale = 1e-300
    # Picard: the linear part solved for the torque's node values, the law's torque for its
    # solution, until the torque changes by less than ITER_TOL·rtol (Anderson mixing)
    ec.sc[0].iters = MAXIT
    for it in range(MAXIT):
        forcings(ec, jh, jr)
        solve_linear(ec, th0, thd0, wm0, k, hw)
        if fade:
            face_rise_nodes(ec, q, rr)
        change = node_torques(ec, q, prof, rr)
        scale = 1e-300
        for i in range(NN):
            scale = max(scale, abs(ec.gnew[i]))
        if change <= ITER_TOL * rtol * scale:
            converged = True
            ec.sc[0].iters = it + 1
            break
        # a step far too long for its forcing is rejected without converging
        if it >= EARLY_ITER:
            early = tail_error(ec.gnew) / scale
            if early > EARLY_REJECT * rtol:
                ec.sc[0].iters = it + 1
                return True, early
        mix(ec, it)
    if not converged:
        return False, np.inf
    # the error estimate: the forcings' last Chebyshev coefficients, relative to their size
    err = tail_error(ec.d) / scale
    fo_scale = 1e-300
    for i in range(NN):
        fo_scale = max(fo_scale, abs(ec.fo[i]))
    err = max(err, tail_error(ec.fo) / fo_scale)
    if not parked:
        err = max(err, tail_error(ec.fm) * jv / scale)
    return True, err
