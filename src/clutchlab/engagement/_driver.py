"""The driver of the numerical solver (compiled, numba): one scenario's loop, and the batch.

Per scenario (:func:`_simulate_one`): the initial modes (decided from torques, never from
sign(0)), then until the window's end either an exact linear phase of the compliant model
(:func:`_linear_step`) or one DOPRI5 step (:func:`_integrator_step`) with its events detected,
located and switched (:func:`_event_step`, :func:`_switch`) or its peaks, power samples and trace
taken (:func:`_accept_step`); a scenario locked at the window's end is followed until its peaks
are final (:func:`_window_end`). The stick/slip/park state machine's transitions are
:func:`apply_event` (hysteresis of the Modelica friction state machine: a state that locks stays
stuck until BREAK, no chatter).

The physics (forces, events, mode switches) is documented in :mod:`clutchlab.engagement`; this
package only makes it fast:

* no allocation anywhere, so every function is compiled without numba's reference counting
  (``_nrt=False``): the atomic reference-count updates on every call with an array argument
  were half of the run time (a step cost 0.55 µs with them, 0.27 µs without); the scratch arrays
  are allocated once a batch (:func:`simulate_batch`) and passed down as named records;
* only the moving state components are integrated (4 for a held engine, 5 free, 8 compliant; with
  fade, while slipping, the 15 modes of the friction face's temperature too);
* the rigid and the compliant model are compiled as two loops with the flag a constant, and the
  compliant scenarios whose phases are all linear as a third one without the integrators
  (:func:`_simulate_exact`); the driver's stages are inlined into them (``inline="always"``), so
  each loop compiles as one body.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._colloc import new_colloc
from ._dopri import control, copy, err_norm, initial_step, restart, retry_shorter, step
from ._events import detect, locate_events
from ._fade import decay_modes, face_rise_total
from ._layout import (
    ACCEL_JUMP,
    BREAK,
    BREAKAWAY_TIME,
    CAPACITY_AT_LOCKUP,
    CD,
    DAMPING_WORK,
    ENERGY_RESIDUAL,
    FADE,
    FINAL_LOCKED,
    FLASH_PEAK,
    FOLLOW_EVENT,
    FOLLOW_OUT_OF_WORK,
    HELD,
    HIT_STEP_LIMIT,
    INPUT_WORK,
    INV_JE,
    JE,
    JH,
    JR,
    JV,
    KINETIC_ENERGY_CHANGE,
    LOAD_WORK,
    LOCK,
    LOCKUP_SPEED,
    LOCKUP_TIME,
    MAX_JERK,
    MAX_POWER,
    MAX_TORQUE,
    N_EVENT_STEPS,
    N_EVENTS,
    N_FALSE_ALARMS,
    N_LINEAR,
    N_LOCATE,
    N_MAXIMA,
    N_MECH,
    N_POWER_SAMPLES,
    N_REJECTED,
    N_RESULTS,
    N_STATE,
    N_STEPS,
    N_TRACES,
    OUT_OF_WORK,
    PARK,
    PEAK_FRICTION_TORQUE,
    PEAK_JERK,
    PEAK_SLIP_POWER,
    POWER_SAMPLES_MAX,
    POWER_SAMPLES_PER_RAMP,
    RS,
    SCENARIO,
    SLIP_WORK,
    T_CAPACITY,
    T_ENGINE,
    T_FACE_RISE,
    T_HUB,
    T_JERK,
    T_OUTPUT,
    T_SLIP_WORK,
    T_TORQUE,
    TCON,
    TEND,
    TH,
    TR,
    TRUNCATED,
    TSTEP,
    UNPARK,
    WC0,
    WD,
    WE0,
    WI,
    WL,
    WS,
    E,
    H,
    K,
    Mode,
    Options,
    R,
    Work,
)
from ._linear_phase import follow_linear, linear_segment, new_forms, new_polys
from ._peaks import jerk_torque, peaks_inside_step, record_peaks, scan_jerk
from ._physics import events, forces, is_linear, jerk_varies, load_static, n_active
from ._power import duhamel_peak, hist_add, hist_linear, hist_step, slip_spacing
from ._slip_phase import applies, constant_slip, segment

JIT = dict(cache=True, error_model="numpy", _nrt=False)
INLINE = dict(JIT, inline="always")


@njit(**INLINE)
def _mode(sc, compliant, prof):
    """The scenario's current mode (from its record) with the model's constants."""
    return Mode(sc.locked, sc.parked, sc.sign, compliant, prof)


@njit(**INLINE)
def _simulate_one(q, compliant, prof, tt, opts, out, trace, ws, fm, pl, hist, scs, ec):
    """Integrate one scenario over [0, q[TEND]]; fill ``out`` (RESULTS) and ``trace`` (times ×
    TRACES). ``ws``: the batch's :class:`Work` arrays (allocating the ~18 small arrays per scenario
    cost more than a short engagement's integration); ``fm``, ``pl``: the linear phases' scratch
    (:mod:`clutchlab.engagement._linear_phase`); ``hist``: the slip power history; ``scs``: the
    record of the driver's scalars (:data:`SCENARIO`); ``ec``: the collocated slipping phases'
    record (:class:`clutchlab.engagement._colloc.Colloc`).

    Compliant model: linear phases (:func:`is_linear`) are advanced exactly, slipping phases with a
    nonlinear friction law and a held engine (:func:`clutchlab.engagement._slip_phase.applies`) by
    exponential collocation, the others by DOPRI5.
    A scenario locked at the window's end is followed until its peaks are final: a linear locked
    phase exactly to t = ∞; a nonlinear one (rotor drag, engine torque table) by DOPRI5 until its
    linearised hub-output oscillation has decayed by 1e-6. An event after the window (break-away,
    park, unpark) sets TRUNCATED: the metrics of the window would not be final."""
    sc = scs[0]
    w = _views(ws, N_STATE if q[FADE] > 0.0 else N_MECH)  # (the face temperature's modes with fade)
    _start(q, compliant, prof, tt, opts, out, trace, w, hist, sc)
    ec.sc[0].h_next = 0.0  # (no collocation step proposed yet)
    # rigid driveline: the clamp profile's steepest point (x = 1/2 of the cubic and quintic steps)
    # is a breakpoint, so that the slip jerk dC/dt/J_v, largest there, is taken at a step node
    # (the cushion touch TCON, where a later steepest point is, is one already)
    t_rate = 0.5 * q[TR] if (prof != 0 and not compliant) else -1.0
    while sc.effort < opts.max_steps:
        if sc.t >= sc.t_stop:
            if _window_end(q, compliant, prof, opts, out, w, fm, pl, sc):
                break
            continue
        nb = _next_breakpoint(sc.t, sc.t_stop, q, t_rate, tt)
        x_lock = 0.0  # (the slip where a linear slipping phase ends: lock-up)
        linear = compliant and is_linear(q, sc.locked)
        if compliant and applies(q, sc.locked):
            # a Stribeck law's constant part exactly, by the linear phase up to its end x_lock
            x_lock = constant_slip(q)
            linear = sc.sign * (w.y[E] - w.y[H]) > x_lock * (1.0 + 1e-9)
            if not linear:
                if _slip_step(nb, q, compliant, prof, tt, opts, out, trace, w, hist, sc, ec):
                    break
                continue
        if linear:
            if _linear_step(
                nb, q, compliant, prof, tt, opts, out, trace, w, fm, pl, hist, sc, x_lock
            ):
                break
            continue
        if _integrator_step(nb, q, compliant, prof, tt, opts, out, trace, w, hist, sc):
            break
    _finish(q, compliant, opts, out, w, hist, sc)


@njit(**INLINE)
def _simulate_exact(q, prof, tt, opts, out, trace, ws, fm, pl, hist, scs):
    """:func:`_simulate_one` of a compliant scenario whose every phase is linear (:func:`linear_rows`):
    the same loop with only the exact phases, compiled on its own, so that a run with constant μ
    compiles none of the integrators (DOPRI5, the collocated slipping phases)."""
    sc = scs[0]
    w = _views(ws, N_MECH)
    _start(q, True, prof, tt, opts, out, trace, w, hist, sc)
    while sc.effort < opts.max_steps:
        if sc.t >= sc.t_stop:
            if _window_end(q, True, prof, opts, out, w, fm, pl, sc):
                break
            continue
        nb = _next_breakpoint(sc.t, sc.t_stop, q, -1.0, tt)
        if _linear_step(nb, q, True, prof, tt, opts, out, trace, w, fm, pl, hist, sc, 0.0):
            break
    _finish(q, True, opts, out, w, hist, sc)


@njit(**INLINE)
def _views(ws, ns):
    """The scenario's :class:`Work`: the batch's arrays cut to its state length ns."""
    return Work(
        ws.y[:ns],
        ws.d[:ns],
        ws.d1[:ns],
        ws.dm[:ns],
        ws.y1[:ns],
        ws.ym[:ns],
        ws.err[:ns],
        ws.yi[:ns],
        ws.ya[:ns],
        ws.yb[:ns],
        ws.y_best[:ns],
        ws.kk[:, :ns],
        ws.g,
        ws.g1,
        ws.gm,
        ws.tau_hi,
        ws.pk,
        ws.ths,
        ws.rc[:, :ns],
        ws.da[:ns],
        ws.y_end[:ns],
    )


# ---- the start --------------------------------------------------------------------------------


@njit(**INLINE)
def _start(q, compliant, prof, tt, opts, out, trace, w, hist, sc):
    """The results and counters cleared, the initial state and modes, the first step size, the
    first event functions, peaks, trace and power sample."""
    for i in range(out.size):
        out[i] = np.nan
    out[N_REJECTED] = out[N_LOCATE] = out[N_FALSE_ALARMS] = out[N_EVENT_STEPS] = out[TRUNCATED] = (
        0.0
    )
    out[N_LINEAR] = 0.0
    y, pk = w.y, w.pk
    for i in range(N_MAXIMA):  # running maxima: slip power, |friction torque|, |output jerk|
        pk[i] = 0.0
    for i in range(y.size):
        y[i] = 0.0
    y[E] = q[WE0]
    y[H] = q[WC0]
    y[R] = q[WC0]
    w.ths[0] = 0.5  # the step's middle: the first sample of event detection
    _initial_modes(q, compliant, prof, out, w, sc)
    t = sc.t = 0.0
    mode = _mode(sc, compliant, prof)
    fc = forces(t, y, q, mode, w.d)
    h = (
        opts.first_step
        if opts.first_step > 0
        else initial_step(
            t, y, w.d, q, mode, opts.rtol, opts.atol, min(opts.max_step, q[TEND]), w.y1, w.d1
        )
    )
    restart(sc, h)
    events(t, y, q, mode, w.d, fc, w.g)
    jk = record_peaks(t, y, q, mode, w.d, fc, pk)
    store_trace(trace, tt, t, y, q, R if compliant else H, fc, jk)
    sc.j_left, sc.tc_left = jk, fc.torque  # jerk and clutch torque at the left end of the next step
    # (a step or very short clamp rise: spacing from the window, so that a long slip cannot overflow the history)
    sc.dt_s = max(min(q[TR], q[TEND]), q[TEND] / POWER_SAMPLES_PER_RAMP) / POWER_SAMPLES_PER_RAMP
    sc.n_hist = hist_add(hist, 0, 0.0, 0.0 if sc.locked else fc.torque * fc.slip)
    sc.t_slip = 0.0  # start of the current slip phase (power sample spacing)
    sc.n_steps = 0
    # the work budget (max_steps): integrator steps attempted, mode switches and the linear phases'
    # root-search passes all count, so that no input (a damper spring whose period is below the
    # time's round-off, events that repeat at one instant) can keep a scenario running for ever
    sc.effort = 0
    sc.out_of_work = False
    sc.t_stop, sc.past = q[TEND], False


@njit(**INLINE)
def _initial_modes(q, compliant, prof, out, w, sc):
    """The initial modes, decided from torques (never from sign(0)): parked while the static load
    exceeds the drive; locked from the start at equal speeds if the static capacity holds the
    needed torque, else slipping in its direction."""
    y = w.y
    locked = False
    parked = q[WC0] <= 0.0
    s = 1.0
    fc = forces(0.0, y, q, Mode(locked, parked, s, compliant, prof), w.d)
    drive0 = fc.spring if compliant else fc.law * fc.fade * fc.capacity
    parked = parked and load_static(0.0, q) > drive0
    if q[WE0] == q[WC0]:
        fl = forces(0.0, y, q, Mode(True, False, s, compliant, prof), w.d)
        if abs(fl.needed) <= q[RS] * fc.capacity:
            locked = True
            if not compliant:  # (compliant: the lock joins hub and engine; the output stays parked)
                parked = False
            out[LOCKUP_TIME] = 0.0
            out[LOCKUP_SPEED] = q[WC0]
        else:
            s = 1.0 if fl.needed >= 0 else -1.0
    sc.locked, sc.parked, sc.sign = locked, parked, s


# ---- the loop's stages ------------------------------------------------------------------------


@njit(**INLINE)
def _next_breakpoint(t, t_stop, q, t_rate, tt):
    """The next breakpoint after t: the profile's end, the load step, the cushion touch, the
    rigid profile's steepest point, a trace time, or the stop."""
    nb = t_stop
    for b in (q[TR], q[TSTEP], q[TCON], t_rate):
        if t < b < nb:
            nb = b
    for b in tt:
        if t < b < nb:
            nb = b
    return nb


