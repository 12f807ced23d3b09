"""Compiled (numba) stiff contact dynamics: an L-stable SDIRK integrator and the systems it runs.

Hairer & Wanner's 5-stage, order-4 singly diagonally implicit Runge-Kutta method (γ = 1/4,
stiffly accurate, L-stable; Solving ODEs II, Table IV.6.5 "SDIRK4") with its embedded order-3
solution for the error estimate. Each stage is solved by a simplified Newton iteration with the
Jacobian evaluated once per step and the matrix I − hγJ inverted once per step (n ≤ 8: a dense
inverse, cheaper than substitution for ~10 solves); a stage is solved when θ/(1 − θ) times the
scaled Newton increment (θ the contraction rate) is below 0.03, as in Hairer's RADAU5, usually
after one iteration. The error estimate is filtered through (I − hγJ)⁻¹ as in Hairer's codes, so
that stiff components do not force tiny steps. All functions use numba's numpy error model (no
division checks): with Python's, the right-hand side cost 100 ns instead of 6. Every function
below the per-scenario driver allocates nothing and is compiled without numba's reference
counting (``_nrt=False``): the atomic count updates on each call with array arguments were
about half of the run time. (The driver keeps its own small arrays: views of one shared scratch
array, which would let it run without reference counting too, made it 15 % slower.)

Systems (``system`` argument): ``IMPACT`` (a mass hitting a wall through the contact law, the
analytic Hertz reference case) and ``ROLLER`` (the wedging of the roller clutch of seed 003). The
right-hand sides are dispatched by number rather than passed as functions so that numba can cache
the compiled code on disk (first-class function arguments defeat its cache). Physics documented
in :mod:`clutchlab.contact` and :mod:`clutchlab.roller`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

GAMMA = 0.25
_A = np.zeros((5, 5))
for _i, _row in enumerate(
    [
        [1 / 4],
        [1 / 2, 1 / 4],
        [17 / 50, -1 / 25, 1 / 4],
        [371 / 1360, -137 / 2720, 15 / 544, 1 / 4],
        [25 / 24, -49 / 48, 125 / 16, -85 / 12, 1 / 4],
    ]
):
    _A[_i, : len(_row)] = _row
C = _A.sum(axis=1)
B = _A[4].copy()
BHAT = np.array([59 / 48, -17 / 96, 225 / 32, -85 / 12, 0.0])
_E = B - BHAT
ORDER_EMBEDDED = 3
NEWTON_MAXIT = 8
NEWTON_TOL = (
    0.03  # scaled Newton increment (in units of the local tolerance) at which a stage is solved
)


@njit(cache=True, error_model="numpy", _nrt=False)
def invert(m, inv):
    """Gauss-Jordan inverse with partial pivoting of a small dense matrix into ``inv`` (``m`` is
    destroyed); False if singular. For n ≤ 8 and ~10 solves per factorisation a matrix-vector
    product with the inverse is cheaper than LU substitution."""
    n = m.shape[0]
    for i in range(n):
        for j in range(n):
            inv[i, j] = 1.0 if i == j else 0.0
    for k in range(n):
        p = k
        big = abs(m[k, k])
        for i in range(k + 1, n):
            if abs(m[i, k]) > big:
                big, p = abs(m[i, k]), i
        if big == 0.0:
            return False
        if p != k:
            for j in range(n):
                m[k, j], m[p, j] = m[p, j], m[k, j]
                inv[k, j], inv[p, j] = inv[p, j], inv[k, j]
        r = 1.0 / m[k, k]
        for j in range(n):
            m[k, j] *= r
            inv[k, j] *= r
        for i in range(n):
            if i != k:
                a = m[i, k]
                if a != 0.0:
                    for j in range(n):
                        m[i, j] -= a * m[k, j]
                        inv[i, j] -= a * inv[k, j]
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def solve(inv, b, out):
    """out = inv @ b (small dense)."""
    n = b.size
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += inv[i, j] * b[j]
        out[i] = acc


@njit(cache=True, error_model="numpy", _nrt=False)
def scaled_norm(v, y0, y1, rtol, atol):
    """RMS of v / (atol_i + rtol·max(|y0_i|, |y1_i|))."""
    acc = 0.0
    for i in range(v.size):
        acc += (v[i] / (atol[i] + rtol * max(abs(y0[i]), abs(y1[i])))) ** 2
    return math.sqrt(acc / v.size)


@njit(cache=True, error_model="numpy", _nrt=False)
# noqa reason: numba kernel: one SDIRK4 step with its Newton loop and error filter, kept whole so numba inlines it
def sdirk4_step(system, t, y, h, p, mode, rtol, atol, y_new, work):  # noqa: C901
    """One SDIRK4 step from (t, y) of size h. Writes y_new; returns (ok, error norm, f evals).

    ``work`` is a (3n + 14, n) scratch array (the last row is the event location's); after the
    step its row 2n + 11 holds f(t, y) and row 2n + 4 the derivative at the step's end (stiffly
    accurate), for Hermite interpolation. ok is False when the Newton iteration fails (the caller
    shrinks the step). Newton increments are
    measured in the weights 1/(atol + rtol·|y|) of the step's start."""
    n = y.size
    jac = work[0:n]
    m = work[n : 2 * n]
    k = work[2 * n : 2 * n + 5]
    f = work[2 * n + 5]
    w = work[2 * n + 6]
    z = work[2 * n + 7]
    dz = work[2 * n + 8]
    err = work[2 * n + 9]
    f0 = work[2 * n + 11]
    eta = work[2 * n + 12]  # eta[0]: Newton convergence factor, carried from step to step
    eta[0] = max(eta[0], 1e-16) ** 0.8 if eta[0] > 0 else 1.0
    inv = work[2 * n + 13 : 3 * n + 13]
    wt = work[2 * n + 10]  # error weights (the event functions' scratch row is free during a step)
    for i in range(n):
        wt[i] = 1.0 / (atol[i] + rtol * abs(y[i]))
    rhs(system, t, y, p, mode, f0, jac, True)
    nfev = 1
    hg = h * GAMMA
    inv_hg = 1.0 / hg
    tol2 = NEWTON_TOL * NEWTON_TOL * n
    for i in range(n):
        for j in range(n):
            m[i, j] = -hg * jac[i, j]
        m[i, i] += 1.0
    if not invert(m, inv):
        return False, np.inf, nfev
    for s in range(5):
        for i in range(n):
            acc = y[i]
            for j in range(s):
                acc += h * _A[s, j] * k[j, i]
            w[i] = acc
            z[i] = acc + (hg * k[s - 1, i] if s > 0 else hg * f0[i])
        converged = False
        last = np.inf
        for it in range(NEWTON_MAXIT):
            rhs(system, t + C[s] * h, z, p, mode, f, jac, False)
            nfev += 1
            for i in range(n):
                err[i] = w[i] + hg * f[i] - z[i]  # Newton residual (err is free until the end)
            solve(inv, err, dz)
            nrm = 0.0  # squared weighted norm times n
            for i in range(n):
                z[i] += dz[i]
                nrm += (dz[i] * wt[i]) ** 2
            if (
                it > 0
            ):  # contraction rate θ; the remaining error is about θ/(1 − θ) times the increment
                theta = math.sqrt(nrm / last)
                if theta >= 0.99:
                    break
                eta[0] = theta / (1.0 - theta)
            if eta[0] * eta[0] * nrm < tol2 or nrm < 1e-28:
                converged = True
                break
            last = nrm
        if not converged:
            return False, np.inf, nfev
        for i in range(n):
            k[s, i] = (z[i] - w[i]) * inv_hg
    for i in range(n):
        y_new[i] = z[i]  # stiffly accurate: the last stage is the solution
        acc = 0.0
        for s in range(5):
            acc += _E[s] * k[s, i]
        dz[i] = h * acc
    solve(inv, dz, err)
    return True, scaled_norm(err, y, y_new, rtol, atol), nfev


