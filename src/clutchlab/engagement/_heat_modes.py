"""The friction face's temperature modes over a step, exactly: z' = P(τ) − λ·z for a polynomial slip
power P.

Friction fade makes the friction face's temperature a state of the engagement solver
(:mod:`clutchlab.engagement._fade`): Duhamel's integral ∫ P(τ)/√(t − τ) dτ of the slip power with
the smooth part of its kernel as a sum of exponentials Σ w_k·e^(−λ_k·s), i.e. modes
z_k' = P − λ_k·z_k (λ_k from 0.01/s to 6 552/s). The modes are linear in P: over a step on which P
is a polynomial (the exponential collocation of :mod:`clutchlab.engagement._colloc` interpolates it
on the step's nodes) each is integrated exactly, so the step size follows the mechanics, not the
stiffest mode (DOPRI5 had to stay below 3.3/λ_max ≈ 0.5 ms).

With v = 2τ/h − 1 ∈ [−1, 1] and Λ = λh/2 the mode obeys dz/dv = −Λ·z + (h/2)·P(v):

* Λ ≤ ``LAM_SERIES``: z = B·e^(−Λv) + Z(v), Z the power series with Z(0) = 0,
  (n + 1)·Z_{n+1} = −Λ·Z_n + (h/2)·P_n (its terms shrink like Λⁿ/n!; no cancellation);
* Λ > ``LAM_SERIES``: z = z_p(v) + (z₀ − z_p(−1))·e^(−Λ(1 + v)) with the polynomial particular
  solution Λ·z_p,n = (h/2)·P_n − (n + 1)·z_p,n+1 from the top degree down (its terms shrink by
  (n + 1)/Λ).

Both are exact for the polynomial P (to rounding); tests in ``tests/test_heat.py`` against the
closed forms of a constant and a linearly rising slip power.

The weighted sum Σ w_k·z_k at a step's nodes is linear in the slip power's node values and the
modes' start values, and depends on nothing else but the step h. Steps of the grid
2^(m/``LEVELS_PER_OCTAVE``) s (:func:`grid_step`; the collocation's controller rounds its steps
down to it with fade) take it as matrices built once a batch (:func:`level_map`): the forced
response at the nodes to each power vʲ, and the modes' free decay. A Picard iteration of the
step then costs a 13 × 13 matrix-vector product instead of the fifteen series.
"""

from __future__ import annotations

import math

from numba import njit

_JIT = dict(cache=True, error_model="numpy", _nrt=False)

LAM_SERIES = 4.0  # Λ = λh/2 up to which a mode is a power series (else particular + exponential)
SERIES_MAX = 64  # longest series (Λ ≤ 4: terms below 1e-17 of the largest after about 40)
LEVELS_PER_OCTAVE = 8  # the step grid 2^(m/8) s: steps 9 % apart …
LEVEL_LO = -256  # … from 2^-32 s ≈ 2.3e-10 s (m = LEVEL_LO) …
N_LEVELS = 320  # … to below 2^8 s


@njit(**_JIT)
def _series(lam_half, half_h, pc, n, z0, ser):
    """Coefficients (in v) of the series solution z = B·e^(−Λv) + Z(v) with z(−1) = z₀, both parts
    summed into one power series (e^(−Λv) expanded); returns its length."""
    # Z(v): Z_0 = 0, (m + 1)·Z_{m+1} = −Λ·Z_m + (h/2)·P_m
    ser[0] = 0.0
    big = 0.0
    m = 0
    while m + 1 < SERIES_MAX:
        pm = pc[m] if m < n else 0.0
        zn = (-lam_half * ser[m] + half_h * pm) / (m + 1)
        ser[m + 1] = zn
        big = max(big, abs(zn))
        m += 1
        if m >= n and abs(zn) <= 1e-18 * big:
            break
    length = m + 1
    # Z(−1), then B = (z₀ − Z(−1))·e^(−Λ), and B·e^(−Λv) = B·Σ (−Λv)ʲ/j!
    zm1 = 0.0
    for j in range(length - 1, -1, -1):
        zm1 = zm1 * -1.0 + ser[j]
    b = (z0 - zm1) * math.exp(-lam_half)
    term = b
    j = 0
    while True:
        if j < length:
            ser[j] += term
        elif j < SERIES_MAX:
            ser[j] = term
            length = j + 1
        else:
            break
        j += 1
        term *= -lam_half / j
        if abs(term) <= 1e-18 * (abs(b) + big) and j >= length:
            break
    return length


@njit(**_JIT)
def _particular(lam_half, half_h, pc, n, zp):
    """Polynomial particular solution Λ·z_p + dz_p/dv = (h/2)·P (n coefficients in v)."""
    nxt = 0.0
    for m in range(n - 1, -1, -1):
        zp[m] = (half_h * pc[m] - (m + 1) * nxt) / lam_half
        nxt = zp[m]


@njit(**_JIT)
def _poly(c, n, v):
    acc = 0.0
    for j in range(n - 1, -1, -1):
        acc = acc * v + c[j]
    return acc