@njit(**INLINE)
def _window_end(q, compliant, prof, opts, out, w, fm, pl, sc):
    """At the window's end: keep its state, then follow a locked compliant scenario until its peaks
    are final (a linear phase exactly; else by DOPRI5 until the linearised hub-output oscillation
    has decayed by 1e-6: the new stop). Returns whether the scenario ends."""
    if sc.past:
        return True
    sc.past = True  # the window's end: keep its state, then follow a locked scenario
    copy(w.y_end, w.y)
    if not (sc.locked and compliant):
        return True
    held = q[HELD] > 0.0
    if sc.parked and held and w.y[E] == 0.0 and w.y[H] == 0.0:
        return True  # a held engine at rest, hub locked to it, output parked: nothing moves again
    if is_linear(q, True):
        outcome, used = follow_linear(
            sc.t,
            w.y,
            q,
            _mode(sc, compliant, prof),
            opts.peaks,
            w.pk,
            fm,
            pl,
            opts.max_steps - sc.effort,
        )
        sc.effort += used
        if outcome == FOLLOW_OUT_OF_WORK:
            sc.out_of_work = True
        elif outcome == FOLLOW_EVENT:
            out[TRUNCATED] = 1.0
        return True
    jd = q[JR] / (
        1.0 + q[JR] * (0.0 if held else 1.0 / (q[JE] + q[JH]))
    )  # locked oscillator's mass
    decay = 0.5 * q[CD] / jd
    if not decay > 0.0:
        out[TRUNCATED] = 1.0
        return True
    sc.t_stop = max(sc.t, out[LOCKUP_TIME] + math.log(1e6) / decay)
    return False