@njit(cache=True, error_model="numpy", _nrt=False)
def new_step(h, err_norm):
    """Step-size controller for the order-3 embedded estimate (safety 0.9, factor 0.2-5)."""
    if err_norm == 0.0:
        return 5.0 * h
    return h * min(5.0, max(0.2, 0.9 * err_norm ** (-1.0 / (ORDER_EMBEDDED + 1))))


@njit(cache=True, error_model="numpy", _nrt=False)
def _hermite(y0, f0, y1, f1, h, th, out):
    a, b = th * th * (2.0 * th - 3.0) + 1.0, th * (th - 1.0) * (th - 1.0)
    c, d = th * th * (3.0 - 2.0 * th), th * th * (th - 1.0)
    for i in range(y0.size):
        out[i] = a * y0[i] + b * h * f0[i] + c * y1[i] + d * h * f1[i]


@njit(cache=True, error_model="numpy", _nrt=False)
def hermite_root(system, which, t, y, f0, y1, f1, h, g0, g1, p, mode, work):
    """Root θ·h in (0, h] of event ``which`` on the step's cubic Hermite interpolant (Illinois; no
    right-hand-side evaluations except those the event function itself needs)."""
    yt = work[work.shape[0] - 1]  # the last scratch row (see sdirk4_step)
    lo, hi, glo, ghi, side = 0.0, 1.0, g0, g1, 0
    for _ in range(100):
        if hi - lo <= 1e-14:
            break
        x = (lo * ghi - hi * glo) / (ghi - glo)
        if not (lo < x < hi):
            x = 0.5 * (lo + hi)
        _hermite(y, f0, y1, f1, h, x, yt)
        gx = event(system, t + x * h, yt, p, mode, which, work)
        if gx == 0.0:
            return x * h
        if (gx > 0) == (glo > 0):
            lo, glo = x, gx
            if side == -1:
                ghi *= 0.5
            side = -1
        else:
            hi, ghi = x, gx
            if side == 1:
                glo *= 0.5
            side = 1
    return hi * h


