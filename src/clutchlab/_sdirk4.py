"""Compiled L-stable SDIRK4 step for the stiff-contact systems (:mod:`clutchlab._contact_systems`).

Hairer & Wanner's 5-stage, order-4 singly diagonally implicit Runge-Kutta method (γ = 1/4,
stiffly accurate, L-stable; Solving ODEs II, Table IV.6.5 "SDIRK4") with its embedded order-3
solution for the error estimate. Each stage is solved by a simplified Newton iteration with the
Jacobian evaluated once per step and the matrix I − hγJ inverted once per step (n ≤ 8: a dense
inverse, cheaper than substitution for ~10 solves); a stage is solved when θ/(1 − θ) times the
scaled Newton increment (θ the contraction rate) is below 0.03, as in Hairer's RADAU5, usually
after one or two iterations. The error estimate is filtered through (I − hγJ)⁻¹ as in Hairer's
codes, so that stiff components do not force tiny steps. The scratch arrays of a step are the
named fields of a :data:`Sdirk4Work` record (:func:`work`); nothing here allocates (compiled
without numba's reference counting: its atomic count updates on each call with array arguments
were about half of the run time).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ._contact_systems import JIT, rhs

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
# scaled Newton increment (in units of the local tolerance) at which a stage is solved
NEWTON_TOL = 0.03

#: scratch of one step: the Jacobian, I − hγJ and its inverse; the stage derivatives k (5 × n);
#: the right-hand side f, the stage's explicit part w, its value z and Newton increment dz; the
#: error estimate err and weights wt; the derivatives at the step's start f0 and end f1 (for
#: Hermite interpolation); eta[0] the Newton convergence factor, carried from step to step
Sdirk4Work = namedtuple(
    "Sdirk4Work", ["jac", "m", "inv", "k", "f", "w", "z", "dz", "err", "wt", "f0", "f1", "eta"]
)


@njit(cache=True, error_model="numpy")
def work(n):
    """A fresh :data:`Sdirk4Work` for systems of size n."""
    return Sdirk4Work(
        np.zeros((n, n)),
        np.zeros((n, n)),
        np.zeros((n, n)),
        np.zeros((5, n)),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(1),
    )


@njit(**JIT)
def invert(m, inv):
    """Gauss-Jordan inverse with partial pivoting of a small dense matrix into ``inv`` (``m`` is
    destroyed); False if singular. For n ≤ 8 and ~10 solves per factorisation a matrix-vector
    product with the inverse is cheaper than LU substitution."""
    n = m.shape[0]
    for i in range(n):
        for j in range(n):
            inv[i, j] = 1.0 if i == j else 0.0
    for k in range(n):
        # pivot: the largest entry of column k at or below the diagonal
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
        # scale the pivot row, eliminate column k from every other row
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


@njit(**JIT)
def solve(inv, b, out):
    """out = inv @ b (small dense)."""
    n = b.size
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += inv[i, j] * b[j]
        out[i] = acc


@njit(**JIT)
def scaled_norm(v, y0, y1, rtol, atol):
    """RMS of v / (atol_i + rtol·max(|y0_i|, |y1_i|))."""
    acc = 0.0
    for i in range(v.size):
        acc += (v[i] / (atol[i] + rtol * max(abs(y0[i]), abs(y1[i])))) ** 2
    return math.sqrt(acc / v.size)


@njit(**JIT)
def _newton_matrix(system, t, y, h, p, mode, rtol, atol, ws):
    """f0 = f(t, y), the Jacobian, the error weights and the inverse of I − hγJ; False if singular."""
    n = y.size
    for i in range(n):
        ws.wt[i] = 1.0 / (atol[i] + rtol * abs(y[i]))
    rhs(system, t, y, p, mode, ws.f0, ws.jac, True)
    hg = h * GAMMA
    for i in range(n):
        for j in range(n):
            ws.m[i, j] = -hg * ws.jac[i, j]
        ws.m[i, i] += 1.0
    return invert(ws.m, ws.inv)


@njit(**JIT)
def _stage(system, s, t, y, h, p, mode, ws):
    """Solve stage s by simplified Newton: z = w + hγ·f(t + c_s h, z); returns (solved, f evals).
    Newton increments are measured in the weights 1/(atol + rtol·|y|) of the step's start."""
    n = y.size
    hg = h * GAMMA
    # explicit part w of the stage and the first guess of z (the previous stage's slope)
    for i in range(n):
        acc = y[i]
        for j in range(s):
            acc += h * _A[s, j] * ws.k[j, i]
        ws.w[i] = acc
        ws.z[i] = acc + hg * (ws.k[s - 1, i] if s > 0 else ws.f0[i])
    tol2 = NEWTON_TOL * NEWTON_TOL * n
    last = np.inf
    for it in range(NEWTON_MAXIT):
        rhs(system, t + C[s] * h, ws.z, p, mode, ws.f, ws.jac, False)
        for i in range(n):
            ws.err[i] = ws.w[i] + hg * ws.f[i] - ws.z[i]  # Newton residual
        solve(ws.inv, ws.err, ws.dz)
        nrm = 0.0  # squared weighted norm times n
        for i in range(n):
            ws.z[i] += ws.dz[i]
            nrm += (ws.dz[i] * ws.wt[i]) ** 2
        # contraction rate θ; the remaining error is about θ/(1 − θ) times the increment
        if it > 0:
            theta = math.sqrt(nrm / last)
            if theta >= 0.99:
                return False, it + 1
            ws.eta[0] = theta / (1.0 - theta)
        if ws.eta[0] * ws.eta[0] * nrm < tol2 or nrm < 1e-28:
            return True, it + 1
        last = nrm
    return False, NEWTON_MAXIT


