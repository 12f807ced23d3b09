"""Compiled right-hand sides, Jacobians and event functions of the stiff-contact systems.

Two systems, dispatched by number (``system``) so that numba can cache the compiled code on disk
(first-class function arguments defeat its cache): ``IMPACT``, a mass hitting a wall through the
contact law (the analytic Hertz reference case, :func:`clutchlab.contact.hertz_impact`), and
``ROLLER``, the wedging of the roller clutch of the source paper (003)
(:func:`clutchlab.roller.simulate`; its equations are in :mod:`clutchlab.roller`).

The roller's state is y = (q, ω_w, u, ω_o): the slip travel at the friction interface [m], the
wedge ring's speed [rad/s], the tangential travel of the wedge ring over the driven ring [m] and
the driven ring's speed [rad/s]. Its parameters are a row of named columns (``WD`` … ``WSYNC``,
built by :func:`clutchlab.roller.parameter_rows`). Everything the rings feel passes through the
one contact force N(δ, δ̇) with δ = δ₀ + tan(α/2)·u/2 − tan(α)·ξ/2, so the compression obeys

    δ̈ = G·N(δ, δ̇) + H,   G = (tan(α/2)·R_C/2)·(a_w·[slipping] − a_o·[turning]),

a_w = z·R_C·(μ − tan(α/2))/J_w, a_o = z·R_C·tan(α/2)/J_o: the Jacobian has rank 2 and its two
non-zero eigenvalues solve λ² − G·N_δ̇·λ − G·N_δ = 0 (:func:`contact_rates`), which tells the
driver whether an explicit step would be stable.

All functions use numba's numpy error model (no division checks: with Python's, the right-hand
side cost 100 ns instead of 6) and no reference counting (``_nrt=False``: nothing here allocates).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

JIT = dict(cache=True, error_model="numpy", _nrt=False)

IMPACT, ROLLER = 0, 1
# roller parameter columns (clutchlab.roller.parameter_rows): driving speed, load torque, wedge
# and driven ring inertias, contact radius, loaded rollers, tan(α/2), tan(α), friction
# coefficient, contact stiffness, exponent, damping, penetration depth of full damping, preload
# penetration, control-ring stop time, claw clearance, end time, largest step, engagement speed,
# time the claws reach the rollers (TREL + CLR / (RC·WD))
(WD, TL, JW, JO, RC, Z, TH, TA, MU, K, EXP, CD, DMAX, D0, TREL, CLR, TEND, HMAX, WSYNC) = range(19)
TCLAW = 19
N_PARAM = 20
# impact parameter columns (clutchlab.contact.hertz_impact)
I_MASS, I_K, I_EXP, I_CD, I_DMAX = range(5)
# roller state components
Y_SLIP, Y_WEDGE, Y_TRAVEL, Y_DRIVEN = range(4)
# mode bits: the wedge ring slipping on (SLIP) or stuck to (STICK) the driving ring; the driven
# ring held at rest by its passive load (HELD) or turning; the stopped control ring's claws
# pushing the rollers toward the wide end of the wedge (CLAWS, from TCLAW on)
SLIP, STICK, HELD, CLAWS = 0, 1, 2, 4
# roller events, each a fall through zero from > 0: the wedge ring sticks; the driven ring reaches
# the engagement speed; a contact force maximum; the rollers come free; the wedge's drive torque on
# a held driven ring reaches the load (BREAKAWAY); a turning driven ring comes to rest (STOP)
EV_STICK, EV_SYNC, EV_PEAK, EV_RELEASE, EV_BREAKAWAY, EV_STOP = range(6)
N_EVENTS = 6
# the events that change the equations (a step ends at the earliest of them)
SWITCHING = np.array([EV_STICK, EV_RELEASE, EV_BREAKAWAY, EV_STOP])
# impact events: separation from the wall, maximum penetration
EV_SEPARATION, EV_MAX_PENETRATION = 0, 1


@njit(**JIT)
def contact_force(d, dd, k, e, c, dmax):
    """Scalar contact law (F, ∂F/∂δ, ∂F/∂δ̇, unclipped F) at penetration d [m] and its rate dd
    [m/s] — see :func:`clutchlab.contact.impact_force`."""
    if d <= 0.0:
        return 0.0, 0.0, 0.0, k * d  # sign-carrying value for event location (separation)
    # the damping steps in over the penetration depth (cubic STEP)
    x = d / dmax
    if x < 1.0:
        s, ds = x * x * (3.0 - 2.0 * x), 6.0 * x * (1.0 - x) / dmax
    else:
        s, ds = 1.0, 0.0
    de = d * math.sqrt(d) if e == 1.5 else d**e  # the Hertz exponent without pow()
    f = k * de + s * c * dd
    # a contact pushes, never pulls
    if f <= 0.0:
        return 0.0, 0.0, 0.0, f
    return f, k * e * de / d + ds * c * dd, s * c, f


@njit(**JIT)
def _claw(t, p, mode):
    """Shift ξ [m] of the rollers toward the wide end of the wedge by the stopped control ring's
    claws (once they have crossed their clearance, at TCLAW: the driver switches the CLAWS mode
    on there, so that no step straddles the kink), and its rate [m/s]."""
    if (mode & CLAWS) == 0:
        return 0.0, 0.0
    return p[RC] * p[WD] * (t - p[TCLAW]), p[RC] * p[WD]


@njit(**JIT)
def roller_contact(t, y, p, mode):
    """Penetration δ, its rate δ̇, and the force law (F, ∂F/∂δ, ∂F/∂δ̇, unclipped F) at state y
    (all loaded rollers alike)."""
    xi, xid = _claw(t, p, mode)
    ww = p[WD] if mode & STICK else y[Y_WEDGE]
    ud = p[RC] * (ww - y[Y_DRIVEN])
    d = p[D0] + 0.5 * p[TH] * y[Y_TRAVEL] - 0.5 * p[TA] * xi
    dd = 0.5 * p[TH] * ud - 0.5 * p[TA] * xid
    return d, dd, contact_force(d, dd, p[K], p[EXP], p[CD], p[DMAX])


@njit(**JIT)
def _gains(p, mode):
    """Angular accelerations per newton of contact force: of the wedge ring a_w (0 when stuck)
    and of the driven ring a_o (0 while held) [rad/(s² N)]."""
    a_w = p[Z] * p[RC] * (p[MU] - p[TH]) / p[JW] if (mode & STICK) == 0 else 0.0
    a_o = p[Z] * p[RC] * p[TH] / p[JO] if (mode & HELD) == 0 else 0.0
    return a_w, a_o


@njit(**JIT)
def _roller_f(y, p, mode, F, f):
    """The roller's right-hand side f at state y with contact force F."""
    a_w, a_o = _gains(p, mode)
    slip = (mode & STICK) == 0
    ww = y[Y_WEDGE] if slip else p[WD]
    f[Y_SLIP] = p[RC] * (p[WD] - ww) if slip else 0.0
    f[Y_WEDGE] = a_w * F
    f[Y_TRAVEL] = p[RC] * (ww - y[Y_DRIVEN])
    # the passive load opposes the motion of a turning ring (which only turns forward: it stops
    # and is held at rest before it could turn backwards, EV_STOP); a held ring stays at rest
    f[Y_DRIVEN] = a_o * F - p[TL] / p[JO] if (mode & HELD) == 0 else 0.0