@njit(cache=True, error_model="numpy", _nrt=False)
def locate(system, which, t, y, f0, y1, f1, h, g0, g1, p, mode, rtol, atol, y_out, work, time_tol):
    """Event location: the step size h* in (0, h] at which event ``which`` of :func:`event` (g0 at
    the step's start, g1 at its end, opposite signs) is zero on the integrator's own solution: the
    root on the step's Hermite interpolant as first guess, then true SDIRK steps from (t, y) —
    secant iterations from the guess and a probe next to it while they stay inside the bracket,
    Illinois on the bracket otherwise — until the bracket is narrower than ``time_tol``.
    f0, f1: derivatives at the step's ends (copies of the step's work rows, see sdirk4_step).
    Writes the state at t + h* into y_out (and leaves the work rows of that step); returns
    (h*, f evals)."""
    x = min(
        max(hermite_root(system, which, t, y, f0, y1, f1, h, g0, g1, p, mode, work), time_tol), h
    )
    lo, hi, glo, ghi = 0.0, h, g0, g1
    xp, gp = -1.0, 0.0  # previous true point (for the secant)
    nfev = 0
    for it in range(60):
        ok, _, nf = sdirk4_step(system, t, y, x, p, mode, rtol, atol, y_out, work)
        nfev += nf
        gx = event(system, t + x, y_out, p, mode, which, work) if ok else glo
        if gx == 0.0:
            return x, nfev
        if (gx > 0) == (glo > 0):
            lo, glo = x, gx
        else:
            hi, ghi = x, gx
        if hi - lo <= time_tol:
            break
        if it == 0:  # a probe next to the guess, on the root's side
            xn = x + max(1e-9 * h, 2.0 * time_tol) * (1.0 if x == lo else -1.0)
        else:  # secant through the last two true points
            xn = x - gx * (x - xp) / (gx - gp) if gx != gp else -1.0
            if it > 6 or not (lo < xn < hi):
                xn = (lo * ghi - hi * glo) / (ghi - glo)
                if not (lo < xn < hi) or it > 12:
                    xn = 0.5 * (lo + hi)
        xp, gp = x, gx
        x = min(max(xn, lo + 0.25 * time_tol), hi - 0.25 * time_tol)
    if x != hi:
        sdirk4_step(system, t, y, hi, p, mode, rtol, atol, y_out, work)
        nfev += 5
    return hi, nfev


# ----------------------------------------------------------------------------------- systems
IMPACT, ROLLER = 0, 1
# roller parameter columns
(WD, TL, JW, JO, RC, Z, TH, TA, MU, K, EXP, CD, DMAX, D0, TREL, CLR, TEND, HMAX, WSYNC) = range(19)
N_PARAM = 19
# mode bits: the wedge ring slipping on (SLIP) or stuck to (STICK) the driving ring; the driven ring
# held at rest by its passive load (HELD) or turning
SLIP, STICK, HELD = 0, 1, 2
# roller events (each falls through zero from > 0); BREAKAWAY: the wedge's drive torque on a held
# driven ring reaches the load; STOP: a turning driven ring comes to rest
EV_STICK, EV_SYNC, EV_PEAK, EV_RELEASE, EV_BREAKAWAY, EV_STOP = range(6)
N_EVENTS = 6
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
    STATUS,
) = range(12)
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
    "status",
)
ST_OK, ST_NEVER, ST_FAIL = 0, 4, 6  # clutchlab.status codes: ok, never_locked, not_converged
EVENT_TIME_TOL = 1e-14  # s


