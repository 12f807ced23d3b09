"""The slipping friction law μ(|Δω|)/μ_k and the tables of the parameter row (compiled, numba).

One function, :func:`friction_law`, decides the law: constant μ_k, the Stribeck law or a
tabulated μ(|Δω|)/μ_k (a measured curve, as the Modelica library's ``mu_pos``). It returns the
law's value and its slope in |Δω| (the slope feeds the output jerk and the slip power's peak).
"""

from __future__ import annotations

import math

from numba import njit

from ._layout import FTAB, NTAB, RS, VS

JIT = dict(cache=True, error_model="numpy", _nrt=False)


@njit(**JIT)
def table(x, q, base):
    """(value, slope) of np.interp for a scalar (constant beyond the ends, slope 0 there) on a table
    stored in the parameter row from column ``base``: count, abscissae, ordinates. (The tables are
    not separate array arguments: an array argument merely touched in the right-hand side cost
    ~55 ns a call.)"""
    n = int(q[base])
    x0, y0 = base + 1, base + 1 + n
    if x <= q[x0]:
        return q[y0], 0.0
    if x >= q[x0 + n - 1]:
        return q[y0 + n - 1], 0.0
    lo, hi = 0, n - 1
    while hi - lo > 1:  # bisection for the interval [x_lo, x_hi] holding x
        mid = (lo + hi) // 2
        if q[x0 + mid] <= x:
            lo = mid
        else:
            hi = mid
    slope = (q[y0 + hi] - q[y0 + lo]) / (q[x0 + hi] - q[x0 + lo])
    return q[y0 + lo] + slope * (x - q[x0 + lo]), slope


@njit(**JIT)
def engine_torque(x, q):
    """The engine torque table at speed x [N m]."""
    return table(x, q, NTAB)[0]


@njit(**JIT)
def friction_law(slip, q):
    """(f, df/d|Δω|) of the slipping friction law μ(|Δω|)/μ_k: 1 (constant μ_k), the Stribeck law
    1 + (μ_s/μ_k − 1)·exp(−(Δω/v_s)²), or the tabulated μ(|Δω|)/μ_k (linear between its points)."""
    if q[FTAB] > 0.0:
        return table(abs(slip), q, int(q[FTAB]))
    if math.isfinite(q[VS]):
        u = slip / q[VS]
        uu = u * u
        if uu >= 700.0:  # (no underflow: libm's slow path)
            return 1.0, 0.0
        e = (q[RS] - 1.0) * math.exp(-uu)  # f − 1: the slope needs no second exp
        return 1.0 + e, e * (-2.0 * abs(slip) / q[VS] ** 2)
    return 1.0, 0.0
