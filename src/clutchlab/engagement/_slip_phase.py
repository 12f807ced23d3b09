"""The slipping phases solved by exponential collocation (compiled, numba): the step loop of a phase.

A slipping phase of the compliant model with a held engine, no rotor drag and a nonlinear friction
law (a Stribeck law, a friction table) or friction fade (:func:`applies`) is advanced here instead
of by DOPRI5 (a Stribeck law's part above :func:`constant_slip`, where it is μ_k exactly, by the
exact linear phase): steps of :mod:`clutchlab.engagement._slip_step` (the method is described in
:mod:`clutchlab.engagement._colloc`), each accepted step's events, peaks, works and slip power
samples by :mod:`clutchlab.engagement._slip_records`, the friction face's temperature modes
exactly over it (:mod:`clutchlab.engagement._heat_modes`). The driver
(:mod:`clutchlab.engagement._driver`) calls :func:`segment` with its scenario record and switches
the mode at the event returned.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._colloc import JIT, NDEG, NN, fit
from ._fade import SOE_LAMBDA
from ._heat_modes import advance, grid_step
from ._layout import (
    FADE,
    FTAB,
    HELD,
    JH,
    JR,
    KA,
    LOCK,
    NZ,
    OUT_OF_WORK,
    PARK,
    RS,
    TH,
    UNPARK,
    VS,
    Z0,
    E,
    H,
    K,
    R,
)
from ._power import slip_spacing
from ._slip_records import KNOT, first_event, history, record_peaks, works
from ._slip_step import dense, step

ERR_FACTOR = 1.0  # a step is accepted when its forcing's interpolation error is ≤ ERR_FACTOR·rtol
HMAX_PERIODS = 3.5  # longest step, in periods of the twist's oscillation (its nodes resolve it)
BETA_MAX = 2.0  # largest |κ·h/2| of the mean mode (its power series)
FIRST_STEP_PERIODS = 1.0  # a scenario's first step, in periods of the twist's oscillation
SLIP_SCALES = 1.0  # Stribeck: a step's slip change at most this many v_s (see _slip_limit)


@njit(**JIT)
def applies(q, locked):
    """Whether a phase of the compliant model is solved here: slipping with a held engine, no rotor
    drag, a finite damper spring, and a nonlinear friction law (Stribeck, table) or fade."""
    return (
        not locked
        and q[HELD] > 0.0
        and q[KA] == 0.0
        and math.isfinite(q[K])
        and q[K] > 0.0
        and (math.isfinite(q[VS]) or q[FTAB] > 0.0 or q[FADE] > 0.0)
    )


@njit(**JIT)
def constant_slip(q):
    """The slip s·Δω [rad/s] above which a Stribeck law is μ_k exactly in double precision, its
    term |μ_s/μ_k − 1|·e^(−(Δω/v_s)²) below 2⁻⁵⁴/e (1 + it rounds to 1): there a slipping phase
    of the compliant model is linear and is solved exactly by the driver
    (:func:`clutchlab.engagement._linear_phase.linear_segment`, its lock-up form moved to this
    slip), here only below it. 0 for μ_s = μ_k (constant everywhere); inf without a Stribeck law,
    with a friction table or fade (never linear)."""
    if not math.isfinite(q[VS]) or q[FTAB] > 0.0 or q[FADE] > 0.0:
        return np.inf
    r = abs(q[RS] - 1.0)
    if r == 0.0:
        return 0.0
    return abs(q[VS]) * math.sqrt(max(math.log(r) + 54.0 * math.log(2.0) + 1.0, 0.0))


@njit(**JIT)
def _period(q, parked):
    """The period of the twist's oscillation [s] (hub against the parked output or the moving one)."""
    jh, jr = q[JH], q[JR]
    mo = jh if parked else jh * jr / (jh + jr)
    return 2.0 * math.pi / math.sqrt(q[K] / mo)


@njit(**JIT)
def _retry(ec, ok, err, h_try, tol):
    """The shorter step to retry with, or 0 if the step is accepted: a step whose iteration did not
    converge, or whose mean mode's |β| exceeds BETA_MAX, is halved (at most to BETA_MAX); one whose
    error exceeds tol shrinks by (tol/err)^0.2 (near events and regime changes the error falls more
    slowly than the degree says), between 0.2 and 0.9 times."""
    beta = abs(ec.sc[0].beta)
    if not ok or beta > BETA_MAX:
        h = 0.5 * h_try
        if beta > BETA_MAX:
            h = min(h, 0.9 * h_try * BETA_MAX / beta)
        return h
    if err > tol:
        return h_try * max(0.2, min(0.9, 0.9 * (tol / err) ** 0.2))
    return 0.0


@njit(**JIT)
def _next_step(ec, h_try, err, tol):
    """The step the controller proposes after an accepted one: from the error's decay with the
    degree, between 0.3 and 2 times (1.3 after a slowly converging iteration: the forcing is
    changing fast)."""
    grow = 2.0 if ec.sc[0].iters <= 5 else 1.3
    return h_try * min(grow, max(0.3, 0.9 * (tol / max(err, 1e-300)) ** (1.0 / (NDEG - 1))))


@njit(**JIT)
def _slip_limit(q, rate):
    """The longest step [s] over which a Stribeck law's slip changes by SLIP_SCALES·v_s at the mean
    slip rate ``rate`` [rad/s²] of the last accepted step (inf without a rate or a Stribeck law):
    the law varies on the scale v_s, so a longer step near lock-up is rejected (its error grew
    10⁸-fold with one doubling), and each rejection costs an attempt."""
    if not (rate > 0.0 and math.isfinite(q[VS]) and q[FTAB] == 0.0):
        return np.inf
    return SLIP_SCALES * abs(q[VS]) / rate