@njit(cache=True, error_model="numpy", _nrt=False)
def contact_force(d, dd, k, e, c, dmax):
    """Scalar contact law: (F, ∂F/∂δ, ∂F/∂δ̇, unclipped F) — see :func:`clutchlab.contact.impact_force`."""
    if d <= 0.0:
        return 0.0, 0.0, 0.0, k * d  # sign-carrying value for event location (separation)
    x = d / dmax
    if x < 1.0:
        s, ds = x * x * (3.0 - 2.0 * x), 6.0 * x * (1.0 - x) / dmax
    else:
        s, ds = 1.0, 0.0
    de = d * math.sqrt(d) if e == 1.5 else d**e  # the Hertz exponent without pow()
    f = k * de + s * c * dd
    if f <= 0.0:
        return 0.0, 0.0, 0.0, f
    return f, k * e * de / d + ds * c * dd, s * c, f


@njit(cache=True, error_model="numpy", _nrt=False)
def _claw(t, p):
    """Shift ξ of the rollers toward the wide end of the wedge by the stopped control ring, and its rate."""
    if t <= p[TREL]:
        return 0.0, 0.0
    xi = p[RC] * p[WD] * (t - p[TREL]) - p[CLR]
    if xi <= 0.0:
        return 0.0, 0.0
    return xi, p[RC] * p[WD]


@njit(cache=True, error_model="numpy", _nrt=False)
def _roller_contact(t, y, p, mode):
    """Penetration, its rate, and the force law at state y (all loaded rollers alike)."""
    xi, xid = _claw(t, p)
    ww = p[WD] if mode & STICK else y[1]
    ud = p[RC] * (ww - y[3])
    d = p[D0] + 0.5 * p[TH] * y[2] - 0.5 * p[TA] * xi
    dd = 0.5 * p[TH] * ud - 0.5 * p[TA] * xid
    return d, dd, contact_force(d, dd, p[K], p[EXP], p[CD], p[DMAX])


@njit(cache=True, error_model="numpy", _nrt=False)
def _roller_rhs(t, y, p, mode, f, jac, want_jac):
    rc, th = p[RC], p[TH]
    _, _, (F, dF, dFd, _) = _roller_contact(t, y, p, mode)
    a_w = p[Z] * rc * (p[MU] - th) / p[JW]
    a_o = p[Z] * rc * th / p[JO]
    slip = (mode & STICK) == 0
    turning = (mode & HELD) == 0  # a held driven ring stays at rest: its load holds it
    ww = y[1] if slip else p[WD]
    f[0] = rc * (p[WD] - ww) if slip else 0.0
    f[1] = a_w * F if slip else 0.0
    f[2] = rc * (ww - y[3])
    # the passive load opposes the motion of a turning ring (which only turns forward: it stops
    # and is held at rest before it could turn backwards, EV_STOP)
    f[3] = a_o * F - p[TL] / p[JO] if turning else 0.0
    if want_jac:
        g1 = 0.5 * dFd * th * rc if slip else 0.0
        g2 = 0.5 * dF * th
        g3 = -0.5 * dFd * th * rc
        for i in range(4):
            for j in range(4):
                jac[i, j] = 0.0
        if slip:
            jac[0, 1] = -rc
            jac[1, 1], jac[1, 2], jac[1, 3] = a_w * g1, a_w * g2, a_w * g3
            jac[2, 1] = rc
        jac[2, 3] = -rc
        if turning:
            jac[3, 1], jac[3, 2], jac[3, 3] = a_o * g1, a_o * g2, a_o * g3