@njit(**JIT)
def _roller_jac(p, mode, dF, dFd, jac):
    """The roller's Jacobian from the contact force's derivatives ∂F/∂δ, ∂F/∂δ̇."""
    rc, th = p[RC], p[TH]
    a_w, a_o = _gains(p, mode)
    slip = (mode & STICK) == 0
    # ∂F/∂ω_w, ∂F/∂u, ∂F/∂ω_o through δ̇ = tan(α/2)·R_C·(ω_w − ω_o)/2 and δ = δ₀ + tan(α/2)·u/2
    g1 = 0.5 * dFd * th * rc if slip else 0.0
    g2 = 0.5 * dF * th
    g3 = -0.5 * dFd * th * rc
    for i in range(4):
        for j in range(4):
            jac[i, j] = 0.0
    if slip:
        jac[Y_SLIP, Y_WEDGE] = -rc
        jac[Y_TRAVEL, Y_WEDGE] = rc
    jac[Y_TRAVEL, Y_DRIVEN] = -rc
    # the rings' accelerations: the contact force's gradient times their gains
    for j, g in ((Y_WEDGE, g1), (Y_TRAVEL, g2), (Y_DRIVEN, g3)):
        jac[Y_WEDGE, j] = a_w * g
        jac[Y_DRIVEN, j] = a_o * g