@njit(**INLINE)
def _linear_step(nb, q, compliant, prof, tt, opts, out, trace, w, fm, pl, hist, sc, x_lock):
    """A linear phase of the compliant model advanced exactly to its first event (then the mode
    switch) or to the breakpoint nb; slipping with x_lock > 0 [rad/s], its end where the slip
    falls to x_lock is a boundary (the end of a Stribeck law's constant part), not lock-up.
    Returns whether the scenario ends (out of work, or an event after the window)."""
    mode = _mode(sc, compliant, prof)
    t = sc.t
    out[N_LINEAR] += 1
    t_new, kind, _, used, fr = linear_segment(
        t, nb, t, w.y, q, mode, False, opts.peaks, w.pk, fm, pl, opts.max_steps - sc.effort, x_lock
    )
    sc.effort += used
    decay_modes(w.y, q, t_new - t)  # (a linear phase with fade is a locked one)
    if opts.with_hist and not sc.past:
        sc.n_hist = (
            hist_add(hist, sc.n_hist, t_new, 0.0)
            if sc.locked
            else hist_linear(
                hist, sc.n_hist, t, t_new, slip_spacing(sc.dt_s, sc.t_slip, t_new), fm.table, fr
            )
        )
    sc.t = t_new
    if kind == OUT_OF_WORK:
        sc.out_of_work = True
        return True
    if kind == LOCK and x_lock > 0.0:  # the Stribeck law's constant part ends: same mode
        sc.effort += 1
        _at_breakpoint(t_new, q, mode, tt, trace, w, sc)
    elif kind >= 0:
        sc.effort += 1  # a mode switch (a restart at an event)
        if sc.past:
            out[TRUNCATED] = 1.0
            return True
        _switch(kind, q, mode, opts, out, w, sc)
    else:
        _at_breakpoint(nb, q, mode, tt, trace, w, sc)
    return False


