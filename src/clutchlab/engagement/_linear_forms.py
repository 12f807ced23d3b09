"""Polynomial forms of the compliant engagement's exact linear phases (compiled, numba).

Source paper (000), eqs. 1-2 with the damper springs.

With constant μ, a held engine or a free one with constant torque, no rotor drag and a
polynomial clamp profile, every phase of the compliant driveline is linear with polynomial
forcing. Each phase is a body A (the hub while slipping, driven by s·C(t); the engine and hub
while locked, driven by T_e; held: infinite inertia) joined to the output R (load T_m, or parked)
by the damper springs (K, c). Its twist θ obeys one damped oscillator

    m·θ'' + c·θ' + K·θ = f(τ),   τ = t − t_a,

(output parked: m = J_A, f = D; output moving: m = J_A·J_R/(J_A + J_R), f = ρ_r·D + ρ_a·T_m,
ρ_a = J_A/(J_A + J_R), ρ_r = 1 − ρ_a), and the speeds are polynomials plus multiples of θ':
ω_A = ω_m + ρ_r·θ', ω_R = ω_m − ρ_a·θ' with the mass-weighted speed ω_m' = (D − T_m)/(J_A + J_R).
θ = x_p + h: x_p the polynomial particular solution, h the free response

    h = e^(−aτ)·[h₀·C(τ) + (h₁ + a·h₀)·S(τ)],   a = c/(2m), ω_d² = K/m − a²,

C = cos ω_dτ, S = sin(ω_dτ)/ω_d (cosh and sinh for ω_d² < 0; 1 and τ at ω_d = 0), so one exp
and one sin/cos pair give h and h'. Every quantity the engagement needs — slip, output speed,
the torque needed to stay locked, the output jerk (K·θ' + c·θ'')/J_R, the slip power — is of the
form F(τ) = P(τ) + U(τ)·h + W(τ)·h' with polynomials P, U, W, and so is its derivative (h'' is
−(c·h' + K·h)/m). Events (lock-up, break-away, park, unpark) are the first roots of such forms,
found on a grid of half of π/ω₀ (extrema of the free response are ≥ π/ω₀ apart, so a dip below
zero and back is seen as a sign change of F') and placed by bracketed Newton to round-off; peaks
are the roots of F'. The grid is skipped wherever bounds (the free response's envelope and the
polynomials' ranges) exclude a root or a new peak, or keep a form monotone
(:func:`clutchlab.engagement._linear_phase.linear_segment`). Works are exact integrals: of
polynomials, and of Q·h by the recursion K·∫Q·h = −m[Q·h'] + m[Q'·h] − c[Q·h] + c∫Q'·h − m∫Q''·h;
the damping work from the oscillator's energy balance c∫θ'² = ∫f·θ' − Δ(½mθ'² + ½Kθ²).

This module holds the algebra: polynomials of ``NP`` ascending coefficients, the free response
(:class:`FreeResponse`, :func:`hh`, :func:`envelope`) and the form table (rows 3i, 3i+1, 3i+2:
P, U, W of form i; form i + N_FORM its derivative, i + 2·N_FORM its second derivative).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

NP = 14  # polynomial coefficients (ascending); products stay below degree 13
_EPS = np.finfo(float).eps
# forms (rows 3i..3i+2 of a form table: P, U, W); each with its derivative and second derivative
F_LOCK, F_PARK, F_UNPARK, F_BRK_P, F_BRK_M, F_JERK, F_TORQ, F_POW = range(8)
N_FORM = 8
N_FROWS = 3 * 3 * N_FORM  # form, derivative, second derivative
_JNIT = dict(cache=True, error_model="numpy", _nrt=False)

#: The free response of a phase's oscillator, h = e^(−aτ)·[h₀·C(τ) + (h₁ + a·h₀)·S(τ)]
#: (read-only for the phase): ``a`` = c/(2m) [1/s], ``w2`` = ω_d² [1/s²], ``h0`` = h(0) [rad],
#: ``h1`` = h'(0) [rad/s] and ``t0`` the phase's start t_a [s] (τ = t − t_a; round-off of the
#: absolute time bounds the root searches).
FreeResponse = namedtuple("FreeResponse", ["a", "w2", "h0", "h1", "t0"])


@njit(**_JNIT)
def pv(c, x):
    """Polynomial value (ascending coefficients, Horner from the highest non-zero one: the same
    value as from the top for a finite x, without the leading zeros' chain of multiplications)."""
    return pvd(c, degree(c), x)


@njit(**_JNIT)
def pvd(c, deg, x):
    """Polynomial value up to degree ``deg``."""
    acc = 0.0
    for i in range(deg, -1, -1):
        acc = acc * x + c[i]
    return acc


@njit(**_JNIT)
def degree(c):
    for i in range(NP - 1, 0, -1):
        if c[i] != 0.0:
            return i
    return 0


@njit(**_JNIT)
def prange(c, deg, lo, hi, tmp):
    """Bounds (min, max) of the polynomial on [lo, hi]: exact for degree <= 2, else its Bernstein
    bounds from the Taylor coefficients at lo (:func:`taylor_range`); ``tmp`` is a scratch row."""
    if deg > 2:
        taylor(c, deg, lo, tmp)
        return taylor_range(tmp, deg, hi - lo)
    a, b = pvd(c, deg, lo), pvd(c, deg, hi)
    lo_v, hi_v = min(a, b), max(a, b)
    if deg == 2:
        if c[2] != 0.0:
            xv = -0.5 * c[1] / c[2]
            if lo < xv < hi:
                v = c[0] + xv * (c[1] + xv * c[2])
                lo_v, hi_v = min(lo_v, v), max(hi_v, v)
    return lo_v, hi_v


@njit(**_JNIT)
def taylor(c, deg, x, out):
    """The Taylor coefficients of the polynomial at x (out[j] = P⁽ʲ⁾(x)/j!; synthetic division)."""
    for j in range(deg + 1):
        out[j] = c[j]
    for k in range(deg):
        for j in range(deg - 1, k - 1, -1):
            out[j] += x * out[j + 1]


def _bernstein_weights():
    """w[n, k, j] = C(k, j)/C(n, j): the Bernstein coefficients of degree n on [0, 1] from the
    power ones, β_k = Σ_j w[n, k, j]·c_j."""
    w = np.zeros((NP, NP, NP))
    for n in range(NP):
        for k in range(n + 1):
            for j in range(k + 1):
                w[n, k, j] = math.comb(k, j) / math.comb(n, j)
    return w


_BERNSTEIN = _bernstein_weights()


@njit(**_JNIT)
def taylor_range(b, deg, du):
    """Bounds (min, max) of Σ b_j·uʲ over u in [0, du]: its extreme Bernstein coefficients on the
    interval (the polynomial lies in their convex hull, and they tighten as du shrinks), widened
    by their round-off."""
    w = _BERNSTEIN[deg]
    lo_v = hi_v = b[0]
    size = abs(b[0])
    for k in range(1, deg + 1):
        acc, upow, size = b[0], 1.0, abs(b[0])
        for j in range(1, k + 1):
            upow *= du
            term = w[k, j] * b[j] * upow
            acc += term
            size += abs(term)
        lo_v, hi_v = min(lo_v, acc), max(hi_v, acc)
    noise = 4.0 * NP * _EPS * size  # (size: Σ |b_j|·du^j, the last coefficient's terms)
    return lo_v - noise, hi_v + noise


@njit(**_JNIT)
def zero(c):
    for i in range(NP):
        c[i] = 0.0


@njit(**_JNIT)
def der(src, dst):
    for i in range(NP - 1):
        dst[i] = (i + 1) * src[i + 1]
    dst[NP - 1] = 0.0


@njit(**_JNIT)
def integ(src, dst):
    """dst = ∫_0^τ src (src's top coefficient must be zero)."""
    for i in range(NP - 1, 0, -1):
        dst[i] = src[i - 1] / i
    dst[0] = 0.0


@njit(**_JNIT)
def mul(a, b, dst):
    """dst = a·b truncated to NP coefficients (callers keep the degrees inside; dst may be a or b;
    the products of zero coefficients above a's and b's degrees are left out)."""
    da, db = degree(a), degree(b)
    for i in range(NP - 1, -1, -1):
        acc = 0.0
        for j in range(max(0, i - db), min(i, da) + 1):
            acc += a[j] * b[i - j]
        dst[i] = acc


@njit(**_JNIT)
def axpy(alpha, x, beta, y, dst):
    """dst = alpha·x + beta·y."""
    for i in range(NP):
        dst[i] = alpha * x[i] + beta * y[i]


@njit(**_JNIT)
def hh(fr, tau):
    """The free response h and h' at τ ≥ 0 (finite) [rad, rad/s] (fr: :class:`FreeResponse`)."""
    a, w2, h0, h1 = fr.a, fr.w2, fr.h0, fr.h1
    if w2 > 0.0:
        w = math.sqrt(w2)
        e = math.exp(-a * tau)
        cf = e * math.cos(w * tau)
        sf = e * math.sin(w * tau) / w
    elif w2 < 0.0:
        b = math.sqrt(-w2)
        if b * tau < 1.0:  # near critical damping: sinh(bτ)/b without the cancellation of e1 − e2
            e = math.exp(-a * tau)  # (which lost digits as 1/(bτ): 8 of them at ζ = 1 ± round-off)
            cf = e * math.cosh(b * tau)
            sf = e * math.sinh(b * tau) / b
        else:
            e1 = math.exp((b - a) * tau)
            e2 = math.exp(-(a + b) * tau)
            cf = 0.5 * (e1 + e2)
            sf = 0.5 * (e1 - e2) / b
    else:
        e = math.exp(-a * tau)
        cf = e
        sf = e * tau
    w0sq = w2 + a * a
    return h0 * cf + (h1 + a * h0) * sf, h1 * cf - (a * h1 + w0sq * h0) * sf


@njit(**_JNIT)
def fval(ft, i, tau, h, hd):
    """Form i of the table ft at τ given h, h' there."""
    r = 3 * i
    return pv(ft[r], tau) + pv(ft[r + 1], tau) * h + pv(ft[r + 2], tau) * hd


@njit(**_JNIT)
def fvald(ft, fd, i, tau, h, hd):
    """Form i at τ with the rows' degrees ``fd`` (integers)."""
    r = 3 * i
    return (
        pvd(ft[r], int(fd[r]), tau)
        + pvd(ft[r + 1], int(fd[r + 1]), tau) * h
        + pvd(ft[r + 2], int(fd[r + 2]), tau) * hd
    )


@njit(**_JNIT)
def fder(ft, i, j, km, cm):
    """Form j = d/dτ form i (h'' = −km·h − cm·h')."""
    r, s = 3 * i, 3 * j
    der(ft[r], ft[s])
    der(ft[r + 1], ft[s + 1])
    der(ft[r + 2], ft[s + 2])
    for n in range(NP):
        u, w = ft[r + 1, n], ft[r + 2, n]
        ft[s + 1, n] += -w * km
        ft[s + 2, n] += u - w * cm


@njit(**_JNIT)
def fset(ft, i, p, u_scale, w_scale, u_poly, w_poly):
    """Form i = p + (u_scale·u_poly)·h + (w_scale·w_poly)·h' (polys may be the same row)."""
    r = 3 * i
    for n in range(NP):
        ft[r, n] = p[n]
        ft[r + 1, n] = u_scale * u_poly[n]
        ft[r + 2, n] = w_scale * w_poly[n]


@njit(**_JNIT)
def root(ft, i, lo, hi, fr):
    """Root of form i in (lo, hi] with F(lo) > 0 >= F(hi): Newton on form i+N_FORM, bisection
    safeguard, to round-off (Newton's convergence checked before its point is held to the
    bracket)."""
    x = hi
    for _ in range(200):
        h, hd = hh(fr, x)
        f = fval(ft, i, x, h, hd)
        if f > 0:
            lo = x
        else:
            hi = x
        if hi - lo <= 4 * _EPS * (abs(fr.t0) + hi):
            break
        d = fval(ft, i + N_FORM, x, h, hd)
        xn = x - f / d if d != 0 else 0.5 * (lo + hi)
        if abs(xn - x) <= 2 * _EPS * (abs(fr.t0) + x):
            x = xn  # (converged: x may be the bracket's end just moved to it, as Newton
            break  # approaches from one side; bisecting on from the far end took 30 iterations)
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        x = xn
    # the event time is where the function has crossed (≤ 0), as in the integrator: the next mode
    # then starts on the right side of its own switching functions
    step = 2 * _EPS * (abs(fr.t0) + x)
    for _ in range(60):
        if x >= hi:
            return hi
        h, hd = hh(fr, x)
        if fval(ft, i, x, h, hd) <= 0.0:
            return x
        x = min(x + step, hi)
        step *= 2.0
    return hi


@njit(**_JNIT)
def extremum(ft, i, lo, hi, d_lo, fr):
    """A root of form i's derivative in (lo, hi) where it changes sign (d_lo its value at lo):
    Newton on the bracket from lo's Newton point, bisection as the safeguard. Ends where Newton has
    converged (its point may be the bracket's end just moved to it) or the bracket is within the
    time's round-off or 64 ε of the interval (an extremum at the start of a phase that begins at
    t = 0, e.g. a cubic clamp profile's slip power, was bisected towards 0 for 200 iterations)."""
    if d_lo == 0.0:
        return lo  # (a derivative that starts at zero and changes sign: the extremum is lo)
    sgn = 1.0 if d_lo > 0 else -1.0
    floor = 64.0 * _EPS * (hi - lo)
    h, hd = hh(fr, lo)
    dd = sgn * fval(ft, i + 2 * N_FORM, lo, h, hd)
    x = lo - sgn * d_lo / dd if dd < 0.0 else hi
    if x - lo <= 2 * _EPS * (abs(fr.t0) + lo) + floor:
        return x  # (the derivative is zero at lo within its round-off)
    if not (lo < x < hi):
        x = 0.5 * (lo + hi)
    for _ in range(200):
        h, hd = hh(fr, x)
        d = sgn * fval(ft, i + N_FORM, x, h, hd)
        if d > 0:
            lo = x
        else:
            hi = x
        if hi - lo <= 4 * _EPS * (abs(fr.t0) + hi) + floor:
            break
        dd = sgn * fval(ft, i + 2 * N_FORM, x, h, hd)
        xn = x - d / dd if dd != 0 else 0.5 * (lo + hi)
        if abs(xn - x) <= 2 * _EPS * (abs(fr.t0) + x):
            return xn
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        x = xn
    return x


@njit(**_JNIT)
def envelope(fr):
    """Constants of the bounds |h(τ)| ≤ R_h·e^(−rate·τ), |h'(τ)| ≤ R_h'·e^(−rate·τ) (all τ ≥ 0):
    returns (R_h, R_h', rate); rate ≤ 0 where the free response does not decay."""
    a, w2, h0, h1 = fr.a, fr.w2, fr.h0, fr.h1
    w0sq = w2 + a * a
    if w2 > 0.0:
        wd = math.sqrt(w2)
        rh = math.hypot(h0, (h1 + a * h0) / wd)
        rd = math.hypot(h1, (a * h1 + w0sq * h0) / wd)
        rate = a
    elif w2 < 0.0:
        b = math.sqrt(-w2)
        rh = abs(h0) + abs(h1 + a * h0) / b
        rd = abs(h1) + abs(a * h1 + w0sq * h0) / b
        rate = a - b
    else:
        rh = abs(h0) + abs(h1 + a * h0) * 2.0 / (math.e * a) if a > 0 else np.inf
        rd = abs(h1) + abs(a * h1 + w0sq * h0) * 2.0 / (math.e * a) if a > 0 else np.inf
        rate = 0.5 * a
    return rh, rd, rate


@njit(**_JNIT)
def icap(t, q_tr, q_tcon, q_kappa, q_cmax, prof, out, tmp):
    """out = C(t_a + τ) as a polynomial in τ on the clamp profile's piece containing t_a = t
    (C = C_max·max(0, 1 − κ(1 − p(t/t_r))), p the ramp/cubic/quintic profile, 1 after t_r)."""
    zero(out)
    if q_tr <= 0.0 or t >= q_tr:
        out[0] = q_cmax
        return
    if q_kappa != 1.0 and t < q_tcon:
        return  # the air gap is still open: no clamp force
    zero(tmp)  # p(x) coefficients, then Taylor-shifted to x_a = t/t_r and scaled to τ
    if prof == 0:
        tmp[1] = 1.0
    elif prof == 1:
        tmp[2], tmp[3] = 3.0, -2.0
    else:
        tmp[3], tmp[4], tmp[5] = 10.0, -15.0, 6.0
    xa = t / q_tr
    for k in range(6):  # synthetic division: coefficients of p(xa + u) in u
        for j in range(4, k - 1, -1):
            tmp[j] += xa * tmp[j + 1]
    scale = 1.0
    for j in range(6):
        out[j] = q_cmax * q_kappa * tmp[j] * scale
        scale /= q_tr
    out[0] += q_cmax * (1.0 - q_kappa)


@njit(**_JNIT)
def partic(f, m, c, k, xp):
    """Polynomial particular solution of m·x'' + c·x' + k·x = f."""
    zero(xp)
    for j in range(NP - 1, -1, -1):
        acc = f[j]
        if j + 1 < NP:
            acc -= c * (j + 1) * xp[j + 1]
        if j + 2 < NP:
            acc -= m * (j + 2) * (j + 1) * xp[j + 2]
        xp[j] = acc / k


@njit(**_JNIT)
def int_qh(q, m, c, k, tau, h_a, hd_a, h_b, hd_b, tmp):
    """∫_0^τ Q·h (the recursion of the module docstring; tmp holds Q's derivatives)."""
    deg = 0
    for j in range(NP):
        if q[j] != 0.0:
            deg = j
    # tmp rows: derivatives Q^(j), j = 0..deg
    for n in range(NP):
        tmp[0, n] = q[n]
    for j in range(1, deg + 1):
        der(tmp[j - 1], tmp[j])
    i1 = i2 = 0.0  # I(Q^(j+1)), I(Q^(j+2))
    for j in range(deg, -1, -1):
        qa, qb = pv(tmp[j], 0.0), pv(tmp[j], tau)
        dqa = pv(tmp[j + 1], 0.0) if j + 1 <= deg else 0.0
        dqb = pv(tmp[j + 1], tau) if j + 1 <= deg else 0.0
        ij = (
            -m * (qb * hd_b - qa * hd_a)
            + m * (dqb * h_b - dqa * h_a)
            - c * (qb * h_b - qa * h_a)
            + c * i1
            - m * i2
        ) / k
        i2, i1 = i1, ij
    return i1