@njit(**JIT)
def _impact_rhs(y, p, f, jac, want_jac):
    """A mass on the contact law: y = (penetration [m], its rate [m/s])."""
    m = p[I_MASS]
    F, dF, dFd, _ = contact_force(y[0], y[1], p[I_K], p[I_EXP], p[I_CD], p[I_DMAX])
    f[0] = y[1]
    f[1] = -F / m
    if want_jac:
        jac[0, 0], jac[0, 1] = 0.0, 1.0
        jac[1, 0], jac[1, 1] = -dF / m, -dFd / m


@njit(**JIT)
def rhs(system, t, y, p, mode, f, jac, want_jac):
    """Right-hand side f(t, y) of ``system`` into ``f`` (and its Jacobian into ``jac``)."""
    if system == IMPACT:
        _impact_rhs(y, p, f, jac, want_jac)
        return
    _, _, (F, dF, dFd, _) = roller_contact(t, y, p, mode)
    _roller_f(y, p, mode, F, f)
    if want_jac:
        _roller_jac(p, mode, dF, dFd, jac)


@njit(**JIT)
def _roller_event(which, y, p, d, dd, F, dF, dFd, f):
    """Roller event ``which`` at state y with penetration d, its rate dd, the force law's F,
    ∂F/∂δ, ∂F/∂δ̇ and (for the force peak) the right-hand side f."""
    if which == EV_STICK:
        return p[WD] - y[Y_WEDGE]
    if which == EV_SYNC:
        return p[WSYNC] - y[Y_DRIVEN]
    if which == EV_STOP:
        return y[Y_DRIVEN]
    if which == EV_RELEASE:
        return d  # the rollers come free: penetration back to zero
    if which == EV_BREAKAWAY:
        return p[TL] - p[Z] * p[RC] * p[TH] * F  # load minus the wedge's drive torque
    # EV_PEAK: dF/dt = ∂F/∂δ·δ̇ + ∂F/∂δ̇·δ̈ with δ̈ = (tan(α/2)/2)·R_C·(dω_w/dt − dω_o/dt)
    ddd = 0.5 * p[TH] * p[RC] * (f[Y_WEDGE] - f[Y_DRIVEN])
    return dF * dd + dFd * ddd


@njit(**JIT)
def event(system, t, y, p, mode, which, f, jac):
    """Event function ``which`` at (t, y); each event is a fall through zero from > 0. ``f`` and
    ``jac`` are scratch arrays (the force peak needs the right-hand side)."""
    if system == IMPACT:
        return y[0] if which == EV_SEPARATION else y[1]
    d, dd, (F, dF, dFd, _) = roller_contact(t, y, p, mode)
    if which == EV_PEAK:
        _roller_f(y, p, mode, F, f)
    return _roller_event(which, y, p, d, dd, F, dF, dFd, f)