@njit(**INLINE)
def _slip_step(nb, q, compliant, prof, tt, opts, out, trace, w, hist, sc, ec):
    """A slipping phase with a nonlinear friction law and a held engine advanced by exponential
    collocation (:func:`clutchlab.engagement._slip_phase.segment`) to its first event (then the
    mode switch) or to the breakpoint nb. Returns whether the scenario ends (out of work, or an
    event after the window)."""
    kind, used, n_acc, n_rej = segment(
        ec, nb, q, prof, opts, w, hist, sc, opts.max_steps - sc.effort
    )
    sc.effort += used
    sc.n_steps += n_acc + n_rej
    out[N_REJECTED] += n_rej
    if kind == OUT_OF_WORK:
        sc.out_of_work = True
        return True
    mode = _mode(sc, compliant, prof)
    if kind >= 0:
        sc.effort += 1  # a mode switch
        if sc.past:
            out[TRUNCATED] = 1.0
            return True
        _switch(kind, q, mode, opts, out, w, sc)
    else:
        _at_breakpoint(nb, q, mode, tt, trace, w, sc)
    return False


@njit(**INLINE)
def _at_breakpoint(t, q, mode, tt, trace, w, sc):
    """A linear phase that reached the breakpoint t: the event functions, peaks and trace there."""
    sc.t = t
    fc = forces(t, w.y, q, mode, w.d)
    events(t, w.y, q, mode, w.d, fc, w.g)
    jk = record_peaks(t, w.y, q, mode, w.d, fc, w.pk)
    store_trace(trace, tt, t, w.y, q, R if mode.compliant else H, fc, jk)
    sc.j_left, sc.tc_left = jk, fc.torque