@njit(**_JIT)
def mode_at(lam, z0, pc, n, h, v, tmp):
    """z(τ(v)) of z' = P − λ·z, z(0) = z₀, P = Σ_{j<n} pc_j·vʲ on the step [0, h] (v = 2τ/h − 1);
    ``tmp`` a scratch row of at least SERIES_MAX."""
    lam_half = 0.5 * lam * h
    half_h = 0.5 * h
    if lam_half <= LAM_SERIES:
        length = _series(lam_half, half_h, pc, n, z0, tmp)
        return _poly(tmp, length, v)
    _particular(lam_half, half_h, pc, n, tmp)
    return _poly(tmp, n, v) + (z0 - _poly(tmp, n, -1.0)) * math.exp(-lam_half * (1.0 + v))


@njit(**_JIT)
def node_decay(lam, h, nodes, enode):
    """e^(−Λ_k(1 + v_i)) at the nodes for the modes solved by their particular solution (rows of
    ``enode``; the others' rows are left alone)."""
    for k in range(lam.size):
        lam_half = 0.5 * lam[k] * h
        if lam_half > LAM_SERIES:
            for i in range(nodes.size):
                enode[k, i] = math.exp(-lam_half * (1.0 + nodes[i]))


@njit(**_JIT)
def weighted_at_nodes(lam, w, z0, pc, n, h, nodes, enode, out, comb, tmp):
    """out_i = Σ_k w_k·z_k(v_i) at the nodes (``enode`` from :func:`node_decay` for this h): the modes'
    series and particular solutions summed into one polynomial ``comb`` (evaluated once a node),
    the particular solutions' decaying parts node by node."""
    half_h = 0.5 * h
    length = 1
    for j in range(comb.size):
        comb[j] = 0.0
    for i in range(nodes.size):
        out[i] = 0.0
    for k in range(lam.size):
        lam_half = 0.5 * lam[k] * h
        if lam_half <= LAM_SERIES:
            m = _series(lam_half, half_h, pc, n, z0[k], tmp)
        else:
            _particular(lam_half, half_h, pc, n, tmp)
            m = n
            d = w[k] * (z0[k] - _poly(tmp, n, -1.0))
            for i in range(nodes.size):
                out[i] += d * enode[k, i]
        for j in range(m):
            comb[j] += w[k] * tmp[j]
        length = max(length, m)
    for i in range(nodes.size):
        out[i] += _poly(comb, length, nodes[i])


@njit(**_JIT)
def advance(lam, z0, pc, n, h, v, z1, tmp):
    """Every mode at v of the step: z1_k = z_k(τ(v)) (z1 may be z0)."""
    for k in range(lam.size):
        z1[k] = mode_at(lam[k], z0[k], pc, n, h, v, tmp)


@njit(**_JIT)
def grid_step(h):
    """The longest step of the grid 2^(m/LEVELS_PER_OCTAVE) s not above h [s] (h > 0); h itself
    outside the grid's range (or NaN)."""
    x = LEVELS_PER_OCTAVE * math.log2(h)
    if not (LEVEL_LO + 1.0 <= x < LEVEL_LO + N_LEVELS - 1.0):  # (the levels grid_level finds)
        return h
    m = math.floor(x)
    g = 2.0 ** (m / LEVELS_PER_OCTAVE)
    if g > h:  # (log2's rounding)
        g = 2.0 ** ((m - 1) / LEVELS_PER_OCTAVE)
    return g


@njit(**_JIT)
def grid_level(h):
    """The index (0 … N_LEVELS − 1) of a step h [s] on the grid of :func:`grid_step`; −1 off it."""
    x = LEVELS_PER_OCTAVE * math.log2(h)
    if not (LEVEL_LO <= x < LEVEL_LO + N_LEVELS - 1.0):
        return -1
    m = math.floor(x + 0.5)
    if 2.0 ** (m / LEVELS_PER_OCTAVE) != h:
        return -1
    return m - LEVEL_LO


@njit(**_JIT)
def level_map(lam, w, h, nodes, enode, pc, col, zero, comb, tmp, fmap, fdec, fend):
    """The weighted modes at the nodes of a step h [s] as maps of the slip power's power
    coefficients in v: ``fmap[i, j]`` = Σ_k w_k·z_k(v_i) for a slip power vʲ W, the modes starting
    from 0 (:func:`weighted_at_nodes`; monomials, not the nodes' Lagrange polynomials, whose large
    coefficients would cost three digits); ``fdec[k, i]`` = w_k·e^(−λ_k·τ_i), the free decay
    from the step's start; each mode at the step's end, ``fend[k, j]`` = z_k(h) for that power
    (j < n) and ``fend[k, n]`` = e^(−λ_k·h). ``enode``, ``pc``, ``col``, ``comb``, ``tmp``
    scratch; ``zero`` at least lam.size zeros."""
    n = nodes.size
    node_decay(lam, h, nodes, enode)
    for j in range(n):
        for m in range(n):
            pc[m] = 1.0 if m == j else 0.0
        weighted_at_nodes(lam, w, zero, pc, n, h, nodes, enode, col, comb, tmp)
        for i in range(n):
            fmap[i, j] = col[i]
        for k in range(lam.size):
            fend[k, j] = mode_at(lam[k], 0.0, pc, n, h, 1.0, tmp)
    for k in range(lam.size):
        for i in range(n):
            fdec[k, i] = w[k] * math.exp(-0.5 * lam[k] * h * (1.0 + nodes[i]))
        fend[k, n] = math.exp(-lam[k] * h)