@njit(**JIT)
def step(system, t, y, h, p, mode, rtol, atol, y_new, ws):
    """One SDIRK4 step from (t, y) of size h into ``y_new``: (solved, error norm, f evals).

    Not solved when the Newton iteration fails (the caller shrinks the step). After the step
    ``ws.f0`` holds f(t, y) and ``ws.f1`` the derivative at its end (stiffly accurate: the last
    stage's), for Hermite interpolation (:func:`hermite`)."""
    n = y.size
    ws.eta[0] = max(ws.eta[0], 1e-16) ** 0.8 if ws.eta[0] > 0 else 1.0
    if not _newton_matrix(system, t, y, h, p, mode, rtol, atol, ws):
        return False, np.inf, 1
    nfev = 1
    inv_hg = 1.0 / (h * GAMMA)
    # the five stages, each from the slopes of the ones before
    for s in range(5):
        solved, nf = _stage(system, s, t, y, h, p, mode, ws)
        nfev += nf
        if not solved:
            return False, np.inf, nfev
        for i in range(n):
            ws.k[s, i] = (ws.z[i] - ws.w[i]) * inv_hg
    # stiffly accurate: the last stage is the solution; the error of the embedded order-3
    # solution, filtered through (I − hγJ)⁻¹
    for i in range(n):
        y_new[i] = ws.z[i]
        ws.f1[i] = ws.k[4, i]
        acc = 0.0
        for s in range(5):
            acc += _E[s] * ws.k[s, i]
        ws.dz[i] = h * acc
    solve(ws.inv, ws.dz, ws.err)
    return True, scaled_norm(ws.err, y, y_new, rtol, atol), nfev


@njit(**JIT)
def new_step(h, err_norm):
    """Step-size controller for the order-3 embedded estimate (safety 0.9, factor 0.2-5)."""
    if err_norm == 0.0:
        return 5.0 * h
    return h * min(5.0, max(0.2, 0.9 * err_norm ** (-1.0 / (ORDER_EMBEDDED + 1))))


@njit(**JIT)
def hermite(y0, f0, y1, f1, h, th, out):
    """Cubic Hermite interpolant of a step of size h at θ = th ∈ [0, 1] into ``out``."""
    a, b = th * th * (2.0 * th - 3.0) + 1.0, th * (th - 1.0) * (th - 1.0)
    c, d = th * th * (3.0 - 2.0 * th), th * th * (th - 1.0)
    for i in range(y0.size):
        out[i] = a * y0[i] + b * h * f0[i] + c * y1[i] + d * h * f1[i]