@njit(**INLINE)
def _integrator_step(nb, q, compliant, prof, tt, opts, out, trace, w, hist, sc):
    """One DOPRI5 step towards the breakpoint nb: the step-size control, then the events of the
    step detected and located (the earliest ends the step there) or the step accepted as it was.
    Returns whether the scenario ends (an event after the window)."""
    mode = _mode(sc, compliant, prof)
    t = sc.t
    h_try = min(sc.h, opts.max_step, nb - t)
    hit = h_try >= nb - t
    step(t, w.y, h_try, q, mode, w.d, w.kk, w.yi, w.y1, w.err)
    norm = err_norm(w.y, w.y1, w.err, opts.rtol, opts.atol, n_active(q, mode), compliant)
    sc.n_steps += 1
    sc.effort += 1
    if not control(sc, norm, h_try):
        out[N_REJECTED] += 1
        return False
    t_right = nb if hit else t + h_try
    f1 = forces(t_right, w.y1, q, mode, w.d1)
    events(t_right, w.y1, q, mode, w.d1, f1, w.g1)
    fired, jm, tcm = detect(t, h_try, q, mode, w, R if compliant else H)
    if fired:
        tau, kind, norm_e = locate_events(t, h_try, q, mode, opts.rtol, opts.atol, w, out)
        if kind >= 0:
            return _event_step(kind, tau, norm_e, h_try, q, mode, opts, out, w, hist, sc)
    _accept_step(h_try, hit, t_right, f1, fired, jm, tcm, q, mode, tt, opts, trace, w, hist, sc)
    return False


@njit(**INLINE)
def _event_step(kind, tau, norm, h, q, mode, opts, out, w, hist, sc):
    """The step [t, t + h] cut at its earliest event t + tau (state w.y_best): it must meet the
    tolerance itself (else retry shorter); the power samples and peaks up to the event, then the
    mode switch. Returns whether the scenario ends (an event after the window)."""
    if (
        norm > 1.0
    ):  # the located step must meet the tolerance itself; else retry with a shorter step
        out[N_REJECTED] += 1
        retry_shorter(sc, tau, norm)
        return False
    if sc.past:
        out[TRUNCATED] = 1.0
        return True
    t, y = sc.t, w.y
    if opts.with_hist and not mode.locked:
        sc.n_hist = hist_step(
            hist,
            sc.n_hist,
            t,
            h,
            t + tau,
            slip_spacing(sc.dt_s, sc.t_slip, t + tau),
            y,
            w.d,
            w.y1,
            w.d1,
            q,
            mode,
            w.ym,
            w.dm,
        )
    if not (mode.compliant or mode.locked or mode.parked) and jerk_varies(q):
        slip0, slip1 = y[E] - y[H], w.y_best[E] - w.y_best[H]
        scan_jerk(t, h, tau / h, slip0, slip1, sc.j_left, w.rc, q, mode, w.pk, w.yb, w.dm)
    if mode.locked:
        decay_modes(w.y_best, q, tau)
    t = sc.t = t + tau
    copy(y, w.y_best)
    # the peaks up to the event, at the state just before it (a lock-up ends the slip at
    # its largest clutch torque when the clamp still rises: a step may end exactly there)
    fe = forces(t, y, q, mode, w.dm)
    record_peaks(t, y, q, mode, w.dm, fe, w.pk)
    if opts.with_hist:
        sc.n_hist = hist_add(hist, sc.n_hist, t, 0.0 if mode.locked else fe.torque * fe.slip)
    _switch(kind, q, mode, opts, out, w, sc)
    return False