@njit(cache=True, error_model="numpy", _nrt=False)
def _impact_rhs(y, p, f, jac, want_jac):
    m, k, e, c, dmax = p[0], p[1], p[2], p[3], p[4]
    F, dF, dFd, _ = contact_force(y[0], y[1], k, e, c, dmax)
    f[0] = y[1]
    f[1] = -F / m
    if want_jac:
        jac[0, 0], jac[0, 1] = 0.0, 1.0
        jac[1, 0], jac[1, 1] = -dF / m, -dFd / m


@njit(cache=True, error_model="numpy", _nrt=False)
def rhs(system, t, y, p, mode, f, jac, want_jac):
    if system == IMPACT:
        _impact_rhs(y, p, f, jac, want_jac)
    else:
        _roller_rhs(t, y, p, mode, f, jac, want_jac)


@njit(cache=True, error_model="numpy", _nrt=False)
def event(system, t, y, p, mode, which, work):
    """Event functions; each event is a fall through zero from > 0."""
    if system == IMPACT:
        return y[0] if which == 0 else y[1]  # 0: separation, 1: maximum penetration
    if which == EV_STICK:
        return p[WD] - y[1]
    if which == EV_SYNC:
        return p[WSYNC] - y[3]
    if which == EV_STOP:
        return y[3]
    d, dd, (F, dF, dFd, Fu) = _roller_contact(t, y, p, mode)
    if which == EV_RELEASE:
        return d  # the rollers come free: penetration back to zero
    if which == EV_BREAKAWAY:
        return p[TL] - p[Z] * p[RC] * p[TH] * F  # load minus the wedge's drive torque
    # EV_PEAK: dF/dt = ∂F/∂δ·δ̇ + ∂F/∂δ̇·δ̈ with δ̈ = (tan(α/2)/2)·R_C·(dω_w/dt − dω_o/dt)
    n = y.size
    f = work[2 * n + 10]
    rhs(system, t, y, p, mode, f, work[0:n], False)
    return dF * dd + dFd * 0.5 * p[TH] * p[RC] * (f[1] - f[3])


@njit(cache=True, error_model="numpy", _nrt=False)
def initial_mode(p):
    """The mode at t = 0: the wedge ring slipping (it starts at rest), the driven ring held by its
    load unless the spring preload's drive torque already exceeds it."""
    # at rest (y = 0, the claws not yet moving) the rollers hold their preload penetration D0
    F, _, _, _ = contact_force(p[D0], 0.0, p[K], p[EXP], p[CD], p[DMAX])
    return SLIP | HELD if p[Z] * p[RC] * p[TH] * F < p[TL] else SLIP


@njit(cache=True, error_model="numpy", _nrt=False)
def switching_active(e, mode, t, p):
    """Whether switching event ``e`` can happen in ``mode`` at time ``t``."""
    if e == EV_STICK:
        return (mode & STICK) == 0
    if e == EV_RELEASE:
        return t >= p[TREL]
    if e == EV_BREAKAWAY:
        return (mode & HELD) != 0
    return (mode & HELD) == 0  # EV_STOP


@njit(cache=True, error_model="numpy", _nrt=False)
def switch_mode(mode, e, y, p):
    """The mode after switching event ``e`` (the state ``y`` made exact: the wedge ring at the
    driving speed once stuck, the driven ring at rest once held)."""
    if e == EV_STICK:
        y[1] = p[WD]
        return mode | STICK
    if e == EV_STOP:
        y[3] = 0.0
        return mode | HELD
    if e == EV_BREAKAWAY:
        return mode & ~HELD
    return mode


SWITCHING = np.array([EV_STICK, EV_RELEASE, EV_BREAKAWAY, EV_STOP])