@njit(**JIT)
def _advance_state(ec, v_end, q, y):
    """The state at v_end of the accepted step (hub, output, twist)."""
    if v_end >= 1.0:
        wm, th, thd = ec.wm[NN - 1], ec.th[NN - 1], ec.thd[NN - 1]
    else:
        wm, th, thd, _ = dense(ec, v_end, q[K])
    jv = q[JH] + q[JR]
    if ec.sc[0].parked:
        y[H] = thd
    else:
        y[H] = wm + q[JR] / jv * thd
        y[R] = wm - q[JH] / jv * thd
    y[TH] = th


@njit(**JIT)
def _advance_modes(ec, h, v_end):
    """The face temperature's modes at v_end of the accepted step h [s] for its slip power (power
    coefficients ``ap``): over a whole step of the grid by its map, else mode by mode."""
    level = ec.sc[0].level
    if v_end < 1.0 or level < 0:
        advance(SOE_LAMBDA, ec.modes, ec.ap, NN, h, v_end, ec.modes, ec.htmp)
        return
    for k in range(NZ):
        acc = ec.fend[level, k, NN] * ec.modes[k]
        for j in range(NN):
            acc += ec.fend[level, k, j] * ec.ap[j]
        ec.modes[k] = acc


@njit(**JIT)
def _accept(ec, h_try, t_b, q, opts, w, hist, sc):
    """Take the accepted step [sc.t, sc.t + h_try] up to its first event: the peaks, power samples,
    works, the state and the face temperature's modes there; sc.t the new time. Returns the event's
    kind (−1: none)."""
    t = sc.t
    mask = (1 << LOCK) | ((1 << UNPARK) if sc.parked else (1 << PARK))
    jv = q[JH] + q[JR]
    # the first event on the step's dense solution (its forcing is smooth up to and past it)
    kind, v_e = first_event(ec, q, mask, q[JR] / jv, q[JH] / jv)
    v_end = v_e if kind >= 0 else 1.0
    t_new = t + 0.5 * h_try * (1.0 + v_end)
    if v_end >= 1.0 and h_try == t_b - t:
        t_new = t_b
    # its records up to there
    record_peaks(ec, v_end, q, w.pk, opts.peaks)
    if opts.with_hist and not sc.past:
        spacing = slip_spacing(sc.dt_s, sc.t_slip, t_new)
        sc.n_hist = history(ec, v_end, hist, sc.n_hist, spacing, t)
    works(ec, v_end, q, w.y)
    _advance_state(ec, v_end, q, w.y)
    # the face temperature's modes, exactly for the step's slip power
    if q[FADE] > 0.0:
        _advance_modes(ec, h_try, v_end)
        for m in range(NZ):
            w.y[Z0 + m] = ec.modes[m]
    sc.t = t_new
    return kind


@njit(**JIT)
def segment(ec, t_b, q, prof, opts, w, hist, sc, budget):
    """Advance a slipping phase (:func:`applies`) from sc.t to its first event in (sc.t, t_b] or to
    t_b, in at most ``budget`` step attempts. Returns (event kind, −1 or OUT_OF_WORK; step attempts;
    steps accepted; steps rejected); sc.t and w.y (works and face temperature modes included) are
    there, w.pk holds the peaks inside, sc.n_hist the power samples. The step the controller
    proposes carries over between calls in ec.sc[0].h_next (0: none yet)."""
    st = ec.sc[0]
    period = _period(q, sc.parked)
    tol = ERR_FACTOR * opts.rtol
    h = st.h_next if st.h_next > 0.0 else FIRST_STEP_PERIODS * period
    used = n_acc = n_rej = 0
    rate = 0.0  # the mean slip rate of the last accepted step [rad/s²] (0: none yet)
    kind = -1
    while sc.t < t_b:
        if used >= budget:
            kind = OUT_OF_WORK
            break
        # the step: at most HMAX_PERIODS periods, cut at the breakpoint; with fade on the step
        # grid, whose face temperature maps the batch keeps (:func:`_slip_step.heat_setup`)
        h_try = min(h, HMAX_PERIODS * period, _slip_limit(q, rate))
        clipped = h_try >= t_b - sc.t
        if clipped:
            h_try = t_b - sc.t
        elif q[FADE] > 0.0:
            h_try = grid_step(h_try)
        ok, err = step(ec, q, prof, sc.t, h_try, w.y, sc.parked, sc.sign, opts.rtol)
        used += 1
        # the slip power and torque interpolants (the records and the error control use them)
        for i in range(NN):
            ec.p[i] = ec.d[i] * (st.we - ec.wh[i])
        fit(ec.p, ec.ap)
        fit(ec.d, ec.ad)
        h_retry = _retry(ec, ok, err, h_try, tol)
        if h_retry > 0.0:
            n_rej += 1
            h = h_retry
            continue
        # accepted (a step cut short by the breakpoint says little about the next one: the
        # proposal is kept)
        h_next = _next_step(ec, h_try, err, tol)
        t_acc, slip0 = sc.t, w.y[E] - w.y[H]
        kind = _accept(ec, h_try, t_b, q, opts, w, hist, sc)
        if sc.t > t_acc:
            rate = abs(w.y[E] - w.y[H] - slip0) / (sc.t - t_acc)
        n_acc += 1
        h = max(h_next, h) if clipped else h_next
        if 0 <= kind < KNOT:
            break
        kind = -1  # (a friction table point: the next step takes the next segment)
    st.h_next = h
    return kind, used, n_acc, n_rej
