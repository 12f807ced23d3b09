"""Compiled drivers of the stiff-contact systems: the Hertz impact and the roller clutch's wedging.

The roller's wedging (:func:`simulate_roller`, one scenario after another) is integrated step by
step with, at each step, the cheaper method that is stable there:

* DOP853 (:mod:`clutchlab._dop853`: explicit, order 8, 12 right-hand sides a step, no Jacobian)
  wherever the step h the error control asks for is stable explicitly, h·r ≤
  :data:`STIFF_LIMIT` with r the decay rate of the contact's fastest decaying mode, in closed
  form from the two eigenvalues of the contact's (δ, δ̇) dynamics
  (:func:`clutchlab._contact_systems.contact_rates`). On the studies' designs this is nearly
  every step: the slip's exponential build-up of the wedging force and the stick phase's
  overdamped impact are smooth and not stiff, and an order-8 method crosses them in a fifth of
  the steps an order-4 one takes.
* the L-stable SDIRK4 (:mod:`clutchlab._sdirk4`, analytic Jacobian) where the step would not be
  stable explicitly: a stiff contact (heavy damping on a light ring) once its fast transient has
  decayed and the error control asks for steps far beyond it.

Events (:mod:`clutchlab._contact_events`): the switching events (stick, breakaway, stop, release)
end the step at their time; the recording events (the engagement speed reached, force peaks)
are located inside the step without cutting it. The clock's breaks (the control ring stopped,
the claws at the rollers, the end) end a step too. The driver's scalars are the named fields of
a :data:`DRIVER` record, its arrays the named fields of a :data:`Work`; the results are a
row of named columns (:data:`RESULTS`).
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

from . import _contact_events as _ev
from . import _dop853, _sdirk4
from ._contact_events import EVENT_TIME_TOL, EXPLICIT, IMPLICIT
from ._contact_systems import (
    CLAWS,
    EV_MAX_PENETRATION,
    EV_PEAK,
    EV_RELEASE,
    EV_SEPARATION,
    EV_STICK,
    EV_SYNC,
    HMAX,
    IMPACT,
    JIT,
    RC,
    ROLLER,
    STICK,
    SWITCHING,
    TCLAW,
    TEND,
    TREL,
    WD,
    Y_DRIVEN,
    Y_SLIP,
    Y_TRAVEL,
    Y_WEDGE,
    initial_mode,
    next_break,
    point_values,
    rhs,
    roller_contact,
    switch_mode,
    switching_active,
)

# an explicit step is taken where h·r ≤ this (r: contact_rates), inside DOP853's stability radius
# (6.2) with a margin: at 4.0 the engagement time in the slow approach to the engagement speed was
# 10x less accurate (3e-5 against 3e-6 relative at rtol 1e-8)
STIFF_LIMIT = 3.0
# explicit attempts cut to the stability limit in a row after which the implicit method takes over
STIFF_AFTER = 3
# the relative tolerance of each phase, in units of the scenario's rtol, by the stored outputs it
# still sets: the stick phase before the engagement sets the engagement time, the most sensitive
# of them (its error against Radau at rtol 1e-12 is ~300·rtol: the driven ring creeps up to the
# engagement speed); the wedge ring's slip sets the stick time and the backlash, and the phase
# after the engagement the release time, which at these factors stay below that (measured on
# 400 designs of config/million.yaml and the default grid at rtol 1e-8: engagement time 3.2e-6,
# the others at most 2.2e-6; 16 % fewer steps than at one tolerance)
SLIP_RTOL_FACTOR = 10.0
ENGAGED_RTOL_FACTOR = 30.0
# a phase's tolerance is loosened up to this at most (never beyond the scenario's rtol)
LOOSEST_RTOL = 1e-3
# roller result columns
(
    STICK_TIME,
    SLIP_BACKLASH,
    SYNC_TIME,
    TOTAL_BACKLASH,
    PEAK_FORCE,
    RELEASE_TIME,
    FINAL_FORCE,
    N_STEPS,
    N_FEV,
    N_REJECTED,
    N_NEWTON_FAIL,
    N_IMPLICIT,
    STATUS,
) = range(13)
RESULTS = (
    "stick_time",
    "slip_backlash",
    "engagement_time",
    "backlash",
    "peak_contact_force",
    "release_time",
    "final_contact_force",
    "n_steps",
    "n_fev",
    "n_rejected",
    "n_newton_fail",
    "n_implicit",
    "status",
)
ST_OK, ST_NEVER, ST_FAIL = 0, 4, 6  # clutchlab.status codes: ok, never_locked, not_converged
ST_RUNNING = -1
# trace columns: time, driving, wedge and driven ring speeds, contact force per roller
N_TRACE_COLUMNS = 5

#: the roller driver's scalars: time t, next step size h, the current step's size h_step, its
#: piece still looked at h_piece (cut by a switching event), the piece's end t_end and the step's
#: error norm err; the mode, the
#: method of the current step, the status; flags (0/1): engaged (synced), ``dp.k[0]`` holds f at
#: (t, y) (fsal), the step's continuous extension is computed (dense), the last attempt was
#: rejected (after_reject), the implicit method in use (stiff); counters: accepted, rejected and
#: failed steps, implicit steps, f evals, explicit attempts in a row cut to the stability limit
#: (capped); at (t, y) and at the piece's end: the contact force, the contact's decay and growth
#: rates (:func:`clutchlab._contact_systems.contact_rates`)
DRIVER = np.dtype(
    [
        ("t", "f8"),
        ("h", "f8"),
        ("h_step", "f8"),
        ("h_piece", "f8"),
        ("t_end", "f8"),
        ("err", "f8"),
        ("mode", "i8"),
        ("method", "i8"),
        ("status", "i8"),
        ("synced", "i8"),
        ("fsal", "i8"),
        ("dense", "i8"),
        ("after_reject", "i8"),
        ("steps", "i8"),
        ("rejected", "i8"),
        ("failed", "i8"),
        ("implicit", "i8"),
        ("nfev", "i8"),
        ("stiff", "i8"),
        ("capped", "i8"),
        ("force", "f8"),
        ("decay", "f8"),
        ("growth", "f8"),
        ("force_end", "f8"),
        ("decay_end", "f8"),
        ("growth_end", "f8"),
    ]
)
#: a driver's arrays: the state y, a step's end y_new, an event's state y_ev, the absolute
#: tolerances atol, and the workspaces of DOP853 (dp), SDIRK4 (sd) and event location (ev)
Work = namedtuple("Work", ["y", "y_new", "y_ev", "atol", "dp", "sd", "ev"])


@njit(**JIT)
def _copy(src, dst):
    """dst[:] = src (without the temporary copy numba's slice assignment makes)."""
    for i in range(src.size):
        dst[i] = src[i]


@njit(cache=True, error_model="numpy")
def _work(atol):
    """A driver's arrays for a system of size atol.size."""
    n = atol.size
    return Work(
        np.zeros(n), np.zeros(n), np.zeros(n), atol, _dop853.work(n), _sdirk4.work(n), _ev.work(n)
    )


# ----------------------------------------------------------------------------------- impact
@njit(cache=True, error_model="numpy")
def impact(p, v, rtol, atol, h0, max_steps):
    """Hertz impact of a mass on a wall at speed v, by SDIRK4 steps: (max penetration, its time,
    contact time, restitution, f evals). At most ``max_steps`` step attempts (accepted, rejected
    or failed): NaN results beyond."""
    w = _work(atol)
    w.y[1] = v
    t, h = 0.0, h0
    dmax_pen, t_max = 0.0, 0.0
    nfev = 0
    for _ in range(max_steps):
        ok, err, nf = _sdirk4.step(IMPACT, t, w.y, h, p, 0, rtol, atol, w.y_new, w.sd)
        nfev += nf
        if not ok or err > 1.0:
            h = 0.25 * h if not ok else _sdirk4.new_step(h, err)
            continue
        # the step's Hermite data for the events' first guesses
        _copy(w.sd.f0, w.ev.f0)
        _copy(w.sd.f1, w.ev.f1)
        _copy(w.y_new, w.ev.y_end)
        tol = EVENT_TIME_TOL * max(t / 1e-3, 1e-3)
        # the maximum penetration: the rate falls through zero
        if w.y[1] > 0.0 and w.y_new[1] <= 0.0:
            hx, nf = _ev.locate(
                IMPACT, EV_MAX_PENETRATION, IMPLICIT, t, w.y, h, h, w.y[1], w.y_new[1], p, 0,
                rtol, atol, w.y_ev, w, tol,
            )  # fmt: skip
            nfev += nf
            dmax_pen, t_max = w.y_ev[0], t + hx
        # the separation ends the impact
        if w.y_new[0] <= 0.0 and t > 0.0:
            hx, nf = _ev.locate(
                IMPACT, EV_SEPARATION, IMPLICIT, t, w.y, h, h, w.y[0], w.y_new[0], p, 0,
                rtol, atol, w.y_ev, w, tol,
            )  # fmt: skip
            nfev += nf
            return dmax_pen, t_max, t + hx, -w.y_ev[1] / v, nfev
        t += h
        _copy(w.y_new, w.y)
        h = _sdirk4.new_step(h, err)
    return np.nan, np.nan, np.nan, np.nan, nfev


# ----------------------------------------------------------------------------------- roller
@njit(**JIT)
def _start(p, s, w, res):
    """A scenario's start: the state at rest, the initial mode and step, the results' defaults,
    and everything at the first point."""
    for i in range(w.y.size):
        w.y[i] = 0.0
    w.sd.eta[0] = 0.0  # the Newton convergence factor of the implicit steps
    s.mode, s.h, s.status = initial_mode(p), min(1e-8, p[HMAX]), ST_RUNNING
    for k in range(N_STEPS):
        res[k] = np.nan
    res[PEAK_FORCE] = 0.0
    _refresh(p, s, w)


@njit(**JIT)
def _refresh(p, s, w):
    """Everything at the current point (t, y) in the current mode: every event's value (ev.g0),
    the contact force, the contact's decay and growth rates."""
    s.force, s.decay, s.growth = point_values(s.t, w.y, p, s.mode, w.ev.g0, w.ev.f)


@njit(**JIT)
def _controller(method, h, err, after_reject):
    """The next step size after a step of size h with error norm err, by the method's controller."""
    if method == EXPLICIT:
        return _dop853.new_step(h, err, after_reject != 0)
    return _sdirk4.new_step(h, err)


@njit(**JIT)
def _method_and_step(p, s):
    """The method and size of the next attempt: DOP853 at the error control's step, cut to the
    stability limit h·decay = STIFF_LIMIT where it would not be stable; SDIRK4 once STIFF_AFTER
    attempts in a row were cut so, until its own step would be stable explicitly again."""
    h = min(s.h, next_break(s.t, p) - s.t, p[HMAX])
    stable = h * s.decay <= STIFF_LIMIT
    if s.stiff:
        s.stiff = 0 if stable else 1
        if s.stiff:
            return IMPLICIT, h
    if stable:
        s.capped = 0
        return EXPLICIT, h
    s.capped += 1
    if s.capped > STIFF_AFTER:
        s.stiff, s.capped = 1, 0
        return IMPLICIT, h
    return EXPLICIT, STIFF_LIMIT / s.decay


@njit(**JIT)
def _attempt(p, rtol, s, w):
    """One step attempt from (s.t, w.y) into w.y_new (:func:`_method_and_step`); True if
    accepted (the piece looked at for events is then the whole step, its end values in ev.g1)."""
    s.method, hs = _method_and_step(p, s)
    s.h_step = hs
    if s.method == EXPLICIT:
        # the first stage is f at (t, y): the last step's final one unless the equations changed
        if s.fsal == 0:
            rhs(ROLLER, s.t, w.y, p, s.mode, w.dp.k[0], w.dp.jac, False)
            s.nfev += 1
            s.fsal = 1
        err, nf = _dop853.step(ROLLER, s.t, w.y, hs, p, s.mode, rtol, w.atol, w.y_new, w.dp)
        solved = True
    else:
        solved, err, nf = _sdirk4.step(ROLLER, s.t, w.y, hs, p, s.mode, rtol, w.atol, w.y_new, w.sd)
    s.nfev += nf
    # a failed Newton iteration (or an estimate that is not a number): a quarter of the step
    if not solved or err != err:
        s.failed += 1
        s.h = 0.25 * hs
        return False
    if err > 1.0:
        s.rejected += 1
        s.h = _controller(s.method, hs, err, 1)
        s.after_reject = 1
        return False
    # accepted: the piece looked at for events is the whole step
    s.steps += 1
    s.implicit += s.method  # (EXPLICIT = 0, IMPLICIT = 1)
    s.err, s.h_piece, s.dense = err, hs, 0
    _piece_end(p, s, w, w.y_new)
    if s.method == IMPLICIT:
        _copy(w.sd.f0, w.ev.f0)
    return True


@njit(**JIT)
def _piece_end(p, s, w, y_end):
    """The piece ends at y_end: its state, derivative (implicit steps: the last SDIRK4 step's)
    and every event's value there (ev.g1)."""
    _copy(y_end, w.ev.y_end)
    if s.method == IMPLICIT:
        _copy(w.sd.f1, w.ev.f1)
    # a step cut by the clock's break ends exactly at its time
    nb = next_break(s.t, p)
    s.t_end = nb if s.h_piece == s.h_step and s.h_step == nb - s.t else s.t + s.h_piece
    s.force_end, s.decay_end, s.growth_end = point_values(
        s.t_end, w.ev.y_end, p, s.mode, w.ev.g1, w.ev.f
    )


@njit(**JIT)
def _falls(w, e):
    """Whether event e falls through zero in the piece."""
    return w.ev.g0[e] > 0.0 and w.ev.g1[e] <= 0.0


@njit(**JIT)
def _locate(p, rtol, e, s, w):
    """Time after s.t of event e in the piece (its state in w.y_ev): on the continuous extension
    of an explicit step (computed once, when the step's first event needs it), by true steps in
    an implicit one."""
    if s.method == EXPLICIT and s.dense == 0:
        s.nfev += _dop853.prepare_dense(ROLLER, s.t, w.y, w.y_new, s.h_step, p, s.mode, w.dp)
        s.dense = 1
    x, nf = _ev.locate(
        ROLLER, e, s.method, s.t, w.y, s.h_step, s.h_piece, w.ev.g0[e], w.ev.g1[e], p, s.mode,
        rtol, w.atol, w.y_ev, w, EVENT_TIME_TOL,
    )  # fmt: skip
    s.nfev += nf
    return x


@njit(**JIT)
def _earliest_switch(p, rtol, s, w):
    """The earliest switching event in the accepted step (−1 if none). Each one found cuts the
    piece at its time (its end values updated), so the last one found is the earliest."""
    switch = -1
    for e in SWITCHING:
        if switching_active(e, s.mode, s.t, p) and _falls(w, e):
            s.h_piece = _locate(p, rtol, e, s, w)
            _piece_end(p, s, w, w.y_ev)
            switch = e
    return switch


@njit(**JIT)
def _record(p, rtol, s, w, res):
    """The recording events in the piece: the engagement (time and total backlash) and a force
    maximum (its value)."""
    if s.synced == 0 and _falls(w, EV_SYNC):
        x = _locate(p, rtol, EV_SYNC, s, w)
        s.synced = 1
        res[SYNC_TIME] = s.t + x
        res[TOTAL_BACKLASH] = (w.y_ev[Y_SLIP] + w.y_ev[Y_TRAVEL]) / p[RC]
    if _falls(w, EV_PEAK):
        x = _locate(p, rtol, EV_PEAK, s, w)
        _, _, (fp, _, _, _) = roller_contact(s.t + x, w.y_ev, p, s.mode)
        res[PEAK_FORCE] = max(res[PEAK_FORCE], fp)


@njit(**JIT)
def _advance(p, s, w, switch, res):
    """Move to the piece's end; switch the mode there (a switching event, or the claws reaching
    the rollers) and record the switch's outputs; everything at the new point."""
    whole = s.h_piece == s.h_step
    s.t = s.t_end
    _copy(w.ev.y_end, w.y)
    mode = s.mode
    if switch >= 0:
        mode = switch_mode(mode, switch, w.y, p)
    if s.t >= p[TCLAW]:
        mode |= CLAWS
    # f at the step's end is the next step's first stage if the equations stay the same
    same = mode == s.mode and switch < 0
    if s.method == EXPLICIT and whole and same:
        _copy(w.dp.k[_dop853.N_STAGES], w.dp.k[0])
    s.fsal = 1 if s.method == EXPLICIT and whole and same else 0
    s.mode = mode
    if switch == EV_STICK:
        res[STICK_TIME] = s.t
        res[SLIP_BACKLASH] = w.y[Y_SLIP] / p[RC]
    elif switch == EV_RELEASE:
        res[RELEASE_TIME] = s.t - p[TREL]
    # the piece's end values hold at the new point unless the mode or the state changed
    if same:
        _copy(w.ev.g1, w.ev.g0)
        s.force, s.decay, s.growth = s.force_end, s.decay_end, s.growth_end
    else:
        _refresh(p, s, w)
    res[PEAK_FORCE] = max(res[PEAK_FORCE], s.force)


@njit(**JIT)
def _trace_row(p, s, w, trace, row):
    """Trace row: t, ω_d, ω_w, ω_o, N."""
    trace[row, 0], trace[row, 1] = s.t, p[WD]
    trace[row, 2] = w.y[Y_WEDGE] if (s.mode & STICK) == 0 else p[WD]
    trace[row, 3], trace[row, 4] = w.y[Y_DRIVEN], s.force


@njit(**JIT)
def _phase_tolerances(p, rtol, s, w):
    """The current phase's relative tolerance (the scenario's rtol times SLIP_RTOL_FACTOR while
    the wedge ring slips, times ENGAGED_RTOL_FACTOR after the engagement, up to LOOSEST_RTOL)
    and its absolute ones in w.atol (scaled by the driving speed)."""
    rt = rtol
    if s.synced:
        rt = max(rtol, min(rtol * ENGAGED_RTOL_FACTOR, LOOSEST_RTOL))
    elif (s.mode & STICK) == 0:
        rt = max(rtol, min(rtol * SLIP_RTOL_FACTOR, LOOSEST_RTOL))
    w.atol[Y_SLIP], w.atol[Y_WEDGE] = rt * 1e-4, rt * p[WD]
    w.atol[Y_TRAVEL], w.atol[Y_DRIVEN] = rt * 1e-4, rt * p[WD]
    return rt


@njit(**JIT)
def _done(p, s, w, switch):
    """Whether the scenario is over after this step: released; or, without a release, engaged
    and past the force peak (model only what is asked)."""
    if switch == EV_RELEASE:
        return True
    return s.synced != 0 and not p[TREL] < np.inf and w.ev.g0[EV_PEAK] <= 0.0


@njit(**JIT)
def _next_h(s, switch, growth_before):
    """The next step: by the error control (a growing mode that grew faster over the step
    shrinks it in proportion), or after a switch from the piece's size."""
    if switch >= 0:
        return max(s.h_piece, 1e-3 * s.h_step)
    h = _controller(s.method, s.h_step, s.err, s.after_reject)
    return h * growth_before / s.growth if s.growth > growth_before else h


@njit(cache=True, error_model="numpy")
def _roller_one(p, rtol, max_steps, res, trace, n_trace, w):
    """One roller-clutch engagement (and release) with the arrays ``w``; fills ``res``; returns
    the trace length."""
    s = np.zeros(1, DRIVER)[0]
    _start(p, s, w, res)
    n_tr = 0
    while s.t < p[TEND] and s.status == ST_RUNNING:
        # the work budget: every attempt, accepted or not; a step cut to nothing
        if s.steps + s.rejected + s.failed >= max_steps or s.h < 1e-18:
            s.status = ST_FAIL
            break
        rt = _phase_tolerances(p, rtol, s, w)
        if not _attempt(p, rt, s, w):
            continue
        # events in the accepted step: the earliest switch cuts it, the others are recorded
        growth_before = s.growth
        switch = _earliest_switch(p, rt, s, w)
        _record(p, rt, s, w, res)
        _advance(p, s, w, switch, res)
        if n_tr < n_trace:
            _trace_row(p, s, w, trace, n_tr)
            n_tr += 1
        if _done(p, s, w, switch):
            break
        s.h = _next_h(s, switch, growth_before)
        s.after_reject = 0
    if s.status == ST_RUNNING:
        s.status = ST_OK if s.synced else ST_NEVER
    res[FINAL_FORCE] = s.force
    res[N_STEPS], res[N_FEV], res[N_REJECTED] = s.steps, s.nfev, s.rejected
    res[N_NEWTON_FAIL], res[N_IMPLICIT], res[STATUS] = s.failed, s.implicit, s.status
    return n_tr


@njit(cache=True, error_model="numpy")
def simulate_roller(P, rtol, max_steps, trace_row, n_trace):
    """Every scenario (rows of P), one after another with the same arrays; the trace (t, ω_d,
    ω_w, ω_o, F) of row ``trace_row``."""
    out = np.full((P.shape[0], len(RESULTS)), np.nan)
    trace = np.zeros((n_trace, N_TRACE_COLUMNS))
    none = np.zeros((0, N_TRACE_COLUMNS))
    w = _work(np.zeros(4))
    n_tr = 0
    for i in range(P.shape[0]):
        if i == trace_row:
            n_tr = _roller_one(P[i], rtol, max_steps, out[i], trace, n_trace, w)
        else:
            _roller_one(P[i], rtol, max_steps, out[i], none, 0, w)
    return out, trace[:n_tr]