# ----------------------------------------------------------------------------------- drivers
@njit(cache=True, error_model="numpy")
def impact(p, v, rtol, atol, h0, max_steps):
    """Hertz impact of a mass on a wall: (max penetration, its time, contact time, restitution, f evals).
    At most ``max_steps`` step attempts (accepted, rejected or failed): NaN results beyond."""
    y = np.array([0.0, v])
    y_new = np.zeros(2)
    y_ev = np.zeros(2)
    work = np.zeros((20, 2))
    t, h = 0.0, h0
    dmax_pen, t_max = 0.0, 0.0
    nfev = 0
    for _ in range(max_steps):
        ok, err, nf = sdirk4_step(IMPACT, t, y, h, p, 0, rtol, atol, y_new, work)
        nfev += nf
        if not ok or err > 1.0:
            h = 0.25 * h if not ok else new_step(h, err)
            continue
        if y[1] > 0.0 and y_new[1] <= 0.0:
            f0, f1 = work[15].copy(), work[8].copy()  # rows 2n + 11, 2n + 4 (n = 2)
            hx, nf = locate(
                IMPACT,
                1,
                t,
                y,
                f0,
                y_new,
                f1,
                h,
                y[1],
                y_new[1],
                p,
                0,
                rtol,
                atol,
                y_ev,
                work,
                EVENT_TIME_TOL * max(t / 1e-3, 1e-3),
            )
            nfev += nf
            dmax_pen, t_max = y_ev[0], t + hx
        if y_new[0] <= 0.0 and t > 0.0:
            f0, f1 = work[15].copy(), work[8].copy()  # rows 2n + 11, 2n + 4 (n = 2)
            hx, nf = locate(
                IMPACT,
                0,
                t,
                y,
                f0,
                y_new,
                f1,
                h,
                y[0],
                y_new[0],
                p,
                0,
                rtol,
                atol,
                y_ev,
                work,
                EVENT_TIME_TOL * max(t / 1e-3, 1e-3),
            )
            nfev += nf
            return dmax_pen, t_max, t + hx, -y_ev[1] / v, nfev
        t += h
        y[:] = y_new
        h = new_step(h, err)
    return np.nan, np.nan, np.nan, np.nan, nfev


@njit(cache=True, error_model="numpy")
def _earliest_switch(t, y, f0, y_best, f1, h_acc, p, mode, rtol, atol, y_ev, work):
    """The earliest switching event on the accepted piece [t, t + h_acc] (from y to y_best, with
    derivatives f0, f1): (event or -1, the piece's new length, f evals). Each event found cuts the
    piece at its located time (y_best, f1 updated), so the last one found is the earliest."""
    switch, nfev = -1, 0
    n = y.size
    for e in SWITCHING:
        if not switching_active(e, mode, t, p):
            continue
        ga = event(ROLLER, t, y, p, mode, e, work)
        gb = event(ROLLER, t + h_acc, y_best, p, mode, e, work)
        if ga > 0.0 and gb <= 0.0:
            hx, nf = locate(
                ROLLER, e, t, y, f0, y_best, f1, h_acc, ga, gb, p, mode, rtol, atol, y_ev, work,
                EVENT_TIME_TOL,
            )  # fmt: skip
            nfev += nf
            h_acc = hx
            y_best[:] = y_ev
            f1[:] = work[2 * n + 4]
            switch = e
    return switch, h_acc, nfev