@njit(**INLINE)
def _switch(kind, q, mode, opts, out, w, sc):
    """Switch the mode at the event ``kind`` (at sc.t, state w.y) and restart: the start of a slip
    phase, the jerk and clutch torque at the new left end, a fresh starting step."""
    t = sc.t
    new = apply_event(kind, t, w.y, q, mode, w.d, w.dm, w.g, w.pk, out)
    if mode.locked and not new.locked:
        sc.t_slip = t
    sc.locked, sc.parked, sc.sign = new.locked, new.parked, new.sign
    sc.j_left, sc.tc_left = jerk_torque(t, w.y, q, new, w.dm)
    hmax = min(opts.max_step, q[TEND])
    restart(sc, initial_step(t, w.y, w.d, q, new, opts.rtol, opts.atol, hmax, w.y1, w.d1))


@njit(**INLINE)
def _accept_step(h, hit, t_right, f1, fired, jm, tcm, q, mode, tt, opts, trace, w, hist, sc):
    """Take the step [t, t_right] as it was: the peaks at its end and inside it, the power samples,
    the face temperature's decay while locked, the new left end, the trace."""
    t = sc.t
    jk = record_peaks(t_right, w.y1, q, mode, w.d1, f1, w.pk)
    peaks_inside_step(
        t, h, hit, fired, t_right, jk, jm, tcm, f1.torque, sc.j_left, sc.tc_left, q, mode, w
    )
    sc.j_left, sc.tc_left = jk, f1.torque
    if opts.with_hist and not sc.past:
        if not mode.locked:
            spacing = slip_spacing(sc.dt_s, sc.t_slip, t_right)
            sc.n_hist = hist_step(
                hist, sc.n_hist, t, h, t_right, spacing, w.y, w.d, w.y1, w.d1, q, mode, w.ym, w.dm
            )
        sc.n_hist = hist_add(hist, sc.n_hist, t_right, 0.0 if mode.locked else f1.torque * f1.slip)
    if mode.locked:
        decay_modes(w.y1, q, t_right - t)
    sc.t = t_right
    copy(w.y, w.y1)
    copy(w.d, w.d1)
    copy(w.g, w.g1)
    store_trace(trace, tt, t_right, w.y, q, R if mode.compliant else H, f1, jk)


# ---- the state machine ------------------------------------------------------------------------


@njit(**JIT)
def apply_event(kind, t, y, q, mode, d, dm, g, pk, out):
    """Switch the mode at the located event ``kind`` (state y at t): LOCK joins the sides (momentum
    kept), BREAK slips in the direction of the needed torque, (UN)PARK holds or frees the output.
    Records lock-up and break-away; fills d and g at the new mode; returns the new Mode."""
    locked, parked, s, compliant, prof = mode
    held = q[HELD] > 0.0
    if kind == UNPARK and not compliant and not locked and y[E] == y[H]:
        # no slip to start from (e.g. a held engine at 0 rad/s and a parked driven side): the
        # clutch that now carries the load holds the driven side at the engine's speed — a lock-up,
        # not a start of slip into the wrong direction (negative slip work)
        kind = LOCK
        parked = False
    before = forces(t, y, q, Mode(locked, parked, s, compliant, prof), dm)
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
        s = 1.0 if before.needed >= 0 else -1.0
    elif kind == UNPARK:
        parked = False
    elif kind == PARK:
        parked = True
        y[R if compliant else H] = 0.0
        if locked and not compliant:  # a stall: the locked engine stops with the driven side
            y[E] = 0.0
    acc_before = dm[
        H
    ]  # the hub's (rigid: the driven side's); the output's is continuous (compliant)
    new = Mode(locked, parked, s, compliant, prof)
    fc = forces(t, y, q, new, d)
    if kind == LOCK and not compliant and not held and y[H] <= 0.0 and d[H] < 0.0:
        # locked at rest (a free engine slowed to the parked side's standstill) and the engine
        # cannot turn the load: stalled, not spinning backwards
        new = Mode(locked, True, s, compliant, prof)
        y[E] = y[H] = 0.0
        fc = forces(t, y, q, new, d)
    if kind == LOCK:
        out[LOCKUP_TIME] = t
        out[LOCKUP_SPEED] = y[H]
        out[CAPACITY_AT_LOCKUP] = fc.capacity
        out[ACCEL_JUMP] = d[H] - acc_before
    elif kind == BREAK:
        if math.isnan(out[BREAKAWAY_TIME]):
            out[BREAKAWAY_TIME] = t
        out[LOCKUP_TIME] = np.nan
    events(t, y, q, new, d, fc, g)
    record_peaks(t, y, q, new, d, fc, pk)
    return new