@njit(**JIT)
def _rates(p, mode, dF, dFd):
    """(decay, growth) of :func:`contact_rates` from the force law's ∂F/∂δ and ∂F/∂δ̇."""
    a_w, a_o = _gains(p, mode)
    g = 0.5 * p[TH] * p[RC] * (a_w - a_o)
    # λ² − b·λ − c = 0 with b = G·∂N/∂δ̇, c = G·∂N/∂δ
    b, c = g * dFd, g * dF
    disc = b * b + 4.0 * c
    if disc >= 0.0:  # two real roots
        r = math.sqrt(disc)
        return max(0.0, -0.5 * (b - r)), max(0.0, 0.5 * (b + r))
    # a complex pair, |λ|² = −c, Re λ = b/2
    return (math.sqrt(-c), 0.0) if b < 0.0 else (0.0, 0.5 * b)


@njit(**JIT)
def contact_rates(t, y, p, mode):
    """Rates [1/s] of the contact's two modes at (t, y), from the eigenvalues λ of the
    linearised δ̈ = G·N(δ, δ̇) + H: (decay, growth), the largest |λ| with Re λ < 0 (0 if none
    decays: an explicit step h is stable where h·decay lies inside its stability region) and the
    largest Re λ > 0 (0 if none grows: the wedging force's build-up while the wedge ring slips)."""
    _, _, (_, dF, dFd, _) = roller_contact(t, y, p, mode)
    return _rates(p, mode, dF, dFd)


@njit(**JIT)
def point_values(t, y, p, mode, g, f):
    """Everything the roller's driver needs at a point (t, y), from one evaluation of the force
    law: every event's value into g (indexed by EV_*), the right-hand side into f; returns the
    contact force [N] and the rates (decay, growth) [1/s] of :func:`contact_rates`."""
    d, dd, (F, dF, dFd, _) = roller_contact(t, y, p, mode)
    _roller_f(y, p, mode, F, f)
    for e in range(N_EVENTS):
        g[e] = _roller_event(e, y, p, d, dd, F, dF, dFd, f)
    decay, growth = _rates(p, mode, dF, dFd)
    return F, decay, growth


@njit(**JIT)
def initial_mode(p):
    """The mode at t = 0: the wedge ring slipping (it starts at rest), the driven ring held by its
    load unless the spring preload's drive torque already exceeds it."""
    # at rest (y = 0, the claws not yet moving) the rollers hold their preload penetration D0
    F, _, _, _ = contact_force(p[D0], 0.0, p[K], p[EXP], p[CD], p[DMAX])
    mode = SLIP | HELD if p[Z] * p[RC] * p[TH] * F < p[TL] else SLIP
    # the claws at the rollers from the start (control ring stopped at 0, no clearance)
    return mode | CLAWS if p[TCLAW] <= 0.0 else mode


@njit(**JIT)
def switching_active(e, mode, t, p):
    """Whether switching event ``e`` can happen in ``mode`` at time ``t``."""
    if e == EV_STICK:
        return (mode & STICK) == 0
    if e == EV_RELEASE:
        return t >= p[TREL]
    if e == EV_BREAKAWAY:
        return (mode & HELD) != 0
    return (mode & HELD) == 0  # EV_STOP


@njit(**JIT)
def switch_mode(mode, e, y, p):
    """The mode after switching event ``e`` (the state ``y`` made exact: the wedge ring at the
    driving speed once stuck, the driven ring at rest once held)."""
    if e == EV_STICK:
        y[Y_WEDGE] = p[WD]
        return mode | STICK
    if e == EV_STOP:
        y[Y_DRIVEN] = 0.0
        return mode | HELD
    if e == EV_BREAKAWAY:
        return mode & ~HELD
    return mode


@njit(**JIT)
def next_break(t, p):
    """The next time after t at which the equations change by the clock: the control ring stops
    (the release event is watched from then on), the claws reach the rollers, the end."""
    nb = p[TEND]
    for b in (p[TREL], p[TCLAW]):
        if b > t * (1.0 + 1e-15) and b < nb:
            nb = b
    return nb
