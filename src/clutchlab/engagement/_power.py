"""The slip power history and the peak of its Duhamel integral (compiled, numba).

While a scenario slips its slip power P is sampled (:func:`hist_add`; the spacing rules are in
:mod:`clutchlab.engagement._layout`, POWER_SAMPLES_*) into ``hist`` (row 0 times [s], row 1 powers
[W], row 2 the peak search's scratch); ``flash_peak`` is the maximum over t of
Duhamel's integral ∫ P(τ)/√(t − τ) dτ [W s^0.5] (:func:`duhamel_peak`), from which
:func:`clutchlab.heat.face_temperature_rise` gives the friction face's flash temperature.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import _linear_forms as lf
from ._dopri import hermite
from ._layout import POWER_SAMPLES_DENSER, POWER_SAMPLES_MAX, POWER_SAMPLES_PER_SLIP
from ._physics import forces

JIT = dict(cache=True, error_model="numpy", _nrt=False)
# the slip power samples of a linear segment: the free response exact at every EXACT_EVERY-th one,
# carried by its transition between them (the carried values drift by about an ulp a sample)
EXACT_EVERY = 32


@njit(**JIT)
def hist_add(hist, n, t, p):
    """Append (t, p) to the slip power history (times strictly increasing); returns the new count
    (POWER_SAMPLES_MAX + 1 once it overflowed)."""
    if n > POWER_SAMPLES_MAX:
        return n
    if n > 0 and t <= hist[0, n - 1]:
        return n
    if n == POWER_SAMPLES_MAX:
        return n + 1
    hist[0, n] = t
    hist[1, n] = p
    return n + 1


@njit(**JIT)
def slip_spacing(dt, t_slip, t1):
    """Spacing of the power samples of a slipping segment ending at t1 of a slip phase begun at t_slip."""
    return min(dt, max((t1 - t_slip) / POWER_SAMPLES_PER_SLIP, dt / POWER_SAMPLES_DENSER))


@njit(**JIT)
def hist_linear(hist, n, t0, t1, dt, ft, fr):
    """Sample the slip power form of a linear slipping segment (form table ft, free response fr)
    on the grid k·dt in (t0, t1) and at t1. The free response is carried from one grid time to
    the next by its transition over dt (:func:`_transition`; exact again every
    :data:`EXACT_EVERY`-th sample) and the form's polynomials to their degrees: the same samples
    to a few ulp, in about half the time of evaluating both anew at every sample."""
    r = 3 * lf.F_POW
    dp, du, dw = lf.degree(ft[r]), lf.degree(ft[r + 1]), lf.degree(ft[r + 2])
    k = math.floor(t0 / dt) + 1.0
    p11, p12, p21, p22 = _transition(fr, dt)
    hv = hd = 0.0
    j = 0
    while k * dt < t1:
        tau = k * dt - fr.t0
        if j % EXACT_EVERY == 0:
            hv, hd = lf.hh(fr, tau)
        else:
            hv, hd = p11 * hv + p12 * hd, p21 * hv + p22 * hd
        power = lf.pvd(ft[r], dp, tau) + lf.pvd(ft[r + 1], du, tau) * hv
        n = hist_add(hist, n, k * dt, power + lf.pvd(ft[r + 2], dw, tau) * hd)
        k += 1.0
        j += 1
    tau = t1 - fr.t0
    hv, hd = lf.hh(fr, tau)
    return hist_add(hist, n, t1, lf.fval(ft, lf.F_POW, tau, hv, hd))


@njit(**JIT)
def _transition(fr, dt):
    """The free response's transition over dt: (h, h')(τ + dt) = [[p11, p12], [p21, p22]]·(h, h')(τ)
    (the responses to a unit start value and a unit start rate at dt)."""
    p11, p21 = lf.hh(lf.FreeResponse(fr.a, fr.w2, 1.0, 0.0, 0.0), dt)
    p12, p22 = lf.hh(lf.FreeResponse(fr.a, fr.w2, 0.0, 1.0, 0.0), dt)
    return p11, p12, p21, p22


@njit(**JIT)
def hist_step(hist, n, t0, h, t1, dt, y, d, y1, d1, q, mode, ym, dm):
    """Sample the slip power on the grid k·dt in (t0, t1) of a DOPRI5 step [t0, t0 + h] (its cubic
    Hermite interpolant)."""
    k = math.floor(t0 / dt) + 1.0
    while k * dt < t1:
        hermite(y, d, y1, d1, h, (k * dt - t0) / h, ym)
        fc = forces(k * dt, ym, q, mode, dm)
        n = hist_add(hist, n, k * dt, fc.torque * fc.slip)
        k += 1.0
    return n


@njit(**JIT)
def duhamel_at(hist, k):
    """∫₀^{t_k} P(τ)/√(t_k − τ) dτ at sample time t_k, P linear between the samples, each segment
    exactly (an independent check of :func:`_duhamel_kinks`)."""
    tk = hist[0, k]
    acc = 0.0
    u0 = tk - hist[0, 0]
    s0 = math.sqrt(u0)
    for j in range(k):
        u1 = tk - hist[0, j + 1]
        s1 = math.sqrt(u1)
        slope = (hist[1, j + 1] - hist[1, j]) / (hist[0, j + 1] - hist[0, j])
        acc += 2.0 * (hist[1, j] + slope * u0) * (s0 - s1) - (2.0 / 3.0) * slope * (
            u0 * s0 - u1 * s1
        )
        u0, s0 = u1, s1
    return acc


@njit(**JIT, fastmath={"reassoc"})
def _duhamel_kinks(hist, k):
    """:func:`duhamel_at` summed over the kinks of the piecewise linear P: with c_m =
    (4/3)·(b_m − b_{m−1}) in row 2 of ``hist`` (b_m the slope on [t_m, t_{m+1}], b_{−1} = 0),
    ∫₀^{t_k} P/√(t_k − τ) dτ = 2·P₀·√(t_k − t₀) + Σ_{m<k} c_m·(t_k − t_m)^{3/2} (each segment's
    exact integral, summed by parts: 2(P_j + b_j u_j)(σ_j − σ_{j+1}) − (2/3)b_j(u_jσ_j −
    u_{j+1}σ_{j+1}) = σ_j(2P_j + (4/3)b_j u_j) − σ_{j+1}(2P_{j+1} + (4/3)b_j u_{j+1}), u = t_k − t,
    σ = √u). One square root and two products a sample, summed in any order (numba's
    ``fastmath`` reassociation: to round-off)."""
    tk = hist[0, k]
    acc = 0.0
    for m in range(k):
        u = tk - hist[0, m]
        acc += hist[2, m] * u * math.sqrt(u)
    return acc + 2.0 * hist[1, 0] * math.sqrt(tk - hist[0, 0])


@njit(**JIT)
def duhamel_peak(hist, n, stride):
    """max over the sample times of :func:`duhamel_at`: at every ``stride``-th sample (and the last),
    then at every sample within ``stride`` of the best of those (stride 1: every sample; a larger
    stride costs O(n²/stride + n·stride) instead of O(n²)); 0 for fewer than two samples. Row 2
    of ``hist`` (three rows) is its scratch: :func:`_duhamel_kinks`' coefficients."""
    if n < 2:
        return 0.0
    slope_before = 0.0
    for j in range(n - 1):
        slope = (hist[1, j + 1] - hist[1, j]) / (hist[0, j + 1] - hist[0, j])
        hist[2, j] = (4.0 / 3.0) * (slope - slope_before)
        slope_before = slope
    best, kb = 0.0, 0
    k = stride
    while True:
        k = min(k, n - 1)
        v = _duhamel_kinks(hist, k)
        if v > best:
            best, kb = v, k
        if k == n - 1:
            break
        k += stride
    if stride > 1:
        k0 = kb
        for k in range(max(1, k0 - stride + 1), min(n, k0 + stride)):
            v = _duhamel_kinks(hist, k)
            if v > best:
                best, kb = v, k
    if 1 <= kb < n - 1:
        best = _between_samples(hist, kb, best)
    return best


@njit(**JIT)
def _between_samples(hist, kb, best):
    """The peak between samples: the vertex of the parabola through the best sample kb (value
    ``best``) and its neighbours, where it lies between them."""
    ta, tb, tc = hist[0, kb - 1], hist[0, kb], hist[0, kb + 1]
    va, vc = _duhamel_kinks(hist, kb - 1), _duhamel_kinks(hist, kb + 1)
    d1, d2 = (best - va) / (tb - ta), (vc - best) / (tc - tb)
    curv = (d2 - d1) / (tc - ta)  # half the second derivative
    if curv < 0.0:
        slope_b = d1 + curv * (tb - ta)  # derivative of the parabola at tb
        shift = -slope_b / (2.0 * curv)
        if ta - tb < shift < tc - tb:
            best = best - slope_b * slope_b / (4.0 * curv)
    return best


@njit(cache=True, error_model="numpy")
def flash_peaks(times, power):
    """:func:`duhamel_peak` of each row of sampled slip powers (times non-decreasing from 0; a
    repeated time is skipped), e.g. of the closed form's exact slip power."""
    n_s, n = times.shape
    out = np.empty(n_s)
    hist = np.empty((3, n))
    for i in range(n_s):
        m = 0
        for j in range(n):
            m = hist_add(hist, m, times[i, j], power[i, j]) if m < n else m
        out[i] = duhamel_peak(hist, m, max(1, int(math.sqrt(m / 2.0))))
    return out