@njit(cache=True, error_model="numpy")
# noqa reason: numba kernel: one scenario's event loop (stick, breakaway, engagement, peaks, release)
def _roller_one(p, rtol, max_steps, res, trace, n_trace):  # noqa: C901
    """One roller-clutch engagement (and release); fills ``res``; returns the trace length."""
    n = 4
    y = np.zeros(n)
    y_new = np.zeros(n)
    y_ev = np.zeros(n)
    y_best = np.zeros(n)
    f0, f1 = np.zeros(n), np.zeros(n)
    work = np.zeros((3 * n + 14, n))
    atol = np.array([rtol * 1e-4, rtol * p[WD], rtol * 1e-4, rtol * p[WD]])
    mode = initial_mode(p)
    t = 0.0
    h = min(1e-8, p[HMAX])
    for k in range(N_STEPS):
        res[k] = np.nan
    res[PEAK_FORCE] = 0.0
    synced = False
    breaks = np.array([p[TREL], p[TREL] + p[CLR] / (p[RC] * p[WD]), p[TEND]])
    n_tr = 0
    steps, nfev, n_rej, n_fail = 0, 0, 0, 0
    status = ST_OK
    while t < p[TEND]:
        if steps + n_rej + n_fail >= max_steps:  # work: every attempt, accepted or not
            status = ST_FAIL
            break
        nb = p[TEND]
        for b in breaks:
            if b > t * (1.0 + 1e-15) and b < nb:
                nb = b
        hs = min(h, nb - t, p[HMAX])
        ok, err, nf = sdirk4_step(ROLLER, t, y, hs, p, mode, rtol, atol, y_new, work)
        nfev += nf
        if not ok:
            n_fail += 1
            h = 0.25 * hs
            if h < 1e-18:
                status = ST_FAIL
                break
            continue
        if err > 1.0:
            n_rej += 1
            h = new_step(hs, err)
            continue
        steps += 1
        f0[:] = work[2 * n + 11]
        f1[:] = work[2 * n + 4]
        h_acc = hs
        y_best[:] = y_new
        # switching events (they change the equations): the step ends at the earliest one
        switch, h_acc, nf = _earliest_switch(
            t, y, f0, y_best, f1, h_acc, p, mode, rtol, atol, y_ev, work
        )
        nfev += nf
        # recording events on the accepted piece [t, t + h_acc] (the step is not cut)
        if not synced:
            ga = event(ROLLER, t, y, p, mode, EV_SYNC, work)
            gb = event(ROLLER, t + h_acc, y_best, p, mode, EV_SYNC, work)
            if ga > 0.0 and gb <= 0.0:
                hx, nf = locate(
                    ROLLER, EV_SYNC, t, y, f0, y_best, f1, h_acc, ga, gb, p, mode, rtol, atol,
                    y_ev, work, EVENT_TIME_TOL,
                )  # fmt: skip
                nfev += nf
                synced = True
                res[SYNC_TIME] = t + hx
                res[TOTAL_BACKLASH] = (y_ev[0] + y_ev[2]) / p[RC]
        ga = event(ROLLER, t, y, p, mode, EV_PEAK, work)
        gb = event(ROLLER, t + h_acc, y_best, p, mode, EV_PEAK, work)
        if ga > 0.0 and gb <= 0.0:
            # a force maximum inside the piece: its value from a true step to the interpolant's root
            hx = hermite_root(ROLLER, EV_PEAK, t, y, f0, y_best, f1, h_acc, ga, gb, p, mode, work)
            if hx < h_acc:
                ok, _, nf = sdirk4_step(ROLLER, t, y, hx, p, mode, rtol, atol, y_ev, work)
                nfev += nf
                _, _, (fp, _, _, _) = _roller_contact(t + hx, y_ev, p, mode)
                res[PEAK_FORCE] = max(res[PEAK_FORCE], fp)
        t += h_acc
        y[:] = y_best
        _, _, (F, _, _, _) = _roller_contact(t, y, p, mode)
        res[PEAK_FORCE] = max(res[PEAK_FORCE], F)
        best = switch
        if best >= 0:
            mode = switch_mode(mode, best, y, p)
        if best == EV_STICK:
            res[STICK_TIME] = t
            res[SLIP_BACKLASH] = y[0] / p[RC]
        elif best == EV_RELEASE:
            res[RELEASE_TIME] = t - p[TREL]
        if n_tr < n_trace:
            trace[n_tr, 0], trace[n_tr, 1] = t, p[WD]
            trace[n_tr, 2] = y[1] if (mode & STICK) == 0 else p[WD]
            trace[n_tr, 3], trace[n_tr, 4] = y[3], F
            n_tr += 1
        if best == EV_RELEASE:
            break
        # model only what is asked: without a release, stop once engaged and past the force peak
        if synced and not p[TREL] < np.inf and event(ROLLER, t, y, p, mode, EV_PEAK, work) <= 0.0:
            break
        h = new_step(hs, err) if best < 0 else max(h_acc, 1e-3 * hs)
    _, _, (F, _, _, _) = _roller_contact(t, y, p, mode)
    res[FINAL_FORCE] = F
    if status == ST_OK and not synced:
        status = ST_NEVER
    res[N_STEPS], res[N_FEV], res[N_REJECTED], res[N_NEWTON_FAIL], res[STATUS] = (
        steps,
        nfev,
        n_rej,
        n_fail,
        status,
    )
    return n_tr


@njit(cache=True, error_model="numpy")
def simulate_roller(P, rtol, max_steps, trace_row, n_trace):
    """Every scenario (rows of P); the trace (t, ω_d, ω_w, ω_o, F) of row ``trace_row``."""
    out = np.full((P.shape[0], len(RESULTS)), np.nan)
    trace = np.zeros((n_trace, 5))
    dummy = np.zeros((0, 5))
    n_tr = 0
    for i in range(P.shape[0]):
        if i == trace_row:
            n_tr = _roller_one(P[i], rtol, max_steps, out[i], trace, n_trace)
        else:
            _roller_one(P[i], rtol, max_steps, out[i], dummy, 0)
    return out, trace[:n_tr]