@njit(**JIT)
def store_trace(trace, tt, t, y, q, wr_col, fc, jk):
    """Record the state at the trace times equal to t (they are breakpoints: no interpolation); the
    face temperature rise with fade only (the slow modes plus the quasi-static part of the slip
    power, which is 0 when locked: the slip is exactly 0 then)."""
    for i in range(tt.size):
        if tt[i] == t:
            trace[i, T_ENGINE] = y[E]
            trace[i, T_HUB] = y[H]
            trace[i, T_OUTPUT] = y[wr_col]
            trace[i, T_TORQUE] = fc.torque
            trace[i, T_CAPACITY] = fc.capacity
            trace[i, T_SLIP_WORK] = y[WS]
            trace[i, T_JERK] = jk
            if q[FADE] > 0.0:
                trace[i, T_FACE_RISE] = face_rise_total(y, q, fc.torque, fc.slip)


# ---- the end ----------------------------------------------------------------------------------


@njit(**INLINE)
def _finish(q, compliant, opts, out, w, hist, sc):
    """The results: peaks (the friction torque's and the jerk's NaN without ``opts.peaks``), the
    power history's flash peak, solver counts and flags, and the works and energies over the
    window."""
    pk = w.pk
    out[PEAK_SLIP_POWER] = pk[MAX_POWER]
    out[PEAK_FRICTION_TORQUE] = pk[MAX_TORQUE] if opts.peaks else np.nan
    out[PEAK_JERK] = pk[MAX_JERK] if opts.peaks else np.nan
    n_hist = sc.n_hist
    out[N_POWER_SAMPLES] = n_hist if opts.with_hist else 0.0
    out[FLASH_PEAK] = (
        duhamel_peak(hist, n_hist, max(1, int(math.sqrt(n_hist / 2.0))))
        if opts.with_hist and n_hist <= POWER_SAMPLES_MAX
        else np.nan
    )
    out[N_STEPS] = sc.n_steps
    out[FINAL_LOCKED] = 1.0 if sc.locked else 0.0
    out[HIT_STEP_LIMIT] = (
        1.0 if (sc.out_of_work or (sc.effort >= opts.max_steps and sc.t < sc.t_stop)) else 0.0
    )
    if sc.past:
        copy(w.y, w.y_end)
    if not sc.locked:
        out[LOCKUP_TIME] = np.nan
        out[ACCEL_JUMP] = np.nan
    _energies(q, compliant, out, w.y)


@njit(**INLINE)
def _energies(q, compliant, out, y):
    """Works, kinetic (and spring) energy change and the energy balance's relative residual."""
    wh, wr = y[H], y[R if compliant else H]
    if compliant:
        k_el = q[K] if math.isfinite(q[K]) else 0.0
        dke = (
            0.5 * q[JH] * (wh**2 - q[WC0] ** 2)
            + 0.5 * q[JR] * (wr**2 - q[WC0] ** 2)
            + 0.5 * k_el * y[TH] ** 2
        )
    else:
        dke = 0.5 * q[JV] * (wh**2 - q[WC0] ** 2)
    if not q[HELD] > 0.0:
        dke += 0.5 * q[JE] * (y[E] ** 2 - q[WE0] ** 2)
    w_in, w_s, w_l, w_d = y[WI], y[WS], y[WL], y[WD]
    out[SLIP_WORK] = w_s
    out[LOAD_WORK] = w_l
    out[INPUT_WORK] = w_in
    out[KINETIC_ENERGY_CHANGE] = dke
    out[DAMPING_WORK] = w_d
    out[ENERGY_RESIDUAL] = (w_in - dke - w_s - w_l - w_d) / max(abs(w_in), abs(w_s), 1e-300)


