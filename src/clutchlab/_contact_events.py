"""Compiled event location on a step of the stiff-contact integrators.

An event is a fall through zero of one of the event functions of
:mod:`clutchlab._contact_systems` inside an accepted step (its value g0 > 0 at the step's start,
g1 ≤ 0 at the end of the piece looked at). Its time is the root of g on the step's interpolant,
found by the Illinois method to :data:`EVENT_TIME_TOL`:

* an explicit step (:mod:`clutchlab._dop853`): on its continuous extension of order 7, and the
  state there is the extension's (as Hairer's codes and scipy's ``solve_ivp`` do);
* an implicit step (:mod:`clutchlab._sdirk4`): the cubic Hermite interpolant gives the first
  guess only; the root is then located on the integrator's own solution by true SDIRK4 steps
  from the step's start (secant iterations from the guess and a probe next to it while they stay
  inside the bracket, Illinois on the bracket otherwise), because the cubic is less accurate than
  the step.

A piece is the part [t, t + h_piece] of a step of size h that is still looked at (an earlier
switching event cuts it); :data:`EventWork` holds its end state and, for an implicit step, the
derivatives at its ends.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

from . import _dop853, _sdirk4
from ._contact_systems import JIT, N_EVENTS, event

EXPLICIT, IMPLICIT = 0, 1
EVENT_TIME_TOL = 1e-14  # s
ROOT_MAXIT = 100
RESTEP_MAXIT = 60

#: the piece's derivatives at its start f0 and end f1 (implicit steps), its end state y_end, the
#: interpolant's value y_at, every event's value at the piece's start g0 and end g1 (indexed by the
#: event), and scratch f and jac for the event functions
EventWork = namedtuple("EventWork", ["f0", "f1", "y_end", "y_at", "g0", "g1", "f", "jac"])


@njit(cache=True, error_model="numpy")
def work(n):
    """A fresh :data:`EventWork` for systems of size n."""
    return EventWork(
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(N_EVENTS),
        np.zeros(N_EVENTS),
        np.zeros(n),
        np.zeros((n, n)),
    )


@njit(**JIT)
def piece_state(method, x, y, h, h_piece, dw, ew, out):
    """The interpolated state at time x ∈ [0, h_piece] after the start of a step of size h."""
    if method == EXPLICIT:
        _dop853.dense_state(dw, y, x / h, out)
    else:
        _sdirk4.hermite(y, ew.f0, ew.y_end, ew.f1, h_piece, x / h_piece, out)


@njit(**JIT)
def interpolant_root(system, which, method, t, y, h, h_piece, g0, g1, p, mode, dw, ew):
    """The time x ∈ (0, h_piece] after t at which event ``which`` (g0 > 0 at t, g1 ≤ 0 at
    t + h_piece) falls through zero on the step's interpolant (Illinois)."""
    lo, hi, glo, ghi, side = 0.0, h_piece, g0, g1, 0
    for _ in range(ROOT_MAXIT):
        if hi - lo <= EVENT_TIME_TOL:
            break
        # the regula falsi point, bisection if it falls outside the bracket
        x = (lo * ghi - hi * glo) / (ghi - glo)
        if not (lo < x < hi):
            x = 0.5 * (lo + hi)
        piece_state(method, x, y, h, h_piece, dw, ew, ew.y_at)
        gx = event(system, t + x, ew.y_at, p, mode, which, ew.f, ew.jac)
        if gx == 0.0:
            return x
        # Illinois: halve the value kept at the end that did not move twice in a row
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
    return hi


@njit(**JIT)
def restep_root(system, which, t, y, x, h_piece, g0, g1, p, mode, rtol, atol, y_out, sw, ew, tol):
    """The root of event ``which`` on true SDIRK4 steps from (t, y), from the guess x, to a
    bracket narrower than ``tol``: (x*, f evals); the state at t + x* in ``y_out`` and the
    derivative there in ``sw.f1``."""
    x = min(max(x, tol), h_piece)
    lo, hi, glo, ghi = 0.0, h_piece, g0, g1
    xp, gp = -1.0, 0.0  # the previous true point (for the secant)
    nfev = 0
    for it in range(RESTEP_MAXIT):
        # a true step to x and the event there
        ok, _, nf = _sdirk4.step(system, t, y, x, p, mode, rtol, atol, y_out, sw)
        nfev += nf
        gx = event(system, t + x, y_out, p, mode, which, ew.f, ew.jac) if ok else glo
        if gx == 0.0:
            return x, nfev
        if (gx > 0) == (glo > 0):
            lo, glo = x, gx
        else:
            hi, ghi = x, gx
        if hi - lo <= tol:
            break
        # the next point: a probe next to the guess on the root's side, then secants through
        # the last two true points, regula falsi and bisection when they leave the bracket
        if it == 0:
            xn = x + max(1e-9 * h_piece, 2.0 * tol) * (1.0 if x == lo else -1.0)
        else:
            xn = x - gx * (x - xp) / (gx - gp) if gx != gp else -1.0
            if it > 6 or not (lo < xn < hi):
                xn = (lo * ghi - hi * glo) / (ghi - glo)
                if not (lo < xn < hi) or it > 12:
                    xn = 0.5 * (lo + hi)
        xp, gp = x, gx
        x = min(max(xn, lo + 0.25 * tol), hi - 0.25 * tol)
    if x != hi:
        _sdirk4.step(system, t, y, hi, p, mode, rtol, atol, y_out, sw)
        nfev += 5
    return hi, nfev


@njit(**JIT)
def locate(system, which, method, t, y, h, h_piece, g0, g1, p, mode, rtol, atol, y_out, w, tol):
    """Time x* ∈ (0, h_piece] of event ``which`` in the piece, its state in ``y_out``, and the
    f evals spent: on the continuous extension of an explicit step, by true steps from the
    interpolant's guess for an implicit one (``w`` holds the workspaces ``dp``, ``sd``, ``ev``)."""
    x = interpolant_root(system, which, method, t, y, h, h_piece, g0, g1, p, mode, w.dp, w.ev)
    if method == EXPLICIT:
        piece_state(method, x, y, h, h_piece, w.dp, w.ev, y_out)
        return x, 0
    return restep_root(
        system, which, t, y, x, h_piece, g0, g1, p, mode, rtol, atol, y_out, w.sd, w.ev, tol
    )
