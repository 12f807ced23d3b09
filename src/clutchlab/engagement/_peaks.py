"""Peak metrics of the numerical solver (compiled, numba): the running maxima of slip power,
|friction torque| and |output jerk| (slots MAX_POWER, MAX_TORQUE, MAX_JERK of ``pk``).

They are taken at every step node and event (:func:`record_peaks`) and inside the steps, so that
a peak does not depend on where the steps fall: on each step's continuous extension around the
vertex of the parabola through the step's start, middle and end values (:func:`vertex`,
:func:`refine_peak`; the compliant model's oscillating jerk and torque), and for a rigid slip
jerk that depends on the state by sampling the step (:func:`scan_jerk`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._dopri import dense, dense_coefficients
from ._layout import MAX_JERK, MAX_POWER, MAX_TORQUE, VS, E, H
from ._physics import forces, jerk, jerk_varies

JIT = dict(cache=True, error_model="numpy", _nrt=False)
INLINE = dict(JIT, inline="always")

JERK_SCAN_MAX = 32  # samples of the rigid slip jerk in a step, at most (:func:`scan_jerk`)


@njit(**JIT)
def record_peaks(t, y, q, mode, d, fc, pk):
    """Update the running maxima pk at a state (fc its :class:`Forces`, d its derivative); return
    the output jerk there."""
    jk = jerk(t, y, q, mode, d, fc)
    if not mode.locked:
        pk[MAX_POWER] = max(pk[MAX_POWER], fc.torque * fc.slip)
    pk[MAX_TORQUE] = max(pk[MAX_TORQUE], abs(fc.torque))
    pk[MAX_JERK] = max(pk[MAX_JERK], abs(jk))
    return jk


@njit(**JIT)
def jerk_before(t, y, q, mode, dm, pk):
    """The output jerk's limit from the left at t (the state is continuous there, dC/dt need not
    be); recorded in the running maximum and returned."""
    t_l = np.nextafter(t, -np.inf)
    fc = forces(t_l, y, q, mode, dm)
    jk = jerk(t_l, y, q, mode, dm, fc)
    pk[MAX_JERK] = max(pk[MAX_JERK], abs(jk))
    return jk


@njit(**JIT)
def jerk_torque(t, y, q, mode, dm):
    """Output jerk and clutch torque at a state (dm: scratch for the derivatives)."""
    fc = forces(t, y, q, mode, dm)
    return jerk(t, y, q, mode, dm, fc), fc.torque


@njit(**JIT)
def vertex(v0, vm, v1, peak):
    """The parabola through a step's start, middle and end values: the fraction of the step at its
    vertex when that is an interior extremum near the running maximum ``peak``, else −1."""
    a = 2.0 * (v0 - 2.0 * vm + v1)
    b = -3.0 * v0 + 4.0 * vm - v1
    if a == 0.0:
        return -1.0
    th_v = -b / (2.0 * a)
    if not 0.0 < th_v < 1.0 or max(abs(v0 - b * b / (4.0 * a)), abs(vm)) < 0.9 * peak:
        return -1.0
    return th_v


@njit(**JIT)
def peak_value(slot, th, t, h, rc, q, mode, yb, dm):
    """|jerk| (MAX_JERK) or |clutch torque| (MAX_TORQUE) at the fraction th of a step (continuous
    extension)."""
    dense(rc, th, yb)
    fc = forces(t + th * h, yb, q, mode, dm)
    if slot == MAX_TORQUE:
        return abs(fc.torque)
    return abs(jerk(t + th * h, yb, q, mode, dm, fc))


@njit(**JIT)
def refine_peak(slot, th_v, th_max, t, h, rc, q, mode, pk, yb, dm, width=0.25, iterations=40):
    """A maximum of |jerk| (MAX_JERK) or |clutch torque| (MAX_TORQUE) inside an integrated step near
    the fraction th_v (:func:`vertex`), so that a peak does not depend on where the steps fall:
    golden section on the step's continuous extension (order 4: the state to the tolerance) over
    [th_v − width, th_v + width] within [0, th_max] (1: the whole step; less: before an event)."""
    lo, hi = max(0.0, th_v - width), min(th_max, th_v + width)
    gr = 0.5 * (math.sqrt(5.0) - 1.0)
    x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
    f1 = peak_value(slot, x1, t, h, rc, q, mode, yb, dm)
    f2 = peak_value(slot, x2, t, h, rc, q, mode, yb, dm)
    for _ in range(iterations):
        if f1 >= f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - gr * (hi - lo)
            f1 = peak_value(slot, x1, t, h, rc, q, mode, yb, dm)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + gr * (hi - lo)
            f2 = peak_value(slot, x2, t, h, rc, q, mode, yb, dm)
    pk[slot] = max(pk[slot], f1, f2)


@njit(**JIT)
def scan_value(k, m, frac, t, h, rc, q, mode, yb, dm):
    """|jerk| at the sample k of m of :func:`scan_jerk` (the last one: its limit from the left,
    for a step that ends where dC/dt jumps)."""
    th = frac * k / m
    dense(rc, th, yb)
    te = t + th * h
    if k == m:
        te = np.nextafter(te, -np.inf)
    fc = forces(te, yb, q, mode, dm)
    return abs(jerk(te, yb, q, mode, dm, fc))


@njit(**JIT)
def scan_jerk(t, h, frac, slip0, slip1, j0, rc, q, mode, pk, yb, dm):
    """The largest |jerk| of a rigid slipping step [t, t + frac·h] (frac < 1: the part before an
    event): |jerk| sampled on the step's continuous extension (j0: the jerk at t, known), then
    golden section around the vertex of the parabola through the largest sample and its
    neighbours. A Stribeck law's term C·f'(Δω)·Δω' peaks within a few v_s of slip, where a step
    may be longer than the peak is wide: there the samples are spaced v_s/4 in slip (at most
    JERK_SCAN_MAX), elsewhere three."""
    m = 2
    if q[VS] < np.inf:
        near = 4.0 * q[VS]
        lo, hi = min(abs(slip0), abs(slip1)), max(abs(slip0), abs(slip1))
        if lo < near:
            m = max(m, min(JERK_SCAN_MAX, int(math.ceil(4.0 * (min(hi, near) - lo) / q[VS])) + 2))
    # the largest sample, and its two neighbours on each side as they come (no storage)
    best, kb, bm2, bm1, bp1, bp2, p2, p1 = -1.0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for k in range(m + 1):
        v = abs(j0) if k == 0 else scan_value(k, m, frac, t, h, rc, q, mode, yb, dm)
        if v > best:
            best, kb, bm2, bm1 = v, k, p2, p1
        elif k == kb + 1:
            bp1 = v
        elif k == kb + 2:
            bp2 = v
        p2, p1 = p1, v
    pk[MAX_JERK] = max(pk[MAX_JERK], best)
    if best < 0.9 * pk[MAX_JERK]:
        return
    # the parabola through the largest sample and its neighbours (the three nearest at an end),
    # its vertex (a maximum: concave) also up to half the triple past either end, where the
    # samples of a peak close to a step's end all rise (the golden section keeps to the step)
    if kb == 0:
        a, v0, v1, v2 = 0, best, bp1, bp2
    elif kb == m:
        a, v0, v1, v2 = m - 2, bm2, bm1, best
    else:
        a, v0, v1, v2 = kb - 1, bm1, best, bp1
    curv = 2.0 * (v0 - 2.0 * v1 + v2)
    if curv < 0.0:
        b = -3.0 * v0 + 4.0 * v1 - v2
        th = -b / (2.0 * curv)
        if -0.5 < th < 1.5:
            th_v = min(frac, max(0.0, frac * (a + 2.0 * th) / m))
            refine_peak(MAX_JERK, th_v, frac, t, h, rc, q, mode, pk, yb, dm, frac / m, 24)


@njit(**INLINE)
def peaks_inside_step(
    t, h, hit, fired, t_right, jk, jm, tcm, tc_right, j_left, tc_left, q, mode, w
):
    """The peaks inside an accepted step [t, t_right] without an event (the compliant model's
    output jerk and clutch torque oscillate; their maxima must not depend on where the steps
    fall): a rigid slip jerk that depends on the state, its largest value inside the step and its
    value from the left at a breakpoint (the profile's end, where dC/dt jumps); the compliant
    model's jerk and torque refined around the vertex of the parabola through the step's start,
    middle and end values. The continuous extension is computed here unless ``fired`` did."""
    pk = w.pk
    if not (mode.compliant or mode.locked or mode.parked) and jerk_varies(q):
        if hit:
            jerk_before(t_right, w.y1, q, mode, w.dm, pk)
        if not fired:
            dense_coefficients(w.y, w.y1, w.kk, h, w.rc)
        scan_jerk(
            t, h, 1.0, w.y[E] - w.y[H], w.y1[E] - w.y1[H], j_left, w.rc, q, mode, pk, w.yb, w.dm
        )
    if mode.compliant:
        th_j = vertex(j_left, jm, jk, pk[MAX_JERK])
        th_t = vertex(tc_left, tcm, tc_right, pk[MAX_TORQUE])
        if th_j > 0.0 or th_t > 0.0:
            if not fired:
                dense_coefficients(w.y, w.y1, w.kk, h, w.rc)
            if th_j > 0.0:
                refine_peak(MAX_JERK, th_j, 1.0, t, h, w.rc, q, mode, pk, w.yb, w.dm)
            if th_t > 0.0:
                refine_peak(MAX_TORQUE, th_t, 1.0, t, h, w.rc, q, mode, pk, w.yb, w.dm)