# ---- the batch ---------------------------------------------------------------------------------


@njit(**JIT)
def _batch_rigid(Q, prof, tt, opts, out, trace, ws, fm, pl, hist, scs, ec):
    """Every scenario of the rigid model (the flag a constant: its branches compiled away)."""
    for i in range(Q.shape[0]):
        _simulate_one(Q[i], False, prof, tt, opts, out[i], trace[i], ws, fm, pl, hist, scs, ec)


@njit(**JIT)
def _batch_compliant(Q, prof, tt, opts, out, trace, ws, fm, pl, hist, scs, ec):
    """Every scenario of the compliant model."""
    for i in range(Q.shape[0]):
        _simulate_one(Q[i], True, prof, tt, opts, out[i], trace[i], ws, fm, pl, hist, scs, ec)


@njit(**JIT)
def _batch_exact(Q, prof, tt, opts, out, trace, ws, fm, pl, hist, scs):
    """Every scenario of the compliant model whose phases are all linear (:func:`linear_rows`)."""
    for i in range(Q.shape[0]):
        _simulate_exact(Q[i], prof, tt, opts, out[i], trace[i], ws, fm, pl, hist, scs)


@njit(**JIT)
def _linear_rows(Q, lin):
    for i in range(Q.shape[0]):
        lin[i] = is_linear(Q[i], False)


def linear_rows(Q):
    """Which rows of the parameter table Q are compliant scenarios with every phase linear
    (:func:`clutchlab.engagement._physics.is_linear` while slipping, hence also while locked)."""
    lin = np.empty(Q.shape[0], dtype=bool)
    _linear_rows(Q, lin)
    return lin


def new_work():
    """The batch's scratch arrays (:class:`Work`, full state length; cut per scenario)."""
    vec = [np.empty(N_STATE) for _ in range(11)]
    ev = [np.empty(N_EVENTS) for _ in range(4)]
    return Work(
        *vec,
        np.empty((7, N_STATE)),
        *ev,
        np.empty(N_MAXIMA),
        np.empty(5),
        np.empty((5, N_STATE)),
        np.empty(N_STATE),
        np.empty(N_STATE),
    )


def _rows(kernel, rows, Q, prof, tt, opts, out, trace, scratch):
    """Run ``kernel`` on the rows of Q where ``rows`` is True, into those rows of out and trace."""
    if rows.all():
        kernel(Q, prof, tt, opts, out, trace, *scratch)
        return
    o, tr = out[rows], trace[rows]
    kernel(Q[rows], prof, tt, opts, o, tr, *scratch)
    out[rows], trace[rows] = o, tr


def simulate_batch(
    Q, compliant, prof, tt, rtol, atol, max_step, first_step, max_steps, with_hist=False, peaks=True
):
    """Run every row of the parameter table Q; returns (results, traces). The rigid and the
    compliant model are compiled separately (the constant flag removes their branches: ~25 %), and
    the compliant scenarios whose phases are all linear (constant μ, no rotor drag or engine
    torque table) by a loop of their own (:func:`_batch_exact`): a run that has only those
    compiles that loop alone (49 s of CPU from an empty cache against 142 s for the other).
    Without ``peaks`` the exact linear phases and the collocated slipping phases leave the peak
    friction torque and output jerk out (NaN in the results; DOPRI5's, taken at its steps anyway,
    are dropped too)."""
    n = Q.shape[0]
    out = np.empty((n, N_RESULTS))
    trace = np.full((n, tt.size, N_TRACES), np.nan)
    opts = Options(
        float(rtol),
        float(atol),
        float(max_step),
        float(first_step),
        int(max_steps),
        bool(with_hist),
        bool(peaks),
    )
    hist = np.empty((3, POWER_SAMPLES_MAX))  # the slip power history of one scenario (_power)
    scratch = (new_work(), new_forms(), new_polys(), hist, np.zeros(1, SCENARIO))
    exact = linear_rows(Q) if compliant else np.zeros(n, dtype=bool)
    if exact.any():  # (every row of the default study: no integrator compiled or called)
        _rows(_batch_exact, exact, Q, prof, tt, opts, out, trace, scratch)
    if not exact.all():
        run = _batch_compliant if compliant else _batch_rigid
        ec = new_colloc()  # the collocated slipping phases' record
        _rows(run, ~exact, Q, prof, tt, opts, out, trace, (*scratch, ec))
    return out, trace
